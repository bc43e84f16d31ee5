//! Manifold vertices of the boundary mesh: which faces around a lattice point share a
//! vertex.
//!
//! Around a lattice point `p` the mesh covers some of the twelve **quarter faces**
//! between its eight voxels (octants). A quarter face in the plane normal to `a` is
//! bounded near `p` by two of the six **half-edges** leaving `p` (one along each
//! in-plane axis). On a small sphere around `p` the octants are the eight triangles of
//! an octahedron, the half-edges its six vertices and the quarter faces its twelve
//! edges; the faces at `p` are the arcs between full and empty octants, and they form
//! closed curves, the **link** of `p`. Each curve is one sheet of the surface and one
//! mesh vertex.
//!
//! A half-edge has zero, two or four faces. With two, the curve goes on from one to the
//! other. With four (a **touch**: the octants around it alternate full, empty, full,
//! empty, so two voxels meet only along that edge) there are two ways on: pair the
//! faces that bound the same full quarter (`Pairing::Full`, the voxels stay apart) or
//! the same empty quarter (`Pairing::Empty`, they join through the edge). The mesh edge
//! along a touch has four faces; it is manifold when its two pairs end on different
//! vertices at one end at least. By the Jordan curve theorem on the sphere, at one end
//! the two full quarters and the two empty quarters cannot both be joined around the
//! touch, so at each end one pairing at most puts both pairs on one curve. Every touch
//! segment starts with `Full`; a segment whose pairing joins its pairs at both ends is
//! flipped (the other pairing then separates them at both ends), in sorted order,
//! until no segment is left so. Flipping one segment can change the curves at its
//! ends for the others there, so this is a repair loop, not a proof: it stops after
//! `MAX_ROUNDS`; on thousands of random voxel sets it settled after one round of flips. A vertex where voxels meet only at a corner needs no
//! choice: its link already falls into separate curves.

use std::collections::BTreeMap;

use rayon::prelude::*;
use smallvec::SmallVec;

use super::{CHUNK, COORD_BITS, Point, edge_axis, line_point};

/// Rounds of the touch repair loop before it stops (one or two suffice in practice).
const MAX_ROUNDS: usize = 64;

/// Half-edge leaving lattice point `from` towards `to` on an axis-parallel edge:
/// `2 * axis + (1 if towards +axis)`.
pub(super) fn half_edge(from: Point, to: Point) -> u8 {
    let d = edge_axis(from, to);
    2 * d as u8 + u8::from(to[d] > from[d])
}

/// A quarter face at a lattice point, in 5 bits: plane axis `a` (the normal; bits
/// 3..5), the side (1 = `+`) along `(a + 1) % 3` (bit 2) and along `(a + 2) % 3`
/// (bit 1), and whether the outward normal is `+a` (bit 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct QuarterFace(u8);

impl QuarterFace {
    /// No face (a record with one quarter face only).
    pub(super) const NONE: QuarterFace = QuarterFace(31);

    /// The quarter face in the plane normal to `a` between half-edges `h1` and `h2`.
    pub(super) fn new(a: usize, h1: u8, h2: u8, positive: bool) -> Self {
        let side = |axis: usize| if usize::from(h1 / 2) == axis { h1 & 1 } else { h2 & 1 };
        QuarterFace((a as u8) << 3 | side((a + 1) % 3) << 2 | side((a + 2) % 3) << 1 | u8::from(positive))
    }

    fn axis(self) -> usize {
        usize::from(self.0 >> 3)
    }

    fn positive(self) -> bool {
        self.0 & 1 == 1
    }

    /// Side (1 = `+`) along in-plane axis `b`.
    fn side(self, b: usize) -> u8 {
        if b == (self.axis() + 1) % 3 { (self.0 >> 2) & 1 } else { (self.0 >> 1) & 1 }
    }

