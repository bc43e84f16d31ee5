//! CSG with many primitives: the pruned voxelization of CSG trees against the unpruned
//! walk and a dense grid, the k-way octree merge against pairwise folds, patterns
//! against their copies placed one by one, and a hole grid against its exact volume;
//! patterns in patterns against the unpruned walk, trees too high to recurse against
//! the same trees evaluated by recursion, and patterns of 27,000 to 100,000 copies (and
//! 200,000 nested complements) against their bounds, points and voxel counts, on the
//! test threads' stacks; nested patterns refused past the copies with the count.

mod common;

use std::f64::consts::PI;

use common::{Rng, random_octree};
use glam::{DAffine3, DQuat, DVec3};
use octsolid::Aabb;
use octsolid::morton;
use octsolid::octree::{Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
use octsolid::prelude::ShapeExt;
use octsolid::shape::{
    Axis, Class, Cone, Csg, Cuboid, Cylinder, MAX_RECURSION, Shape, ShapeSpec, Sphere, Torus, Transformed,
    linear_array, mirrored, polar_array,
};
use octsolid::{MemoryBudget, NoProgress};

fn options() -> VoxelizeOptions<'static> {
    VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress }
}

/// A CSG tree seen only as a shape, through the identity map (exact: `x + 0 y + 0 z`
/// is `x`), so it has no [`Shape::as_csg`]: what the unpruned walk voxelizes, asking
/// the whole tree at every node.
fn opaque(tree: &Csg) -> Transformed<Csg> {
    let opaque = Transformed::new(tree.clone(), DAffine3::IDENTITY).unwrap();
    assert!(opaque.as_csg().is_none() && tree.as_csg().is_some());
    opaque
}

fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

/// A random primitive in the unit cube, sometimes moved by a random affine map.
fn random_leaf(rng: &mut Rng) -> Csg {
    let c = rng.vec(-0.8, 0.8);
    let r = rng.range(0.1, 0.5);
    let axis = [Axis::X, Axis::Y, Axis::Z][rng.below(3) as usize];
    let leaf: Csg = match rng.below(5) {
        0 => Sphere::new(c, r).unwrap().into(),
        1 => Cuboid::new(c, rng.vec(0.1, 0.9)).unwrap().into(),
        2 => Cylinder::new(c, axis, r, rng.range(0.2, 1.2)).unwrap().into(),
        3 => Cone::new(c, axis, r, rng.range(0.2, 1.0)).unwrap().into(),
        _ => Torus::new(c, axis, r, 0.3 * r).unwrap().into(),
    };
    if rng.below(4) == 0 {
        let turn = DQuat::from_axis_angle(rng.vec(-1.0, 1.0).normalize_or(DVec3::Z), rng.range(0.0, PI));
        let map = DAffine3::from_scale_rotation_translation(rng.vec(0.7, 1.3), turn, rng.vec(-0.2, 0.2));
        Transformed::new(leaf, map).unwrap().into()
    } else {
        leaf
    }
}

/// A random tree of `leaves` leaves: unions, intersections, differences, symmetric
/// differences and complements, nested any way, sometimes a whole subtree moved.
fn random_tree(rng: &mut Rng, leaves: usize) -> Csg {
    if leaves == 1 {
        return random_leaf(rng);
    }
    let left = 1 + rng.below(leaves as u64 - 1) as usize;
    let (a, b) = (random_tree(rng, left), random_tree(rng, leaves - left));
    let tree = match rng.below(4) {
        0 => a | b,
        1 => a & b,
        2 => a - b,
        _ => a ^ b,
    };
    match rng.below(8) {
        0 => !tree,
        1 => tree.translate(rng.vec(-0.1, 0.1)).into(),
        _ => tree,
    }
}

