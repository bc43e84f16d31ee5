//! The world cube an octree lives in, and its depth.

use glam::DVec3;

use crate::aabb::Aabb;
use crate::error::{Error, Number, Result, Vector};
use crate::morton;

/// Deepest allowed octree: 21 levels, 2,097,152 voxels a side, Morton codes in 63 bits.
pub const MAX_DEPTH: u8 = morton::MAX_BITS as u8;

/// Domain edges octsolid accepts: far enough from the limits of `f64` that areas,
/// volumes and the fifth powers in moments of inertia (`edge^5`) stay finite and
/// normal at every depth.
pub const EDGE_RANGE: std::ops::RangeInclusive<f64> = 1e-50..=1e50;

/// How far from the origin a domain's corners may lie.
pub const MAX_COORDINATE: f64 = 1e50;

/// Bits of a voxel's edge that must lie above the last place of the domain's largest
/// coordinate, so voxel corners and centres are distinct numbers with room for the
/// sub-voxel positions of rays and surfaces.
pub const LATTICE_BITS: u32 = 8;

/// A world-space cube `[min, min + edge]^3` split into `2^depth` voxels per axis.
///
/// Voxel `(i, j, k)` covers `min + h * [i, i+1) x [j, j+1) x [k, k+1)` with
/// `h = edge / 2^depth`; its centre is `min + h * (i + 1/2, ...)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain {
    min: DVec3,
    edge: f64,
    depth: u8,
}

impl Domain {
    /// A domain with lowest corner `min`, edge length `edge` and `depth` levels.
    ///
    /// Fails when the depth is outside `1..=21`, any number is not finite, the edge is
    /// outside [`EDGE_RANGE`], a corner is farther than [`MAX_COORDINATE`] from the
    /// origin, or the corner's coordinates are so large against the voxel that
    /// neighbouring voxel corners would round to the same number (fewer than
    /// [`LATTICE_BITS`] bits of a voxel left below the coordinates' last place).
    pub fn new(min: DVec3, edge: f64, depth: u8) -> Result<Self> {
        if !(1..=MAX_DEPTH).contains(&depth) {
            return Err(Error::invalid("depth", format!("{depth} is outside 1..={MAX_DEPTH}")));
        }
        if !min.is_finite() || !edge.is_finite() || edge <= 0.0 {
            return Err(Error::invalid(
                "domain",
                format!("min {} and edge {} must be finite with a positive edge", Vector(min), Number(edge)),
            ));
        }
        if !EDGE_RANGE.contains(&edge) {
            return Err(Error::invalid(
                "domain",
                format!(
                    "edge {edge:e} is outside the supported {:e}..={:e} (scale the model's units)",
                    EDGE_RANGE.start(),
                    EDGE_RANGE.end()
                ),
            ));
        }
        let reach = min.abs().max(min + DVec3::splat(edge)).max_element();
        if reach > MAX_COORDINATE {
            return Err(Error::invalid(
                "domain",
                format!("it reaches {reach:e} from the origin, beyond the supported {MAX_COORDINATE:e}"),
            ));
        }
        let voxel = edge / f64::from(1u32 << depth);
        if reach * f64::EPSILON * f64::from(1u32 << LATTICE_BITS) > voxel {
            return Err(Error::invalid(
                "domain",
                format!(
                    "its corners reach {reach:e} from the origin, too far for voxels of {voxel:e} \
                     (double precision keeps {LATTICE_BITS} bits of a voxel only within {:e}); \
                     move the model nearer the origin or use a smaller depth",
                    voxel / (f64::EPSILON * f64::from(1u32 << LATTICE_BITS))
                ),
            ));
        }
        Ok(Domain { min, edge, depth })
    }

    /// The cube of depth `depth` centred on `bounds`, with edge the longest side of
    /// `bounds` grown by `margin` (a fraction, e.g. 0.02) so the shape touches no face.
    /// Bounds that are a point (a mesh of coincident vertices) get the unit cube
    /// around it.
    pub fn around(bounds: &Aabb, margin: f64, depth: u8) -> Result<Self> {
        if !bounds.is_finite() {
            return Err(Error::invalid("bounds", "shape bounds are not finite; give a domain"));
        }
        let longest = bounds.size().max_element();
        let edge = if longest == 0.0 { 1.0 } else { longest * (1.0 + 2.0 * margin) };
        Domain::new(bounds.center() - DVec3::splat(edge * 0.5), edge, depth)
    }

