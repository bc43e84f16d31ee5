//! Octree transforms against a dense-grid oracle (a `Vec<bool>` of every voxel, moved
//! voxel by voxel), and resampling against the exact transforms, a point-sampling
//! oracle and analytic volumes.

use std::f64::consts::PI;

use glam::{DAffine3, DMat3, DQuat, DVec3};
use octsolid::octree::{Domain, Fit, LinearOctree, Motion, Node, Turn, VoxelizeOptions, common_domain, voxelize};
use octsolid::shape::{Axis, Class, Cuboid, ShapeExt};

mod common;

use common::Rng;

/// A domain not centred on the origin, so rotations about "the centre" are tested
/// with a real centre.
fn domain(depth: u8) -> Domain {
    Domain::new(DVec3::new(-1.5, 0.25, 2.0), 2.0, depth).unwrap()
}

/// The oracle: one bool a voxel, index `x + n (y + n z)`.
#[derive(Clone, Debug, PartialEq)]
struct Grid {
    n: i64,
    cells: Vec<bool>,
}

impl Grid {
    fn empty(n: u32) -> Grid {
        Grid { n: i64::from(n), cells: vec![false; (n as usize).pow(3)] }
    }

    fn index(&self, v: [i64; 3]) -> Option<usize> {
        v.iter().all(|c| (0..self.n).contains(c)).then(|| (v[0] + self.n * (v[1] + self.n * v[2])) as usize)
    }

    fn get(&self, v: [i64; 3]) -> bool {
        self.index(v).is_some_and(|i| self.cells[i])
    }

    fn set(&mut self, v: [i64; 3]) {
        let i = self.index(v).expect("voxel inside");
        self.cells[i] = true;
    }

    fn voxels(&self) -> impl Iterator<Item = [i64; 3]> + '_ {
        let n = self.n;
        (0..n).flat_map(move |z| (0..n).flat_map(move |y| (0..n).map(move |x| [x, y, z])))
    }

    fn full(&self) -> impl Iterator<Item = [i64; 3]> + '_ {
        self.voxels().filter(|&v| self.get(v))
    }

    /// Voxel by voxel: `v` goes to `f(v)`; what lands outside is dropped.
    fn map(&self, f: impl Fn([i64; 3]) -> [i64; 3]) -> Grid {
        let mut out = Grid { n: self.n, cells: vec![false; self.cells.len()] };
        for v in self.full() {
            let w = f(v);
            if out.index(w).is_some() {
                out.set(w);
            }
        }
        out
    }

    /// The grid of an octree, read node by node.
    fn of(tree: &LinearOctree) -> Grid {
        let mut g = Grid::empty(tree.domain().resolution());
        for node in tree.nodes() {
            let s = node.size;
            for dz in 0..s {
                for dy in 0..s {
                    for dx in 0..s {
                        g.set([node.min[0] + dx, node.min[1] + dy, node.min[2] + dz].map(i64::from));
                    }
                }
            }
        }
        g
    }
}

/// A random solid and its grid, built independently: scattered voxels
/// (`from_voxels`), a union of aligned nodes (`from_nodes`), or both.
fn random_solid(rng: &mut Rng, depth: u8) -> (LinearOctree, Grid) {
    let d = domain(depth);
    let n = d.resolution();
    let mut grid = Grid::empty(n);
    let kind = rng.below(3);
    let mut voxels = Vec::new();
    if kind != 1 {
        let count = rng.below(u64::from(n).pow(3) / 2);
        for _ in 0..count {
            let v = [0; 3].map(|_| rng.below(u64::from(n)) as u32);
            grid.set(v.map(i64::from));
            voxels.push(v);
        }
    }
    let mut nodes = Vec::new();
    if kind != 0 {
        for _ in 0..1 + rng.below(30) {
            let k = rng.below(u64::from(depth)) as u32;
            let min = [0; 3].map(|_| (rng.below(u64::from(n >> k)) as u32) << k);
            let node = Node { level: depth - k as u8, min, size: 1 << k };
            for v in Grid::of(&LinearOctree::from_nodes(d, [node]).unwrap()).full() {
                grid.set(v);
            }
            nodes.push(node);
        }
    }
    let tree =
        LinearOctree::from_voxels(d, voxels).unwrap().union(&LinearOctree::from_nodes(d, nodes).unwrap()).unwrap();
    tree.validate().unwrap();
    assert_eq!(Grid::of(&tree), grid);
    (tree, grid)
}

