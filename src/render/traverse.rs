//! Ray traversal of an octree: a compact pointer octree built from the linear octree,
//! and an exact first-hit walk that skips empty space at every level.
//!
//! Layout (a contract, 8 bytes an inner node): for each inner node the masks of its
//! non-empty and of its full children and the index of its first inner child; the inner
//! children of a node are stored together in child order, so child `i` is at
//! `first + popcount(inner & ((1 << i) - 1))`. Built by one recursive partition of the
//! sorted keys, O(n * depth).
//!
//! The walk (after Revelles et al., "An efficient parametric algorithm for octree
//! traversal", 2000): a node's interval `[ta, tb]` along the ray is cut at the times the
//! ray crosses its three mid planes; each non-empty piece is one child, visited in ray
//! order; full children end the walk, empty ones are skipped, inner ones recurse.
//! Deviation from the paper: child times are computed from their planes, `(plane - o) /
//! d`, not averaged from the parent's, so every plane's time is one formula and
//! ties are decided the same way everywhere (and by the tests' brute force).
//!
//! Semantics: the hit is the first point (t >= 0) where the ray enters the interior of a
//! full voxel; a ray that only touches full voxels along an edge, a corner or a face it
//! grazes does not hit them. A ray parallel to an axis counts as inside the half-open
//! cells `[i, i + 1)` along that axis. The entered face is the axis of the plane crossed
//! there; when several voxel planes are crossed at once (an edge or corner), the
//! lowest axis.
//!
//! Precision: coordinates are in voxel units of the domain (`0..2^depth`), so every
//! plane is an integer below 2^21, exact in f64, at any depth.

use glam::DVec3;

use crate::octree::{Domain, LinearOctree, NodeKey};

/// One inner node of the traversal octree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub struct Inner {
    /// Index of the first inner child.
    pub first: u32,
    /// Children that hold some solid.
    pub valid: u8,
    /// Children that are wholly solid.
    pub full: u8,
    _pad: u16,
}

const _: () = assert!(std::mem::size_of::<Inner>() == 8);

/// What the root is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Root {
    Empty,
    Full,
    Inner,
}

/// A ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the entry point (0 when the origin is inside the solid).
    pub t: f64,
    /// The full voxel entered, in integer coordinates.
    pub voxel: [u32; 3],
    /// Axis of the entered face (0, 1, 2), `None` when the origin is inside.
    pub axis: Option<usize>,
}

impl Hit {
    /// The axis normal of the entered face, facing the ray (zero when inside).
    #[must_use]
    pub fn normal(&self, dir: DVec3) -> DVec3 {
        match self.axis {
            Some(a) => {
                let mut n = DVec3::ZERO;
                n[a] = -dir[a].signum();
                n
            }
            None => DVec3::ZERO,
        }
    }
}

/// The traversal octree of one solid.
#[derive(Clone, Debug)]
pub struct Traversal {
    domain: Domain,
    root: Root,
    nodes: Vec<Inner>,
}

impl Traversal {
    /// Builds the pointer octree from a canonical linear octree.
    #[must_use]
    pub fn new(tree: &LinearOctree) -> Self {
        let domain = *tree.domain();
        let keys = tree.keys();
        let root_key = NodeKey::new(0, u32::from(domain.depth()));
        let root = match keys {
            [] => Root::Empty,
            [k] if *k == root_key => Root::Full,
            _ => Root::Inner,
        };
        let mut t = Traversal { domain, root, nodes: Vec::new() };
        if root == Root::Inner {
            t.nodes.push(Inner { first: 0, valid: 0, full: 0, _pad: 0 });
            t.build(0, root_key, keys);
        }
        t
    }

    /// Fills inner node `index` for `key`, whose solid is `keys`.
    fn build(&mut self, index: usize, key: NodeKey, keys: &[NodeKey]) {
        let mut ranges = [(0usize, 0usize); 8];
        let mut pos = 0;
        let (mut valid, mut full) = (0u8, 0u8);
        for (i, range) in ranges.iter_mut().enumerate() {
            let child = key.child(i as u64).expect("an inner node is not a voxel");
            let start = pos;
            while pos < keys.len() && keys[pos].start() < child.end() {
                pos += 1;
            }
            *range = (start, pos);
            if pos > start {
                valid |= 1 << i;
                if pos - start == 1 && keys[start] == child {
                    full |= 1 << i;
                }
            }
        }
        let inner = valid & !full;
        let first = self.nodes.len();
        self.nodes[index] = Inner { first: first as u32, valid, full, _pad: 0 };
        self.nodes
            .extend(std::iter::repeat_n(Inner { first: 0, valid: 0, full: 0, _pad: 0 }, inner.count_ones() as usize));
        let mut slot = first;
        for (i, &(a, b)) in ranges.iter().enumerate() {
            if inner >> i & 1 == 1 {
                self.build(slot, key.child(i as u64).expect("inner"), &keys[a..b]);
                slot += 1;
            }
        }
    }

