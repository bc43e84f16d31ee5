//! Polygon rendering of triangle meshes (seed: shading of polygon objects): a scan-line
//! Z-buffer with flat, Gouraud or Phong interpolation shading, no shadows.
//!
//! Visibility: every triangle is projected by the camera; a row of the image gathers
//! the triangles whose projected rows cover it (the active polygons of that scan line),
//! and for each pixel centre `(x, y)` inside a triangle's projection (screen-space
//! barycentrics `l0, l1, l2` from the edge functions, all `>= 0`; top-left rule-free:
//! an edge pixel may be claimed by both neighbours and the nearer wins) the depth is
//! interpolated perspective-correctly, `1/z = sum li / zi`, and the nearest triangle is
//! kept in one row of depths. Both sides of a triangle are drawn (meshes may be open);
//! a normal facing away from the viewer is flipped.
//!
//! Shading, with the Phong model `I = ka Ia C + sum_i Ii (kd C cos(alpha_i) + ks
//! cos^n(theta_i))` of the scene's lights:
//! - flat: once a triangle, at its centroid with its plane normal (Mach bands show);
//! - Gouraud: at the vertices with the vertex normals (area-weighted means of the
//!   faces' normals), colours interpolated bilinearly across the projection (along the
//!   edges by row, along the span by column: screen-linear, as the seed describes);
//! - Phong: the vertex normals interpolated the same way, renormalized, and the model
//!   evaluated at every pixel at the (perspective-correct) surface point.

use glam::DVec3;
use image::RgbImage;
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::mesh::TriangleMesh;
use crate::render::film::resolve::resolve;
use crate::render::film::{Camera, Projection};
use crate::render::scene::{Light, Material};
use crate::render::shade::phong;

/// How colour is spread over a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// One colour a triangle.
    Flat,
    /// Colours computed at the vertices, interpolated.
    Gouraud,
    /// Normals interpolated, colour computed at every pixel.
    Phong,
}

impl std::str::FromStr for Interpolation {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "flat" => Ok(Interpolation::Flat),
            "gouraud" => Ok(Interpolation::Gouraud),
            "phong" => Ok(Interpolation::Phong),
            other => Err(format!("{other:?} is not flat, gouraud or phong")),
        }
    }
}

/// What lights a mesh and where it stands.
#[derive(Clone, Debug)]
pub struct MeshScene<'a> {
    /// The mesh.
    pub mesh: &'a TriangleMesh,
    /// Its material (textures are not used here).
    pub material: Material,
    /// The lights.
    pub lights: Vec<Light>,
    /// Ambient intensity `Ia`.
    pub ambient: DVec3,
    /// Colour where no triangle is seen.
    pub background: DVec3,
}

/// What a pixel centre sees: the triangle and its screen-space barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    /// Index of the triangle.
    pub triangle: usize,
    /// Screen-space barycentric coordinates of the pixel centre.
    pub weights: [f64; 3],
    /// View depth of the surface point (distance along the view axis).
    pub depth: f64,
}

/// A triangle as drawn: its projected corners in pixels and their view depths.
struct Projected {
    screen: [(f64, f64); 3],
    depth: [f64; 3],
    /// Twice the signed screen area (edge function normalizer).
    area: f64,
}

/// The triangle seen at every pixel centre of a `width x height` image, row-major.
/// Triangles with a corner behind a perspective camera are skipped.
#[must_use]
pub fn fragments(mesh: &TriangleMesh, camera: &Camera, width: u32, height: u32) -> Vec<Option<Fragment>> {
    let aspect = f64::from(width) / f64::from(height);
    let forward = (camera.target - camera.eye).normalize();
    // Polygon table: the projected triangles, and for each row the ones covering it.
    let projected: Vec<Option<Projected>> = mesh
        .triangles
        .par_iter()
        .map(|t| {
            let mut screen = [(0.0, 0.0); 3];
            let mut depth = [0.0; 3];
            for k in 0..3 {
                let p = mesh.vertices[t[k] as usize];
                let (x, y) = camera.project(p, aspect)?;
                screen[k] = ((x + 1.0) * 0.5 * f64::from(width), (1.0 - y) * 0.5 * f64::from(height));
                depth[k] = (p - camera.eye).dot(forward);
            }
            let [a, b, c] = screen;
            let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
            (area != 0.0).then_some(Projected { screen, depth, area })
        })
        .collect();
    let rows = height as usize;
    let mut by_row: Vec<Vec<usize>> = vec![Vec::new(); rows];
    for (i, p) in projected.iter().enumerate() {
        let Some(p) = p else { continue };
        let ys = p.screen.map(|s| s.1);
        let first = (ys.iter().copied().fold(f64::INFINITY, f64::min) - 0.5).ceil().max(0.0);
        let last = (ys.iter().copied().fold(f64::NEG_INFINITY, f64::max) - 0.5).floor().min(rows as f64 - 1.0);
        if first <= last {
            for row in &mut by_row[first as usize..=last as usize] {
                row.push(i);
            }
        }
    }
    let perspective = matches!(camera.projection, Projection::Perspective { .. });
    // Each row: the active triangles' spans, kept where nearest.
    by_row
        .par_iter()
        .enumerate()
        .flat_map_iter(|(row, active)| {
            let y = row as f64 + 0.5;
            let mut line: Vec<Option<Fragment>> = vec![None; width as usize];
            for &i in active {
                let p = projected[i].as_ref().expect("only drawable triangles are listed");
                let Some((x0, x1)) = span(p, y) else { continue };
                let first = (x0 - 0.5).ceil().max(0.0) as usize;
                let last = ((x1 - 0.5).floor()).min(f64::from(width) - 1.0);
                if last < 0.0 {
                    continue;
                }
                for (col, slot) in line.iter_mut().enumerate().take(last as usize + 1).skip(first) {
                    let x = col as f64 + 0.5;
                    let Some(weights) = barycentric(p, x, y) else { continue };
                    let depth = if perspective {
                        1.0 / (0..3).map(|k| weights[k] / p.depth[k]).sum::<f64>()
                    } else {
                        (0..3).map(|k| weights[k] * p.depth[k]).sum()
                    };
                    if slot.is_none_or(|f| depth < f.depth) {
                        *slot = Some(Fragment { triangle: i, weights, depth });
                    }
                }
            }
            line
        })
        .collect()
}