/// Checks the invariants and the voxels against the oracle.
fn check(got: &LinearOctree, want: &Grid, what: &str) {
    got.validate().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(Grid::of(got), *want, "{what}");
}

/// One right-handed quarter turn about `axis`, voxel by voxel, spelled out per axis.
fn quarter_turn(axis: usize, n: i64, [x, y, z]: [i64; 3]) -> [i64; 3] {
    match axis {
        0 => [x, n - 1 - z, y],
        1 => [z, y, n - 1 - x],
        _ => [n - 1 - y, x, z],
    }
}

fn opts() -> VoxelizeOptions<'static> {
    VoxelizeOptions::default()
}

/// The world map that turns by `turns` quarter turns about `axis` through the centre of `d`.
fn turn_about_centre(d: &Domain, axis: usize, turns: i32) -> DAffine3 {
    let c = d.aabb().center();
    let rot = DQuat::from_axis_angle(DVec3::AXES[axis], f64::from(turns) * PI / 2.0);
    DAffine3::from_translation(c) * DAffine3::from_quat(rot) * DAffine3::from_translation(-c)
}

#[test]
fn translate_matches_dense_grid() {
    let mut rng = Rng(21);
    for depth in 3..=5 {
        for round in 0..12 {
            let (tree, grid) = random_solid(&mut rng, depth);
            let n = i64::from(tree.domain().resolution());
            let mut offsets = vec![
                [0, 0, 0],
                [1, 0, 0],
                [0, -1, 0],
                [n, 0, 0],
                [0, 0, -n],
                [n - 1, 1 - n, 0],
                [i64::MAX, 0, 0],
                [0, i64::MIN, 3],
                // Multiples of node sizes: nodes move whole.
                [4, -8, 2],
                [2, -6, 4],
                [8, 8, -8],
                [n / 2, n / 2, -n / 2],
                [n / 4, 3, -n / 2],
            ];
            for _ in 0..8 {
                // Positive, negative and beyond the domain.
                offsets.push([0; 3].map(|_| rng.below(3 * n as u64 + 1) as i64 - (3 * n) / 2));
            }
            if round == 0 {
                for _ in 0..4 {
                    offsets.push([0; 3].map(|_| rng.below(2 * n as u64) as i64 - n));
                }
            }
            for offset in offsets {
                let got = tree.translate(offset);
                let want = grid.map(|v| std::array::from_fn(|a| v[a].saturating_add(offset[a])));
                check(&got, &want, &format!("depth {depth} offset {offset:?}"));
            }
            // Back and forth keeps exactly what stayed inside.
            let o = [2, -3, 1];
            let kept = grid.map(|v| std::array::from_fn(|a| v[a] + o[a])).map(|v| std::array::from_fn(|a| v[a] - o[a]));
            check(&tree.translate(o).translate([-2, 3, -1]), &kept, "round trip");
        }
    }
}

