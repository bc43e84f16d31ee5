//! Linear octree storage, queries, CSG and depth change against a dense-grid oracle.

use octsolid::octree::{CoarsenRule, Domain, LinearOctree, NodeKey, SetOp};
use octsolid::{Error, morton};

use glam::DVec3;

mod common;

use common::{Rng, random_octree};

fn domain(depth: u8) -> Domain {
    Domain::new(DVec3::new(-1.0, 2.0, 0.5), 3.0, depth).unwrap()
}

/// A dense boolean grid indexed by Morton code: the oracle.
fn dense(tree: &LinearOctree) -> Vec<bool> {
    let mut grid = vec![false; tree.domain().voxel_total() as usize];
    for key in tree.keys() {
        grid[key.start() as usize..key.end() as usize].fill(true);
    }
    grid
}

fn random_tree(rng: &mut Rng, depth: u8) -> LinearOctree {
    random_octree(rng, domain(depth))
}

fn from_dense(d: Domain, grid: &[bool]) -> LinearOctree {
    let voxels = grid.iter().enumerate().filter(|(_, f)| **f).map(|(c, _)| morton::decode(c as u64));
    LinearOctree::from_voxels(d, voxels).unwrap()
}

#[test]
fn from_voxels_is_canonical_and_exact() {
    let mut rng = Rng(7);
    for depth in 1..=5 {
        for _ in 0..20 {
            let tree = random_tree(&mut rng, depth);
            let grid = dense(&tree);
            let again = from_dense(*tree.domain(), &grid);
            again.validate().unwrap();
            // One solid, one canonical form: equal key lists.
            assert_eq!(again, tree);
            assert_eq!(tree.voxel_count(), grid.iter().filter(|f| **f).count() as u64);
        }
    }
}

#[test]
fn full_domain_collapses_to_the_root() {
    let d = domain(3);
    let all = (0..8u32).flat_map(|x| (0..8u32).flat_map(move |y| (0..8u32).map(move |z| [x, y, z])));
    let tree = LinearOctree::from_voxels(d, all).unwrap();
    assert_eq!(tree, LinearOctree::full(d));
    assert_eq!(tree.node_count(), 1);
    assert_eq!(tree.voxel_count(), 512);
    assert!((tree.volume() - 27.0).abs() < 1e-12);
}

#[test]
fn csg_matches_dense_grid() {
    let mut rng = Rng(99);
    for depth in 1..=5 {
        for _ in 0..30 {
            let (a, b) = (random_tree(&mut rng, depth), random_tree(&mut rng, depth));
            let (ga, gb) = (dense(&a), dense(&b));
            for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
                let got = a.combine(&b, op).unwrap();
                got.validate().unwrap();
                let want: Vec<bool> = ga.iter().zip(&gb).map(|(x, y)| op.apply(*x, *y)).collect();
                assert_eq!(dense(&got), want, "{op:?} at depth {depth}");
                assert_eq!(got, from_dense(*a.domain(), &want), "{op:?} not canonical");
            }
            let not_a = !&a;
            not_a.validate().unwrap();
            assert_eq!(dense(&not_a), ga.iter().map(|f| !f).collect::<Vec<_>>());
            // The operators are the methods.
            assert_eq!(&a | &b, a.union(&b).unwrap());
            assert_eq!(&a & &b, a.intersection(&b).unwrap());
            assert_eq!(&a - &b, a.difference(&b).unwrap());
            assert_eq!(&a ^ &b, a.symmetric_difference(&b).unwrap());
        }
    }
}

#[test]
fn csg_refuses_different_domains() {
    let a = LinearOctree::full(domain(4));
    let b = LinearOctree::full(domain(5));
    let err = a.union(&b).unwrap_err();
    assert!(matches!(err, Error::DomainMismatch { .. }), "{err}");
    assert!(err.to_string().contains("depth 4") && err.to_string().contains("depth 5"), "{err}");
    let c = LinearOctree::full(Domain::new(DVec3::ZERO, 3.0, 4).unwrap());
    assert!(a.intersection(&c).is_err());
}

