//! Change of depth: refine exactly, coarsen by a rule.

use crate::error::{Error, Result};
use crate::octree::domain::Domain;
use crate::octree::linear::LinearOctree;
use crate::octree::node::NodeKey;
use crate::octree::ranges;

/// How a coarse voxel is decided from the fine voxels it covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoarsenRule {
    /// Full when any fine voxel is full (the result holds the solid).
    Any,
    /// Full when every fine voxel is full (the result lies in the solid).
    All,
    /// Full when at least half the fine voxels are full.
    Majority,
}

impl LinearOctree {
    /// The same solid at a depth at least as fine: every node keeps its level and
    /// extent, so the result is exact and the node count unchanged.
    pub fn refine(&self, depth: u8) -> Result<LinearOctree> {
        if depth < self.depth() {
            return Err(Error::invalid("depth", format!("refine to {depth} is coarser than {}", self.depth())));
        }
        let domain = self.domain().with_depth(depth)?;
        let shift = 3 * u32::from(depth - self.depth());
        let keys = self.keys().iter().map(|k| NodeKey::new(k.start() << shift, k.k() + shift / 3)).collect();
        Ok(LinearOctree::from_canonical(domain, keys))
    }

    /// The solid at a depth at most as fine, each coarse voxel decided by `rule`.
    pub fn coarsen(&self, depth: u8, rule: CoarsenRule) -> Result<LinearOctree> {
        if depth > self.depth() {
            return Err(Error::invalid("depth", format!("coarsen to {depth} is finer than {}", self.depth())));
        }
        let domain: Domain = self.domain().with_depth(depth)?;
        let shift = 3 * u32::from(self.depth() - depth);
        let fine_per_coarse = 1u64 << shift;
        let needed = match rule {
            CoarsenRule::Any => 1,
            CoarsenRule::All => fine_per_coarse,
            CoarsenRule::Majority => fine_per_coarse.div_ceil(2),
        };
        // Walk the nodes once: nodes of at least one coarse voxel map whole; smaller
        // ones accumulate their voxel counts into the coarse voxel they fall in.
        let mut runs: Vec<(u64, u64)> = Vec::new();
        let mut pending: Option<(u64, u64)> = None; // (coarse code, fine voxels counted)
        let flush = |pending: &mut Option<(u64, u64)>, runs: &mut Vec<(u64, u64)>| {
            if let Some((code, count)) = pending.take()
                && count >= needed
            {
                runs.push((code, code + 1));
            }
        };
        for key in self.keys() {
            if key.len() >= fine_per_coarse {
                flush(&mut pending, &mut runs);
                runs.push((key.start() >> shift, key.end() >> shift));
            } else {
                let code = key.start() >> shift;
                match &mut pending {
                    Some((c, count)) if *c == code => *count += key.len(),
                    _ => {
                        flush(&mut pending, &mut runs);
                        pending = Some((code, key.len()));
                    }
                }
            }
        }
        flush(&mut pending, &mut runs);
        Ok(LinearOctree::from_canonical(domain, ranges::cut_runs(runs)))
    }
}
