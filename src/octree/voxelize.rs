//! Adaptive top-down voxelization of any [`Shape`] into a canonical linear octree.
//!
//! Algorithm: classify the root box; `Inside` emits the node whole, `Outside` drops it,
//! `Boundary` recurses into the eight children in Morton order; a voxel is decided by
//! its centre ([`Shape::contains`]). Work and output are proportional to the surface,
//! not the volume. Children come out in Morton order, so the output is sorted without
//! a sort, and eight children that all come out full are replaced by their parent, so
//! it is canonical without a pass.
//!
//! Parallelism: the top [`PARALLEL_LEVELS`] levels fan out with rayon; each task fills
//! its own buffer and buffers are joined in child order, so the result is the same
//! for any number of threads.

use rayon::prelude::*;

use super::domain::Domain;
use super::linear::LinearOctree;
use super::node::NodeKey;
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::morton;
use crate::progress::{NoProgress, Progress};
use crate::shape::{Class, Shape};

/// Levels below the root that are split into parallel tasks (up to 8^3 = 512 tasks).
pub const PARALLEL_LEVELS: u8 = 3;

/// Options of a voxelization.
#[derive(Clone, Copy)]
pub struct VoxelizeOptions<'a> {
    /// Refuse the job when its estimated memory exceeds this.
    pub budget: MemoryBudget,
    /// Receives progress in units of level-3 subtrees.
    pub progress: &'a dyn Progress,
}

impl Default for VoxelizeOptions<'_> {
    fn default() -> Self {
        VoxelizeOptions { budget: MemoryBudget::default(), progress: &NoProgress }
    }
}

/// Estimated peak bytes to voxelize `shape` in `domain`: nodes near the surface,
/// taken as twice the area of the shape's box (clipped to the domain) in voxel faces,
/// at 8 bytes a node, doubled for the per-task buffers joined at the end.
#[must_use]
pub fn estimate_bytes(shape: &dyn Shape, domain: &Domain) -> u64 {
    let domain_box = domain.aabb();
    let area = match shape.bounds() {
        Some(b) => b.intersection(&domain_box).map_or(0.0, |b| b.area()),
        None => domain_box.area(),
    };
    let faces = area / domain.voxel_size().powi(2);
    (2.0 * faces * 8.0 * 2.0).min(u64::MAX as f64) as u64 + 4096
}

/// Voxelizes `shape` into the canonical linear octree of `domain`.
///
/// Refuses (before any work) when [`estimate_bytes`] exceeds `options.budget`.
pub fn voxelize(shape: &dyn Shape, domain: Domain, options: &VoxelizeOptions) -> Result<LinearOctree> {
    let estimate = estimate_bytes(shape, &domain);
    options.budget.check(format!("voxelizing at depth {}", domain.depth()), estimate)?;
    let parallel_levels = PARALLEL_LEVELS.min(domain.depth());
    options.progress.start(1 << (3 * u32::from(parallel_levels)));
    let job = Job { shape, domain, progress: options.progress, parallel_levels };
    let root = NodeKey::new(0, u32::from(domain.depth()));
    let mut keys = Vec::new();
    job.node(root, &mut keys);
    options.progress.finish();
    Ok(LinearOctree::from_canonical(domain, keys))
}

/// One voxelization's fixed inputs.
struct Job<'a> {
    shape: &'a dyn Shape,
    domain: Domain,
    progress: &'a dyn Progress,
    parallel_levels: u8,
}

impl Job<'_> {
    /// Appends the canonical nodes of the solid inside `key` to `out`.
    fn node(&self, key: NodeKey, out: &mut Vec<NodeKey>) {
        let min = morton::decode(key.start());
        let level = key.level(self.domain.depth());
        // Step 1: a voxel is decided by its centre.
        if key.k() == 0 {
            self.report(level);
            if self.shape.contains(self.domain.voxel_center(min)) {
                out.push(key);
            }
            return;
        }
        // Step 2: classify the node's box.
        let class = self.shape.classify(&self.domain.cube_box(min, 1 << key.k()));
        if class != Class::Boundary || level >= self.parallel_levels {
            self.report(level);
        }
        match class {
            Class::Inside => out.push(key),
            Class::Outside => {}
            // Step 3: recurse, in parallel near the root, and merge eight full children.
            Class::Boundary => {
                let before = out.len();
                if level < self.parallel_levels {
                    let parts: Vec<Vec<NodeKey>> = (0..8)
                        .into_par_iter()
                        .map(|i| {
                            let mut part = Vec::new();
                            self.node(key.child(i).expect("k > 0"), &mut part);
                            part
                        })
                        .collect();
                    out.reserve(parts.iter().map(Vec::len).sum());
                    parts.into_iter().for_each(|p| out.extend(p));
                } else {
                    for i in 0..8 {
                        self.node(key.child(i).expect("k > 0"), out);
                    }
                }
                if out.len() == before + 8 && out[before..].iter().all(|c| c.k() + 1 == key.k()) {
                    out.truncate(before);
                    out.push(key);
                }
            }
        }
    }

    /// Reports a finished node at `level`: its share of the level-`parallel_levels` grid.
    fn report(&self, level: u8) {
        if level <= self.parallel_levels {
            self.progress.advance(1 << (3 * u32::from(self.parallel_levels - level)));
        }
    }
}
