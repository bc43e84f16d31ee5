//! Polygon rendering of triangle meshes (seed: shading of polygon objects): visibility
//! by the scan-line Z-buffer (the default), a whole-image Z-buffer or the depth sort
//! ([`MeshVisibility`]; painter's in `depth_sort`), then flat, Gouraud or Phong
//! interpolation shading, no shadows.
//!
//! Visibility by scan lines ([`fragments`]; the Z-buffer, [`z_buffer_fragments`], tests
//! the same pixel centres with the same barycentrics and depths): every triangle is projected by the camera; a row of the image gathers
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
use rayon::prelude::*;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::mesh::TriangleMesh;
use crate::render::film::Picture;
use crate::render::film::resolve::{exposure_scale, resolve};
use crate::render::film::{Camera, Projection};
use crate::render::pipeline::MAX_IMAGE_SIZE;
use crate::render::scene::{Light, Material};
use crate::render::shade::phong;
use crate::render::visibility::Method;

pub use super::depth_sort::DepthSortCounts;
use super::depth_sort::depth_sort_fragments;
pub use super::projected::Fragment;
use super::projected::{Projected, barycentric, project_triangles};

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

impl Interpolation {
    /// Every value, in the order `--help` lists them.
    pub const ALL: [Interpolation; 3] = [Interpolation::Flat, Interpolation::Gouraud, Interpolation::Phong];

    /// The value's one spelling (the command line's, `Display`'s).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Flat => "flat",
            Interpolation::Gouraud => "gouraud",
            Interpolation::Phong => "phong",
        }
    }
}

crate::spelling::spelled!(Interpolation);

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

/// How a triangle mesh's visibility is decided (`octsolid render MESH --shading S
/// --method painter|zbuffer|scanline`): each gives the same nearest triangle at every
/// pixel centre, except where two surfaces lie within rounding of each other.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshVisibility {
    /// The chapter's depth sort (Newell, Newell and Sancha): far to near with the five
    /// overlap tests, swaps and splits ([`DepthSortCounts`] says what settled what).
    Painter,
    /// A whole-image depth buffer, the triangles drawn in mesh order.
    ZBuffer,
    /// The scan-line Z-buffer: one row of depths, the row's active triangles
    /// ([`fragments`]).
    #[default]
    ScanLine,
}

impl MeshVisibility {
    /// The same method for triangle meshes drawn as polygons (painter's, the Z-buffer
    /// and the scan-line Z-buffer); `None` for the octree's own (trace, front-to-back).
    #[must_use]
    pub fn of(method: Method) -> Option<MeshVisibility> {
        match method {
            Method::Painter => Some(MeshVisibility::Painter),
            Method::ZBuffer => Some(MeshVisibility::ZBuffer),
            Method::ScanLine => Some(MeshVisibility::ScanLine),
            Method::Trace | Method::FrontToBack => None,
        }
    }
}

/// The triangle seen at every pixel centre of a `width x height` image, row-major, by
/// the scan-line Z-buffer. Triangles with a corner behind a perspective camera are
/// skipped. Refused when the rows' triangle lists (8 bytes for every row a triangle
/// covers, counted after projecting and before listing) exceed `budget`: a few thousand
/// triangles that each span the picture would otherwise list millions of entries.
pub fn fragments(
    mesh: &TriangleMesh,
    camera: &Camera,
    width: u32,
    height: u32,
    budget: MemoryBudget,
) -> Result<Vec<Option<Fragment>>> {
    // Polygon table: the projected triangles, and for each row the ones covering it.
    let projected = project_triangles(mesh, camera, width, height);
    let rows = height as usize;
    let row_span = |p: &Projected| {
        let ys = p.screen.map(|s| s.1);
        let first = (ys.iter().copied().fold(f64::INFINITY, f64::min) - 0.5).ceil().max(0.0);
        let last = (ys.iter().copied().fold(f64::NEG_INFINITY, f64::max) - 0.5).floor().min(rows as f64 - 1.0);
        (first <= last).then_some(first as usize..=last as usize)
    };
    let entries: u64 = projected.iter().flatten().filter_map(row_span).map(|r| r.count() as u64).sum();
    budget.check(format!("listing triangles on {rows} rows"), entries.saturating_mul(8))?;
    let mut by_row: Vec<Vec<usize>> = vec![Vec::new(); rows];
    for (i, p) in projected.iter().enumerate() {
        if let Some(span) = p.as_ref().and_then(row_span) {
            for row in &mut by_row[span] {
                row.push(i);
            }
        }
    }
    let perspective = matches!(camera.projection, Projection::Perspective { .. });
    // Each row: the active triangles' spans, kept where nearest.
    let seen = by_row
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
                    let depth = p.depth_at(weights, perspective);
                    if slot.is_none_or(|f| depth < f.depth) {
                        *slot = Some(Fragment { triangle: i, weights, depth });
                    }
                }
            }
            line
        })
        .collect::<Vec<_>>();
    Ok(seen)
}

/// The triangle seen at every pixel centre by a whole-image Z-buffer: the triangles in
/// mesh order, each over the pixel centres of its projected bounding box, a fragment
/// kept where nearer than the one stored (the same tie rule as [`fragments`]: the
/// earlier triangle keeps an equal depth).
pub fn z_buffer_fragments(mesh: &TriangleMesh, camera: &Camera, width: u32, height: u32) -> Vec<Option<Fragment>> {
    let projected = project_triangles(mesh, camera, width, height);
    let perspective = matches!(camera.projection, Projection::Perspective { .. });
    let mut buffer: Vec<Option<Fragment>> = vec![None; width as usize * height as usize];
    for (i, p) in projected.iter().enumerate() {
        let Some(p) = p else { continue };
        p.for_each_pixel(width, height, |pixel, x, y| {
            let Some(weights) = barycentric(p, x, y) else { return };
            let depth = p.depth_at(weights, perspective);
            let slot = &mut buffer[pixel];
            if slot.is_none_or(|f| depth < f.depth) {
                *slot = Some(Fragment { triangle: i, weights, depth });
            }
        });
    }
    buffer
}