#[test]
fn pruned_voxelization_is_the_unpruned_walk_on_random_trees() {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let mut rng = Rng(0x5eed_c56a);
    let mut solid = 0;
    for case in 0..60 {
        let leaves = 1 + rng.below(64) as usize;
        let tree = random_tree(&mut rng, leaves);
        let unpruned = voxelize(&opaque(&tree), domain, &options()).unwrap();
        let pruned = voxelize(&tree, domain, &options()).unwrap();
        pruned.validate().unwrap();
        assert_eq!(pruned, unpruned, "case {case}: {leaves} leaves {tree:?}");
        solid += usize::from(pruned.node_count() > 8);
    }
    // The trees are not trivial: most have a boundary to voxelize.
    assert!(solid > 30, "{solid} of 60");
}

/// A random tree of boxes and cylinders whose faces, axes and radii lie on the
/// half-voxel lattice of the depth-6 domain over [-1, 1]^3: faces on voxel
/// boundaries and through voxel centres, where rounding decides.
fn lattice_tree(rng: &mut Rng, leaves: usize) -> Csg {
    let snap = |x: f64| (x * 64.0).round() / 64.0;
    let mut tree: Option<Csg> = None;
    for _ in 0..leaves {
        let c = rng.vec(-0.8, 0.8).map(snap);
        let leaf: Csg = if rng.below(2) == 0 {
            Cuboid::new(c, rng.vec(0.1, 0.9).map(snap)).unwrap().into()
        } else {
            let axis = [Axis::X, Axis::Y, Axis::Z][rng.below(3) as usize];
            Cylinder::new(c, axis, snap(rng.range(0.1, 0.5)), snap(rng.range(0.2, 1.2))).unwrap().into()
        };
        tree = Some(match (tree, rng.below(3)) {
            (None, _) => leaf,
            (Some(t), 0) => t | leaf,
            (Some(t), 1) => t - leaf,
            (Some(t), _) => t & !leaf,
        });
    }
    tree.expect("at least one leaf")
}

#[test]
fn pruned_voxelization_is_the_unpruned_walk_with_faces_on_the_lattice() {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let mut rng = Rng(0x1a77_1ce5);
    for case in 0..40 {
        let leaves = 1 + rng.below(24) as usize;
        let tree = lattice_tree(&mut rng, leaves);
        let unpruned = voxelize(&opaque(&tree), domain, &options()).unwrap();
        assert_eq!(voxelize(&tree, domain, &options()).unwrap(), unpruned, "case {case}: {tree:?}");
    }
}

#[test]
fn pruned_voxelization_matches_a_dense_grid_and_any_thread_count() {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
    let mut rng = Rng(0xdead_beef_0017);
    for case in 0..20 {
        let leaves = 8 + rng.below(40) as usize;
        let tree = random_tree(&mut rng, leaves);
        // Oracle: every voxel decided by its centre.
        let n = domain.resolution();
        let voxels = (0..domain.voxel_total()).map(morton::decode).filter(|&v| tree.contains(domain.voxel_center(v)));
        let want = LinearOctree::from_voxels(domain, voxels).unwrap();
        assert_eq!(want.domain().resolution(), n);
        for threads in [1, 2] {
            let got = on_threads(threads, || voxelize(&tree, domain, &options()).unwrap());
            assert_eq!(got, want, "case {case} on {threads} threads");
        }
    }
}

/// The left fold of the binary operation over the operands.
fn pairwise(operands: &[&LinearOctree], op: SetOp) -> LinearOctree {
    operands[1..].iter().fold(operands[0].clone(), |acc, t| acc.combine(t, op).unwrap())
}

