//! The occupancy gradient at a voxel centre: the octree's estimate of the outward
//! normal there, as the normalized `-sum_c occ(c) w(|c - c0|) (c - c0)` over the voxel
//! centres `c` within `R = r + 1/2` voxels of the centre `c0`, with `w(s) = 1 - s^2 /
//! R^2` (`r` = [`SMOOTH_RADIUS`]): a smooth, symmetric window, so a flat surface at any
//! orientation gives a normal close to its own. (The gradient of the occupancy
//! smoothed by the kernel `w`, as in density-field normals of volume rendering:
//! Levoy, "Display of surfaces from volume data", 1988, which takes central
//! differences; the wider window here averages the voxel staircase out.)
//!
//! Method: the cube of `2r + 1` voxels around `c0` is one bit pattern a row of voxels
//! along x (`occupancy::Window`). With offsets in voxels from `c0` all integers, `4 R^2
//! w(s) = (2r + 1)^2 - 4 s^2` is an integer and the sum is made exactly in integers: a
//! row at `(dy, dz)` with `c = 4 R^2 - 4 (dy^2 + dz^2)` adds, over its full voxels
//! inside the ball, `(c S1 - 4 S3, dy (c S0 - 4 S2), dz (c S0 - 4 S2))` with `Sk = sum
//! dx^k`, and the sums `Sk` of a row's pattern (masked to the ball) are one table
//! lookup. Exactness is what keeps flat faces flat: where the occupancy is
//! mirror-symmetric across the planes through `c0` normal to two axes (a face on a
//! lattice plane, far enough from its edges), those two components cancel to zero and
//! the normal is the third axis exactly (normalized by division, which leaves an axis
//! exact, not by multiplying with a rounded reciprocal).

use glam::DVec3;

use super::occupancy::Window;

/// Window radius in voxels.
pub const SMOOTH_RADIUS: u32 = 4;

/// Voxels a side of the window around a voxel centre.
pub(crate) const WINDOW: usize = 2 * SMOOTH_RADIUS as usize + 1;

/// `4 R^2` with `R = r + 1/2`: `4 R^2 w(s) = FOUR_R2 - 4 s^2`.
const FOUR_R2: i64 = (2 * SMOOTH_RADIUS as i64 + 1) * (2 * SMOOTH_RADIUS as i64 + 1);

/// The offset of window index `i` from the middle voxel.
const fn offset(i: usize) -> i64 {
    i as i64 - SMOOTH_RADIUS as i64
}

/// `[S0, S1, S2, S3]` (`Sk = sum dx^k` over the set bits, `dx` the bits' offsets from
/// the middle) of every row pattern of [`WINDOW`] bits.
static ROW_SUMS: [[i16; 4]; 1 << WINDOW] = {
    let mut sums = [[0; 4]; 1 << WINDOW];
    let mut bits = 0;
    while bits < 1 << WINDOW {
        let mut i = 0;
        while i < WINDOW {
            if bits >> i & 1 == 1 {
                let dx = offset(i) as i16;
                let [s0, s1, s2, s3] = sums[bits];
                sums[bits] = [s0 + 1, s1 + dx, s2 + dx * dx, s3 + dx * dx * dx];
            }
            i += 1;
        }
        bits += 1;
    }
    sums
};

/// A row of the window at offsets `(dy, dz)`: the bits of its voxels inside the ball
/// (`4 |d|^2 < 4 R^2`) and `c = 4 R^2 - 4 (dy^2 + dz^2)`.
#[derive(Clone, Copy)]
struct BallRow {
    mask: u32,
    dy: i64,
    dz: i64,
    c: i64,
}

/// The rows of a window, `y + WINDOW z`.
static BALL_ROWS: [BallRow; WINDOW * WINDOW] = {
    let mut rows = [BallRow { mask: 0, dy: 0, dz: 0, c: 0 }; WINDOW * WINDOW];
    let mut row = 0;
    while row < WINDOW * WINDOW {
        let (dy, dz) = (offset(row % WINDOW), offset(row / WINDOW));
        let c = FOUR_R2 - 4 * (dy * dy + dz * dz);
        let mut mask = 0;
        let mut i = 0;
        while i < WINDOW {
            if 4 * offset(i) * offset(i) < c {
                mask |= 1 << i;
            }
            i += 1;
        }
        rows[row] = BallRow { mask, dy, dz, c };
        row += 1;
    }
    rows
};

