//! Object-order visibility: the solids' voxel faces drawn into the sample grid, by
//! Meagher's front-to-back octree display (`front_to_back`), painter's algorithm,
//! a Z-buffer and the seed's scan-line Z-buffer (`scan_line`); and triangle meshes
//! drawn as polygons with interpolation shading ([`polygon`]), their visibility by the
//! scan-line Z-buffer, a Z-buffer or the chapter's depth sort (`depth_sort`: the five
//! overlap tests, swaps and splits).
//!
//! A face covers a sample when the sample's ray crosses the face's plane (at the time
//! `(plane - o) / d`, the formula of the ray walk) and then enters the node's interior
//! there; the hit is then computed by `VoxelRay::entry`, as in the walk (`face`). So
//! every method here hands the shading stage the hits the ray tracer finds, bit for
//! bit (see [`super::visibility`]).
//!
//! - Painter's: the full nodes visited far to near (the reverse of the front-to-back
//!   order), every face looking at the viewer drawn over what is under it.
//! - Z-buffer: the faces in any order (here: the octree's, with children in storage
//!   order), kept where nearer than the depth stored for the sample.

mod depth_sort;
mod face;
mod front_to_back;
pub mod polygon;
mod projected;
mod scan_line;

use glam::DVec3;

pub(crate) use front_to_back::{Display, Strip, front_to_back};

use super::film::{Projection, SampleGrid, View};
use super::trace::{Hit, Traversal, VoxelRay};
use crate::octree::Domain;
use crate::ray::Ray;
use face::{Face, Viewer};

/// Draws one solid's faces into a per-sample hit buffer (painter's, the Z-buffer and
/// the scan-line Z-buffer).
pub(crate) struct FaceDrawer<'a> {
    view: &'a View,
    samples: &'a SampleGrid,
    rays: &'a [Ray],
    domain: Domain,
    viewer: Viewer,
}

impl<'a> FaceDrawer<'a> {
    /// A drawer for one solid's `domain`; `rays[i]` is sample `i`'s camera ray.
    pub(crate) fn new(view: &'a View, samples: &'a SampleGrid, rays: &'a [Ray], domain: Domain) -> Self {
        FaceDrawer { view, samples, rays, domain, viewer: Viewer::new(view, &domain) }
    }

    /// Painter's algorithm: the solid's hit per sample and the faces drawn.
    pub(crate) fn painter(&self, traversal: &Traversal) -> (Vec<Option<Hit>>, u64) {
        let mut hits: Vec<Option<Hit>> = vec![None; self.rays.len()];
        let mut faces = 0;
        let viewer = self.viewer;
        let mut nodes = Vec::new();
        let eye_high = |a, plane| viewer.is_high(a, plane);
        traversal.front_to_back(&eye_high, &mut |_, _| true, &mut |min, size| nodes.push((min, size)));
        for &(min, size) in nodes.iter().rev() {
            faces += self.draw_node(min, size, &mut |i, hit| hits[i] = Some(hit));
        }
        (hits, faces)
    }

    /// The Z-buffer: the solid's hit per sample and the faces drawn.
    pub(crate) fn z_buffer(&self, traversal: &Traversal) -> (Vec<Option<Hit>>, u64) {
        let mut hits: Vec<Option<Hit>> = vec![None; self.rays.len()];
        let mut faces = 0;
        let mut nodes = Vec::new();
        traversal.front_to_back(&|_, _| false, &mut |_, _| true, &mut |min, size| nodes.push((min, size)));
        for (min, size) in nodes {
            faces += self.draw_node(min, size, &mut |i, hit| {
                if hits[i].is_none_or(|old| hit.t < old.t) {
                    hits[i] = Some(hit);
                }
            });
        }
        (hits, faces)
    }

    /// The sample-grid rectangle (inclusive) that the box `[min, min + size]` may cover:
    /// none when the box lies behind the eye (no primary ray meets it), the whole grid
    /// when it reaches behind the eye.
    fn footprint(&self, lo: DVec3, hi: DVec3) -> (u32, u32, u32, u32) {
        const EMPTY: (u32, u32, u32, u32) = (1, 0, 1, 0);
        let full = (0, self.samples.columns() - 1, 0, self.samples.rows() - 1);
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        let corner = |i: usize| {
            DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        if (0..8).all(|i| (corner(i) - self.view.eye).dot(self.view.forward) < 0.0)
            && matches!(self.view.projection, Projection::Perspective { .. })
        {
            return EMPTY;
        }
        for i in 0..8 {
            let Some((x, y)) = self.view.project(corner(i)) else { return full };
            let (c, r) = (self.samples.column_of(x), self.samples.row_of(y));
            x0 = x0.min(c);
            x1 = x1.max(c);
            y0 = y0.min(r);
            y1 = y1.max(r);
        }
        let clamp = |v: f64, n: u32| (v.max(0.0) as u32).min(n - 1);
        if x1 < -1.0 || y1 < -1.0 || x0 > f64::from(self.samples.columns()) || y0 > f64::from(self.samples.rows()) {
            return EMPTY;
        }
        (
            clamp(x0.floor() - 1.0, self.samples.columns()),
            clamp(x1.ceil() + 1.0, self.samples.columns()),
            clamp(y0.floor() - 1.0, self.samples.rows()),
            clamp(y1.ceil() + 1.0, self.samples.rows()),
        )
    }

    /// Draws the faces of the full node `[min, min + size)` that look at the viewer:
    /// `put(sample, hit)` for every sample whose ray enters the node through them.
    /// Returns the faces drawn.
    fn draw_node(&self, min: [u32; 3], size: u32, put: &mut impl FnMut(usize, Hit)) -> u64 {
        let mut faces = 0;
        for face in Face::visible(&self.viewer, min, size) {
            faces += 1;
            let (mut flo, mut fhi) = (DVec3::from_array(face.lo), DVec3::from_array(face.hi));
            flo[face.axis] = face.plane;
            fhi[face.axis] = face.plane;
            let h = self.domain.voxel_size();
            let (wlo, whi) = (self.domain.min() + flo * h, self.domain.min() + fhi * h);
            let (c0, c1, r0, r1) = self.footprint(wlo, whi);
            let columns = self.samples.columns() as usize;
            for r in r0..=r1 {
                for c in c0..=c1 {
                    let i = r as usize * columns + c as usize;
                    let ray = VoxelRay::new(&self.domain, &self.rays[i]);
                    if let Some(hit) = face.enters(&ray) {
                        put(i, hit);
                    }
                }
            }
        }
        faces
    }
}