    /// The domain.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// Number of inner nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes used: the struct plus the node buffer.
    #[must_use]
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.nodes.capacity() * std::mem::size_of::<Inner>()
    }

    /// Visits the full nodes front to back for a viewer (Meagher's octree display
    /// order): in every inner node, the child on the viewer's side of all three mid
    /// planes first, then those across one plane, two, three. A node can only hide
    /// nodes visited after it. `eye_high(axis, plane)` says whether the viewer is on
    /// the high side of `plane` (voxel units); `enter(min, size)` may prune a subtree;
    /// `full(min, size)` receives each full node.
    pub fn front_to_back(
        &self,
        eye_high: &impl Fn(usize, f64) -> bool,
        enter: &mut impl FnMut([u32; 3], u32) -> bool,
        full: &mut impl FnMut([u32; 3], u32),
    ) {
        let n = self.domain.resolution();
        match self.root {
            Root::Empty => {}
            Root::Full => full([0, 0, 0], n),
            Root::Inner => self.front_to_back_node(0, [0, 0, 0], n, eye_high, enter, full),
        }
    }

    fn front_to_back_node(
        &self,
        index: u32,
        min: [u32; 3],
        size: u32,
        eye_high: &impl Fn(usize, f64) -> bool,
        enter: &mut impl FnMut([u32; 3], u32) -> bool,
        full: &mut impl FnMut([u32; 3], u32),
    ) {
        if !enter(min, size) {
            return;
        }
        let inner = self.nodes[index as usize];
        let half = size / 2;
        let e = (0..3).fold(0usize, |bits, a| bits | usize::from(eye_high(a, f64::from(min[a] + half))) << a);
        for j in [0usize, 1, 2, 4, 3, 5, 6, 7] {
            let child = e ^ j;
            if inner.valid >> child & 1 == 0 {
                continue;
            }
            let cmin: [u32; 3] = std::array::from_fn(|a| min[a] + if child >> a & 1 == 1 { half } else { 0 });
            if inner.full >> child & 1 == 1 {
                full(cmin, half);
            } else {
                let slot = inner.first + (inner.valid & !inner.full & ((1u8 << child) - 1)).count_ones();
                self.front_to_back_node(slot, cmin, half, eye_high, enter, full);
            }
        }
    }

    /// First hit of the world-space ray `origin + t dir` with `0 <= t < t_max`; `t` is
    /// in the ray's own parameter (world units when `dir` is a unit vector).
    #[must_use]
    pub fn hit(&self, origin: DVec3, dir: DVec3, t_max: f64) -> Option<Hit> {
        let r = VoxelRay::new(&self.domain, origin, dir);
        self.hit_voxel_units(r.o, r.d, t_max)
    }

    /// Whether anything lies on the ray before `t_max` (shadow rays).
    #[must_use]
    pub fn occluded(&self, origin: DVec3, dir: DVec3, t_max: f64) -> bool {
        self.hit(origin, dir, t_max).is_some()
    }

    /// [`Traversal::hit`] with the ray already in voxel units of the domain.
    #[must_use]
    pub fn hit_voxel_units(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<Hit> {
        if self.root == Root::Empty {
            return None;
        }
        let inv = DVec3::ONE / d;
        let n = f64::from(self.domain.resolution());
        // Entry and exit times of the root's slabs, with the axis of the entry plane.
        let (mut ta, mut tb, mut face) = (f64::NEG_INFINITY, f64::INFINITY, None);
        for a in 0..3 {
            if d[a] == 0.0 {
                if o[a] < 0.0 || o[a] >= n {
                    return None;
                }
                continue;
            }
            let (near, far) = if d[a] > 0.0 { (0.0, n) } else { (n, 0.0) };
            let (t0, t1) = ((near - o[a]) * inv[a], (far - o[a]) * inv[a]);
            if t0 > ta {
                ta = t0;
                face = Some(a);
            }
            tb = tb.min(t1);
        }
        if ta >= tb || tb <= 0.0 || ta >= t_max {
            return None;
        }
        let walk = Walk { t: self, o, d, inv, t_max };
        let n = self.domain.resolution();
        if self.root == Root::Full {
            walk.full_hit([0, 0, 0], n, ta, face)
        } else {
            walk.node(0, [0, 0, 0], n, ta, tb, face)
        }
    }
}

/// A ray in voxel units of a domain: origin, direction and reciprocal direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelRay {
    /// Origin in voxel units.
    pub o: DVec3,
    /// Direction in voxel units (same ray parameter as the world ray).
    pub d: DVec3,
    /// `1 / d` per axis (infinite where `d` is 0).
    pub inv: DVec3,
}

impl VoxelRay {
    /// The world ray `origin + t dir` seen in the lattice of `domain`.
    #[must_use]
    pub fn new(domain: &Domain, origin: DVec3, dir: DVec3) -> Self {
        let h = domain.voxel_size();
        let d = dir / h;
        VoxelRay { o: (origin - domain.min()) / h, d, inv: DVec3::ONE / d }
    }

