//! Axis-aligned boxes in world space.

use glam::DVec3;

/// A closed axis-aligned box `[min, max]` in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lowest corner.
    pub min: DVec3,
    /// Highest corner.
    pub max: DVec3,
}

impl Aabb {
    /// The box between two corners (in any order).
    #[must_use]
    pub fn new(a: DVec3, b: DVec3) -> Self {
        Aabb { min: a.min(b), max: a.max(b) }
    }

    /// The box centred on `center` with half extents `half`.
    #[must_use]
    pub fn from_center_half(center: DVec3, half: DVec3) -> Self {
        Aabb::new(center - half, center + half)
    }

    /// The smallest box holding all `points`; `None` for no points.
    #[must_use]
    pub fn from_points(points: impl IntoIterator<Item = DVec3>) -> Option<Self> {
        let mut it = points.into_iter();
        let first = it.next()?;
        Some(it.fold(Aabb { min: first, max: first }, |b, p| Aabb { min: b.min.min(p), max: b.max.max(p) }))
    }

    /// Centre point.
    #[must_use]
    pub fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }

    /// Edge lengths.
    #[must_use]
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }

    /// Corner `i` (bit 0 picks x max, bit 1 y max, bit 2 z max).
    #[must_use]
    pub fn corner(&self, i: usize) -> DVec3 {
        DVec3::new(
            if i & 1 == 0 { self.min.x } else { self.max.x },
            if i & 2 == 0 { self.min.y } else { self.max.y },
            if i & 4 == 0 { self.min.z } else { self.max.z },
        )
    }

    /// The smallest box holding both.
    #[must_use]
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// The overlap of both, `None` when they are disjoint.
    #[must_use]
    pub fn intersection(&self, o: &Aabb) -> Option<Aabb> {
        let b = Aabb { min: self.min.max(o.min), max: self.max.min(o.max) };
        (b.min.cmple(b.max).all()).then_some(b)
    }

    /// Whether `p` lies in the closed box.
    #[must_use]
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Surface area `2(xy + yz + zx)`.
    #[must_use]
    pub fn area(&self) -> f64 {
        let s = self.size();
        2.0 * (s.x * s.y + s.y * s.z + s.z * s.x)
    }

    /// Whether every coordinate is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }
}
