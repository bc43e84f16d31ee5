//! Offsets, shells and rounds (issue 39) against independent oracles: a dense grid's
//! brute force (each voxel's distance to the other phase by every offset of a ball;
//! along the surface, to its nearest sites' tangent planes by alternating
//! projections), Steiner's formula for cubes, a sphere's shell, and the identities of
//! morphology.

mod common;

use std::f64::consts::PI;

use common::{Rng, random_csg, random_octree};
use glam::DVec3;
use octsolid::octree::{Domain, LinearOctree, Metric, OffsetOptions, VoxelizeOptions, voxelize};
use octsolid::scene_file::build_solid;
use octsolid::shape::{Csg, Cuboid, Sphere, round, shell};
use octsolid::surface::{
    FaceKey, HermiteData, offset_with_surface, resolve_offsets, round_with_surface, shell_with_surface,
};

/// Where the random CSG trees' primitives are centred, on each axis.
const UNIT_CENTRES: (f64, f64) = (0.1, 0.9);

fn unit_domain(depth: u8) -> Domain {
    Domain::new(DVec3::ZERO, 1.0, depth).unwrap()
}

/// Four times the squared distance from a voxel's centre to the voxel `o` voxels away
/// along one axis, as a cube: the gap to its near face is `|o| - 1/2`.
fn cost(o: i64) -> i64 {
    if o == 0 { 0 } else { (2 * o.abs() - 1).pow(2) }
}

/// Four times the squared distance from every voxel's centre of the domain to the
/// nearest voxel of the other phase (outside the domain empty), by brute force over
/// every lattice offset up to `cap` voxels an axis; `None` when none is that near.
fn brute_distances(tree: &LinearOctree, cap: i64) -> Vec<Option<i64>> {
    let n = i64::from(tree.domain().resolution());
    let full = tree.occupancy([0; 3], n as u32);
    let at = |p: [i64; 3]| p.iter().all(|&c| (0..n).contains(&c)) && full[(p[0] + n * (p[1] + n * p[2])) as usize];
    let mut ball: Vec<([i64; 3], i64)> = Vec::new();
    for z in -cap..=cap {
        for y in -cap..=cap {
            for x in -cap..=cap {
                let d = cost(x) + cost(y) + cost(z);
                if d > 0 && d < 4 * cap * cap {
                    ball.push(([x, y, z], d));
                }
            }
        }
    }
    ball.sort_by_key(|b| b.1);
    let mut out = Vec::with_capacity((n * n * n) as usize);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let phase = at([x, y, z]);
                let near = ball.iter().find(|(o, _)| at([x + o[0], y + o[1], z + o[2]]) != phase).map(|b| b.1);
                out.push(near);
            }
        }
    }
    out
}

/// The solid a distance grid says the offset by `d` is.
fn oracle_offset(tree: &LinearOctree, dist: &[Option<i64>], d: f64) -> LinearOctree {
    let n = tree.domain().resolution();
    let full = tree.occupancy([0; 3], n);
    let keep = |i: usize| {
        let near = dist[i].is_some_and(|s| (s as f64) < 4.0 * d * d);
        if d > 0.0 { full[i] || near } else { full[i] && !near }
    };
    let voxels = (0..full.len())
        .filter(|&i| keep(i))
        .map(|i| {
            let i = i as u32;
            [i % n, i / n % n, i / (n * n)]
        })
        .collect::<Vec<_>>();
    LinearOctree::from_voxels(*tree.domain(), voxels).unwrap()
}

#[test]
fn offsets_of_random_csg_solids_are_the_brute_force_ones_voxel_for_voxel() {
    let mut rng = Rng(0x0ff5_e739);
    let options = OffsetOptions::default();
    for round in 0..8 {
        let depth = if round < 6 { 5 } else { 6 };
        let tree = if round % 3 == 2 {
            random_octree(&mut rng, unit_domain(depth))
        } else {
            voxelize(&random_csg(&mut rng, 3, UNIT_CENTRES), unit_domain(depth), &VoxelizeOptions::default()).unwrap()
        };
        let dist = brute_distances(&tree, 5);
        for d in [0.7, 1.0, 1.5, 2.9, 4.0, 5.0, -0.7, -1.0, -1.5, -2.9, -4.0, -5.0] {
            let got = tree.offset(d, &options).unwrap();
            got.validate().unwrap();
            assert!(got == oracle_offset(&tree, &dist, d), "round {round} depth {depth} offset {d}");
        }
    }
}

/// The distance by `metric` from a voxel's centre to the voxel `o` away, as a cube, by
/// its definition: the gap on each axis is `max(|o| - 1/2, 0)`.
fn metric_distance(metric: Metric, o: [i64; 3]) -> f64 {
    let gaps = o.map(|c| (c.abs() as f64 - 0.5).max(0.0));
    match metric {
        Metric::Euclidean => gaps.iter().map(|g| g * g).sum::<f64>().sqrt(),
        Metric::Manhattan => gaps.iter().sum(),
        Metric::Chebyshev => gaps.iter().copied().fold(0.0, f64::max),
    }
}

