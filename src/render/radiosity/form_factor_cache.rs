//! The form factors of a shooting patch kept for its next shot.
//!
//! Progressive refinement shoots a patch again whenever it has gathered enough new
//! light (the turned Cornell box: 1,247 shots of 877 patches to 1% unshot), and each
//! shot computes every receiver's form factor to it, which costs the solve its rays
//! (`form_factor`: up to 64 a receiver). A form factor depends only on the receiving
//! element, the shooting patch (or, for a near receiver, each of its base elements)
//! and the scene's solids, never on the light, so the row of a patch's first shot
//! answers its later shots with the same bits and no ray cast: the far receivers'
//! form factors to the patch, and each near receiver's to the patch's elements in
//! their order (module `near_field`). Which receivers are skipped and which are near
//! is geometry too, worked out again at each shot.
//!
//! Memory: a row is 8 bytes an element and 8 a near receiver's factor; rows are kept,
//! first come, while they fit within [`CACHE_BYTES`] and a quarter of the memory
//! budget, and a patch whose row did not fit computes its factors at every shot, as
//! before. Adaptive subdivision (which adds elements and turns leaves into parents)
//! empties the cache.

use crate::budget::MemoryBudget;

/// Most bytes the kept rows take, whatever the budget.
pub(crate) const CACHE_BYTES: usize = 256 << 20;

/// One shooting patch's form factors, element by element.
pub(super) struct Row {
    /// Each element's form factor to the whole patch where it is a far receiver
    /// (anything where it is near or skipped).
    pub far: Vec<f64>,
    /// The near receivers, ascending.
    near: Vec<u32>,
    /// Each near receiver's form factors to the patch's elements, `parts` a receiver,
    /// in `near`'s order.
    near_factors: Vec<f64>,
    /// The patch's elements a near receiver sees one by one.
    parts: usize,
}

impl Row {
    /// A row of `elements` elements for a patch of `parts` parts, its far factors
    /// `far`, its near receivers' factors to follow ([`Row::push_near`], in ascending
    /// element order).
    pub fn new(far: Vec<f64>, parts: usize) -> Row {
        Row { far, near: Vec::new(), near_factors: Vec::new(), parts }
    }

    /// Adds near receiver `element` (above every one added before) with its factors.
    pub fn push_near(&mut self, element: u32, factors: &[f64]) {
        debug_assert_eq!(factors.len(), self.parts);
        debug_assert!(self.near.last().is_none_or(|&last| last < element));
        self.near.push(element);
        self.near_factors.extend_from_slice(factors);
    }

    /// Near receiver `element`'s factors to the patch's parts (`None` if it is not one).
    pub fn near(&self, element: u32) -> Option<&[f64]> {
        let k = self.near.binary_search(&element).ok()?;
        Some(&self.near_factors[k * self.parts..(k + 1) * self.parts])
    }

    fn bytes(&self) -> usize {
        8 * self.far.len() + 4 * self.near.len() + 8 * self.near_factors.len()
    }
}

/// The rows kept, one slot a patch (module doc).
pub(super) struct FormFactorCache {
    rows: Vec<Option<Row>>,
    bytes: usize,
    limit: usize,
}

impl FormFactorCache {
    /// An empty cache for `patches` patches within `budget` (module doc).
    pub fn new(patches: usize, budget: MemoryBudget) -> Self {
        let quarter = usize::try_from(budget.0 / 4).unwrap_or(usize::MAX);
        FormFactorCache { rows: (0..patches).map(|_| None).collect(), bytes: 0, limit: CACHE_BYTES.min(quarter) }
    }

    /// Patch `patch`'s row, if kept.
    pub fn row(&self, patch: usize) -> Option<&Row> {
        self.rows[patch].as_ref()
    }

    /// Whether a row of `elements` elements could still be kept (its near factors
    /// aside, checked when it is [`FormFactorCache::keep`]).
    pub fn has_room_for(&self, elements: usize) -> bool {
        self.bytes + 8 * elements <= self.limit
    }

    /// Keeps `row` as patch `patch`'s, if it fits.
    pub fn keep(&mut self, patch: usize, row: Row) {
        let bytes = row.bytes();
        if self.bytes + bytes <= self.limit {
            self.bytes += bytes;
            self.rows[patch] = Some(row);
        }
    }

    /// Forgets every row (the elements changed).
    pub fn clear(&mut self) {
        self.rows.iter_mut().for_each(|r| *r = None);
        self.bytes = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_gives_back_each_near_receivers_factors_and_the_cache_keeps_within_its_limit() {
        let mut row = Row::new(vec![0.5, 0.0, 0.25, 0.0], 2);
        row.push_near(1, &[0.1, 0.2]);
        row.push_near(3, &[0.3, 0.4]);
        assert_eq!(row.near(1), Some(&[0.1, 0.2][..]));
        assert_eq!(row.near(3), Some(&[0.3, 0.4][..]));
        assert_eq!(row.near(2), None);
        assert_eq!(row.bytes(), 8 * 4 + 4 * 2 + 8 * 4);
        // A budget of 4 * 100 bytes keeps rows of up to 100 bytes in all.
        let mut cache = FormFactorCache::new(3, MemoryBudget(400));
        assert!(cache.has_room_for(4));
        cache.keep(0, row);
        assert!(cache.row(0).is_some());
        assert!(!cache.has_room_for(4));
        cache.keep(1, Row::new(vec![1.0; 4], 1));
        assert!(cache.row(1).is_none(), "over the limit");
        cache.clear();
        assert!(cache.row(0).is_none() && cache.has_room_for(12));
    }
}