    /// The hit on entering the full cube at `min` of `size` voxels at time `ta` through
    /// `face`: the voxel just after the entry point, and the lowest axis among the
    /// voxel planes crossed at `ta` (`t = 0` and no face when `ta <= 0`).
    #[must_use]
    pub fn entry(&self, min: [u32; 3], size: u32, ta: f64, face: Option<usize>) -> Hit {
        let t = ta.max(0.0);
        let inside = ta <= 0.0;
        let voxel: [u32; 3] = std::array::from_fn(|a| {
            let lo = min[a];
            let hi = min[a] + size - 1;
            if self.d[a] > 0.0 && !inside && face == Some(a) {
                lo
            } else if self.d[a] < 0.0 && !inside && face == Some(a) {
                hi
            } else {
                let p = self.o[a] + self.d[a] * t;
                // Just inside along the ray: nudge by the direction's sign on ties.
                let f = p.floor();
                let c = if p == f && self.d[a] < 0.0 { f - 1.0 } else { f };
                (c.max(f64::from(lo)).min(f64::from(hi))) as u32
            }
        });
        // A voxel plane inside the node crossed at the same time is entered too: the
        // face is the lowest axis among them.
        let face = face.map(|f| {
            (0..f)
                .find(|&a| {
                    let plane = if self.d[a] > 0.0 { voxel[a] } else { voxel[a] + 1 };
                    self.d[a] != 0.0 && (f64::from(plane) - self.o[a]) * self.inv[a] == ta
                })
                .unwrap_or(f)
        });
        Hit { t, voxel, axis: if inside { None } else { face } }
    }
}

/// One ray's walk.
struct Walk<'a> {
    t: &'a Traversal,
    o: DVec3,
    d: DVec3,
    inv: DVec3,
    t_max: f64,
}

impl Walk<'_> {
    /// The hit in inner node `index` at `min` of `size` voxels, entered at `ta` through
    /// `face` and left at `tb`.
    #[allow(clippy::needless_range_loop)] // `i == count` stands for the exit at `tb`
    fn node(&self, index: u32, min: [u32; 3], size: u32, ta: f64, tb: f64, face: Option<usize>) -> Option<Hit> {
        let inner = self.t.nodes[index as usize];
        let half = size / 2;
        // Step 1: per axis, the mid plane's crossing time; the child holding the ray just
        // after ta (the high half when the position there is at or past the mid plane);
        // the crossings inside (ta, tb). A mid plane crossed exactly at ta is entered
        // with the node's face (the lowest axis names the face).
        let mut cuts = [(f64::INFINITY, 0usize); 3];
        let mut count = 0;
        let mut child = 0usize;
        let mut face = face;
        for (a, &lo) in min.iter().enumerate() {
            let mid = f64::from(lo + half);
            let high = if self.d[a] == 0.0 {
                self.o[a] >= mid
            } else {
                let tm = (mid - self.o[a]) * self.inv[a];
                if tm > ta && tm < tb {
                    cuts[count] = (tm, a);
                    count += 1;
                } else if tm == ta && face.is_some_and(|f| a < f) {
                    face = Some(a);
                }
                if self.d[a] > 0.0 { tm <= ta } else { tm > ta }
            };
            child |= usize::from(high) << a;
        }
        // Step 2: order the crossings by time, then axis (three compare-swaps).
        let before = |x: (f64, usize), y: (f64, usize)| x.0 < y.0 || (x.0 == y.0 && x.1 < y.1);
        if count > 1 {
            if before(cuts[1], cuts[0]) {
                cuts.swap(0, 1);
            }
            if count > 2 {
                if before(cuts[2], cuts[1]) {
                    cuts.swap(1, 2);
                }
                if before(cuts[1], cuts[0]) {
                    cuts.swap(0, 1);
                }
            }
        }
        // Step 3: the pieces between crossings, each one child, in ray order.
        let mut start = ta;
        let mut start_face = face;
        for i in 0..=count {
            let end = if i < count { cuts[i].0 } else { tb };
            if end > start && end > 0.0 && inner.valid >> child & 1 == 1 {
                if start >= self.t_max {
                    return None;
                }
                let cmin: [u32; 3] = std::array::from_fn(|a| min[a] + if child >> a & 1 == 1 { half } else { 0 });
                let hit = if inner.full >> child & 1 == 1 {
                    self.full_hit(cmin, half, start, start_face)
                } else {
                    let slot = inner.first + (inner.valid & !inner.full & ((1u8 << child) - 1)).count_ones();
                    self.node(slot, cmin, half, start, end, start_face)
                };
                if hit.is_some() {
                    return hit;
                }
            }
            if i == count {
                return None;
            }
            // Crossing a mid plane flips that axis's bit; simultaneous crossings flip
            // several (the pieces between them have zero length). Crossings are sorted,
            // so the first at a time is the lowest axis: it names the face.
            let axis = cuts[i].1;
            child ^= 1 << axis;
            if end > start {
                start_face = Some(axis);
            }
            start = end;
        }
        None
    }

    /// A full node entered at `ta`: the voxel of the entry point.
    fn full_hit(&self, min: [u32; 3], size: u32, ta: f64, face: Option<usize>) -> Option<Hit> {
        if ta.max(0.0) >= self.t_max {
            return None;
        }
        Some(VoxelRay { o: self.o, d: self.d, inv: self.inv }.entry(min, size, ta, face))
    }
}