#[test]
fn point_queries_and_bounds_match_dense_grid() {
    let mut rng = Rng(3);
    for _ in 0..20 {
        let tree = random_tree(&mut rng, 4);
        let d = *tree.domain();
        let grid = dense(&tree);
        let mut lo = [u32::MAX; 3];
        let mut hi = [0; 3];
        for (code, &full) in grid.iter().enumerate() {
            let v = morton::decode(code as u64);
            assert_eq!(tree.contains_voxel(v), full);
            assert_eq!(tree.contains_point(d.voxel_center(v)), full);
            if full {
                for a in 0..3 {
                    lo[a] = lo[a].min(v[a]);
                    hi[a] = hi[a].max(v[a] + 1);
                }
            }
        }
        assert_eq!(tree.voxel_bounds(), (!tree.is_empty()).then_some((lo, hi)));
        assert!(!tree.contains_point(d.min() - DVec3::splat(0.1)));
    }
    // A few scattered voxels at depth 7: bounds from the list itself.
    for count in 1..40 {
        let voxels: Vec<[u32; 3]> = (0..count).map(|_| [0; 3].map(|_| rng.below(128) as u32)).collect();
        let tree = LinearOctree::from_voxels(domain(7), voxels.iter().copied()).unwrap();
        let lo = std::array::from_fn(|a| voxels.iter().map(|v| v[a]).min().unwrap());
        let hi = std::array::from_fn(|a| voxels.iter().map(|v| v[a] + 1).max().unwrap());
        assert_eq!(tree.voxel_bounds(), Some((lo, hi)), "{voxels:?}");
    }
}

#[test]
fn validate_catches_every_broken_invariant() {
    let d = domain(2);
    let ok = |keys: Vec<NodeKey>| LinearOctree::from_keys(d, keys);
    assert!(ok(vec![NodeKey::new(0, 0), NodeKey::new(8, 1)]).is_ok());
    // Out of order.
    assert!(ok(vec![NodeKey::new(8, 1), NodeKey::new(0, 0)]).is_err());
    // Overlapping.
    assert!(ok(vec![NodeKey::new(8, 1), NodeKey::new(9, 0)]).is_err());
    // Outside the domain (64 voxels at depth 2).
    assert!(ok(vec![NodeKey::new(64, 0)]).is_err());
    assert!(ok(vec![NodeKey::new(0, 3)]).is_err());
    // Eight full siblings.
    let eight: Vec<_> = (0..8).map(|i| NodeKey::new(i, 0)).collect();
    let err = ok(eight).unwrap_err();
    assert!(err.to_string().contains("eight full siblings"), "{err}");
}

#[test]
fn refine_is_exact_and_coarsen_follows_its_rule() {
    let mut rng = Rng(11);
    for _ in 0..20 {
        let tree = random_tree(&mut rng, 4);
        let fine = tree.refine(6).unwrap();
        fine.validate().unwrap();
        assert_eq!(fine.node_count(), tree.node_count());
        assert!((fine.volume() - tree.volume()).abs() < 1e-9);
        assert_eq!(fine.coarsen(4, CoarsenRule::All).unwrap(), tree);

        let grid = dense(&tree);
        for (rule, test) in [
            (CoarsenRule::Any, (|n: usize| n >= 1) as fn(usize) -> bool),
            (CoarsenRule::All, |n| n == 8),
            (CoarsenRule::Majority, |n| n >= 4),
        ] {
            let coarse = tree.coarsen(3, rule).unwrap();
            coarse.validate().unwrap();
            let want: Vec<bool> = grid.chunks(8).map(|c| test(c.iter().filter(|f| **f).count())).collect();
            assert_eq!(dense(&coarse), want, "{rule:?}");
        }
    }
    let t = LinearOctree::full(domain(3));
    assert!(t.refine(2).is_err() && t.coarsen(4, CoarsenRule::Any).is_err());
}