#[test]
fn k_way_merge_is_the_pairwise_fold_for_every_operator() {
    let domain = Domain::new(DVec3::ZERO, 1.0, 5).unwrap();
    let mut rng = Rng(0x00c0_ffee);
    for case in 0..40 {
        let k = 1 + rng.below(9) as usize;
        let trees: Vec<LinearOctree> = (0..k).map(|_| random_octree(&mut rng, domain)).collect();
        let refs: Vec<&LinearOctree> = trees.iter().collect();
        for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
            let merged = LinearOctree::combine_all(&refs, op).unwrap();
            merged.validate().unwrap();
            assert_eq!(merged, pairwise(&refs, op), "case {case}: {op:?} of {k}");
        }
        // Dense oracle: each voxel by how many operands hold it (and whether the first does).
        for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
            let holds = |v: [u32; 3]| {
                let count = trees.iter().filter(|t| t.contains_voxel(v)).count();
                match op {
                    SetOp::Union => count > 0,
                    SetOp::Intersection => count == k,
                    SetOp::Difference => trees[0].contains_voxel(v) && count == 1,
                    SetOp::SymmetricDifference => count % 2 == 1,
                }
            };
            let want =
                LinearOctree::from_voxels(domain, (0..domain.voxel_total()).map(morton::decode).filter(|&v| holds(v)));
            assert_eq!(LinearOctree::combine_all(&refs, op).unwrap(), want.unwrap(), "case {case}: {op:?} of {k}");
        }
    }
    assert!(LinearOctree::combine_all(&[], SetOp::Union).is_err());
    let other = LinearOctree::empty(Domain::new(DVec3::ZERO, 1.0, 4).unwrap());
    let one = LinearOctree::full(domain);
    assert!(LinearOctree::combine_all(&[&one, &other], SetOp::Union).is_err());
}

#[test]
fn large_merges_split_over_morton_ranges_give_the_same_keys_on_one_and_two_threads() {
    // Spheres at depth 9 have tens of thousands of nodes: the merge runs in chunks.
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 9).unwrap();
    let spheres: Vec<LinearOctree> = [(-0.3, 0.7), (0.25, 0.6), (0.0, 0.45), (0.5, 0.3)]
        .iter()
        .map(|&(x, r)| voxelize(&Sphere::new(DVec3::new(x, 0.1 * x, 0.0), r).unwrap(), domain, &options()).unwrap())
        .collect();
    assert!(spheres[0].node_count() > 1 << 15, "{}", spheres[0].node_count());
    let whole = voxelize(&Cuboid::new(DVec3::ZERO, DVec3::splat(2.0)).unwrap(), domain, &options()).unwrap();
    for operands in [&spheres[..2], &spheres[..], &[spheres[0].clone(), whole][..]] {
        let refs: Vec<&LinearOctree> = operands.iter().collect();
        for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
            let one = on_threads(1, || LinearOctree::combine_all(&refs, op).unwrap());
            let two = on_threads(2, || LinearOctree::combine_all(&refs, op).unwrap());
            two.validate().unwrap();
            assert_eq!(one, two, "{op:?} of {}", refs.len());
            // The fold on one thread runs each binary merge as one sweep.
            assert_eq!(two, on_threads(1, || pairwise(&refs, op)), "{op:?} of {}", refs.len());
        }
    }
}

