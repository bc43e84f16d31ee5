//! What the library's unit tests share: the tests' one seeded generator, the same
//! file as `tests/common`'s, so a test moved beside the code keeps its cases, and the
//! random solids of boxes and scattered voxels the offsets' tests draw from it.

#[path = "../tests/common/rng.rs"]
mod rng;

use glam::DVec3;

use crate::octree::{Domain, LinearOctree};
pub(crate) use rng::Rng;

/// How [`boxes_and_noise`] draws its solid.
pub(crate) struct BoxesAndNoise {
    /// The fewest boxes; `fewest + rng.below(more)` of them.
    pub fewest: u64,
    /// One more than the most boxes past `fewest`.
    pub more: u64,
    /// When not 0, a box's low corner lies on the domain's low face on an axis one time
    /// in this many (a draw of its own before the coordinate's).
    pub against_face: u64,
    /// A box's shortest edge in voxels (`shortest + rng.below(20)`, cut at the domain).
    pub shortest: u32,
    /// One voxel in this many flipped (scattered voxels inside and out).
    pub noise: u64,
}

/// A solid at depth 5 (32 voxels a side, the unit cube at the origin) of a few random
/// boxes and scattered voxels, drawn from `rng` as `how` says: site, mixed and free
/// tiles for the offsets, and ties between equally near sites.
pub(crate) fn boxes_and_noise(rng: &mut Rng, how: &BoxesAndNoise) -> LinearOctree {
    let domain = Domain::new(DVec3::ZERO, 1.0, 5).unwrap();
    let boxes: Vec<([u32; 3], [u32; 3])> = (0..how.fewest + rng.below(how.more))
        .map(|_| {
            let lo: [u32; 3] = std::array::from_fn(|_| {
                if how.against_face != 0 && rng.below(how.against_face) == 0 { 0 } else { rng.below(28) as u32 }
            });
            let hi = lo.map(|c| (c + how.shortest + rng.below(20) as u32).min(32));
            (lo, hi)
        })
        .collect();
    let mut voxels = Vec::new();
    for z in 0..32 {
        for y in 0..32 {
            for x in 0..32 {
                let p = [x, y, z];
                let boxed = boxes.iter().any(|(lo, hi)| (0..3).all(|a| lo[a] <= p[a] && p[a] < hi[a]));
                if boxed != (rng.below(how.noise) == 0) {
                    voxels.push(p);
                }
            }
        }
    }
    LinearOctree::from_voxels(domain, voxels).unwrap()
}