#[test]
fn depth_21_counts_are_exact() {
    let d = domain(21);
    let full = LinearOctree::full(d);
    assert_eq!(full.voxel_count(), 1u64 << 63);
    let one = LinearOctree::from_voxels(d, [[2_097_151, 2_097_151, 2_097_151]]).unwrap();
    let rest = &full - &one;
    rest.validate().unwrap();
    assert_eq!(rest.voxel_count(), (1u64 << 63) - 1);
    // Seven siblings at each of the 21 levels.
    assert_eq!(rest.node_count(), 7 * 21);
    assert!(rest.contains_voxel([0, 0, 0]) && !rest.contains_voxel([2_097_151; 3]));
    assert_eq!(&rest | &one, full);
}

/// The storage budget: every way of making a solid keeps exactly 8 bytes a node (the
/// key list holds no spare capacity), whatever the node count.
#[test]
fn every_constructor_keeps_exactly_eight_bytes_a_node() {
    use octsolid::octree::{VoxelizeOptions, voxelize};
    use octsolid::shape::Sphere;
    let exact = |what: &str, t: &LinearOctree| {
        let want = std::mem::size_of::<LinearOctree>() + 8 * t.node_count();
        assert_eq!(t.bytes(), want, "{what}: {} nodes", t.node_count());
    };
    let mut rng = Rng(5);
    let d = domain(5);
    let (a, b) = (random_tree(&mut rng, 5), random_tree(&mut rng, 5));
    exact("random", &a);
    exact("from_voxels", &from_dense(d, &dense(&a)));
    exact("from_nodes", &LinearOctree::from_nodes(d, a.nodes()).unwrap());
    exact("from_keys", &LinearOctree::from_keys(d, a.keys().to_vec()).unwrap());
    for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
        exact(&format!("{op:?}"), &a.combine(&b, op).unwrap());
    }
    exact("complement", &a.complement());
    exact("refine", &a.refine(7).unwrap());
    exact("coarsen", &a.coarsen(3, CoarsenRule::Majority).unwrap());
    exact("translate", &a.translate([3, -2, 5]));
    exact("mirror", &a.mirror(1));
    exact("rotate90", &a.rotate90(2, 1));
    let ball = Sphere::new(d.min() + DVec3::splat(1.5), 1.2).unwrap();
    exact("voxelize", &voxelize(&ball, domain(7), &VoxelizeOptions::default()).unwrap());
    let file = common::scratch_dir("octree", "bytes").join("solid.oct");
    octsolid::io::oct::write(&a, &file).unwrap();
    let loaded = octsolid::io::oct::read(&file, octsolid::MemoryBudget::unlimited()).unwrap();
    std::fs::remove_file(&file).unwrap();
    assert_eq!(loaded, a);
    exact("oct::read", &loaded);
    exact("empty", &LinearOctree::empty(d));
    exact("full", &LinearOctree::full(d));
}

#[test]
fn occupancy_of_a_box_matches_voxel_queries() {
    let mut rng = Rng(8086);
    for depth in [1u8, 3, 5] {
        let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
        let n = i64::from(domain.resolution());
        for _ in 0..40 {
            let tree = random_octree(&mut rng, domain);
            for _ in 0..10 {
                let size = 1 + rng.below(9) as u32;
                let lo = [0; 3].map(|_| rng.below(n as u64 + 8) as i64 - 6);
                let got = tree.occupancy(lo, size);
                let s = size as i64;
                for (i, &full) in got.iter().enumerate() {
                    let i = i as i64;
                    let v = [lo[0] + i % s, lo[1] + i / s % s, lo[2] + i / (s * s)];
                    let inside = v.iter().all(|&c| (0..n).contains(&c));
                    let want = inside && tree.contains_voxel(v.map(|c| c as u32));
                    assert_eq!(full, want, "depth {depth} box {lo:?}+{size} voxel {v:?}");
                }
            }
        }
    }
}