/// The triangle seen at every pixel centre by `method`, and the depth sort's counts
/// (zero unless `method` is [`MeshVisibility::Painter`]). The budget bounds the
/// scan-line's row lists and the depth sort's polygons.
pub fn visible_fragments(
    mesh: &TriangleMesh,
    camera: &Camera,
    width: u32,
    height: u32,
    budget: MemoryBudget,
    method: MeshVisibility,
) -> Result<(Vec<Option<Fragment>>, DepthSortCounts)> {
    Ok(match method {
        MeshVisibility::ScanLine => (fragments(mesh, camera, width, height, budget)?, DepthSortCounts::default()),
        MeshVisibility::ZBuffer => (z_buffer_fragments(mesh, camera, width, height), DepthSortCounts::default()),
        MeshVisibility::Painter => depth_sort_fragments(mesh, camera, width, height, budget)?,
    })
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

/// The picture [`render_mesh`] makes.
#[derive(Clone, Copy, Debug)]
pub struct MeshRenderOptions {
    /// Image width in pixels, `1..=`[`MAX_IMAGE_SIZE`].
    pub width: u32,
    /// Image height in pixels, `1..=`[`MAX_IMAGE_SIZE`].
    pub height: u32,
    /// `spp x spp` samples a pixel, `1..=16`.
    pub spp: u32,
    /// How colours are interpolated across a triangle.
    pub interpolation: Interpolation,
    /// Refuse pictures whose estimated memory ([`estimate_mesh_render_bytes`]) exceeds this.
    pub budget: MemoryBudget,
    /// Exposure in stops: every pixel's radiance times `2^exposure` (as
    /// [`RenderOptions::exposure`](crate::render::RenderOptions::exposure)).
    pub exposure: f64,
}

/// Estimated peak bytes of [`render_mesh`]: a fragment (48 bytes) and a linear colour
/// (24 bytes) for each of the `(width spp) x (height spp)` samples, a scan line of
/// fragments, the 24-byte linear pixels, and a normal and a colour (48 bytes) a vertex.
#[must_use]
pub fn estimate_mesh_render_bytes(options: &MeshRenderOptions, vertices: usize) -> u64 {
    let (w, h) =
        (u64::from(options.width) * u64::from(options.spp), u64::from(options.height) * u64::from(options.spp));
    let per_sample = (std::mem::size_of::<Option<Fragment>>() + std::mem::size_of::<DVec3>()) as u64;
    (w * h).saturating_mul(per_sample)
        + w * 48
        + u64::from(options.width) * u64::from(options.height) * std::mem::size_of::<DVec3>() as u64
        + 48 * vertices as u64
}

/// Renders `scene` through `camera` to a `width x height` picture of linear radiance
/// with `spp x spp` samples a pixel (a box filter over the supersampled image, times
/// the exposure's `2^stops`; [`Picture::to_srgb8`] for a PNG). Refused before any
/// work when the size, samples or exposure are out of range, the camera cannot make a
/// picture ([`Camera::validate`]) or the estimate exceeds the budget.
pub fn render_mesh(scene: &MeshScene, camera: &Camera, options: &MeshRenderOptions) -> Result<Picture> {
    Ok(render_mesh_by(scene, camera, options, MeshVisibility::ScanLine)?.0)
}

/// [`render_mesh`] with the visibility decided by `method`, and the depth sort's
/// counts (zero unless `method` is [`MeshVisibility::Painter`]).
pub fn render_mesh_by(
    scene: &MeshScene,
    camera: &Camera,
    options: &MeshRenderOptions,
    method: MeshVisibility,
) -> Result<(Picture, DepthSortCounts)> {
    let MeshRenderOptions { width, height, spp, interpolation, budget, exposure } = *options;
    if !(1..=MAX_IMAGE_SIZE).contains(&width) || !(1..=MAX_IMAGE_SIZE).contains(&height) {
        return Err(Error::invalid("image size", format!("{width}x{height} is outside 1..={MAX_IMAGE_SIZE} a side")));
    }
    if !(1..=16).contains(&spp) {
        return Err(Error::invalid("samples", format!("{spp} a side is outside 1..=16")));
    }
    camera.validate()?;
    let scale = exposure_scale(exposure)?;
    budget.check(
        format!("a {width}x{height} polygon picture at {spp}x{spp} samples a pixel"),
        estimate_mesh_render_bytes(options, scene.mesh.vertices.len()),
    )?;
    scene.material.validate()?;
    let (w, h) = (width * spp, height * spp);
    let (seen, counts) = visible_fragments(scene.mesh, camera, w, h, budget, method)?;
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
                    let (x, y) = ((i % w as usize) as f64 + 0.5, (i / w as usize) as f64 + 0.5);
                    let ray = camera.ray(2.0 * x / f64::from(w) - 1.0, 1.0 - 2.0 * y / f64::from(h), aspect);
                    let forward = (camera.target - camera.eye).normalize();
                    let p = ray.at(f.depth / ray.dir.dot(forward));
                    shader.light(p, n.normalize_or_zero())
                }
            }
        })
        .collect();
    let mut picture = Picture::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let mut sum = DVec3::ZERO;
            for sy in 0..spp {
                for sx in 0..spp {
                    sum += linear[(y * spp + sy) as usize * w as usize + (x * spp + sx) as usize];
                }
            }
            picture.set(x, y, resolve(sum, spp * spp, scale));
        }
    }
    Ok((picture, counts))
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