/// The estimate (see the module doc) at the centre of the voxel `at + (r, r, r)` of
/// `window` (which must hold the [`WINDOW`]-voxel cube at `at`), `None` where the
/// gradient is zero.
pub(crate) fn centre_normal(window: &Window, at: [usize; 3]) -> Option<DVec3> {
    debug_assert!((0..3).all(|a| at[a] + WINDOW <= window.size));
    let mut gradient = [0i64; 3];
    for (z, balls) in BALL_ROWS.chunks_exact(WINDOW).enumerate() {
        let rows = &window.rows[at[1] + window.size * (at[2] + z)..][..WINDOW];
        for (&row, ball) in rows.iter().zip(balls) {
            let bits = (row >> at[0]) & ball.mask;
            if bits == 0 {
                continue;
            }
            let [s0, s1, s2, s3] = ROW_SUMS[bits as usize].map(i64::from);
            let across = ball.c * s0 - 4 * s2;
            gradient[0] += ball.c * s1 - 4 * s3;
            gradient[1] += ball.dy * across;
            gradient[2] += ball.dz * across;
        }
    }
    let n = -DVec3::from_array(gradient.map(|g| g as f64));
    (n != DVec3::ZERO).then(|| n / n.length())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::{Domain, VoxelizeOptions, voxelize};
    use crate::render::scene::occupancy::MAX_WINDOW;
    use crate::shape::{Csg, Cuboid, Sphere};
    use crate::test_util::Rng;

    /// The module doc's sum as written, in floating point, voxel by voxel.
    fn brute_force(window: &Window, at: [usize; 3]) -> DVec3 {
        let reach = f64::from(SMOOTH_RADIUS) + 0.5;
        let mut sum = DVec3::ZERO;
        for (x, y, z) in (0..WINDOW).flat_map(|x| (0..WINDOW).flat_map(move |y| (0..WINDOW).map(move |z| (x, y, z)))) {
            let full = window.rows[at[1] + y + window.size * (at[2] + z)] >> (at[0] + x) & 1 == 1;
            let d = DVec3::new(x as f64, y as f64, z as f64) - DVec3::splat(f64::from(SMOOTH_RADIUS));
            if full && d.length() < reach {
                sum += d * (1.0 - d.length_squared() / (reach * reach));
            }
        }
        -sum
    }

    #[test]
    fn the_integer_sum_is_the_formula() {
        // Random windows of a carved ball, at every offset within a larger window.
        let ball = Sphere::new(DVec3::new(0.1, -0.05, 0.02), 0.7).unwrap();
        let notch = Cuboid::new(DVec3::new(0.5, 0.3, 0.4), DVec3::splat(0.6)).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
        let tree = voxelize(&(Csg::leaf(ball) - Csg::leaf(notch)), domain, &VoxelizeOptions::default()).unwrap();
        let mut rng = Rng(21);
        let mut some = 0;
        for _ in 0..400 {
            let lo: [i64; 3] = std::array::from_fn(|_| rng.below(60) as i64);
            let window = Window::read(&tree, lo, WINDOW + 3);
            let at: [usize; 3] = std::array::from_fn(|_| rng.below(4) as usize);
            let want = brute_force(&window, at);
            match centre_normal(&window, at) {
                Some(got) => {
                    some += 1;
                    assert!((got - want.normalize()).length() < 1e-12, "at {lo:?} + {at:?}: {got} against {want}");
                }
                None => assert!(want.length() < 1e-9, "at {lo:?} + {at:?}: no gradient against {want}"),
            }
        }
        assert!(some > 100, "{some} windows with a gradient");
    }

    #[test]
    fn a_face_on_a_lattice_plane_gives_its_axis_exactly() {
        // A half space below z = k (any k in the window's reach): exactly +z, and the
        // mirror images along the other axes.
        for k in 1..WINDOW {
            let mut window = Window { size: WINDOW, rows: [0; MAX_WINDOW * MAX_WINDOW] };
            for z in 0..k {
                for y in 0..WINDOW {
                    window.rows[y + WINDOW * z] = (1 << WINDOW) - 1;
                }
            }
            assert_eq!(centre_normal(&window, [0; 3]), Some(DVec3::Z), "plane {k}");
            for row in &mut window.rows[..WINDOW * WINDOW] {
                *row ^= (1 << WINDOW) - 1;
            }
            assert_eq!(centre_normal(&window, [0; 3]), Some(-DVec3::Z), "plane {k}, flipped");
        }
    }
}