#[test]
fn translate_deeper_solids_and_extremes() {
    let mut rng = Rng(4);
    let d = domain(6);
    let n = 64;
    for round in 0..6 {
        // Mostly big nodes: the pull has to split them at every alignment.
        let tree = common::random_octree(&mut rng, d);
        let grid = Grid::of(&tree);
        for offset in [[1, 2, 3], [-5, 17, 0], [32, -16, 8], [6, -12, 20], [63, -63, 1]] {
            let got = tree.translate(offset);
            check(&got, &grid.map(|v| std::array::from_fn(|a| v[a] + offset[a])), &format!("{round} {offset:?}"));
            // Two moves are one move when nothing leaves the domain in between.
            let (a, b) = ([offset[0] / 2, 0, offset[2]], [offset[0] - offset[0] / 2, offset[1], 0]);
            let inner = tree.translate(a);
            if inner.voxel_count() == tree.voxel_count() {
                assert_eq!(inner.translate(b), got, "{a:?} then {b:?}");
            }
        }
    }
    // The whole domain, the empty solid, a single voxel to every corner.
    let full = LinearOctree::full(d);
    let want = Grid::of(&full).map(|v| [v[0] + 3, v[1] - 1, v[2] + 40]);
    check(&full.translate([3, -1, 40]), &want, "full");
    assert!(LinearOctree::empty(d).translate([1, 1, 1]).is_empty());
    let one = LinearOctree::from_voxels(d, [[0, 0, 0]]).unwrap();
    for c in [[63, 0, 0], [0, 63, 63], [63, 63, 63]] {
        let at = LinearOctree::from_voxels(d, [c]).unwrap();
        assert_eq!(one.translate(c.map(i64::from)), at);
        assert_eq!(at.translate(c.map(|c| -i64::from(c))), one);
    }
    assert_eq!(n, i64::from(d.resolution()));
}

#[test]
fn mirrors_match_dense_grid() {
    let mut rng = Rng(8);
    for depth in 3..=5 {
        for _ in 0..10 {
            let (tree, grid) = random_solid(&mut rng, depth);
            let n = grid.n;
            for axis in 0..3 {
                let m = tree.mirror(axis);
                let want = grid.map(|mut v| {
                    v[axis] = n - 1 - v[axis];
                    v
                });
                check(&m, &want, &format!("mirror {axis}"));
                assert_eq!(m.node_count(), tree.node_count());
                assert_eq!(m.mirror(axis), tree, "mirror twice");
            }
        }
    }
}

#[test]
fn quarter_turns_match_dense_grid() {
    let mut rng = Rng(9);
    for depth in 3..=5 {
        for _ in 0..10 {
            let (tree, grid) = random_solid(&mut rng, depth);
            let n = grid.n;
            for axis in 0..3 {
                for turns in [1, 2, 3, -1, -2, -3, 4, 5, -4, 7] {
                    let got = tree.rotate90(axis, turns);
                    let want = grid.map(|mut v| {
                        for _ in 0..turns.rem_euclid(4) {
                            v = quarter_turn(axis, n, v);
                        }
                        v
                    });
                    check(&got, &want, &format!("axis {axis} turns {turns}"));
                    assert_eq!(got.node_count(), tree.node_count());
                }
                // Four single quarter turns are the identity; -1 undoes +1.
                let once = tree.rotate90(axis, 1);
                assert_eq!(once.rotate90(axis, 1).rotate90(axis, 1).rotate90(axis, 1), tree);
                assert_eq!(once.rotate90(axis, -1), tree);
                assert_eq!(tree.rotate90(axis, 0), tree);
            }
        }
    }
    // +90 about z takes +x to +y: voxel (x, y, z) -> (N - 1 - y, x, z).
    let d = domain(3);
    let one = LinearOctree::from_voxels(d, [[6, 1, 2]]).unwrap();
    assert_eq!(one.rotate90(2, 1), LinearOctree::from_voxels(d, [[6, 6, 2]]).unwrap());
    // About x, +y goes to +z; about y, +z goes to +x.
    assert_eq!(one.rotate90(0, 1), LinearOctree::from_voxels(d, [[6, 5, 1]]).unwrap());
    assert_eq!(one.rotate90(1, 1), LinearOctree::from_voxels(d, [[2, 1, 1]]).unwrap());
}