/// `tree` offset by `d` by brute force under `metric`: each voxel of the phase the step
/// spreads into flips when a voxel of the other phase (outside the domain empty) lies
/// under `|d|` away, every lattice offset up to `cap` voxels an axis tried.
fn oracle_metric_offset(tree: &LinearOctree, metric: Metric, d: f64, cap: i64) -> LinearOctree {
    let n = i64::from(tree.domain().resolution());
    let full = tree.occupancy([0; 3], n as u32);
    let at = |p: [i64; 3]| p.iter().all(|&c| (0..n).contains(&c)) && full[(p[0] + n * (p[1] + n * p[2])) as usize];
    let mut near: Vec<[i64; 3]> = Vec::new();
    for z in -cap..=cap {
        for y in -cap..=cap {
            for x in -cap..=cap {
                if [x, y, z] != [0; 3] && metric_distance(metric, [x, y, z]) < d.abs() {
                    near.push([x, y, z]);
                }
            }
        }
    }
    let mut voxels = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let phase = at([x, y, z]);
                let flips = phase != (d > 0.0) && near.iter().any(|o| at([x + o[0], y + o[1], z + o[2]]) != phase);
                if phase != flips {
                    voxels.push([x, y, z].map(|c| c as u32));
                }
            }
        }
    }
    LinearOctree::from_voxels(*tree.domain(), voxels).unwrap()
}

#[test]
fn offsets_by_the_manhattan_and_chebyshev_distances_are_the_brute_force_ones_voxel_for_voxel() {
    let mut rng = Rng(0x4d65_7472);
    for round in 0..4 {
        let tree = if round == 3 {
            random_octree(&mut rng, unit_domain(5))
        } else {
            voxelize(&random_csg(&mut rng, 3, UNIT_CENTRES), unit_domain(5), &VoxelizeOptions::default()).unwrap()
        };
        for metric in [Metric::Manhattan, Metric::Chebyshev] {
            let options = OffsetOptions { metric, ..OffsetOptions::default() };
            for d in [0.5, 0.7, 1.0, 1.5, 2.5, 2.9, 4.0, -0.7, -1.0, -1.5, -2.9, -4.0] {
                let got = tree.offset(d, &options).unwrap();
                got.validate().unwrap();
                assert!(got == oracle_metric_offset(&tree, metric, d, 5), "round {round} {metric} offset {d}");
            }
        }
    }
}

#[test]
fn a_cube_grown_by_the_chebyshev_distance_is_a_cube_and_by_the_manhattan_one_its_sum_with_an_octahedron() {
    // Reaches over the Euclidean transform's window (32 voxels) too.
    let tree = cube(40);
    for d in [3.2, 12.0, 40.4] {
        let reach = ((d + 0.5_f64).ceil() - 1.0) as u64;
        let chebyshev = OffsetOptions { metric: Metric::Chebyshev, ..OffsetOptions::default() };
        assert_eq!(tree.offset(d, &chebyshev).unwrap().voxel_count(), (40 + 2 * reach).pow(3), "grown by {d}");
        let manhattan = OffsetOptions { metric: Metric::Manhattan, ..OffsetOptions::default() };
        // The lattice points whose L1 gap to the cube's voxels is under d: each axis's
        // gap is how far past the cube's 40 voxels the coordinate lies.
        let r = reach as i64;
        let gap = |c: i64| if c < 0 { -c } else { (c - 39).max(0) };
        let mut want = 0u64;
        for z in -r..40 + r {
            for y in -r..40 + r {
                for x in -r..40 + r {
                    let o = [gap(x), gap(y), gap(z)];
                    want += u64::from(metric_distance(Metric::Manhattan, o) < d);
                }
            }
        }
        assert_eq!(tree.offset(d, &manhattan).unwrap().voxel_count(), want, "grown by {d}");
    }
    let chebyshev = OffsetOptions { metric: Metric::Chebyshev, ..OffsetOptions::default() };
    assert_eq!(tree.offset(-7.0, &chebyshev).unwrap().voxel_count(), (40 - 2 * 7u64).pow(3), "shrunk");
}

#[test]
fn offsets_by_any_metric_past_the_domain_fill_it() {
    // One voxel in a corner of 8^3: the far corner's gaps are 6.5 a side, so it lies
    // 19.5 away (Manhattan), 11.26 (Euclidean), 6.5 (Chebyshev). Every radius past that
    // fills the domain; one just under leaves out that corner (Chebyshev: the three far
    // faces, all 6.5 away).
    let tree = LinearOctree::from_voxels(unit_domain(3), vec![[0, 0, 0]]).unwrap();
    let euclidean = (3.0 * 6.5f64.powi(2)).sqrt();
    for (metric, far, under) in
        [(Metric::Manhattan, 19.5, 511), (Metric::Euclidean, euclidean, 511), (Metric::Chebyshev, 6.5, 7u64.pow(3))]
    {
        let options = OffsetOptions { metric, ..OffsetOptions::default() };
        assert_eq!(tree.offset(far + 0.01, &options).unwrap().voxel_count(), 512, "{metric}");
        assert_eq!(tree.offset(far + 100.0, &options).unwrap().voxel_count(), 512, "{metric}");
        assert_eq!(tree.offset(far - 0.01, &options).unwrap().voxel_count(), under, "{metric}");
    }
}

#[test]
fn along_a_surface_only_the_euclidean_distance_is_measured() {
    let (tree, data) = with_surface(&Sphere::new(DVec3::splat(0.5), 0.3).unwrap(), 5);
    let options = OffsetOptions { metric: Metric::Chebyshev, ..OffsetOptions::default() };
    let e = offset_with_surface(&tree, &data, 1.5, &options).unwrap_err().to_string();
    assert!(e.contains("Euclidean") && e.contains("chebyshev"), "{e}");
}