#[test]
fn patterns_are_their_copies_placed_one_by_one() {
    let domain = Domain::new(DVec3::new(-6.0, -6.0, -6.0), 12.0, 7).unwrap();
    let peg = Cylinder::new(DVec3::new(-4.0, -4.0, 0.0), Axis::Z, 0.6, 2.0).unwrap();
    let step = DVec3::new(2.5, 2.0, 0.0);
    let grid = linear_array(peg.clone(), [4, 5, 1], step).unwrap();
    let mut by_hand: Csg = peg.clone().into();
    for j in 0..5 {
        for i in 0..4 {
            if (i, j) != (0, 0) {
                by_hand = by_hand | peg.clone().translate(DVec3::new(f64::from(i), f64::from(j), 0.0) * step);
            }
        }
    }
    let got = voxelize(&grid, domain, &options()).unwrap();
    assert_eq!(got, voxelize(&opaque(&by_hand), domain, &options()).unwrap());
    // Twenty disjoint pegs of 6.4 voxels radius, as tall as their digitized height:
    // twenty pegs' volume up to the digitization of their circles.
    let exact = 20.0 * PI * 0.36 * digitized(domain, -1.0, 1.0);
    assert!((got.volume() / exact - 1.0).abs() < 0.05, "{} vs {exact}", got.volume());

    let bolt = Cylinder::new(DVec3::new(4.0, 0.0, 0.0), Axis::Z, 0.5, 1.0).unwrap();
    let centre = DVec3::new(0.5, 0.0, 0.0);
    let circle = polar_array(bolt.clone(), Axis::Z, centre, 8, None).unwrap();
    let mut by_hand: Csg = bolt.clone().into();
    for i in 1..8 {
        let turn = DQuat::from_axis_angle(DVec3::Z, (45.0 * f64::from(i)).to_radians());
        let map = DAffine3::from_translation(centre) * DAffine3::from_quat(turn) * DAffine3::from_translation(-centre);
        by_hand = by_hand | Transformed::new(bolt.clone(), map).unwrap();
    }
    let got = voxelize(&circle, domain, &options()).unwrap();
    assert_eq!(got, voxelize(&opaque(&by_hand), domain, &options()).unwrap());
    let exact = 8.0 * PI * 0.25 * digitized(domain, -0.5, 0.5);
    assert!((got.volume() / exact - 1.0).abs() < 0.05, "{} vs {exact}", got.volume());
    let pair = mirrored(bolt.clone(), DVec3::X, centre).unwrap();
    let mirror_image = Cylinder::new(DVec3::new(-3.0, 0.0, 0.0), Axis::Z, 0.5, 1.0).unwrap();
    let got = voxelize(&pair, domain, &options()).unwrap();
    // The reflection of a cylinder is the cylinder at the reflected centre, voxelized
    // on a lattice that is not symmetric about the plane: equal volumes up to digitization.
    let want = voxelize(&(Csg::from(bolt) | mirror_image), domain, &options()).unwrap();
    let diff = got.combine(&want, SetOp::SymmetricDifference).unwrap();
    assert!(diff.voxel_count() * 50 < want.voxel_count(), "{} of {}", diff.voxel_count(), want.voxel_count());
}

/// The length of `[lo, hi]` along z on the domain's lattice: its voxel layers whose
/// centres lie in it, times the voxel size.
fn digitized(domain: Domain, lo: f64, hi: f64) -> f64 {
    let layers = (0..domain.resolution()).filter(|&k| (lo..=hi).contains(&domain.voxel_center([0, 0, k]).z));
    layers.count() as f64 * domain.voxel_size()
}

/// The plate: 200 x 200 x 10 minus a 20 x 20 grid of through-holes of radius 3
/// at (5 + 10i, 5 + 10j), in a domain of 204.8 whose lattice puts the plate's faces on
/// voxel boundaries.
fn plate(depth: u8) -> (Csg, Domain) {
    let plate = Cuboid::from_corners(DVec3::ZERO, DVec3::new(200.0, 200.0, 10.0)).unwrap();
    let hole = Cylinder::new(DVec3::new(5.0, 5.0, 5.0), Axis::Z, 3.0, 12.0).unwrap();
    let tree = plate - linear_array(hole, [20, 20, 1], DVec3::new(10.0, 10.0, 0.0)).unwrap();
    (tree, Domain::new(DVec3::new(-2.4, -2.4, -97.2), 204.8, depth).unwrap())
}

#[test]
fn a_hole_grid_has_the_plate_minus_the_holes_volume_and_equals_the_octree_difference() {
    let (tree, domain) = plate(9);
    let got = voxelize(&tree, domain, &options()).unwrap();
    let exact = 400_000.0 - 3600.0 * PI * 10.0;
    // The faces on voxel boundaries, holes of 7.5 voxels radius: the plate is the
    // analytic volume within the digitization of the circles (0.6% at 15 voxels).
    assert!((got.volume() / exact - 1.0).abs() < 0.015, "{} vs {exact}", got.volume());
    // The same solid as the octree CSG of the 401 shapes voxelized one by one.
    let slab =
        voxelize(&Cuboid::from_corners(DVec3::ZERO, DVec3::new(200.0, 200.0, 10.0)).unwrap(), domain, &options());
    let mut operands = vec![slab.unwrap()];
    for j in 0..20 {
        for i in 0..20 {
            let c = DVec3::new(5.0, 5.0, 5.0);
            let hole = Cylinder::new(c, Axis::Z, 3.0, 12.0).unwrap();
            let offset = DVec3::new(f64::from(i), f64::from(j), 0.0) * DVec3::new(10.0, 10.0, 0.0);
            let placed: Csg = if (i, j) == (0, 0) { hole.into() } else { hole.translate(offset).into() };
            operands.push(voxelize(&placed, domain, &options()).unwrap());
        }
    }
    let refs: Vec<&LinearOctree> = operands.iter().collect();
    assert_eq!(LinearOctree::combine_all(&refs, SetOp::Difference).unwrap(), got);
}

