//! Hermite data through a set operation: the crossings of a CSG result's boundary
//! faces taken from its operands' own, so a solid made by combining saved solids keeps
//! their exact surface, with sharp edges where the operands' surfaces meet.
//!
//! Along a boundary face's segment, from the result's full voxel `v` (at `t = 0`) to
//! its empty neighbour `n` (at `t = 1`), each operand holds `v` and `n` or not, as its
//! voxels say. An operand that holds one and not the other crosses the segment once
//! (the resolved case of [`super::hermite`]): **leaving** at its own crossing of the
//! face `(v, d)` when it holds `v`, or **entering** at `1 - t` of its crossing of the
//! opposite face `(n, -d)` when it holds `n`, seen from the other side (normal
//! negated). An operand that holds both or neither does not change on the segment.
//! The result's membership is the operator over the operands' memberships (union: any;
//! intersection: all; difference: the first and none of the others; xor: an odd
//! number, as [`LinearOctree::combine_all`]), true at `v` and false at `n`; walking
//! the changes in order of `t`, the result's crossing is the first change that makes
//! it false, and its outward normal that operand's (leaving) or its opposite
//! (entering). This is the CSG of the operands' surfaces restricted to one segment,
//! and it gives the rules one would write by hand:
//!
//! - union: the farthest crossing among the operands that hold `v` (all of them have
//!   `n` empty);
//! - intersection: the nearest among the operands that leave (those with `n` empty);
//! - difference `A - B - ...`: the nearest of `A` leaving and each `B` entering;
//! - xor: the nearest change of any operand (each flips the parity, and the first
//!   flip makes it even).
//!
//! An operand without data for a face gives the face itself ([`Crossing::face`]), so
//! a solid read from a file without a surface section takes part as a staircase.
//! Departure from the exact CSG: an operand whose surface crosses the segment twice
//! (a feature thinner than a voxel) holds both ends or neither and is taken as not
//! crossing, as its voxels say; where several changes fall at the same `t` the
//! operand listed first wins.

use rayon::prelude::*;

use super::faces::{boundary_faces, neighbour};
use super::hermite::{Crossing, FaceKey, HermiteData};
use crate::error::{Error, Result};
use crate::octree::{LinearOctree, SetOp};

impl HermiteData {
    /// The Hermite data of `result`, the `op` of the operands' solids, from each
    /// operand's solid and its data (see the module doc); `HermiteData::none()` for an
    /// operand without data. Every face of `result`'s boundary gets a crossing.
    ///
    /// Fails when there are no operands or an operand's domain is not `result`'s.
    pub fn combine(
        op: SetOp,
        operands: &[(&LinearOctree, &HermiteData)],
        result: &LinearOctree,
    ) -> Result<HermiteData> {
        if operands.is_empty() {
            return Err(Error::invalid("operands", "no operand to take the surface from"));
        }
        if let Some(i) = operands.iter().position(|(tree, _)| tree.domain() != result.domain()) {
            return Err(Error::invalid(
                "operands",
                format!("operand {i} is over {}, not the result's {}", operands[i].0.domain(), result.domain()),
            ));
        }
        let faces = boundary_faces(result);
        let faces = faces.par_iter().map(|&key| (key, crossing(op, operands, key))).collect();
        Ok(HermiteData::from_sorted(faces))
    }
}

/// Whether the result of `op` holds a point its operands hold as `members` says.
fn holds(op: SetOp, members: impl ExactSizeIterator<Item = bool>) -> bool {
    let mut members = members;
    match op {
        SetOp::Union => members.any(|m| m),
        SetOp::Intersection => members.all(|m| m),
        SetOp::Difference => members.next().unwrap_or(false) && !members.any(|m| m),
        SetOp::SymmetricDifference => members.filter(|&m| m).count() % 2 == 1,
    }
}