/// Four times the squared distance from each voxel's centre to the nearest voxel (as a
/// cube) of the other phase, the outside of the domain empty: the minimum over every
/// voxel of the other phase with a face towards this phase (the nearest point of a
/// union of cubes to a point outside it lies on such a face) and the domain's faces.
fn brute_distances_far(tree: &LinearOctree) -> Vec<i64> {
    let n = i64::from(tree.domain().resolution());
    let full = tree.occupancy([0; 3], n as u32);
    let at = |p: [i64; 3]| p.iter().all(|&c| (0..n).contains(&c)) && full[(p[0] + n * (p[1] + n * p[2])) as usize];
    let mut exposed: [Vec<[i64; 3]>; 2] = [Vec::new(), Vec::new()];
    for i in 0..n * n * n {
        let p = [i % n, i / n % n, i / (n * n)];
        let faces = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]];
        if faces.iter().any(|f| at([p[0] + f[0], p[1] + f[1], p[2] + f[2]]) != at(p)) {
            exposed[usize::from(at(p))].push(p);
        }
    }
    (0..n * n * n)
        .map(|i| {
            let p = [i % n, i / n % n, i / (n * n)];
            let phase = at(p);
            let to_cubes = exposed[usize::from(!phase)]
                .iter()
                .map(|s| (0..3).map(|a| cost(p[a] - s[a])).sum::<i64>())
                .min()
                .unwrap_or(i64::MAX);
            // A full voxel is also near the empty outside, across the nearest face.
            let to_outside =
                if phase { (0..3).map(|a| cost(p[a] + 1).min(cost(n - p[a]))).min().unwrap() } else { i64::MAX };
            to_cubes.min(to_outside)
        })
        .collect()
}

#[test]
fn offsets_reaching_over_several_tiles_are_the_brute_force_ones_voxel_for_voxel() {
    let mut rng = Rng(0x7113_5039);
    let options = OffsetOptions::default();
    for round in 0..4 {
        let tree = if round % 2 == 1 {
            random_octree(&mut rng, unit_domain(5))
        } else {
            voxelize(&random_csg(&mut rng, 3, UNIT_CENTRES), unit_domain(5), &VoxelizeOptions::default()).unwrap()
        };
        let dist: Vec<Option<i64>> =
            brute_distances_far(&tree).into_iter().map(|d| (d < i64::MAX).then_some(d)).collect();
        for d in [7.9, 8.5, 9.3, 12.0, 16.5, 23.2, 60.0, -7.9, -8.5, -9.3, -12.0, -16.5, -60.0] {
            let got = tree.offset(d, &options).unwrap();
            got.validate().unwrap();
            assert!(got == oracle_offset(&tree, &dist, d), "round {round} offset {d}");
        }
    }
}

#[test]
fn offset_by_zero_or_up_to_half_a_voxel_is_the_identity() {
    let mut rng = Rng(39);
    let tree = voxelize(&random_csg(&mut rng, 3, UNIT_CENTRES), unit_domain(6), &VoxelizeOptions::default()).unwrap();
    for d in [0.0, 0.5, -0.5, 0.25] {
        assert_eq!(tree.offset(d, &OffsetOptions::default()).unwrap(), tree, "offset {d}");
    }
    // Along the surface only 0 is: a voxel a quarter voxel off the surface is reached.
    let data = HermiteData::from_shape(&random_csg(&mut Rng(39), 3, UNIT_CENTRES), &tree);
    assert_eq!(offset_with_surface(&tree, &data, 0.0, &OffsetOptions::default()).unwrap().0, tree);
}

#[test]
fn an_opening_never_exceeds_the_solid_and_a_closing_covers_it() {
    let mut rng = Rng(0x39_39);
    let options = OffsetOptions::default();
    // Kept 8 voxels from the domain's faces, which cut a growth (and so a closing).
    let inset = Cuboid::new(DVec3::splat(0.5), DVec3::splat(1.0 - 16.0 / 128.0)).unwrap();
    for round in 0..4 {
        let shape = random_csg(&mut rng, 3, UNIT_CENTRES) & Csg::from(inset.clone());
        let tree = voxelize(&shape, unit_domain(7), &VoxelizeOptions::default()).unwrap();
        for r in [2.0, 3.5, 7.0] {
            let opened = tree.offset(-r, &options).unwrap().offset(r, &options).unwrap();
            assert!(opened.difference(&tree).unwrap().is_empty(), "round {round} radius {r}");
            let closed = tree.round(r, false, true, &options).unwrap();
            assert!(tree.difference(&closed).unwrap().is_empty(), "round {round} radius {r}");
        }
    }
}

#[test]
fn offsets_are_the_same_on_one_and_two_threads() {
    let tree =
        voxelize(&random_csg(&mut Rng(7), 4, UNIT_CENTRES), unit_domain(8), &VoxelizeOptions::default()).unwrap();
    let run = |threads: usize, d: f64| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| tree.offset(d, &OffsetOptions::default()).unwrap())
    };
    for d in [6.0, -6.0, 40.0] {
        assert_eq!(run(1, d), run(2, d), "offset {d}");
    }
    // Along the surface, the crossings too.
    let data = HermiteData::from_shape(&random_csg(&mut Rng(7), 4, UNIT_CENTRES), &tree);
    let run = |threads: usize, d: f64| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| offset_with_surface(&tree, &data, d, &OffsetOptions::default()).unwrap())
    };
    for d in [6.0, -6.0] {
        assert!(run(1, d) == run(2, d), "offset {d} along the surface");
    }
}