    /// The quarter around half-edge `h` behind the face (the full one) or in front of
    /// it (the empty one): its sides along the two axes other than `h`'s, lower axis
    /// in bit 0.
    fn quarter(self, h: u8, behind: bool) -> u8 {
        let (a, d) = (self.axis(), usize::from(h / 2));
        let b = 3 - a - d;
        let along_a = u8::from(self.positive() != behind);
        let along_b = self.side(b);
        if a < b { along_a | along_b << 1 } else { along_b | along_a << 1 }
    }
}

/// Bits of a record: position (3 x 22) | quarter faces (2 x 5) | polygon point index (32).
const POSITION_SHIFT: u32 = 42;

/// The sort record of one polygon point: sorting groups records by lattice point.
pub(super) fn record(p: Point, faces: [QuarterFace; 2], index: usize) -> u128 {
    let position = u128::from(p[0]) << (2 * COORD_BITS) | u128::from(p[1]) << COORD_BITS | u128::from(p[2]);
    position << POSITION_SHIFT | u128::from(faces[0].0) << 37 | u128::from(faces[1].0) << 32 | index as u128
}

fn record_index(r: u128) -> usize {
    (r as u32) as usize
}

fn record_point(r: u128) -> Point {
    let mask = (1u128 << COORD_BITS) - 1;
    let position = r >> POSITION_SHIFT;
    [2, 1, 0].map(|k| ((position >> (k * COORD_BITS)) & mask) as u32)
}

/// How the four faces around a touch are paired (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pairing {
    /// Faces bounding the same full quarter: the voxels stay apart.
    Full,
    /// Faces bounding the same empty quarter: the voxels join through the edge.
    Empty,
}

/// Most quarter faces at a lattice point (each of the twelve is covered once at most).
const MAX_FACES: usize = 12;

/// The quarter faces at one lattice point, each with its record's place in the group,
/// and the faces each half-edge bounds.
struct Link {
    faces: [QuarterFace; MAX_FACES],
    record: [u8; MAX_FACES],
    len: usize,
    around: [[u8; 4]; 6],
    count: [u8; 6],
}

impl Link {
    fn new(group: &[u128]) -> Link {
        let mut link = Link {
            faces: [QuarterFace::NONE; MAX_FACES],
            record: [0; MAX_FACES],
            len: 0,
            around: [[0; 4]; 6],
            count: [0; 6],
        };
        for (r, &rec) in group.iter().enumerate() {
            for shift in [37, 32] {
                let f = QuarterFace(((rec >> shift) & 31) as u8);
                if f == QuarterFace::NONE || link.len == MAX_FACES {
                    continue;
                }
                let i = link.len;
                (link.faces[i], link.record[i]) = (f, r as u8);
                link.len += 1;
                let a = f.axis();
                for b in [(a + 1) % 3, (a + 2) % 3] {
                    let h = usize::from(2 * b as u8 + f.side(b));
                    if usize::from(link.count[h]) < 4 {
                        link.around[h][usize::from(link.count[h])] = i as u8;
                    }
                    link.count[h] += 1;
                }
            }
        }
        link
    }