#[test]
fn scene_pattern_nodes_build_the_library_patterns() {
    #[derive(serde::Deserialize)]
    struct Doc {
        shape: ShapeSpec,
    }
    let read = |text: &str| toml::from_str::<Doc>(text).map(|d| d.shape);
    let peg = "{ cylinder = { center = [-4, -4, 0], axis = \"z\", radius = 0.6, height = 2 } }";
    let domain = Domain::new(DVec3::new(-6.0, -6.0, -6.0), 12.0, 6).unwrap();
    let voxels = |tree: &Csg| voxelize(tree, domain, &options()).unwrap();
    let peg_shape = || Cylinder::new(DVec3::new(-4.0, -4.0, 0.0), Axis::Z, 0.6, 2.0).unwrap();

    let array = read(&format!("shape = {{ array = {{ shape = {peg}, count = [3, 4, 1], step = [3, 2.5, 0] }} }}"));
    let want = linear_array(peg_shape(), [3, 4, 1], DVec3::new(3.0, 2.5, 0.0)).unwrap();
    assert_eq!(voxels(&array.unwrap().build().unwrap()), voxels(&want));

    let polar = read(&format!(
        "shape = {{ polar = {{ shape = {peg}, count = 5, axis = \"z\", center = [1, 0, 0], step_degrees = 30 }} }}"
    ));
    let want = polar_array(peg_shape(), Axis::Z, DVec3::X, 5, Some(30.0)).unwrap();
    assert_eq!(voxels(&polar.unwrap().build().unwrap()), voxels(&want));

    let mirror = read(&format!("shape = {{ mirror = {{ shape = {peg}, normal = [1, 1, 0] }} }}"));
    let want = mirrored(peg_shape(), DVec3::new(1.0, 1.0, 0.0), DVec3::ZERO).unwrap();
    let got = voxels(&mirror.unwrap().build().unwrap());
    assert_eq!(got, voxels(&want));
    // The plane x + y = 0 maps the peg at (-4, -4) to (4, 4): two pegs, one each side.
    assert!(got.contains_point(DVec3::new(-4.0, -4.0, 0.0)) && got.contains_point(DVec3::new(4.0, 4.0, 0.0)));

    // Refused where they are read, with the constructor's reason.
    let e = read(&format!("shape = {{ array = {{ shape = {peg}, count = [3, 0, 1], step = [1, 1, 1] }} }}"));
    assert!(e.unwrap_err().to_string().contains("0 copies"));
    let e = read(&format!("shape = {{ mirror = {{ shape = {peg}, normal = [0, 0, 0] }} }}"));
    assert!(e.unwrap_err().to_string().contains("non-zero"));
}

/// A random tree of at most `leaves` leaves whose nodes may be patterns (a linear
/// array, a polar array, a mirror, a move) of random subtrees, nested in each other.
fn random_patterned_tree(rng: &mut Rng, leaves: usize) -> Csg {
    let size = 1 + rng.below(leaves as u64) as usize;
    let tree = random_tree(rng, size);
    let tree = match rng.below(5) {
        0 => linear_array(tree, [2, 1 + rng.below(3) as u32, 1], rng.vec(-0.4, 0.4)).unwrap(),
        1 => polar_array(tree, Axis::Y, rng.vec(-0.2, 0.2), 1 + rng.below(5) as u32, None).unwrap(),
        2 => mirrored(tree, rng.vec(-1.0, 1.0), rng.vec(-0.2, 0.2)).unwrap(),
        3 => tree.rotate(DVec3::Z, rng.range(0.0, PI)).into(),
        _ => tree,
    };
    if leaves > 2 && rng.below(2) == 0 {
        let other = random_patterned_tree(rng, leaves / 2);
        match rng.below(3) {
            0 => tree | other,
            1 => tree - other,
            _ => linear_array(tree ^ other, [1, 1, 2], rng.vec(-0.3, 0.3)).unwrap(),
        }
    } else {
        tree
    }
}