/// A cube of `a` voxels a side at the centre of a depth-8 domain.
fn cube(a: u32) -> LinearOctree {
    let d = unit_domain(8);
    let shape = Cuboid::new(DVec3::splat(0.5), DVec3::splat(f64::from(a) * d.voxel_size())).unwrap();
    let tree = voxelize(&shape, d, &VoxelizeOptions::default()).unwrap();
    assert_eq!(tree.voxel_count(), u64::from(a).pow(3));
    tree
}

fn assert_close(got: u64, want: f64, tolerance: f64, what: &str) {
    let error = (got as f64 - want).abs() / want;
    assert!(error <= tolerance, "{what}: {got} voxels against {want:.0}, {:.3}% off", error * 100.0);
}

#[test]
fn a_cube_grown_shrunk_and_rounded_follows_steiners_formula() {
    let options = OffsetOptions::default();
    let (a, r) = (96.0, 16.0);
    let steiner = |a: f64, r: f64| a.powi(3) + 6.0 * a * a * r + 3.0 * PI * a * r * r + 4.0 / 3.0 * PI * r.powi(3);
    let tree = cube(96);
    assert_close(tree.offset(r, &options).unwrap().voxel_count(), steiner(a, r), 0.002, "grown");
    assert_eq!(tree.offset(-r, &options).unwrap().voxel_count(), (a - 2.0 * r).powi(3) as u64, "shrunk");
    let rounded = tree.round(r, true, true, &options).unwrap();
    assert_close(rounded.voxel_count(), steiner(a - 2.0 * r, r), 0.002, "rounded");
}

/// A solid of `shape` at `depth` in the unit domain, with its exact crossings.
fn with_surface(shape: &impl octsolid::shape::Shape, depth: u8) -> (LinearOctree, HermiteData) {
    let tree = voxelize(shape, unit_domain(depth), &VoxelizeOptions::default()).unwrap();
    let data = HermiteData::from_shape(shape, &tree);
    (tree, data)
}

#[test]
fn along_the_surface_a_cube_grown_shrunk_and_rounded_follows_steiners_formula_at_depth_9() {
    let options = OffsetOptions::default();
    let voxel = unit_domain(9).voxel_size();
    // A cube of 192 voxels on the lattice (an offset cube off it is sampled with up to
    // a voxel's slab too few or too many a side, whatever the rule).
    let (a, r) = (192.0, 24.0);
    let steiner = |a: f64, r: f64| a.powi(3) + 6.0 * a * a * r + 3.0 * PI * a * r * r + 4.0 / 3.0 * PI * r.powi(3);
    let shape = Cuboid::new(DVec3::splat(0.5), DVec3::splat(a * voxel)).unwrap();
    let (tree, data) = with_surface(&shape, 9);
    let grown = offset_with_surface(&tree, &data, r, &options).unwrap().0;
    assert_close(grown.voxel_count(), steiner(a, r), 0.002, "grown");
    let shrunk = offset_with_surface(&tree, &data, -r, &options).unwrap().0;
    assert_close(shrunk.voxel_count(), (a - 2.0 * r).powi(3), 0.002, "shrunk");
    let rounded = round_with_surface(&tree, &data, r, true, false, &options).unwrap().0;
    assert_close(rounded.voxel_count(), steiner(a - 2.0 * r, r), 0.002, "rounded");
}

#[test]
fn along_the_surface_a_spheres_shell_has_the_volume_between_its_spheres_at_depth_9() {
    let options = OffsetOptions::default();
    let voxel = unit_domain(9).voxel_size();
    let (radius, t) = (100.0, 10.0);
    let ball = Sphere::new(DVec3::new(0.5, 0.49, 0.51), radius * voxel).unwrap();
    let (tree, data) = with_surface(&ball, 9);
    let want = 4.0 / 3.0 * PI * (radius.powi(3) - (radius - t).powi(3));
    let inward = shell_with_surface(&tree, &data, t, false, &options).unwrap().0;
    assert_close(inward.voxel_count(), want, 0.002, "inward shell");
    let want = 4.0 / 3.0 * PI * ((radius + t).powi(3) - radius.powi(3));
    let outward = shell_with_surface(&tree, &data, t, true, &options).unwrap().0;
    assert_close(outward.voxel_count(), want, 0.002, "outward shell");
}

#[test]
fn along_the_surface_rounding_a_ball_by_less_than_its_radius_gives_the_ball() {
    let voxel = unit_domain(7).voxel_size();
    let ball = Sphere::new(DVec3::new(0.5, 0.47, 0.52), 40.0 * voxel).unwrap();
    let (tree, data) = with_surface(&ball, 7);
    for r in [3.0, 10.0, 25.0] {
        let rounded = round_with_surface(&tree, &data, r, true, true, &OffsetOptions::default()).unwrap().0;
        let moved = tree.symmetric_difference(&rounded).unwrap().voxel_count();
        // Of its 20 000 surface voxels some 500 move: the crossings interpolated
        // between voxels whose distances come from neighbouring sites differ from
        // the sphere's by hundredths of a voxel, which flips voxels near the surface.
        assert!(moved * 300 < tree.voxel_count(), "radius {r}: {moved} of {} voxels moved", tree.voxel_count());
    }
}