    /// Half-edges with four faces.
    fn touches(&self) -> impl Iterator<Item = u8> + '_ {
        (0..6u8).filter(|&h| self.count[usize::from(h)] == 4)
    }

    /// The two pairs of faces at touch `h` under `pairing`.
    fn pairs(&self, h: u8, pairing: Pairing) -> [[usize; 2]; 2] {
        let around = self.around[usize::from(h)].map(usize::from);
        let key = |i: usize| self.faces[i].quarter(h, pairing == Pairing::Full);
        let mate = (1..4).find(|&k| key(around[k]) == key(around[0])).unwrap_or(1);
        let rest: [usize; 2] = match mate {
            1 => [2, 3],
            2 => [1, 3],
            _ => [1, 2],
        };
        [[around[0], around[mate]], rest.map(|k| around[k])]
    }

    /// The curve of each face (a union-find root), touches paired by `pairing(h)`.
    fn curves(&self, pairing: impl Fn(u8) -> Pairing) -> [u8; MAX_FACES] {
        fn find(parent: &mut [u8], mut i: usize) -> usize {
            while usize::from(parent[i]) != i {
                parent[i] = parent[usize::from(parent[i])];
                i = usize::from(parent[i]);
            }
            i
        }
        fn union(parent: &mut [u8], i: usize, j: usize) {
            let (a, b) = (find(parent, i), find(parent, j));
            parent[a.max(b)] = a.min(b) as u8;
        }
        let mut parent: [u8; MAX_FACES] = std::array::from_fn(|i| i as u8);
        // A record's two faces (a point inside a square's edge) are one curve.
        for i in 1..self.len {
            if self.record[i] == self.record[i - 1] {
                union(&mut parent, i - 1, i);
            }
        }
        for h in 0..6u8 {
            let around = self.around[usize::from(h)];
            match self.count[usize::from(h)] {
                2 => union(&mut parent, usize::from(around[0]), usize::from(around[1])),
                4 => {
                    for [i, j] in self.pairs(h, pairing(h)) {
                        union(&mut parent, i, j);
                    }
                }
                n => debug_assert!(n == 0, "{n} faces around a half-edge"),
            }
        }
        for i in 0..self.len {
            parent[i] = find(&mut parent, i) as u8;
        }
        parent
    }

    /// Whether `pairing` at touch `h` leaves both its pairs on one curve.
    fn joins(&self, h: u8, pairing: impl Fn(u8) -> Pairing) -> bool {
        let curves = self.curves(&pairing);
        let [[a, _], [c, _]] = self.pairs(h, pairing(h));
        curves[a] == curves[c]
    }

    /// The sheet (0, 1, ...) of each of the group's `records`, numbered by first
    /// appearance, and the number of sheets.
    fn sheets(&self, pairing: impl Fn(u8) -> Pairing) -> ([u8; MAX_FACES], u8) {
        let curves = self.curves(pairing);
        let mut number = [u8::MAX; MAX_FACES];
        let mut sheets = [0; MAX_FACES];
        let mut count = 0;
        for i in 0..self.len {
            let root = usize::from(curves[i]);
            if number[root] == u8::MAX {
                number[root] = count;
                count += 1;
            }
            sheets[usize::from(self.record[i])] = number[root];
        }
        (sheets, count)
    }
}

/// A lattice point with touches: its group of records and, for each touch, the
/// half-edge and the key of its segment.
struct TouchPoint {
    /// Index of the group.
    index: usize,
    touches: SmallVec<[(u8, u128); 6]>,
}

/// Welds polygon points into vertices, one a sheet (module doc). `records` has one
/// [`record`] a polygon point; `along(i, h)` is polygon point `i`'s neighbour in the
/// direction of half-edge `h`. Returns each vertex's lattice point and each polygon
/// point's vertex index.
pub(super) fn weld(
    mut records: Vec<u128>,
    points: usize,
    along: impl Fn(usize, u8) -> Point + Sync,
) -> (Vec<Point>, Vec<u32>) {
    records.par_sort_unstable();
    let groups = groups(&records);
    // Sheets of every record with touches paired `Full`, in parallel; touch points marked.
    let mut sheet_of: Vec<([u8; MAX_FACES], u8, bool)> = groups
        .par_iter()
        .with_min_len(CHUNK)
        .map(|group| {
            let link = Link::new(&records[group.clone()]);
            let (sheets, count) = link.sheets(|_| Pairing::Full);
            (sheets, count, link.touches().next().is_some())
        })
        .collect();
    let touch_points = touch_points(&records, &groups, &sheet_of, along);
    let pairing = choose_pairings(&records, &groups, &touch_points);
    // Touch points again with the chosen pairings, then vertex numbers in sorted order.
    for tp in &touch_points {
        let link = Link::new(&records[groups[tp.index].clone()]);
        let (sheets, count) = link.sheets(|h| pairing_at(&pairing, tp, h));
        sheet_of[tp.index] = (sheets, count, true);
    }
    let mut ids = vec![0u32; points];
    let mut vertices = Vec::with_capacity(groups.len());
    for (group, (sheets, count, _)) in groups.iter().zip(&sheet_of) {
        let base = vertices.len() as u32;
        for (&r, &sheet) in records[group.clone()].iter().zip(sheets) {
            ids[record_index(r)] = base + u32::from(sheet);
        }
        vertices.extend(std::iter::repeat_n(record_point(records[group.start]), usize::from(*count)));
    }
    (vertices, ids)
}

