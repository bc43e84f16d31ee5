//! Triangle / axis-aligned box overlap by the separating axis theorem.
//!
//! Akenine-Moller, "Fast 3D Triangle-Box Overlap Testing" (2001): a triangle and a box
//! are disjoint iff one of 13 axes separates them: the 3 box normals, the triangle's
//! normal, and the 9 cross products of box and triangle edges. The box is grown by a
//! relative hair so that rounding can only report an overlap that is not there, never
//! miss one (the voxelizers need conservative answers).

use glam::DVec3;

/// Whether triangle `t` meets the closed box with centre `center` and half extents `half`.
#[must_use]
pub fn triangle_box_overlap(t: &[DVec3; 3], center: DVec3, half: DVec3) -> bool {
    let half = half * (1.0 + 1e-9) + DVec3::splat(1e-300);
    // Step 1: move the box to the origin.
    let v = [t[0] - center, t[1] - center, t[2] - center];
    // Step 2: the box normals (the triangle's bounding box against the box).
    for a in 0..3 {
        let (lo, hi) = (v[0][a].min(v[1][a]).min(v[2][a]), v[0][a].max(v[1][a]).max(v[2][a]));
        if lo > half[a] || hi < -half[a] {
            return false;
        }
    }
    // Step 3: the triangle's plane: n . x = n . v0 against the box's projection radius
    // (cheap, and it rejects most near misses).
    let edges = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let n = edges[0].cross(edges[1]);
    if n.dot(v[0]).abs() > half.dot(n.abs()) {
        return false;
    }
    // Step 4: the nine edge cross products: project triangle and box on axis = e_i x edge.
    for e in edges {
        for axis in [DVec3::new(0.0, -e.z, e.y), DVec3::new(e.z, 0.0, -e.x), DVec3::new(-e.y, e.x, 0.0)] {
            let p = [axis.dot(v[0]), axis.dot(v[1]), axis.dot(v[2])];
            let r = half.dot(axis.abs());
            if p[0].min(p[1]).min(p[2]) > r || p[0].max(p[1]).max(p[2]) < -r {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_cases() {
        let t = [DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, -1.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
        assert!(triangle_box_overlap(&t, DVec3::ZERO, DVec3::splat(0.1)));
        assert!(!triangle_box_overlap(&t, DVec3::new(0.0, 0.0, 0.2), DVec3::splat(0.1)));
        // Beside the hypotenuse: the box-normal tests pass, an edge axis separates.
        assert!(!triangle_box_overlap(&t, DVec3::new(0.9, 0.9, 0.0), DVec3::splat(0.1)));
    }
}
