//! Per-thread direct-mapped caches for values at lattice points, so that the renderer's
//! threads look up what they computed before without touching memory another core
//! writes (no lock, no atomic operation, no cache line moving between cores).
//!
//! A cache is a table of `2^bits` slots; a key (its owner's process-unique id and a
//! lattice point) has one slot, chosen by a multiplicative hash, and a new value
//! evicts the slot's old one. A value must be a pure function of its key: then a hit,
//! a miss and an evicted value all give the same result, and results never depend on
//! which thread asked first or what else it asked.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};
use std::thread::LocalKey;

/// A key: the owner's id ([`new_owner`]) and a lattice point.
pub(crate) type Key = (u64, [i64; 3]);

/// A fresh owner id, never handed out before in this process.
pub(crate) fn new_owner() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// A direct-mapped table of `2^bits` slots.
pub(crate) struct DirectMapped<V> {
    slots: Vec<Option<(Key, V)>>,
    bits: u32,
}

impl<V: Copy> DirectMapped<V> {
    /// An empty table of `2^bits` slots.
    pub(crate) fn new(bits: u32) -> Self {
        DirectMapped { slots: vec![None; 1 << bits], bits }
    }

    /// The slot of `key`: the top bits of a multiplicative hash of its parts.
    fn slot(&self, (owner, p): &Key) -> usize {
        const M: [u64; 4] =
            [0x9e37_79b9_7f4a_7c15, 0xc2b2_ae3d_27d4_eb4f, 0x1656_67b1_9e37_79f9, 0x27d4_eb2f_1656_67c5];
        let h = [*owner, p[0] as u64, p[1] as u64, p[2] as u64]
            .iter()
            .zip(M)
            .fold(0u64, |h, (&part, m)| (h ^ part).wrapping_mul(m));
        (h >> (64 - self.bits)) as usize
    }

    /// The value cached for `key`, if it is still there.
    pub(crate) fn get(&self, key: &Key) -> Option<V> {
        self.get_ref(key).copied()
    }

    /// A reference to the value cached for `key`, if it is still there.
    pub(crate) fn get_ref(&self, key: &Key) -> Option<&V> {
        match &self.slots[self.slot(key)] {
            Some((k, v)) if k == key => Some(v),
            _ => None,
        }
    }

    /// Whether `key` is cached.
    pub(crate) fn holds(&self, key: &Key) -> bool {
        self.get_ref(key).is_some()
    }

    /// Caches `value` for `key`, evicting whatever held its slot.
    pub(crate) fn put(&mut self, key: Key, value: V) {
        let slot = self.slot(&key);
        self.slots[slot] = Some((key, value));
    }
}

/// The value for `key` from this thread's `cache`, else `compute()`d and cached.
/// `compute` may use other caches, not this one.
pub(crate) fn cached<V: Copy + 'static>(
    cache: &'static LocalKey<RefCell<DirectMapped<V>>>,
    key: Key,
    compute: impl FnOnce() -> V,
) -> V {
    if let Some(v) = cache.with_borrow(|c| c.get(&key)) {
        return v;
    }
    let v = compute();
    cache.with_borrow_mut(|c| c.put(key, v));
    v
}

/// `f` of the value for `key` as this thread's `cache` holds it, `compute()`d and cached
/// first when it is not there (for values too large to copy out). Neither `compute`
/// nor `f` may use this cache.
pub(crate) fn with_cached<V: Copy + 'static, R>(
    cache: &'static LocalKey<RefCell<DirectMapped<V>>>,
    key: Key,
    compute: impl FnOnce() -> V,
    f: impl FnOnce(&V) -> R,
) -> R {
    if !cache.with_borrow(|c| c.holds(&key)) {
        let v = compute();
        cache.with_borrow_mut(|c| c.put(key, v));
    }
    cache.with_borrow(|c| f(c.get_ref(&key).expect("cached just now")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    thread_local! {
        static SMALL: RefCell<DirectMapped<i64>> = RefCell::new(DirectMapped::new(4));
    }

    #[test]
    fn a_cached_value_is_the_computed_one_and_computed_again_only_after_eviction() {
        // 16 slots, 200 keys asked at random: every answer is the function's, and the
        // function runs exactly once for each miss (a first ask or an evicted key).
        let f = |p: [i64; 3]| p[0] * 1_000_000 + p[1] * 1_000 + p[2];
        let owner = new_owner();
        let mut rng = Rng(11);
        let mut resident: std::collections::HashMap<usize, Key> = std::collections::HashMap::new();
        let probe = DirectMapped::<i64>::new(4);
        let (mut computed, mut expected_misses) = (0, 0);
        for _ in 0..5_000 {
            let p = [rng.below(10) as i64, rng.below(5) as i64, rng.below(4) as i64];
            let key = (owner, p);
            let slot = probe.slot(&key);
            if resident.get(&slot) != Some(&key) {
                expected_misses += 1;
                resident.insert(slot, key);
            }
            let got = cached(&SMALL, key, || {
                computed += 1;
                f(p)
            });
            assert_eq!(got, f(p));
        }
        assert_eq!(computed, expected_misses);
        assert!(computed < 5_000, "{computed} computations: the cache never hit");
    }
}