#[test]
fn classify_voxel_box_matches_brute_force() {
    let mut rng = Rng(5);
    for depth in 3..=5 {
        for _ in 0..20 {
            let (tree, grid) = random_solid(&mut rng, depth);
            let n = tree.domain().resolution();
            let mut boxes =
                vec![([0; 3], [n; 3]), ([0; 3], [u32::MAX; 3]), ([3, 1, 1], [3, 5, 5]), ([n; 3], [n + 4; 3])];
            for _ in 0..60 {
                let lo = [0; 3].map(|_| rng.below(u64::from(n)) as u32);
                // Small boxes, large boxes, and some that run past the domain.
                let reach = if rng.below(2) == 0 { 3 } else { n + 2 };
                let hi: [u32; 3] = std::array::from_fn(|a| lo[a] + 1 + rng.below(u64::from(reach)) as u32);
                boxes.push((lo, hi));
            }
            // Every node of the tree, and its one-voxel neighbourhood.
            for node in tree.nodes().take(20) {
                let hi = node.min.map(|c| c + node.size);
                boxes.push((node.min, hi));
                boxes.push((node.min.map(|c| c.saturating_sub(1)), hi.map(|c| c + 1)));
            }
            for (lo, hi) in boxes {
                let (mut full, mut total) = (0u64, 0u64);
                for x in lo[0]..hi[0].min(n) {
                    for y in lo[1]..hi[1].min(n) {
                        for z in lo[2]..hi[2].min(n) {
                            total += 1;
                            full += u64::from(grid.get([x, y, z].map(i64::from)));
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
}

#[test]
fn resample_agrees_with_exact_transforms() {
    let mut rng = Rng(77);
    for depth in 3..=5 {
        for _ in 0..6 {
            let (tree, _) = random_solid(&mut rng, depth);
            let d = *tree.domain();
            let n = i64::from(d.resolution());
            let h = d.voxel_size();
            // Identity into the same domain gives back the same octree.
            assert_eq!(tree.resample_to(d, &opts()).unwrap(), tree);
            assert_eq!(tree.resample(DAffine3::IDENTITY, d, &opts()).unwrap(), tree);
            // Whole-voxel translations, also partly out of the domain.
            for _ in 0..3 {
                let o = [0; 3].map(|_| rng.below(n as u64) as i64 - n / 2);
                let shift = DVec3::new(o[0] as f64, o[1] as f64, o[2] as f64) * h;
                let moved = tree.resample(DAffine3::from_translation(shift), d, &opts()).unwrap();
                assert_eq!(moved, tree.translate(o), "offset {o:?}");
                // The same move as a target domain shifted the other way.
                let target = Domain::new(d.min() - shift, d.edge(), d.depth()).unwrap();
                let seen = tree.resample_to(target, &opts()).unwrap();
                assert_eq!(seen.keys(), tree.translate(o).keys(), "target moved by {o:?}");
            }
            // Quarter turns and mirrors about the domain's centre.
            for axis in 0..3 {
                for turns in [1, 2, 3, -1] {
                    let got = tree.resample(turn_about_centre(&d, axis, turns), d, &opts()).unwrap();
                    assert_eq!(got, tree.rotate90(axis, turns), "axis {axis} turns {turns}");
                }
                let c = d.aabb().center();
                let mut scale = DVec3::ONE;
                scale[axis] = -1.0;
                let flip = DAffine3::from_translation(c) * DAffine3::from_scale(scale) * DAffine3::from_translation(-c);
                assert_eq!(tree.resample(flip, d, &opts()).unwrap(), tree.mirror(axis), "mirror {axis}");
            }
            // Into a finer domain: the refinement.
            let finer = tree.resample_to(d.with_depth(depth + 1).unwrap(), &opts()).unwrap();
            assert_eq!(finer, tree.refine(depth + 1).unwrap());
        }
    }
}

#[test]
fn resample_matches_point_sampling_oracle() {
    // Any affine map, any target: each target voxel is full iff the preimage of its
    // centre lies in a full source voxel. An unsound box classification would show
    // up here as a wrong voxel.
    let mut rng = Rng(31);
    for round in 0..24 {
        let depth = 3 + (round % 3) as u8;
        let (tree, _) = random_solid(&mut rng, depth);
        let d = *tree.domain();
        let rot = DQuat::from_axis_angle(rng.vec(-1.0, 1.0).normalize(), rng.range(-PI, PI));
        let linear = DMat3::from_quat(rot) * DMat3::from_diagonal(rng.vec(0.6, 1.4));
        let shear = if round % 2 == 0 {
            DMat3::IDENTITY
        } else {
            DMat3::from_cols_array(&[1.0, 0.0, 0.0, 0.3, 1.0, 0.0, -0.2, 0.1, 1.0])
        };
        let c = d.aabb().center();
        let map = DAffine3::from_translation(c + rng.vec(-0.4, 0.4))
            * DAffine3::from_mat3(linear * shear)
            * DAffine3::from_translation(-c);
        let target_depth = 3 + rng.below(3) as u8;
        let target = Domain::new(d.min() + rng.vec(-0.5, 0.5), d.edge() * rng.range(0.7, 1.5), target_depth).unwrap();
        let got = tree.resample(map, target, &opts()).unwrap();
        got.validate().unwrap();
        let back = map.inverse();
        let mut want = Grid::empty(target.resolution());
        for v in want.clone().voxels() {
            let centre = target.voxel_center(v.map(|c| c as u32));
            if tree.contains_point(back.transform_point3(centre)) {
                want.set(v);
            }
        }
        assert_eq!(Grid::of(&got), want, "round {round}");
    }
    // A singular map is refused; a target away from the image is empty.
    let (tree, _) = random_solid(&mut rng, 4);
    assert!(tree.resample(DAffine3::from_scale(DVec3::new(1.0, 0.0, 1.0)), *tree.domain(), &opts()).is_err());
    assert!(tree.resample(DAffine3::from_translation(DVec3::NAN), *tree.domain(), &opts()).is_err());
    let far = Domain::new(DVec3::splat(100.0), 1.0, 4).unwrap();
    assert!(tree.resample_to(far, &opts()).unwrap().is_empty());
}

#[test]
fn resample_to_a_coarser_depth_samples_voxel_centres() {
    // The centre of a coarse voxel is the corner shared by eight fine voxels; with a
    // dyadic domain the arithmetic is exact and the fine voxel above it is sampled.
    let mut rng = Rng(12);
    for depth in 4..=5 {
        let (tree, grid) = random_solid(&mut rng, depth);
        let coarse = tree.resample_to(tree.domain().with_depth(depth - 1).unwrap(), &opts()).unwrap();
        let mut want = Grid::empty(grid.n as u32 / 2);
        for v in want.clone().voxels() {
            if grid.get(v.map(|c| 2 * c + 1)) {
                want.set(v);
            }
        }
        check(&coarse, &want, "coarser");
    }
}

/// A cube of `side` voxels centred in the domain, made by hand from voxels.
fn hand_cube(d: Domain, side: u32) -> LinearOctree {
    let n = d.resolution();
    let lo = (n - side) / 2;
    let mut voxels = Vec::new();
    for x in lo..lo + side {
        for y in lo..lo + side {
            for z in lo..lo + side {
                voxels.push([x, y, z]);
            }
        }
    }
    LinearOctree::from_voxels(d, voxels).unwrap()
}

#[test]
fn resampled_rotation_keeps_the_volume() {
    for depth in [6, 7] {
        let d = domain(depth);
        let side = d.resolution() * 2 / 5;
        let cube = hand_cube(d, side);
        let exact = cube.volume();
        let c = d.aabb().center();
        let about_centre =
            |q: DQuat| DAffine3::from_translation(c) * DAffine3::from_quat(q) * DAffine3::from_translation(-c);
        for q in [
            DQuat::from_rotation_z(PI / 4.0),
            DQuat::from_rotation_x(PI / 4.0),
            DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.3).normalize(), PI / 4.0),
        ] {
            let turned = cube.resample(about_centre(q), d, &opts()).unwrap();
            turned.validate().unwrap();
            let error = (turned.volume() / exact - 1.0).abs();
            assert!(error < 0.03, "depth {depth} {q:?}: volume {} vs {exact}", turned.volume());
            // Turning back lands near the original cube: only a boundary layer differs.
            let back = turned.resample(about_centre(q.inverse()), d, &opts()).unwrap();
            let differ = (&back ^ &cube).voxel_count() as f64;
            assert!(differ < 0.15 * cube.voxel_count() as f64, "{differ} voxels differ after the round trip");
        }
    }
    // Against voxelizing the rotated box directly: the same up to a thin boundary layer.
    let d = domain(7);
    let h = d.voxel_size();
    let side = d.resolution() * 2 / 5;
    let lo = d.lattice_point([(d.resolution() - side) / 2; 3]);
    let shape = Cuboid::from_corners(lo, lo + DVec3::splat(f64::from(side) * h)).unwrap();
    let c = d.aabb().center();
    let turn = DAffine3::from_translation(c)
        * DAffine3::from_quat(DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.3).normalize(), PI / 4.0))
        * DAffine3::from_translation(-c);
    let turned = hand_cube(d, side).resample(turn, d, &opts()).unwrap();
    let direct = voxelize(&shape.transform(turn).unwrap(), d, &opts()).unwrap();
    let differ = (&turned ^ &direct).voxel_count() as f64;
    assert!(differ < 0.08 * direct.voxel_count() as f64, "{differ} voxels differ");
}

/// The point-sampling oracle: target voxel `v` is full iff `tree` holds the preimage
/// under `map` of its centre.
fn sampled(tree: &LinearOctree, map: DAffine3, target: &Domain) -> Grid {
    let back = map.inverse();
    let mut want = Grid::empty(target.resolution());
    for v in want.clone().voxels() {
        if tree.contains_point(back.transform_point3(target.voxel_center(v.map(|c| c as u32)))) {
            want.set(v);
        }
    }
    want
}

#[test]
fn fit_to_is_exact_where_lattices_nest_and_samples_otherwise() {
    let mut rng = Rng(57);
    for round in 0..30 {
        let depth = 3 + (round % 2) as u8;
        let (tree, _) = random_solid(&mut rng, depth);
        let d = *tree.domain();
        let h = d.voxel_size();
        // A target whose voxels nest: finer by 0 or 1 level, corner on the source's
        // finer lattice, larger (more levels) or smaller (fewer) than the source.
        let refined = rng.below(2) as u8;
        let fine = h / f64::from(1 << refined);
        let levels = depth + refined + rng.below(3) as u8 - 1;
        let shift = [0; 3].map(|_| rng.below(9) as f64 - 4.0);
        let target = Domain::new(d.min() + DVec3::from(shift) * fine, fine * f64::from(1 << levels), levels).unwrap();
        let (got, fit) = tree.fit_to(target, &opts()).unwrap();
        assert!(matches!(fit, Fit::Exact { refined: r, .. } if r == refined), "round {round}: {fit:?}");
        assert_eq!(got.domain(), &target);
        check(&got, &sampled(&tree, DAffine3::IDENTITY, &target), &format!("round {round} exact"));
        // Off the lattice by a third of a voxel: sampled, and still the oracle's.
        let off = Domain::new(target.min() + DVec3::splat(fine / 3.0), target.edge(), target.depth()).unwrap();
        let (got, fit) = tree.fit_to(off, &opts()).unwrap();
        assert_eq!(fit, Fit::Resampled);
        check(&got, &sampled(&tree, DAffine3::IDENTITY, &off), &format!("round {round} resampled"));
    }
    let (tree, _) = random_solid(&mut rng, 4);
    assert_eq!(tree.fit_to(*tree.domain(), &opts()).unwrap(), (tree.clone(), Fit::Same));
}

#[test]
fn common_domain_covers_all_and_keeps_the_finest_voxels() {
    let a = Domain::new(DVec3::ZERO, 2.0, 5).unwrap();
    // An octant of `a` at the same depth has voxels half as big: one level more.
    let octant = Domain::new(DVec3::new(1.0, 0.0, 1.0), 1.0, 5).unwrap();
    let c = common_domain(&[a, octant]).unwrap();
    assert_eq!((c.min(), c.edge(), c.depth()), (DVec3::ZERO, 2.0, 6));
    // Unrelated domains: the smallest cube holding both, at the deeper depth.
    let b = Domain::new(DVec3::new(-1.05, -1.05, -1.05), 2.1, 4).unwrap();
    let s = Domain::new(DVec3::new(-1.02, -1.0, -1.0), 2.04, 6).unwrap();
    let c = common_domain(&[b, s]).unwrap();
    assert_eq!((c.min(), c.edge(), c.depth()), (DVec3::splat(-1.05), 2.1, 6));
    for d in [b, s] {
        let (inner, outer) = (d.aabb(), c.aabb());
        assert!(inner.min.cmpge(outer.min).all() && inner.max.cmple(outer.max + 1e-12).all(), "{d:?} in {c:?}");
    }
    for d in [a, octant, b, s] {
        assert_eq!(common_domain(&[d]).unwrap(), d);
    }
    assert!(common_domain(&[]).is_err());
}

#[test]
fn motions_by_quarter_turns_and_powers_of_two_are_exact() {
    let mut rng = Rng(91);
    for round in 0..20 {
        let (tree, _) = random_solid(&mut rng, 4);
        let axes = [Axis::X, Axis::Y, Axis::Z];
        let turns = (0..rng.below(3))
            .map(|_| Turn { axis: axes[rng.below(3) as usize], degrees: 90.0 * (rng.below(7) as f64 - 3.0) })
            .collect();
        let motion = Motion { scale: [0.5, 1.0, 2.0][rng.below(3) as usize], turns, translate: rng.vec(-3.0, 3.0) };
        let (got, fit) = tree.transformed(motion.affine(), Ok, &opts()).unwrap();
        assert!(matches!(fit, Fit::Exact { .. }), "round {round}: {fit:?}");
        assert_eq!(got.node_count(), tree.node_count(), "round {round}");
        let want = sampled(&tree, motion.affine(), got.domain());
        check(&got, &want, &format!("round {round}"));
        let ratio = got.volume() / tree.volume().max(f64::MIN_POSITIVE);
        assert!(tree.is_empty() || (ratio - motion.scale.powi(3)).abs() < 1e-9, "round {round}: {ratio}");
    }
}

#[test]
fn other_motions_resample_once_into_the_target() {
    let d = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
    let tree = voxelize(&Cuboid::new(DVec3::ZERO, DVec3::ONE).unwrap(), d, &opts()).unwrap();
    let motion = Motion { scale: 1.5, turns: vec![Turn { axis: Axis::Z, degrees: 30.0 }], translate: DVec3::X };
    let target = Domain::new(DVec3::new(-1.0, -2.0, -2.0), 4.0, 6).unwrap();
    let (got, fit) = tree.transformed(motion.affine(), |_| Ok(target), &opts()).unwrap();
    assert_eq!(fit, Fit::Resampled);
    check(&got, &sampled(&tree, motion.affine(), &target), "into the target");
    // The default target holds the whole moved cube (volume 1.5^3 within a voxel shell).
    let (got, _) = tree.transformed(motion.affine(), Ok, &opts()).unwrap();
    let h = got.domain().voxel_size();
    assert!((got.volume() - 1.5f64.powi(3)).abs() < 6.0 * 1.5 * 1.5 * h * 2.0, "{}", got.volume());
    let bad = Motion { scale: -1.0, ..Motion::default() };
    assert!(bad.checked_affine().is_err());
}

/// The oracle of a moved solid: voxel `v` of `got`'s domain is full iff the source
/// voxel under the preimage of its centre is (nearest sampling, which is the exact
/// image when the map sends voxels to voxels).
fn check_moved(got: &LinearOctree, source: &Domain, grid: &Grid, map: DAffine3, what: &str) {
    got.validate().unwrap_or_else(|e| panic!("{what}: {e}"));
    let (d, back) = (*got.domain(), map.inverse());
    let n = d.resolution();
    for x in 0..n {
        for y in 0..n {
            for z in 0..n {
                let p = back.transform_point3(d.voxel_center([x, y, z]));
                let want = source.voxel_of(p).is_some_and(|s| grid.get(s.map(i64::from)));
                assert_eq!(got.contains_voxel([x, y, z]), want, "{what}: voxel {:?}", [x, y, z]);
            }
        }
    }
}

#[test]
fn transformed_is_exact_for_cube_symmetries_and_resampled_otherwise() {
    let mut rng = Rng(2024);
    let deg = |a: f64| a.to_radians();
    let point = DVec3::new(0.3, -2.0, 1.7);
    let about = |m: DAffine3| DAffine3::from_translation(point) * m * DAffine3::from_translation(-point);
    // (name, map, exact: a cube symmetry times a scale plus a translation)
    let maps = [
        ("translation by a fraction of a voxel", DAffine3::from_translation(DVec3::new(0.37, -1.2, 5.01)), true),
        ("uniform scale", DAffine3::from_scale(DVec3::splat(2.5)), true),
        ("quarter turn in degrees", about(DAffine3::from_axis_angle(DVec3::Z, deg(90.0))), true),
        ("three quarter turns about x", about(DAffine3::from_axis_angle(DVec3::X, deg(270.0))), true),
        ("mirror", DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0)), true),
        (
            "turn, mirror, shrink and move",
            DAffine3::from_translation(DVec3::new(4.0, 0.5, -3.0))
                * DAffine3::from_scale(DVec3::new(0.5, -0.5, 0.5))
                * DAffine3::from_axis_angle(DVec3::Y, deg(-90.0)),
            true,
        ),
        ("eighth turn", about(DAffine3::from_axis_angle(DVec3::Z, deg(45.0))), false),
        ("stretch", DAffine3::from_scale(DVec3::new(1.0, 2.0, 1.0)), false),
    ];
    for trial in 0..6 {
        let (tree, grid) = random_solid(&mut rng, 4);
        for (name, map, exact) in maps {
            let what = format!("trial {trial}, {name}");
            let moved = tree.transformed(map, Ok, &opts()).unwrap().0;
            check_moved(&moved, tree.domain(), &grid, map, &what);
            if exact {
                let scale = map.matrix3.determinant().abs().cbrt();
                assert_eq!(moved.voxel_count(), tree.voxel_count(), "{what}");
                assert!((moved.domain().edge() / tree.domain().edge() - scale).abs() < 1e-12, "{what}");
                assert_eq!(moved.depth(), tree.depth(), "{what}");
            } else if let Some(b) = tree.bounds() {
                // The moved solid's box lies in the new domain: nothing is clipped.
                let d = moved.domain().aabb();
                for i in 0..8 {
                    let c = map.transform_point3(b.corner(i));
                    assert!(c.cmpge(d.min).all() && c.cmple(d.max).all(), "{what}: corner {c} outside {d:?}");
                }
            }
        }
    }
    assert!(LinearOctree::empty(domain(3)).transformed(DAffine3::from_scale(DVec3::ZERO), Ok, &opts()).is_err());
}

#[test]
fn an_empty_solid_moves_to_an_empty_solid() {
    // A resampling sampled the solid's surface, and an empty one has none ("invalid
    // mesh: it has no triangles"); the exact moves already gave an empty solid.
    let empty = LinearOctree::empty(domain(5));
    for map in [DAffine3::from_rotation_z(30f64.to_radians()), DAffine3::from_translation(DVec3::X)] {
        let (moved, _) = empty.transformed(map, Ok, &opts()).unwrap();
        assert!(moved.is_empty() && moved.depth() == 5, "{map:?}");
    }
}
