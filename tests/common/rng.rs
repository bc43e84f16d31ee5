//! The one random generator of the tests, unit and integration alike: a seeded
//! xorshift64 (Marsaglia 2003, shifts 13, 7, 17), so a failure is reproduced by its
//! seed and a test moved between `src/` and `tests/` keeps its cases. The library's
//! unit tests include this file (`src/test_util.rs`); generators of product code (a
//! texture's noise, the harness's ray sets, the fuzzer's mutations) are their own.

use glam::DVec3;

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