/// The distance from the origin to the intersection of the half-spaces `n . x <= b`
/// by Dykstra's alternating projections (Boyle and Dykstra 1986), and whether the point
/// found lies in all of them.
fn dykstra_distance(planes: &[(DVec3, f64)]) -> Option<f64> {
    let mut x = DVec3::ZERO;
    let mut q = vec![DVec3::ZERO; planes.len()];
    // Between planes nearly parallel it converges slowly: sweeps until the point
    // found lies in every half-space.
    for sweep in 0..400_000 {
        for (i, &(n, b)) in planes.iter().enumerate() {
            let y = x + q[i];
            let over = n.dot(y) - b;
            let projected = if over > 0.0 { y - n * over } else { y };
            q[i] = y - projected;
            x = projected;
        }
        if sweep >= 2000 && planes.iter().all(|&(n, b)| n.dot(x) <= b + 1e-6) {
            return Some(x.length());
        }
    }
    None
}

/// The sub-voxel rule, by brute force over every site: for each voxel, the offsets
/// its nearest sites (by the cube metric) allow, `None` where the distance lies within
/// a ten-thousandth of a voxel of the radius (the alternating projections converge slowly between planes nearly parallel) (a float's call).
fn oracle_along_surface(tree: &LinearOctree, data: &HermiteData, d: f64) -> Vec<Option<Vec<bool>>> {
    let n = i64::from(tree.domain().resolution());
    let full = tree.occupancy([0; 3], n as u32);
    let grow = d > 0.0;
    let is_full = |p: [i64; 3]| p.iter().all(|&c| (0..n).contains(&c)) && full[(p[0] + n * (p[1] + n * p[2])) as usize];
    let is_site = |p: [i64; 3]| is_full(p) == grow;
    let reach = d.abs().ceil() as i64 + 1;
    let key = |v: [i64; 3], dir: u8| FaceKey::new(v.map(|c| c as u32), dir);
    let mut out = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = [x, y, z];
                if is_site(p) {
                    out.push(Some(vec![false]));
                    continue;
                }
                let mut nearest: Vec<[i64; 3]> = Vec::new();
                let mut best = i64::MAX;
                for oz in -reach..=reach {
                    for oy in -reach..=reach {
                        for ox in -reach..=reach {
                            let s = [x + ox, y + oy, z + oz];
                            if !is_site(s) {
                                continue;
                            }
                            let c = cost(ox) + cost(oy) + cost(oz);
                            if c < best {
                                (best, nearest) = (c, vec![s]);
                            } else if c == best {
                                nearest.push(s);
                            }
                        }
                    }
                }
                if nearest.is_empty() {
                    out.push(Some(vec![false]));
                    continue;
                }
                let d_cube = (best as f64).sqrt() / 2.0;
                let mut allowed = Vec::new();
                let mut ambiguous = false;
                for s in nearest {
                    let rel = DVec3::new((s[0] - x) as f64, (s[1] - y) as f64, (s[2] - z) as f64);
                    let mut planes = Vec::new();
                    let mut crossings = f64::INFINITY;
                    for dir in 0..6u8 {
                        let (axis, sign) = (usize::from(dir / 2), if dir & 1 == 1 { 1 } else { -1 });
                        let mut nb = s;
                        nb[axis] += sign;
                        if is_site(nb) {
                            continue;
                        }
                        let mut e = DVec3::ZERO;
                        e[axis] = sign as f64;
                        let (point, normal) = if grow {
                            let c = data.crossing(key(s, dir));
                            (rel + e * f64::from(c.t), c.normal.as_dvec3())
                        } else {
                            let c = data.crossing(key(nb, dir ^ 1));
                            (rel + e * (1.0 - f64::from(c.t)), -c.normal.as_dvec3())
                        };
                        crossings = crossings.min(point.length());
                        planes.push((normal, normal.dot(point)));
                    }
                    let cone = dykstra_distance(&planes).unwrap_or(crossings);
                    let dist = crossings.min(cone.max(d_cube - 0.5));
                    ambiguous |= (dist - d.abs()).abs() < 1e-4;
                    allowed.push(dist < d.abs());
                }
                out.push((!ambiguous).then_some(allowed));
            }
        }
    }
    out
}

#[test]
fn offsets_along_the_surface_of_random_csg_solids_are_the_brute_force_ones() {
    let mut rng = Rng(0x0005_eb39);
    let options = OffsetOptions::default();
    for round in 0..4 {
        let shape = random_csg(&mut rng, 3, UNIT_CENTRES);
        let (tree, data) = with_surface(&shape, 5);
        let n = tree.domain().resolution();
        for d in [0.3, 1.3, 2.7, 4.0, -0.3, -1.3, -2.7, -4.0] {
            let got = offset_with_surface(&tree, &data, d, &options).unwrap().0;
            got.validate().unwrap();
            let (before, after) = (tree.occupancy([0; 3], n), got.occupancy([0; 3], n));
            let oracle = oracle_along_surface(&tree, &data, d);
            let mut checked = 0;
            for (i, allowed) in oracle.iter().enumerate() {
                let Some(allowed) = allowed else { continue };
                let changed = before[i] != after[i];
                assert!(
                    allowed.contains(&changed),
                    "round {round} offset {d} voxel {i}: changed {changed}, the rule allows {allowed:?}"
                );
                checked += 1;
            }
            assert!(checked * 100 > oracle.len() * 99, "round {round} offset {d}: only {checked} voxels decided");
        }
    }
}

