//! Mass properties of a solid of unit density: volume, centre of mass and the inertia
//! tensor about it, as exact sums over the octree's cubes.
//!
//! A cube of edge `s` with centre `c` and volume `V = s^3` has first moment `V c` and
//! second moments `int x_a x_b dV = V (c_a c_b + delta_ab s^2 / 12)` (its inertia
//! about its centre, `V s^2 / 6` on each axis, moved to the origin by the parallel
//! axis theorem). Summed over the nodes:
//!
//! ```text
//! M = sum V,   C = sum V c / M,   S_ab = int (x - C)_a (x - C)_b dV,
//! I = trace(S) Id - S            (I_aa = S_bb + S_cc, I_ab = -S_ab, a != b)
//! ```
//!
//! Exactness: in lattice units with doubled coordinates (`c2 = 2 min + s`, an integer),
//! `2 int x dV = sum V c2` and `12 int x_a x_b dV = sum V (3 c2_a c2_b + delta_ab s^2)`
//! are integers; with `V <= 2^63` and `c2 <= 2^22` every sum fits an `i128`, so the
//! sums are exact and the same for any order of summation (and any thread count). The
//! shift to the centre, `12 S = 12 int x x^T - 3 (sum V c2)(sum V c2)^T / M`, would
//! cancel catastrophically in floating point for a small solid far from the origin;
//! splitting `sum V c2 = q M + r` (`0 <= r < M`) leaves all but `3 r_a r_b / M` (at
//! most `3 M`, while `12 S_aa >= M`) to exact integer arithmetic, so at most two bits
//! are lost. Only that term, the conversion to `f64` and the world units (`h^3`, `h^5`
//! for the voxel edge `h`) round.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use crate::octree::{LinearOctree, MAX_DEPTH, NodeKey};

/// Volume, centre of mass and inertia tensor of a solid of unit density
/// ([`LinearOctree::mass_properties`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Volume (the mass at unit density), world units cubed.
    pub volume: f64,
    /// Centre of mass in world coordinates; `None` for the empty solid.
    pub centre_of_mass: Option<DVec3>,
    /// Inertia tensor about the centre of mass, world units to the fifth (symmetric:
    /// rows equal columns); zero for the empty solid.
    pub inertia: DMat3,
}

/// Exact moment sums over nodes in doubled lattice coordinates.
#[derive(Clone, Copy, Debug, Default)]
struct Moments {
    /// `sum V`: voxels.
    volume: i128,
    /// `sum V c2`: twice the first moment.
    first: [i128; 3],
    /// `sum V (3 c2_a c2_b + delta_ab s^2)`: twelve times the second
    /// moments (upper triangle `xx, yy, zz, xy, xz, yz`).
    second: [i128; 6],
}

/// The index pairs `(a, b)` of [`Moments::second`].
const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// Keys a parallel task sums.
const CHUNK: usize = 1 << 14;

/// Levels a key can have above the voxels: `k` in `0..=21`.
const LEVELS: usize = MAX_DEPTH as usize + 1;

impl Moments {
    /// The sums over all nodes of `tree` (in parallel; exact, so in any order). Nodes of one level share `V = 8^k`, so the per-node terms (at most
    /// `2^47`) are summed by level and multiplied by `V` once.
    fn sum(tree: &LinearOctree) -> Moments {
        let depth = tree.depth();
        let by_level = tree
            .keys()
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut acc = [Moments::default(); LEVELS];
                chunk.iter().for_each(|&key| acc[key.k() as usize].add_node(key, depth));
                acc
            })
            .reduce(|| [Moments::default(); LEVELS], |a, b| std::array::from_fn(|k| a[k].plus(&b[k])));
        by_level.iter().enumerate().fold(Moments::default(), |acc, (k, m)| acc.plus(&m.times(1i128 << (3 * k))))
    }

    /// Adds one node's terms with unit volume (`V` is applied by level).
    fn add_node(&mut self, key: NodeKey, depth: u8) {
        let node = key.node(depth);
        let s = i64::from(node.size);
        let d: [i64; 3] = std::array::from_fn(|a| 2 * i64::from(node.min[a]) + s);
        self.volume += 1;
        (0..3).for_each(|a| self.first[a] += i128::from(d[a]));
        for (i, &(a, b)) in PAIRS.iter().enumerate() {
            self.second[i] += i128::from(3 * d[a] * d[b] + if a == b { s * s } else { 0 });
        }
    }

    fn plus(&self, o: &Moments) -> Moments {
        Moments {
            volume: self.volume + o.volume,
            first: std::array::from_fn(|a| self.first[a] + o.first[a]),
            second: std::array::from_fn(|i| self.second[i] + o.second[i]),
        }
    }

    fn times(&self, v: i128) -> Moments {
        Moments { volume: self.volume * v, first: self.first.map(|f| f * v), second: self.second.map(|t| t * v) }
    }
}

impl LinearOctree {
    /// Volume, centre of mass and inertia tensor about the centre of mass at unit
    /// density, exact sums over the nodes (see the module doc); the voxelized solid's
    /// own values, which differ from a shape's by at most the integrals over the band
    /// of half-width `sqrt(3) h / 2` around its surface.
    #[must_use]
    pub fn mass_properties(&self) -> MassProperties {
        let sums = Moments::sum(self);
        if sums.volume == 0 {
            return MassProperties { volume: 0.0, centre_of_mass: None, inertia: DMat3::ZERO };
        }
        let m = sums.volume;
        // first = q m + r with 0 <= r < m (first >= 0): the centre is (q + r / m) / 2,
        // and 12 S = second - 3 first first^T / m = second - 3 (q_a q_b m + q_a r_b +
        // r_a q_b) - 3 r_a r_b / m, where everything large cancels in exact integers.
        let (q, r) = (sums.first.map(|f| f / m), sums.first.map(|f| f % m));
        let mf = m as f64;
        let centre = DVec3::from_array(std::array::from_fn(|a| (q[a] as f64 + r[a] as f64 / mf) / 2.0));
        let s: [f64; 6] = std::array::from_fn(|i| {
            let (a, b) = PAIRS[i];
            let whole = sums.second[i] - 3 * (q[a] * q[b] * m + q[a] * r[b] + r[a] * q[b]);
            (whole as f64 - 3.0 * (r[a] as f64 / mf) * r[b] as f64) / 12.0
        });
        let h = self.domain().voxel_size();
        let [xx, yy, zz, xy, xz, yz] = s.map(|v| v * h.powi(5));
        // 0 - p, not -p: no negative zeros where a product of inertia vanishes.
        let [pxy, pxz, pyz] = [xy, xz, yz].map(|p| 0.0 - p);
        let inertia = DMat3::from_cols_array(&[yy + zz, pxy, pxz, pxy, xx + zz, pyz, pxz, pyz, xx + yy]);
        MassProperties { volume: mf * h.powi(3), centre_of_mass: Some(self.domain().min() + centre * h), inertia }
    }
}