/// `tree`, united with a leaf outside `[-1, 1]^3` under `2 * pairs` complements: the
/// same solid in the domain, in a tree higher than the recursion bound, which is
/// evaluated by the fold on the heap and voxelized as one leaf.
fn too_deep_to_recurse(tree: &Csg, pairs: usize) -> Csg {
    let mut far: Csg = Sphere::new(DVec3::splat(10.0), 1.0).unwrap().into();
    for _ in 0..2 * pairs {
        far = !far;
    }
    let deep = tree.clone() | far;
    assert!(deep.height() > MAX_RECURSION, "{}", deep.height());
    deep
}

#[test]
fn patterns_in_patterns_voxelize_as_the_unpruned_walk_and_the_heap_fold_answers_as_recursion() {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
    let mut rng = Rng(0x9a77_e125);
    for case in 0..30 {
        let tree = random_patterned_tree(&mut rng, 12);
        let unpruned = voxelize(&opaque(&tree), domain, &options()).unwrap();
        let pruned = voxelize(&tree, domain, &options()).unwrap();
        assert_eq!(pruned, unpruned, "case {case}: {tree:?}");
        let deep = too_deep_to_recurse(&tree, 150);
        assert_eq!(voxelize(&deep, domain, &options()).unwrap(), pruned, "case {case}: deep");
        for _ in 0..200 {
            let p = rng.vec(-1.0, 1.0);
            assert_eq!(deep.contains(p), tree.contains(p), "case {case} at {p}");
            let b = Aabb::from_center_half(p, rng.vec(0.0, 0.3));
            assert_eq!(deep.classify(&b), tree.classify(&b), "case {case} in {b:?}");
            if let Some(s) = tree.surface(p) {
                // The far leaf is at least 15 away: the union keeps the tree's surface.
                assert_eq!(deep.surface(p), Some(s), "case {case} at {p}");
            }
        }
    }
}

#[test]
fn a_linear_array_of_45000_copies_has_its_bounds_and_its_voxels() {
    // A cube of edge 0.6 in each unit cell (i, j, 0): on the lattice of voxels of 0.5
    // from the origin, eight voxel centres a cube.
    let cube = Cuboid::new(DVec3::splat(0.5), DVec3::splat(0.6)).unwrap();
    let grid = linear_array(cube, [300, 150, 1], DVec3::new(1.0, 1.0, 0.0)).unwrap();
    let b = grid.bounds().unwrap();
    let want = Aabb::new(DVec3::splat(0.2), DVec3::new(299.8, 149.8, 0.8));
    assert!(b.min.abs_diff_eq(want.min, 1e-9) && b.max.abs_diff_eq(want.max, 1e-9), "{b:?}");
    assert!(grid.contains(DVec3::new(299.5, 149.5, 0.5)) && !grid.contains(DVec3::new(150.0, 75.0, 0.5)));
    let domain = Domain::new(DVec3::ZERO, 512.0, 10).unwrap();
    let voxels = voxelize(&grid, domain, &options()).unwrap();
    assert_eq!(voxels.voxel_count(), 45_000 * 8);
}