/// A scene of one shape solid `shape` in the unit domain at `depth`, built.
fn scene_solid(name: &str, shape: &str, depth: u8) -> LinearOctree {
    let dir = common::scratch_dir("offset", name);
    let path = dir.join("scene.toml");
    let text = format!("[domain]\nmin = [0, 0, 0]\nedge = 1\ndepth = {depth}\n[[solid]]\nshape = {shape}\n");
    std::fs::write(&path, text).unwrap();
    build_solid(&path, None, &VoxelizeOptions::default()).unwrap()
}

#[test]
fn offset_nodes_are_the_operations_on_their_voxelized_child_voxel_for_voxel() {
    // The scene's round(shell(box)) united with a ball, its child voxelized with its
    // crossings and the operations applied one after the other as the commands do.
    let (depth, per) = (7, unit_domain(7).voxels_per_unit());
    let part = Cuboid::new(DVec3::new(0.45, 0.5, 0.5), DVec3::new(0.6, 0.5, 0.4)).unwrap();
    let ball = Sphere::new(DVec3::new(0.8, 0.5, 0.5), 0.15).unwrap();
    let (tree, data) = with_surface(&part, depth);
    let options = OffsetOptions::default();
    let (walled, data) = shell_with_surface(&tree, &data, 0.08 * per, false, &options).unwrap();
    let rounded = round_with_surface(&walled, &data, 0.02 * per, true, true, &options).unwrap().0;
    let want = rounded.union(&voxelize(&ball, unit_domain(depth), &VoxelizeOptions::default()).unwrap()).unwrap();
    let text = "{ union = [\n  { round = { solid = { shell = { solid = { box = { center = [0.45, 0.5, 0.5], size = \
                [0.6, 0.5, 0.4] } }, thickness = 0.08 } }, radius = 0.02 } },\n  { sphere = { center = [0.8, 0.5, 0.5], \
                radius = 0.15 } },\n] }";
    let built = scene_solid("round-shell", text, depth);
    assert!(built.keys() == want.keys(), "{} voxels against {}", built.voxel_count(), want.voxel_count());
    // The shape API's functions make the same tree.
    let api: Csg = round(shell(part, 0.08), 0.02) | ball;
    let resolved = resolve_offsets(&api, unit_domain(depth), &VoxelizeOptions::default()).unwrap();
    assert!(voxelize(&resolved, unit_domain(depth), &VoxelizeOptions::default()).unwrap().keys() == want.keys());
    // Unresolved, the voxelizer refuses it.
    let e = voxelize(&api, unit_domain(depth), &VoxelizeOptions::default()).unwrap_err().to_string();
    assert!(e.contains("resolve_offsets"), "{e}");
}

#[test]
fn offset_and_shell_nodes_follow_steiners_formula_at_depth_9() {
    let voxel = unit_domain(9).voxel_size();
    // A cube of 192 voxels on the lattice grown by 24 voxels, in world units.
    let (a, r): (f64, f64) = (192.0, 24.0);
    let steiner = a.powi(3) + 6.0 * a * a * r + 3.0 * PI * a * r * r + 4.0 / 3.0 * PI * r.powi(3);
    let text = format!(
        "{{ offset = {{ solid = {{ box = {{ center = [0.5, 0.5, 0.5], size = [{s}, {s}, {s}] }} }}, by = {by} }} }}",
        s = a * voxel,
        by = r * voxel
    );
    assert_close(scene_solid("grown-cube", &text, 9).voxel_count(), steiner, 0.002, "grown cube");
    // A ball's wall, `voxels` thick.
    let (radius, t): (f64, f64) = (100.0, 10.0);
    let text = format!(
        "{{ shell = {{ solid = {{ sphere = {{ center = [0.5, 0.49, 0.51], radius = {} }} }}, thickness = {} }} }}",
        radius * voxel,
        t * voxel
    );
    let want = 4.0 / 3.0 * PI * (radius.powi(3) - (radius - t).powi(3));
    assert_close(scene_solid("ball-wall", &text, 9).voxel_count(), want, 0.002, "ball's shell");
}

#[test]
fn offset_nodes_refuse_bad_distances_where_the_scene_writes_them() {
    let dir = common::scratch_dir("offset", "bad-nodes");
    let path = dir.join("scene.toml");
    let cases = [
        ("{ shell = { solid = { sphere = { center = [0, 0, 0], radius = 1 } }, thickness = -1 } }", "thickness"),
        ("{ offset = { solid = { sphere = { center = [0, 0, 0], radius = 1 } }, by = 1, voxels = 2 } }", "one of by"),
        (
            "{ round = { solid = { sphere = { center = [0, 0, 0], radius = 1 } }, radius = 1, convex = false, \
          concave = false } }",
            "convex edges, concave edges or both",
        ),
    ];
    for (shape, says) in cases {
        std::fs::write(&path, format!("[[solid]]\nshape = {shape}\n")).unwrap();
        let e = build_solid(&path, None, &VoxelizeOptions::default()).unwrap_err().to_string();
        assert!(e.contains("scene.toml:2:") && e.contains(says), "{e}");
    }
}

