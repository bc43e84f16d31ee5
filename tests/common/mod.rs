//! Generators shared by the test suites: a seeded generator and random solids.
#![allow(dead_code)]

use glam::DVec3;
use octsolid::octree::{Domain, LinearOctree, Node};

/// Small deterministic xorshift generator (fixed seeds make failures reproducible).
pub struct Rng(pub u64);

impl Rng {
    /// Next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// Uniform in `0..n`.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Each coordinate uniform in `[lo, hi)`.
    pub fn vec(&mut self, lo: f64, hi: f64) -> DVec3 {
        DVec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
}

/// A random solid in `domain`: a few aligned nodes of random sizes and scattered
/// voxels, so both big nodes and ragged boundaries occur.
pub fn random_octree(rng: &mut Rng, domain: Domain) -> LinearOctree {
    let depth = domain.depth();
    let mut nodes = Vec::new();
    for _ in 0..rng.below(40) {
        let k = rng.below(u64::from(depth)) as u32;
        let cells = domain.resolution() >> k;
        let min = [0; 3].map(|_| (rng.below(u64::from(cells)) as u32) << k);
        nodes.push(Node { level: depth - k as u8, min, size: 1 << k });
    }
    for _ in 0..rng.below(200) {
        nodes.push(Node {
            level: depth,
            min: [0; 3].map(|_| rng.below(u64::from(domain.resolution())) as u32),
            size: 1,
        });
    }
    let tree = LinearOctree::from_nodes(domain, nodes).unwrap();
    tree.validate().unwrap();
    tree
}