/// The columns `[x0, x1]` where the row `y` crosses the projected triangle.
fn span(p: &Projected, y: f64) -> Option<(f64, f64)> {
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..3 {
        let (a, b) = (p.screen[k], p.screen[(k + 1) % 3]);
        if (a.1 <= y && y <= b.1) || (b.1 <= y && y <= a.1) {
            let x = if a.1 == b.1 { a.0.min(b.0) } else { a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1) };
            let xm = if a.1 == b.1 { a.0.max(b.0) } else { x };
            x0 = x0.min(x);
            x1 = x1.max(xm);
        }
    }
    (x0 <= x1).then_some((x0, x1))
}

/// Screen-space barycentrics of `(x, y)`, `None` outside the triangle.
fn barycentric(p: &Projected, x: f64, y: f64) -> Option<[f64; 3]> {
    let edge = |a: (f64, f64), b: (f64, f64)| (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0);
    let [a, b, c] = p.screen;
    let w = [edge(b, c) / p.area, edge(c, a) / p.area, edge(a, b) / p.area];
    w.iter().all(|&w| w >= 0.0).then_some(w)
}

/// Area-weighted vertex normals: the sum of the adjacent faces' `(b - a) x (c - a)`,
/// normalized (zero for a vertex of degenerate faces only).
#[must_use]
pub fn vertex_normals(mesh: &TriangleMesh) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; mesh.vertices.len()];
    for (i, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = mesh.corners(i);
        let n = (b - a).cross(c - a);
        for &v in t {
            normals[v as usize] += n;
        }
    }
    normals.iter().map(|n| n.normalize_or_zero()).collect()
}

/// Renders `scene` through `camera` to a `width x height` image with `spp x spp`
/// samples a pixel (a box filter over the supersampled image).
pub fn render_mesh(
    scene: &MeshScene,
    camera: &Camera,
    width: u32,
    height: u32,
    spp: u32,
    interpolation: Interpolation,
) -> Result<RgbImage> {
    if width == 0 || height == 0 || !(1..=16).contains(&spp) {
        return Err(Error::invalid("image", format!("{width}x{height} at {spp}x{spp} samples a pixel")));
    }
    scene.material.check()?;
    let (w, h) = (width * spp, height * spp);
    let seen = fragments(scene.mesh, camera, w, h);
    let normals = vertex_normals(scene.mesh);
    let shader = Shader { scene, camera };
    // Gouraud: the vertex colours, once.
    let vertex_colors: Vec<DVec3> = match interpolation {
        Interpolation::Gouraud => (0..scene.mesh.vertices.len())
            .into_par_iter()
            .map(|v| shader.light(scene.mesh.vertices[v], normals[v]))
            .collect(),
        _ => Vec::new(),
    };
    let aspect = f64::from(w) / f64::from(h);
    let linear: Vec<DVec3> = seen
        .par_iter()
        .enumerate()
        .map(|(i, f)| {
            let Some(f) = f else { return scene.background };
            let t = scene.mesh.triangles[f.triangle];
            let corners = scene.mesh.corners(f.triangle);
            match interpolation {
                Interpolation::Flat => {
                    let [a, b, c] = corners;
                    shader.light((a + b + c) / 3.0, (b - a).cross(c - a).normalize_or_zero())
                }
                Interpolation::Gouraud => (0..3).map(|k| vertex_colors[t[k] as usize] * f.weights[k]).sum(),
                Interpolation::Phong => {
                    let n: DVec3 = (0..3).map(|k| normals[t[k] as usize] * f.weights[k]).sum();
                    let (x, y) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
                    let ray = camera.ray(2.0 * x / f64::from(w) - 1.0, 1.0 - 2.0 * y / f64::from(h), aspect);
                    let forward = (camera.target - camera.eye).normalize();
                    let p = ray.at(f.depth / ray.dir.dot(forward));
                    shader.light(p, n.normalize_or_zero())
                }
            }
        })
        .collect();
    let mut img = RgbImage::new(width, height);
    for (x, y, px) in img.enumerate_pixels_mut() {
        let mut sum = DVec3::ZERO;
        for sy in 0..spp {
            for sx in 0..spp {
                sum += linear[((y * spp + sy) * w + x * spp + sx) as usize];
            }
        }
        *px = resolve(sum, spp * spp);
    }
    Ok(img)
}

/// The Phong model for a mesh scene.
struct Shader<'a> {
    scene: &'a MeshScene<'a>,
    camera: &'a Camera,
}

impl Shader<'_> {
    /// Light leaving the point `p` of normal `n` towards the camera (both sides lit:
    /// the normal is turned towards the viewer).
    fn light(&self, p: DVec3, n: DVec3) -> DVec3 {
        let m = &self.scene.material;
        let v = match self.camera.projection {
            Projection::Perspective { .. } => (self.camera.eye - p).normalize_or_zero(),
            Projection::Orthographic { .. } => (self.camera.eye - self.camera.target).normalize_or_zero(),
        };
        let n = if n.dot(v) < 0.0 { -n } else { n };
        phong(m, m.color, self.scene.ambient, (p, n, v), &self.scene.lights, |_| 1.0)
    }
}