#[test]
fn an_offset_node_in_a_pattern_is_made_once_in_its_own_frame() {
    // Two copies of a grown box along x, 0.5 apart (32 voxels): the copies are the
    // node's solid moved, so each is the other moved by 32 voxels, and the first is
    // the node resolved in the domain (the node's own lattice is the domain's there).
    let depth = 6;
    let text = "{ array = { shape = { offset = { solid = { box = { center = [0.25, 0.5, 0.5], size = [0.2, 0.2, 0.2] } }, \
                by = 0.05 } }, count = [2, 1, 1], step = [0.5, 0, 0] } }";
    let built = scene_solid("pattern", text, depth);
    let d = unit_domain(depth);
    let left = built
        .intersection(
            &voxelize(
                &Cuboid::new(DVec3::new(0.25, 0.5, 0.5), DVec3::splat(0.5)).unwrap(),
                d,
                &VoxelizeOptions::default(),
            )
            .unwrap(),
        )
        .unwrap();
    let right = built.difference(&left).unwrap();
    assert!(left.voxel_count() > 0 && left.voxel_count() == right.voxel_count());
    assert!(left.translate([32, 0, 0]).keys() == right.keys());
    let alone = "{ offset = { solid = { box = { center = [0.25, 0.5, 0.5], size = [0.2, 0.2, 0.2] } }, by = 0.05 } }";
    assert!(scene_solid("pattern-alone", alone, depth).keys() == left.keys());
}

#[test]
fn the_offset_example_of_the_scene_docs_is_its_commands_run_in_turn() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/SCENES.md")).unwrap();
    let after = doc.split("parsed and built by tests/offset.rs").nth(1).expect("the marker");
    let block = after.split("```toml\n").nth(1).expect("a toml block").split("```").next().unwrap();
    let path = common::scratch_dir("offset", "docs-example").join("tray.toml");
    std::fs::write(&path, block).unwrap();
    let built = build_solid(&path, None, &VoxelizeOptions::default()).unwrap();
    // The tray's child voxelized in the scene's domain, its wall outward, then rounded.
    let (_, domain) = octsolid::scene_file::build_shape(&path, None, octsolid::MemoryBudget::default()).unwrap();
    let tub: Csg = Csg::from(Cuboid::new(DVec3::ZERO, DVec3::new(4.0, 3.0, 1.0)).unwrap())
        - Cuboid::new(DVec3::new(0.0, 0.0, 0.6), DVec3::new(3.6, 2.6, 1.0)).unwrap();
    let tree = voxelize(&tub, domain, &VoxelizeOptions::default()).unwrap();
    let data = HermiteData::from_shape(&tub, &tree);
    let (per, options) = (domain.voxels_per_unit(), OffsetOptions::default());
    let (wall, data) = shell_with_surface(&tree, &data, 0.2 * per, true, &options).unwrap();
    let want = round_with_surface(&wall, &data, 0.05 * per, true, true, &options).unwrap().0;
    assert!(built.voxel_count() > 0 && built.keys() == want.keys());
}

#[test]
fn shells_and_rounds_over_the_budget_are_refused_before_any_step_runs() {
    // Issue 39, point 3: the largest step's estimate is checked before the first step,
    // so a round whose first step fits but whose other does not starts no work.
    use octsolid::{Error, MemoryBudget};
    let ball = Sphere::new(DVec3::new(0.45, 0.5, 0.55), 0.3).unwrap();
    let (tree, data) = with_surface(&ball, 7);
    let r = 6.0;
    for along_surface in [false, true] {
        let (shrink, grow) = (tree.offset_estimate(-r, along_surface), tree.offset_estimate(r, along_surface));
        // The two steps' bands differ (the ball's inside and outside), so a budget
        // under the larger lets the smaller through: a round starting with it would
        // have run a step before this check.
        assert!(shrink != grow && shrink.min(grow) > 0, "{shrink} {grow}");
        let largest = shrink.max(grow);
        let budget = MemoryBudget(largest - 1);
        // Every operation (shells inward and outward, rounds convex then concave or
        // concave alone) is refused naming the largest estimate and the budget.
        for (job, op) in [(0, "shell in"), (1, "shell out"), (2, "round convex"), (3, "round concave")] {
            let progress = common::Recorder::default();
            let options = OffsetOptions { budget, progress: &progress, ..OffsetOptions::default() };
            let result = match (job, along_surface) {
                (0 | 1, false) => tree.shell(r, job == 1, &options),
                (2 | 3, false) => tree.round(r, job == 2, true, &options),
                (0 | 1, true) => shell_with_surface(&tree, &data, r, job == 1, &options).map(|s| s.0),
                _ => round_with_surface(&tree, &data, r, job == 2, true, &options).map(|s| s.0),
            };
            let step = match job {
                0 => shrink,
                1 => grow,
                _ => largest,
            };
            if step < largest {
                // A shell's one step fits: it runs.
                assert!(result.is_ok(), "{op}: {result:?}");
                continue;
            }
            let e = result.expect_err(op);
            assert!(
                matches!(e, Error::OverBudget { estimate, budget: b, .. } if estimate == largest && b == largest - 1),
                "{op}: {e}"
            );
            let message = e.to_string();
            assert!(
                message.contains(&format!("{largest} bytes")) && message.contains(&format!("{} bytes", largest - 1)),
                "{message}"
            );
            assert_eq!(progress.read().0, 0, "{op} (along the surface: {along_surface}) started a step");
        }
    }
}