#[test]
fn a_polar_array_of_100000_copies_has_its_bounds_and_its_points() {
    let ball = Sphere::new(DVec3::new(1000.0, 0.0, 0.0), 0.01).unwrap();
    let ring = polar_array(ball, Axis::Z, DVec3::ZERO, 100_000, None).unwrap();
    let b = ring.bounds().unwrap();
    let want = Aabb::new(DVec3::new(-1000.01, -1000.01, -0.01), DVec3::new(1000.01, 1000.01, 0.01));
    assert!(b.min.abs_diff_eq(want.min, 1e-6) && b.max.abs_diff_eq(want.max, 1e-6), "{b:?}");
    // Copy k's centre is inside; halfway to copy k + 1 (3.1 apart from each) is not.
    for k in [0.0, 1.0, 12_345.0, 99_999.0] {
        let at = |turns: f64| {
            let angle = (turns * 360.0 / 100_000.0).to_radians();
            DVec3::new(1000.0 * angle.cos(), 1000.0 * angle.sin(), 0.0)
        };
        assert!(ring.contains(at(k)) && !ring.contains(at(k + 0.5)), "copy {k}");
    }
}

#[test]
fn a_transformed_array_of_27000_copies_answers_on_a_small_stack() {
    let ball = Sphere::new(DVec3::splat(0.5), 0.3).unwrap();
    let grid = linear_array(ball, [30, 30, 30], DVec3::ONE).unwrap();
    let turn = DQuat::from_axis_angle(DVec3::Z, 0.3);
    let turned: Csg = grid.rotate(DVec3::Z, 0.3).into();
    // A render worker's stack is smaller than the main thread's: 256 KiB here.
    let worker = std::thread::Builder::new().stack_size(256 << 10);
    let answers = worker
        .spawn(move || {
            let centre = turn * DVec3::new(29.5, 0.5, 17.5);
            let corner = turn * DVec3::new(29.0, 1.0, 17.0);
            (turned.contains(centre), turned.contains(corner), turned.surface(centre).map(|s| s.distance))
        })
        .unwrap()
        .join()
        .unwrap();
    assert!(answers.0 && !answers.1, "{answers:?}");
    assert!((answers.2.unwrap() + 0.3).abs() < 1e-9, "{answers:?}");
}

#[test]
fn nested_patterns_multiply_and_are_refused_past_the_copies() {
    let ball = || Sphere::new(DVec3::splat(0.5), 0.3).unwrap();
    let row = linear_array(ball(), [100, 1, 1], DVec3::X).unwrap();
    let square = linear_array(row, [1, 100, 1], DVec3::Y).unwrap();
    let e = linear_array(square.clone(), [1, 1, 100], DVec3::Z).unwrap_err().to_string();
    assert!(e.contains("1000000 copies"), "{e}");
    let e = polar_array(square.clone(), Axis::Z, DVec3::ZERO, 11, None).unwrap_err().to_string();
    assert!(e.contains("110000 copies"), "{e}");
    assert!(polar_array(square, Axis::Z, DVec3::ZERO, 10, None).is_ok());
    // Mirrors double: the 17th of 30 nested makes 2^17 = 131072 copies.
    let mut tree: Csg = ball().into();
    for i in 1..=30 {
        match mirrored(tree.clone(), DVec3::new(f64::from(i), 1.0, 0.0), DVec3::ZERO) {
            Ok(more) => tree = more,
            Err(e) => {
                assert_eq!(i, 17, "{e}");
                assert!(e.to_string().contains("131072 copies"), "{e}");
                return;
            }
        }
    }
    panic!("30 nested mirrors were accepted");
}

#[test]
fn a_tree_of_200000_nested_complements_is_asked_printed_and_dropped_without_recursion() {
    let mut tree: Csg = Sphere::new(DVec3::ZERO, 1.0).unwrap().into();
    for _ in 0..200_001 {
        tree = !tree;
    }
    // An odd number of complements: the outside of the ball.
    assert!(!tree.contains(DVec3::ZERO) && tree.contains(DVec3::splat(2.0)));
    assert_eq!(tree.classify(&Aabb::from_center_half(DVec3::ZERO, DVec3::splat(0.1))), Class::Outside);
    assert_eq!(tree.bounds(), None);
    assert_eq!(format!("{tree:?}"), format!("{}Leaf", "!".repeat(200_001)));
    drop(tree);
}