/// The result's crossing of boundary face `key` (see the module doc).
fn crossing(op: SetOp, operands: &[(&LinearOctree, &HermiteData)], key: FaceKey) -> Crossing {
    let v = key.voxel();
    let resolution = operands[0].0.domain().resolution();
    let n = neighbour(key, resolution);
    // (t, operand, crossing in the face's frame): every operand that changes.
    let mut changes: Vec<(f32, usize, Crossing)> = Vec::with_capacity(operands.len());
    let mut members: Vec<bool> = Vec::with_capacity(operands.len());
    for (i, (tree, data)) in operands.iter().enumerate() {
        let (at_v, at_n) = (tree.contains_voxel(v), n.is_some_and(|n| tree.contains_voxel(n)));
        members.push(at_v);
        match (at_v, at_n, n) {
            (true, false, _) => {
                let c = data.crossing(key);
                changes.push((c.t, i, c));
            }
            (false, true, Some(n)) => {
                let back = FaceKey::new(n, key.direction ^ 1);
                let c = data.crossing(back);
                let seen = Crossing { t: 1.0 - c.t, normal: -c.normal };
                changes.push((seen.t, i, seen));
            }
            _ => {}
        }
    }
    changes.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (_, i, c) in &changes {
        members[*i] = !members[*i];
        if !holds(op, members.iter().copied()) {
            return *c;
        }
    }
    // Unreachable for a boundary face of the result (after every change the operands
    // hold what they hold at `n`, where the result is empty); the face as a fallback.
    Crossing::face(key)
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, Vec3};

    use super::*;
    use crate::octree::Domain;

    fn c(t: f32, normal: Vec3) -> Crossing {
        Crossing { t, normal }
    }

    /// Two one-voxel-wide solids along x: `a` at x = 1, `b` at x = 2, each with data
    /// on its faces towards the other.
    #[test]
    fn each_operator_takes_the_crossing_its_membership_changes_at() {
        let d = Domain::new(DVec3::ZERO, 4.0, 2).unwrap();
        let a = LinearOctree::from_voxels(d, [[1, 1, 1]]).unwrap();
        let ab = LinearOctree::from_voxels(d, [[1, 1, 1], [2, 1, 1]]).unwrap();
        let b = LinearOctree::from_voxels(d, [[2, 1, 1]]).unwrap();
        // a's +x face crosses at 0.3; ab's +x face of voxel 1 is inside ab; ab's -x face
        // of voxel 2 is inside too. b's -x face crosses at 0.2 from voxel 2 (x = 1.8).
        let a_data = HermiteData::from_faces(vec![(FaceKey::new([1, 1, 1], 1), c(0.3, Vec3::X))]);
        let b_data = HermiteData::from_faces(vec![(FaceKey::new([2, 1, 1], 0), c(0.2, -Vec3::X))]);
        let face = FaceKey::new([1, 1, 1], 1);
        // Difference a - b: voxel 1 full, voxel 2 in b. a leaves at 0.3, b enters at
        // 1 - 0.2 = 0.8: the nearest, a's.
        let diff = a.difference(&b).unwrap();
        let got = HermiteData::combine(SetOp::Difference, &[(&a, &a_data), (&b, &b_data)], &diff).unwrap();
        assert_eq!(got.get(face), Some(c(0.3, Vec3::X)));
        // ab - b is a: same membership at the face, but now the first operand holds
        // both voxels, so only b enters, at 0.8, normal -(-x) = +x.
        let ab_data = HermiteData::none();
        let got = HermiteData::combine(SetOp::Difference, &[(&ab, &ab_data), (&b, &b_data)], &diff).unwrap();
        let e = got.get(face).unwrap();
        assert!((e.t - 0.8).abs() < 1e-6 && e.normal == Vec3::X, "{e:?}");
        // Intersection of ab and a: a leaves at 0.3, ab holds both.
        let got = HermiteData::combine(SetOp::Intersection, &[(&ab, &ab_data), (&a, &a_data)], &a).unwrap();
        assert_eq!(got.get(face), Some(c(0.3, Vec3::X)));
        // Union of a and a copy crossing farther: the farthest.
        let far = HermiteData::from_faces(vec![(face, c(0.7, Vec3::Y))]);
        let got = HermiteData::combine(SetOp::Union, &[(&a, &a_data), (&a, &far)], &a).unwrap();
        assert_eq!(got.get(face), Some(c(0.7, Vec3::Y)));
        // Xor of a and b is ab, whose +x face of voxel 1 is inside: not a face; its
        // face of voxel 1 towards -x takes a's (no data there: the face itself).
        let x = a.combine(&b, SetOp::SymmetricDifference).unwrap();
        let got = HermiteData::combine(SetOp::SymmetricDifference, &[(&a, &a_data), (&b, &b_data)], &x).unwrap();
        assert_eq!(got.get(face), None);
        let left = FaceKey::new([1, 1, 1], 0);
        assert_eq!(got.get(left), Some(Crossing::face(left)));
        // Every boundary face of the result has one.
        assert_eq!(got.len(), boundary_faces(&x).len());
    }
}