    /// The cube of voxels of edge `voxel` whose lattice falls on the multiples of
    /// `voxel`, holding `bounds` with at least one voxel to spare on every side, the
    /// bounds centred to a whole voxel: the domain for dimensions that come out exact.
    /// A voxel is full when its centre is inside, so a face of a shape on a multiple of
    /// `voxel` is a voxel plane, and a box from 0 to 80 voxelized on a grid of 0.5 is
    /// 80 long, where a domain chosen by the bounds alone rounds each face to its
    /// nearest voxel plane (up to half a voxel off). The depth is the least that holds
    /// the bounds; with `depth`, that one, refused when too small to hold them.
    ///
    /// Fails when `voxel` is not a finite positive number, the bounds are not finite,
    /// or they need more than [`MAX_DEPTH`] levels, and as [`Domain::new`].
    pub fn on_grid(bounds: &Aabb, voxel: f64, depth: Option<u8>) -> Result<Self> {
        if !(voxel.is_finite() && voxel > 0.0) {
            return Err(Error::invalid("voxel size", format!("{} must be a finite positive number", Number(voxel))));
        }
        if !bounds.is_finite() {
            return Err(Error::invalid("bounds", "shape bounds are not finite; give a domain"));
        }
        // Lattice indices of the bounds, a voxel to spare each side.
        let lo = (bounds.min / voxel).floor() - DVec3::ONE;
        let hi = (bounds.max / voxel).ceil() + DVec3::ONE;
        let span = (hi - lo).max_element();
        let needed = (span.max(1.0)).log2().ceil().max(1.0);
        if needed > f64::from(MAX_DEPTH) {
            return Err(Error::invalid(
                "voxel size",
                format!(
                    "{voxel}: the shapes span {span} voxels, more than the {} of depth {MAX_DEPTH}",
                    1u32 << MAX_DEPTH
                ),
            ));
        }
        let depth = match depth {
            None => needed as u8,
            Some(d) if f64::from(d) >= needed => d,
            Some(d) => {
                return Err(Error::invalid(
                    "depth",
                    format!(
                        "{d} holds {} voxels of {voxel} a side; the shapes span {span}: use depth {needed} or more",
                        1u64 << d
                    ),
                ));
            }
        };
        let side = f64::from(1u32 << depth);
        // Centred: the spare voxels split evenly (to a whole voxel) on each axis.
        let min = (lo - ((DVec3::splat(side) - (hi - lo)) * 0.5).floor()) * voxel;
        Domain::new(min, side * voxel, depth)
    }

    /// Lowest corner.
    #[must_use]
    pub fn min(&self) -> DVec3 {
        self.min
    }

    /// Edge length of the cube.
    #[must_use]
    pub fn edge(&self) -> f64 {
        self.edge
    }

    /// Number of levels below the root.
    #[must_use]
    pub fn depth(&self) -> u8 {
        self.depth
    }

    /// Voxels per axis, `2^depth`.
    #[must_use]
    pub fn resolution(&self) -> u32 {
        1 << self.depth
    }

    /// Number of voxels in the whole domain, `8^depth` (fits: at most `2^63`).
    #[must_use]
    pub fn voxel_total(&self) -> u64 {
        1 << (3 * u32::from(self.depth))
    }

    /// Edge of one voxel, `edge / 2^depth`.
    #[must_use]
    pub fn voxel_size(&self) -> f64 {
        self.edge / f64::from(self.resolution())
    }

    /// Voxels a unit of length, `2^depth / edge` (the lattice's scale).
    #[must_use]
    pub fn voxels_per_unit(&self) -> f64 {
        f64::from(self.resolution()) / self.edge
    }

    /// The same cube at another depth.
    pub fn with_depth(&self, depth: u8) -> Result<Self> {
        Domain::new(self.min, self.edge, depth)
    }

    /// The cube as a box.
    #[must_use]
    pub fn aabb(&self) -> Aabb {
        Aabb { min: self.min, max: self.min + DVec3::splat(self.edge) }
    }

    /// The voxel holding `p`, `None` outside the domain (the upper faces belong to no voxel).
    #[must_use]
    pub fn voxel_of(&self, p: DVec3) -> Option<[u32; 3]> {
        let t = (p - self.min) / self.voxel_size();
        let n = f64::from(self.resolution());
        if !(t.cmpge(DVec3::ZERO).all() && t.cmplt(DVec3::splat(n)).all()) {
            return None;
        }
        // floor of a value in [0, 2^21) is exact in f64.
        Some([t.x as u32, t.y as u32, t.z as u32].map(|v| v.min(self.resolution() - 1)))
    }

    /// World position of the integer lattice point `c` (voxel corners).
    #[must_use]
    pub fn lattice_point(&self, c: [u32; 3]) -> DVec3 {
        self.min + DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])) * self.voxel_size()
    }

    /// Centre of voxel `c`.
    #[must_use]
    pub fn voxel_center(&self, c: [u32; 3]) -> DVec3 {
        self.lattice_point(c) + DVec3::splat(0.5 * self.voxel_size())
    }

    /// The world box of the cube with lowest voxel `c` and `size` voxels a side.
    #[must_use]
    pub fn cube_box(&self, c: [u32; 3], size: u32) -> Aabb {
        let lo = self.lattice_point(c);
        Aabb { min: lo, max: lo + DVec3::splat(f64::from(size) * self.voxel_size()) }
    }
}

impl std::fmt::Display for Domain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cube at ({}, {}, {}) edge {} depth {}", self.min.x, self.min.y, self.min.z, self.edge, self.depth)
    }
}
