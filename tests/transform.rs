//! Octree transforms against a dense-grid oracle, and resampling against the exact
//! transforms and analytic volumes.

use std::f64::consts::PI;

use glam::{DAffine3, DQuat, DVec3};
use octsolid::morton;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::shape::{Class, Cuboid, ShapeExt};

mod common;

use common::{Rng, random_octree};

fn domain(depth: u8) -> Domain {
    Domain::new(DVec3::new(-1.0, -1.0, -1.0), 2.0, depth).unwrap()
}

fn random_tree(rng: &mut Rng, depth: u8) -> LinearOctree {
    random_octree(rng, domain(depth))
}

/// The full voxels as a set of coordinates, mapped by `f` (None = dropped).
fn dense_map(tree: &LinearOctree, f: impl Fn([i64; 3]) -> Option<[i64; 3]>) -> LinearOctree {
    let n = i64::from(tree.domain().resolution());
    let voxels = tree
        .keys()
        .iter()
        .flat_map(|k| k.start()..k.end())
        .filter_map(|c| f(morton::decode(c).map(i64::from)))
        .filter(|v| v.iter().all(|&c| (0..n).contains(&c)))
        .map(|v| v.map(|c| c as u32));
    LinearOctree::from_voxels(*tree.domain(), voxels.collect::<Vec<_>>()).unwrap()
}

#[test]
fn translate_matches_dense_grid() {
    let mut rng = Rng(21);
    for depth in 3..=5 {
        for _ in 0..15 {
            let tree = random_tree(&mut rng, depth);
            let n = i64::from(tree.domain().resolution());
            let offset = [0; 3].map(|_| rng.below(2 * n as u64 + 1) as i64 - n);
            let got = tree.translate(offset);
            got.validate().unwrap();
            assert_eq!(got, dense_map(&tree, |v| Some(std::array::from_fn(|a| v[a] + offset[a]))), "{offset:?}");
        }
    }
}

#[test]
fn mirrors_and_quarter_turns_match_dense_grid() {
    let mut rng = Rng(8);
    for depth in 3..=5 {
        for _ in 0..10 {
            let tree = random_tree(&mut rng, depth);
            let n = i64::from(tree.domain().resolution());
            for axis in 0..3 {
                let m = tree.mirror(axis);
                m.validate().unwrap();
                let want = dense_map(&tree, |mut v| {
                    v[axis] = n - 1 - v[axis];
                    Some(v)
                });
                assert_eq!(m, want);
                assert_eq!(m.mirror(axis), tree);

                let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                let r = tree.rotate90(axis, 1);
                r.validate().unwrap();
                let want = dense_map(&tree, |v| {
                    let mut out = v;
                    out[u] = n - 1 - v[w];
                    out[w] = v[u];
                    Some(out)
                });
                assert_eq!(r, want, "axis {axis}");
                assert_eq!(tree.rotate90(axis, -1), r.rotate90(axis, 2));
                assert_eq!(r.rotate90(axis, 3), tree);
                assert_eq!(tree.rotate90(axis, 4), tree);
            }
        }
    }
    // +90 about z takes +x to +y: voxel (x, y, z) -> (N - 1 - y, x, z).
    let d = domain(3);
    let one = LinearOctree::from_voxels(d, [[6, 1, 2]]).unwrap();
    assert_eq!(one.rotate90(2, 1), LinearOctree::from_voxels(d, [[6, 6, 2]]).unwrap());
}

#[test]
fn classify_voxel_box_matches_brute_force() {
    let mut rng = Rng(5);
    for _ in 0..30 {
        let tree = random_tree(&mut rng, 4);
        for _ in 0..50 {
            let lo = [0; 3].map(|_| rng.below(16) as u32);
            let hi: [u32; 3] = std::array::from_fn(|a| lo[a] + 1 + rng.below(16 - u64::from(lo[a])) as u32);
            let mut full = 0;
            let mut total = 0;
            for x in lo[0]..hi[0] {
                for y in lo[1]..hi[1] {
                    for z in lo[2]..hi[2] {
                        total += 1;
                        full += u32::from(tree.contains_voxel([x, y, z]));
                    }
                }
            }
            let want = match full {
                0 => Class::Outside,
                f if f == total => Class::Inside,
                _ => Class::Boundary,
            };
            assert_eq!(tree.classify_voxel_box(lo, hi), want, "{lo:?}..{hi:?}");
        }
    }
}

#[test]
fn resample_agrees_with_exact_transforms() {
    let mut rng = Rng(77);
    let opts = VoxelizeOptions::default();
    for _ in 0..10 {
        let tree = random_tree(&mut rng, 5);
        let d = *tree.domain();
        // Identity into the same domain.
        assert_eq!(tree.resample_to(d, &opts).unwrap(), tree);
        // A whole-voxel translation.
        let h = d.voxel_size();
        let moved = tree.resample(DAffine3::from_translation(DVec3::new(3.0, -2.0, 5.0) * h), d, &opts).unwrap();
        assert_eq!(moved, tree.translate([3, -2, 5]));
        // A quarter turn about the domain's centre (the origin here).
        let turn = DAffine3::from_quat(DQuat::from_rotation_z(PI / 2.0));
        assert_eq!(tree.resample(turn, d, &opts).unwrap(), tree.rotate90(2, 1));
        // Into a finer domain: the refinement.
        assert_eq!(tree.resample_to(d.with_depth(6).unwrap(), &opts).unwrap(), tree.refine(6).unwrap());
    }
}

#[test]
fn resampled_rotation_keeps_the_volume() {
    let d = domain(7);
    let opts = VoxelizeOptions::default();
    let cube = voxelize(&Cuboid::new(DVec3::ZERO, DVec3::new(1.0, 0.8, 0.6)).unwrap(), d, &opts).unwrap();
    let turn = DAffine3::from_quat(DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.3).normalize(), PI / 4.0));
    let turned = cube.resample(turn, d, &opts).unwrap();
    turned.validate().unwrap();
    assert!((turned.volume() / 0.48 - 1.0).abs() < 0.03, "{}", turned.volume());
    // It agrees with voxelizing the rotated shape up to a thin boundary layer.
    let direct =
        voxelize(&Cuboid::new(DVec3::ZERO, DVec3::new(1.0, 0.8, 0.6)).unwrap().transform(turn).unwrap(), d, &opts)
            .unwrap();
    let differ = (&turned ^ &direct).voxel_count() as f64;
    assert!(differ < 0.08 * direct.voxel_count() as f64, "{differ} voxels differ");
}
