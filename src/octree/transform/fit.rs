//! Bringing octrees into one domain: the common domain of several solids, and each
//! solid moved into it, exactly where the lattices nest and by resampling otherwise.
//!
//! Two domains' lattices nest when the target voxel edge `h_t` divides the source's
//! `h_s` by a power of two (`h_s = 2^k h_t`, `k >= 0`) and the source's corner sits on
//! the target lattice (`(min_s - min_t) / h_t` integral). Then the move is exact and
//! cheap, in three key-level steps:
//!
//! 1. [`LinearOctree::refine`] by `k` levels: the source voxels become target-sized;
//! 2. a change of frame that keeps every key: a node key holds only the node's Morton
//!    start and its height above the voxels (see [`crate::octree::node`]), so the same keys
//!    describe the same cubes in a domain `2^j` times larger with the same corner and
//!    voxel size (`j` more levels), or, for `j < 0`, the lowest-corner part of a
//!    larger one;
//! 3. [`LinearOctree::translate`] by the integer offset between the corners, which
//!    clips what leaves the target.
//!
//! Otherwise the solid is sampled at the target's voxel centres
//! ([`LinearOctree::resample_to`]). "Integral" and "a power of two" are tested to a
//! relative 1e-9 of the voxel edge, far below any rounding that could move a voxel.
//!
//! The common domain ([`common_domain`]) is the smallest cube holding every domain,
//! put at the lowest corner of their union (so it is some input's own corner on every
//! axis where that input reaches lowest, which keeps lattices aligned where they can
//! be). Its depth keeps the finest input's voxels: the deepest input depth, raised
//! where an input's voxels nest in the common cube only at a deeper level (an input
//! that is one octant of another at the same depth needs one level more).

use crate::error::{Error, Result};
use crate::octree::domain::{Domain, MAX_DEPTH};
use crate::octree::driver::VoxelizeOptions;
use crate::octree::linear::LinearOctree;

/// How a solid was brought into a domain (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fit {
    /// The domain was already the target: nothing changed.
    Same,
    /// The lattices nest: refined by `refined` levels and moved by `offset` whole
    /// target voxels, with no sampling.
    Exact {
        /// Levels added by refinement.
        refined: u8,
        /// The source corner's place on the target lattice, in target voxels.
        offset: [i64; 3],
    },
    /// The lattices do not nest: sampled at the target's voxel centres.
    Resampled,
}

impl std::fmt::Display for Fit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Fit::Same => write!(f, "already in the domain"),
            Fit::Exact { refined, offset } => {
                write!(f, "exact (voxels nest")?;
                if *refined > 0 {
                    write!(f, ", refined {refined} level{}", if *refined == 1 { "" } else { "s" })?;
                }
                if *offset != [0; 3] {
                    write!(f, ", moved by {offset:?} voxels")?;
                }
                write!(f, ")")
            }
            Fit::Resampled => write!(f, "resampled (voxels do not nest)"),
        }
    }
}

/// `x` as an integer when it is one to a relative 1e-9 (absolute for |x| < 1).
fn integral(x: f64) -> Option<i64> {
    let r = x.round();
    ((x - r).abs() <= 1e-9 * x.abs().max(1.0) && r.abs() < 2f64.powi(62)).then_some(r as i64)
}

/// `k` with `ratio = 2^k`, when `ratio` is a power of two (k may be negative).
fn power_of_two(ratio: f64) -> Option<i32> {
    let k = ratio.log2().round();
    (k.abs() < 64.0 && (ratio - k.exp2()).abs() <= 1e-9 * ratio).then_some(k as i32)
}

/// The levels to refine `source` by and its corner's offset on `target`'s lattice,
/// when its lattice nests in the target's.
fn nesting(source: &Domain, target: &Domain) -> Option<(u8, [i64; 3])> {
    let k = power_of_two(source.voxel_size() / target.voxel_size())?;
    let refined = u8::try_from(k).ok().filter(|r| source.depth() + r <= MAX_DEPTH)?;
    let o = (source.min() - target.min()) / target.voxel_size();
    Some((refined, [integral(o.x)?, integral(o.y)?, integral(o.z)?]))
}

/// The smallest cube holding every domain in `domains`, at the lowest corner of their
/// union, with the depth that keeps the finest input's voxels (see the module doc);
/// capped at [`MAX_DEPTH`]. Fails on an empty list.
pub fn common_domain(domains: &[Domain]) -> Result<Domain> {
    let first = domains.first().ok_or_else(|| Error::invalid("domains", "no domain to cover"))?;
    let union = domains.iter().fold(first.aabb(), |acc, d| acc.union(&d.aabb()));
    let edge = union.size().max_element();
    let depth = domains
        .iter()
        .map(|d| match power_of_two(edge / d.voxel_size()) {
            Some(k) if k >= i32::from(d.depth()) => k.min(i32::from(MAX_DEPTH)) as u8,
            _ => d.depth(),
        })
        .max()
        .unwrap_or(first.depth());
    Domain::new(union.min, edge, depth)
}

impl LinearOctree {
    /// This solid in `target`: unchanged when it is already there, exact when the
    /// lattices nest, resampled at the target's voxel centres otherwise (see the
    /// module doc); says which.
    ///
    /// Fails when the result exceeds `options.budget` (the exact path can only
    /// shrink or keep the node count after refinement, which keeps it).
    pub fn fit_to(&self, target: Domain, options: &VoxelizeOptions) -> Result<(LinearOctree, Fit)> {
        if *self.domain() == target {
            return Ok((self.clone(), Fit::Same));
        }
        let Some((refined, offset)) = nesting(self.domain(), &target) else {
            return Ok((self.resample_to(target, options)?, Fit::Resampled));
        };
        let fine = self.refine(self.depth() + refined)?;
        let (fine_depth, target_depth) = (i32::from(fine.depth()), i32::from(target.depth()));
        let moved = if target_depth >= fine_depth {
            // The same keys in the target-sized cube at the source's corner, then moved.
            let frame = Domain::new(fine.domain().min(), target.edge(), target.depth())?;
            fine.reframed(frame).translate(offset)
        } else {
            // Moved in the source's larger frame so the target is its lowest corner,
            // then cut to that corner.
            fine.translate(offset).lowest_corner(target)
        };
        Ok((moved.reframed(target), Fit::Exact { refined, offset }))
    }

    /// Whether [`LinearOctree::fit_to`] brings this solid into `target` without
    /// sampling: it is there already, or the lattices nest.
    pub(crate) fn fits_exactly(&self, target: &Domain) -> bool {
        self.domain() == target || nesting(self.domain(), target).is_some()
    }

    /// The part of this solid in its domain's lowest-corner cube of `corner`'s depth
    /// (fewer levels than this tree's, same voxel size), as keys of `corner`.
    fn lowest_corner(&self, corner: Domain) -> LinearOctree {
        let cells = 8u64.pow(u32::from(corner.depth()));
        let keys = self
            .keys()
            .iter()
            .take_while(|k| k.start() < cells)
            .map(|k| if k.len() > cells { LinearOctree::full(corner).keys()[0] } else { *k })
            .collect();
        LinearOctree::from_canonical(corner, keys)
    }
}