#[test]
fn a_coarse_solid_at_a_fine_depth_is_refused_while_its_band_is_counted() {
    // A cube of 8 nodes at depth 21: 6.6e12 voxel faces, a band of terabytes. Its tile
    // lists used to be made whole before the estimate (an abort out of memory); they are
    // counted as they grow and the step refused once they pass the budget.
    use octsolid::{Error, MemoryBudget};
    let cube = Cuboid::new(DVec3::splat(0.5), DVec3::splat(0.25)).unwrap();
    let tree = voxelize(&cube, unit_domain(2), &VoxelizeOptions::default()).unwrap().refine(21).unwrap();
    assert!(tree.depth() == 21 && tree.node_count() < 100, "{} nodes", tree.node_count());
    let budget = MemoryBudget(64 << 20);
    let options = OffsetOptions { budget, ..OffsetOptions::default() };
    for r in [3.0, -3.0] {
        let e = tree.offset(r, &options).unwrap_err();
        assert!(matches!(e, Error::OverBudget { estimate, .. } if estimate > budget.0), "{r}: {e}");
    }
    // Shrinking, its volume alone bounds its surface (1.3e12 voxel faces at least, the
    // isoperimetric inequality; it has 1.6e12): refused at once with that bound (770
    // GiB), before a tile is listed (listing the faces of its big nodes took 20 s at 1
    // GiB on a depth-21 sphere).
    let e = tree.offset(-3.0, &options).unwrap_err();
    assert!(matches!(e, Error::OverBudget { estimate, .. } if estimate > 1 << 38), "{e}");
    let e = tree.shell(2.0, false, &options).unwrap_err();
    assert!(matches!(e, Error::OverBudget { estimate, .. } if estimate > 1 << 38), "{e}");
    assert!(e.to_string().contains("shell of 2 voxels"), "{e}");
    let e = tree.shell(2.0 / 3.0, false, &options).unwrap_err();
    assert!(e.to_string().contains("shell of 0.667 voxels"), "{e}");
}

/// Issue 39: a bore's rim, the convex edge where a box's top face meets a cylindrical
/// bore's wall, grown by `D` along the surface is the round of radius `D` around the
/// rim circle (a quarter of a torus): the result's crossings near it lie `D` from the
/// solid, with the distance's gradient as their normal. (The faces next to the rim
/// took the normal of the end nearest the face's axis, snapping the round's normals
/// towards the axes: 21 degrees off at worst, 3 on average, at 2.4 voxels.)
#[test]
fn along_the_surface_a_grown_rim_is_the_round_of_radius_d_around_it() {
    use octsolid::shape::{Axis, Cylinder};
    let n = 128.0;
    // In voxels: the box's centre and half side, the bore's radius.
    let (c, half, bore) = (DVec3::new(64.3, 63.8, 64.2), 40.0, 20.3);
    let top = c.z + half;
    let part = Cuboid::new(c / n, DVec3::splat(2.0 * half / n)).unwrap()
        - Cylinder::new(c / n, Axis::Z, bore / n, 3.0 * half / n).unwrap();
    let (tree, data) = with_surface(&part, 7);
    // The distance from the solid near the rim and its gradient.
    let field = |q: DVec3| -> (f64, DVec3) {
        let radial = DVec3::new(q.x - c.x, q.y - c.y, 0.0);
        let r = radial.length();
        let radial = radial / r;
        if q.z < top {
            (bore - r, -radial)
        } else if r >= bore {
            (q.z - top, DVec3::Z)
        } else {
            let away = q - (DVec3::new(c.x, c.y, top) + radial * bore);
            (away.length(), away.normalize())
        }
    };
    let mut stats = Vec::new();
    for d in [2.4, 3.3, 6.7] {
        let (_, grown) = offset_with_surface(&tree, &data, d, &OffsetOptions::default()).unwrap();
        let (mut worst, mut worst_angle, mut sum, mut sum_angle, mut count) = (0.0f64, 0.0f64, 0.0, 0.0, 0);
        for &(key, crossing) in grown.faces() {
            let q = crossing.point(key);
            let r = DVec3::new(q.x - c.x, q.y - c.y, 0.0).length();
            if (r - bore).hypot((q.z - top).max(0.0)) > 2.0 * d || q.z < top - 2.0 * d {
                continue;
            }
            let (dist, gradient) = field(q);
            let angle = crossing.normal.as_dvec3().dot(gradient).clamp(-1.0, 1.0).acos().to_degrees();
            worst = worst.max((dist - d).abs());
            worst_angle = worst_angle.max(angle);
            sum += (dist - d).abs();
            sum_angle += angle;
            count += 1;
        }
        let (mean, mean_angle) = (sum / f64::from(count), sum_angle / f64::from(count));
        eprintln!(
            "rim grown by {d}: {count} crossings, |dist - D| worst {worst:.3} mean {mean:.4} voxels, \
             normal worst {worst_angle:.1} mean {mean_angle:.2} degrees"
        );
        stats.push((d, count, worst, mean, worst_angle, mean_angle));
    }
    for (d, count, worst, mean, worst_angle, mean_angle) in stats {
        assert!(count > 1000, "{d}: {count} crossings near the rim");
        assert!(worst < 0.25 && mean < 0.05, "{d}: distance off D by {worst} at worst, {mean} on average");
        assert!(
            worst_angle < 15.0 && mean_angle < 2.0,
            "{d}: normal off by {worst_angle} degrees, {mean_angle} on average"
        );
    }
}