/// The groups of sorted records that share a lattice point.
fn groups(records: &[u128]) -> Vec<std::ops::Range<usize>> {
    let mut groups = Vec::new();
    let mut start = 0;
    while start < records.len() {
        let position = records[start] >> POSITION_SHIFT;
        // A point has at most twelve records: a linear scan, not a search of the rest.
        let end = start + records[start..].iter().take_while(|&&r| r >> POSITION_SHIFT == position).count();
        groups.push(start..end);
        start = end;
    }
    groups
}

/// The lattice points with touches, each touch with its half-edge and the key of its
/// segment (the segment's lower end on its line).
fn touch_points(
    records: &[u128],
    groups: &[std::ops::Range<usize>],
    sheet_of: &[([u8; MAX_FACES], u8, bool)],
    along: impl Fn(usize, u8) -> Point,
) -> Vec<TouchPoint> {
    (0..groups.len())
        .filter(|&g| sheet_of[g].2)
        .map(|g| {
            let group = groups[g].clone();
            let link = Link::new(&records[group.clone()]);
            let p = record_point(records[group.start]);
            let touches = link
                .touches()
                .map(|h| {
                    let face = usize::from(link.around[usize::from(h)][0]);
                    let q = along(record_index(records[group.start + usize::from(link.record[face])]), h);
                    (h, line_point(usize::from(h / 2), if h & 1 == 1 { p } else { q }))
                })
                .collect();
            TouchPoint { index: g, touches }
        })
        .collect()
}

/// The pairing of every touch segment: start `Full`, then flip segments whose pairing
/// joins their pairs at both ends, until none is left (at most `MAX_ROUNDS` rounds).
fn choose_pairings(
    records: &[u128],
    groups: &[std::ops::Range<usize>],
    touch_points: &[TouchPoint],
) -> BTreeMap<u128, Pairing> {
    let mut pairing: BTreeMap<u128, Pairing> = BTreeMap::new();
    let mut ends: BTreeMap<u128, SmallVec<[(usize, u8); 2]>> = BTreeMap::new();
    for (t, tp) in touch_points.iter().enumerate() {
        for &(h, key) in &tp.touches {
            pairing.insert(key, Pairing::Full);
            ends.entry(key).or_default().push((t, h));
        }
    }
    for _ in 0..MAX_ROUNDS {
        let mut flipped = false;
        for (key, at) in &ends {
            let joined = at.iter().all(|&(t, h)| {
                let tp = &touch_points[t];
                Link::new(&records[groups[tp.index].clone()]).joins(h, |g| pairing_at(&pairing, tp, g))
            });
            if joined {
                let p = pairing.entry(*key).or_insert(Pairing::Full);
                *p = if *p == Pairing::Full { Pairing::Empty } else { Pairing::Full };
                flipped = true;
            }
        }
        if !flipped {
            break;
        }
    }
    pairing
}

/// The pairing of touch point `tp`'s segment along half-edge `h` (`Full` where it has
/// none).
fn pairing_at(pairing: &BTreeMap<u128, Pairing>, tp: &TouchPoint, h: u8) -> Pairing {
    tp.touches.iter().find(|t| t.0 == h).and_then(|t| pairing.get(&t.1)).copied().unwrap_or(Pairing::Full)
}
