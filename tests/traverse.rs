//! Ray traversal against a brute-force oracle: slab tests on every node, then on every
//! voxel of the node entered first, with the same semantics (first entry into the
//! interior of a full voxel; half-open cells for axis-parallel rays; lowest axis on ties).

mod common;

use common::{Rng, random_octree};
use glam::DVec3;
use octsolid::morton;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::{Camera, PACKET, TILE, Traversal, Tree64};
use octsolid::samples;
use octsolid::{Ray, RayCast};

/// Entry and exit times of the ray (voxel units) through the box `[lo, lo + size)`,
/// and the lowest axis whose entry plane gives the entry time.
fn slab(o: DVec3, d: DVec3, lo: [u32; 3], size: u32) -> Option<(f64, f64, Option<usize>)> {
    let (mut tn, mut tf, mut face) = (f64::NEG_INFINITY, f64::INFINITY, None);
    for a in 0..3 {
        let (l, h) = (f64::from(lo[a]), f64::from(lo[a] + size));
        if d[a] == 0.0 {
            if o[a] < l || o[a] >= h {
                return None;
            }
            continue;
        }
        let inv = 1.0 / d[a];
        let (t0, t1) =
            if d[a] > 0.0 { ((l - o[a]) * inv, (h - o[a]) * inv) } else { ((h - o[a]) * inv, (l - o[a]) * inv) };
        if t0 > tn {
            tn = t0;
            face = Some(a);
        }
        tf = tf.min(t1);
    }
    (tn < tf && tf > 0.0).then_some((tn, tf, face))
}

/// The oracle: (t, voxel, face) of the first hit.
fn brute_force(tree: &LinearOctree, o: DVec3, d: DVec3) -> Option<(f64, [u32; 3], Option<usize>)> {
    let node = tree
        .nodes()
        .filter_map(|n| slab(o, d, n.min, n.size).map(|(tn, _, _)| (tn, n)))
        .min_by(|a, b| a.0.total_cmp(&b.0))?
        .1;
    let mut best: Option<(f64, [u32; 3], Option<usize>)> = None;
    for x in 0..node.size {
        for y in 0..node.size {
            for z in 0..node.size {
                let v = [node.min[0] + x, node.min[1] + y, node.min[2] + z];
                if let Some((tn, _, face)) = slab(o, d, v, 1)
                    && best.is_none_or(|b| tn < b.0)
                {
                    best = Some((tn, v, face));
                }
            }
        }
    }
    best.map(|(tn, v, face)| if tn <= 0.0 { (0.0, v, None) } else { (tn, v, face) })
}

/// Rays of every kind the tests need, in voxel units of a domain of `n` voxels a side.
fn rays(rng: &mut Rng, n: f64, count: usize) -> Vec<(DVec3, DVec3)> {
    let mut out = Vec::with_capacity(count);
    let lattice = |rng: &mut Rng| {
        DVec3::new(rng.below(n as u64 + 1) as f64, rng.below(n as u64 + 1) as f64, rng.below(n as u64 + 1) as f64)
    };
    for i in 0..count {
        let ray = match i % 6 {
            // From outside towards a random point inside.
            0 => {
                let o = rng.vec(-0.5 * n, 1.5 * n);
                (o, rng.vec(0.0, n) - o)
            }
            // From inside, any direction.
            1 => (rng.vec(0.0, n), rng.vec(-1.0, 1.0)),
            // Axis-parallel through voxel centres and along lattice planes.
            2 => {
                let mut d = DVec3::ZERO;
                d[i % 3] = if rng.below(2) == 0 { 1.0 } else { -1.0 };
                let mut o = lattice(rng) + if rng.below(2) == 0 { DVec3::splat(0.5) } else { DVec3::ZERO };
                o[i % 3] = if d[i % 3] > 0.0 { -1.0 } else { n + 1.0 };
                (o, d)
            }
            // Diagonals through lattice corners (ties of two or three planes).
            3 => {
                let d = DVec3::new(
                    if rng.below(2) == 0 { 1.0 } else { -1.0 },
                    if rng.below(2) == 0 { 1.0 } else { -1.0 },
                    if rng.below(3) == 0 {
                        0.0
                    } else if rng.below(2) == 0 {
                        1.0
                    } else {
                        -1.0
                    },
                );
                (lattice(rng) - d * (n + 2.0), d)
            }
            // Grazing: almost parallel to a face.
            4 => {
                let mut d = rng.vec(-1e-3, 1e-3);
                d[i % 3] = 1.0;
                let mut o = rng.vec(0.0, n);
                o[i % 3] = -1.0;
                (o, d)
            }
            // Integer origins and small integer directions (exact plane hits).
            _ => {
                let d = DVec3::new(rng.below(5) as f64 - 2.0, rng.below(5) as f64 - 2.0, rng.below(5) as f64 - 2.0);
                (lattice(rng), if d == DVec3::ZERO { DVec3::X } else { d })
            }
        };
        out.push(ray);
    }
    out
}

/// `tree`'s keys in the domain `[0, n]^3` of its depth, `n` its resolution: a voxel of
/// edge 1, so a world ray there is the voxel ray the brute force walks (the corner 0
/// and the scale 1 change no bit).
fn in_voxel_units(tree: &LinearOctree) -> LinearOctree {
    let n = f64::from(tree.domain().resolution());
    let domain = Domain::new(DVec3::ZERO, n, tree.depth()).unwrap();
    LinearOctree::from_keys(domain, tree.keys().to_vec()).unwrap()
}

fn check(tree: &LinearOctree, rng: &mut Rng, count: usize) {
    let t = Traversal::new(tree);
    let voxel_units = Traversal::new(&in_voxel_units(tree));
    let n = f64::from(tree.domain().resolution());
    for (o, d) in rays(rng, n, count) {
        let got = voxel_units.hit(&Ray::new(o, d));
        let want = brute_force(tree, o, d);
        // The same ray in world units (a power-of-two scale: the same walk), which is
        // first tested against the full voxels' box in world space.
        if tree.domain().min() == DVec3::ZERO && tree.domain().edge() == 1.0 {
            let world = Ray::new(o / n, d);
            assert_eq!(t.hit(&world).map(|h| (h.voxel, h.axis)), got.map(|h| (h.voxel, h.axis)), "world ray {o} {d}");
            assert_eq!(t.occluded(&world), got.is_some(), "world ray {o} {d}");
        }
        match (got, want) {
            (None, None) => {}
            (Some(h), Some((tw, vw, fw))) => {
                assert!((h.t - tw).abs() * d.length() <= 1e-9 * n, "t {} vs {tw} for {o} {d}", h.t);
                assert_eq!((h.voxel, h.axis.map(usize::from)), (vw, fw), "voxel/face for ray {o} {d}");
            }
            _ => panic!("hit {got:?} vs brute force {want:?} for ray {o} {d}"),
        }
    }
}

#[test]
fn traversal_matches_brute_force_on_random_solids() {
    let mut rng = Rng(0xdead_beef);
    for depth in 1..=5 {
        for _ in 0..6 {
            let d = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
            let tree = random_octree(&mut rng, d);
            check(&tree, &mut rng, 600);
        }
    }
}

#[test]
fn traversal_matches_brute_force_on_solids_in_a_corner_of_their_domain() {
    // The walk starts where a ray enters the box of the full voxels and skips rays that
    // miss it: random solids cut to a random box, rays of every kind and rays from and
    // along that box's planes.
    let mut rng = Rng(0x0cc0_b1ed);
    for depth in 3..=6 {
        for _ in 0..8 {
            let d = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
            let n = d.resolution();
            let lo = [0; 3].map(|_| rng.below(u64::from(n / 2)) as u32);
            let hi = lo.map(|l| l + 1 + rng.below(u64::from(n - l)) as u32);
            let cells =
                (lo[0]..hi[0]).flat_map(|x| (lo[1]..hi[1]).flat_map(move |y| (lo[2]..hi[2]).map(move |z| [x, y, z])));
            let window = LinearOctree::from_voxels(d, cells).unwrap();
            let tree = random_octree(&mut rng, d).intersection(&window).unwrap();
            check(&tree, &mut rng, 400);
            let Some((blo, bhi)) = tree.voxel_bounds() else { continue };
            let t = Traversal::new(&tree);
            let voxel_units = Traversal::new(&in_voxel_units(&tree));
            for _ in 0..400 {
                // From a point of one of the box's planes, or a lattice point beside it.
                let a = rng.below(3) as usize;
                let mut o = rng.vec(-1.0, f64::from(n) + 1.0);
                o[a] = f64::from(if rng.below(2) == 0 { blo[a] } else { bhi[a] });
                if rng.below(2) == 0 {
                    o = o.round();
                }
                let mut dir = rng.vec(-1.0, 1.0);
                if rng.below(3) == 0 {
                    dir[a] = 0.0; // along the plane
                }
                if dir == DVec3::ZERO {
                    continue;
                }
                let got = voxel_units.hit(&Ray::new(o, dir)).map(|h| (h.voxel, h.axis.map(usize::from)));
                let brute = brute_force(&tree, o, dir);
                let want = brute.map(|(_, v, f)| (v, f));
                assert_eq!(got, want, "ray {o} {dir}, box {blo:?}..{bhi:?}");
                // The world ray of the unit domain (scaled by a power of two: the same walk).
                let world = Ray::new(o / f64::from(n), dir);
                assert_eq!(t.occluded(&world), want.is_some(), "any hit, ray {o} {dir}");
                // Limited rays (the walk stops at the box's exit or the limit, whichever
                // comes first): a hit only before the limit (world time = voxel time / n).
                let limit = rng.range(0.0, 3.0);
                let hit_t = brute.map(|(tv, _, _)| tv / f64::from(n));
                if hit_t.is_none_or(|th| (th - limit).abs() > 1e-9) {
                    let want = hit_t.is_some_and(|th| th < limit);
                    assert_eq!(t.occluded(&world.until(limit)), want, "ray {o} {dir} until {limit}");
                    assert_eq!(t.hit(&world.until(limit)).is_some(), want, "ray {o} {dir} until {limit}");
                }
            }
        }
    }
}

#[test]
fn traversal_matches_brute_force_on_the_showcase_at_depth_6() {
    let mut rng = Rng(42);
    let d = samples::showcase_domain(6).unwrap();
    let tree = voxelize(&samples::showcase(), d, &VoxelizeOptions::default()).unwrap();
    check(&tree, &mut rng, 3000);
    check(&LinearOctree::full(d), &mut rng, 300);
    check(&LinearOctree::empty(d), &mut rng, 100);
}

#[test]
fn world_rays_and_deep_trees() {
    // A depth-21 solid: one voxel at the far corner, hit exactly.
    let d = Domain::new(DVec3::splat(-1.0), 2.0, 21).unwrap();
    let last = (1u32 << 21) - 1;
    let tree = LinearOctree::from_voxels(d, [[last, last, last]]).unwrap();
    let t = Traversal::new(&tree);
    let h = d.voxel_size();
    let target = d.voxel_center([last; 3]);
    let origin = target - DVec3::new(0.0, 0.0, 3.0);
    let hit = t.hit(&Ray::new(origin, DVec3::Z)).expect("hit");
    assert_eq!((hit.voxel, hit.axis), ([last; 3], Some(2)));
    assert!((hit.t - (3.0 - 0.5 * h)).abs() < 1e-12, "{}", hit.t);
    // Bytes: 21 inner nodes on the path, 8 bytes each.
    assert_eq!(t.node_count(), 21);
    let _ = morton::encode(0, 0, 0);
}

#[test]
fn non_finite_rays_hit_nothing() {
    let d = Domain::new(DVec3::ZERO, 1.0, 3).unwrap();
    let solids = [LinearOctree::full(d), LinearOctree::from_voxels(d, [[3, 4, 5]]).unwrap()];
    let centre = DVec3::splat(0.5);
    let rays = [
        (DVec3::new(f64::NAN, 0.5, 0.5), DVec3::X),
        (DVec3::new(-1.0, f64::INFINITY, 0.5), DVec3::X),
        (centre, DVec3::new(f64::NEG_INFINITY, 0.0, 0.0)),
        (centre, DVec3::new(1.0, f64::NAN, 0.0)),
    ];
    for tree in &solids {
        let t = Traversal::new(tree);
        for (o, dir) in rays {
            assert_eq!(t.hit(&Ray::new(o, dir)), None, "{o} {dir}");
            assert!(!t.occluded(&Ray::new(o, dir)), "{o} {dir}");
        }
        // The same solid is hit by a finite ray through its voxel, but not before a
        // NaN limit, whether or not the ray runs along an axis.
        let v = d.voxel_center([3, 4, 5]);
        assert!(t.hit(&Ray::new(v - DVec3::X, DVec3::X)).is_some());
        for dir in [DVec3::X, DVec3::new(1.0, 0.1, 0.1)] {
            let ray = Ray::new(v, dir).until(f64::NAN);
            assert_eq!(t.hit(&ray), None, "{dir} until NaN");
            assert!(!t.occluded(&ray), "{dir} until NaN");
        }
    }
}

/// Packets of rays of every kind (camera tiles, small bundles from one point, the
/// oracle suite's rays in groups) against single rays: `hit_packet` must give the bits
/// of `hit` for every ray, whatever its `t_max`.
#[test]
fn packets_match_single_rays() {
    let mut rng = Rng(0x5eed);
    let mut trees = Vec::new();
    for depth in [3, 5, 6] {
        let d = Domain::new(DVec3::new(-0.5, 0.25, 1.0), 1.5, depth).unwrap();
        trees.push(random_octree(&mut rng, d));
    }
    let d6 = samples::showcase_domain(6).unwrap();
    trees.push(voxelize(&samples::showcase(), d6, &VoxelizeOptions::default()).unwrap());
    trees.push(LinearOctree::full(d6));
    trees.push(LinearOctree::empty(d6));
    for tree in &trees {
        let t = Traversal::new(tree);
        let d = tree.domain();
        let (c, edge) = (d.min() + DVec3::splat(0.5 * d.edge()), d.edge());
        let mut packets: Vec<Vec<Ray>> = Vec::new();
        // Tiles of cameras around and inside the domain.
        for _ in 0..40 {
            let eye = c + rng.vec(-1.5, 1.5) * edge;
            let camera = Camera::look_at(eye, c + rng.vec(-0.3, 0.3) * edge, DVec3::Z, 40.0);
            let n = 64.0;
            let (c0, r0) = (rng.below(56) as f64, rng.below(56) as f64);
            packets.push(
                (0..PACKET)
                    .map(|i| {
                        let (x, y) = (c0 + (i % TILE) as f64 + 0.5, r0 + (i / TILE) as f64 + 0.5);
                        camera.ray(2.0 * x / n - 1.0, 1.0 - 2.0 * y / n, 1.0)
                    })
                    .collect(),
            );
        }
        // The oracle suite's rays (voxel units moved to world units) in small groups.
        let h = d.voxel_size();
        let n = f64::from(d.resolution());
        let odd: Vec<Ray> = rays(&mut rng, n, 600).into_iter().map(|(o, dir)| Ray::new(d.min() + o * h, dir)).collect();
        packets.extend(odd.chunks(5).map(<[_]>::to_vec));
        packets.push(odd[..150].to_vec());
        for rays in &packets {
            let rays: Vec<Ray> =
                rays.iter().map(|r| if rng.below(3) == 0 { r.until(rng.range(0.0, 3.0) * edge) } else { *r }).collect();
            let mut got = vec![None; rays.len()];
            t.hit_packet(&rays, &mut got);
            for (ray, got) in rays.iter().zip(&got) {
                assert_eq!(*got, t.hit(ray), "ray {ray:?}");
            }
        }
    }
}

/// The 64-tree's walk against the traversal octree's, bit for bit (time, voxel, face),
/// and any-hit answers against it, on the world rays of `tree`'s own domain and on the
/// voxel-unit rays `rays` (also against the brute force where the node it would search
/// holds at most `16^3` voxels and the direction's reciprocal is finite).
fn check_tree64(tree: &LinearOctree, rays: &[(DVec3, DVec3)], rng: &mut Rng) {
    let units = in_voxel_units(tree);
    let (walk, tree64) = (Traversal::new(&units), Tree64::new(&units));
    let small = units.nodes().all(|n| n.size <= 16);
    for &(o, d) in rays {
        let ray = Ray::new(o, d);
        let ray = if rng.below(5) == 0 {
            ray.until(rng.range(0.0, 2.0) * f64::from(tree.domain().resolution()))
        } else {
            ray
        };
        let got = tree64.hit(&ray);
        same_hit(got, walk.hit(&ray), &ray);
        assert_eq!(tree64.occluded(&ray), walk.occluded(&ray), "any hit, ray {ray:?}");
        assert_eq!(tree64.occluded(&ray), got.is_some(), "any hit, ray {ray:?}");
        // (A subnormal direction follows the walk's rule of `off_lattice`, not the
        // brute force's: a plane through the origin is behind the ray.)
        if small && ray.t_max == f64::INFINITY && (DVec3::ONE / d).is_finite() {
            let want = brute_force(&units, o, d);
            assert_eq!(got.map(|h| (h.voxel, h.axis.map(usize::from))), want.map(|(_, v, f)| (v, f)), "ray {o} {d}");
        }
    }
    // The same solid in a domain of its own (world units, the reach test first).
    let (walk, tree64) = (Traversal::new(tree), Tree64::new(tree));
    let d = tree.domain();
    let h = d.voxel_size();
    for &(o, dir) in rays.iter().step_by(3) {
        let ray = Ray::new(d.min() + o * h, dir);
        same_hit(tree64.hit(&ray), walk.hit(&ray), &ray);
        assert_eq!(tree64.occluded(&ray), walk.occluded(&ray), "world ray {ray:?}");
    }
}

/// The 64-tree's hit `got` is the walk's `want`, bit for bit, but where the direction
/// is subnormal on an axis: there the walks keep the ray on the low side of a plane
/// through the origin (`off_lattice`), and the voxel of a hit is placed by the position
/// (`VoxelRay::entry`), clamped to the full node entered, which may be finer in the
/// 64-tree (the rule in its walk's module doc): the time, the face and the voxel on
/// every other axis are the same.
fn same_hit(got: Option<octsolid::render::Hit>, want: Option<octsolid::render::Hit>, ray: &Ray) {
    let subnormal = ray.dir.to_array().map(|x| x != 0.0 && (1.0 / x).is_infinite());
    if !subnormal.contains(&true) {
        assert_eq!(got, want, "ray {ray:?}");
        return;
    }
    let strip = |h: Option<octsolid::render::Hit>| {
        h.map(|mut h| {
            for a in (0..3).filter(|&a| subnormal[a]) {
                h.voxel[a] = 0;
            }
            h
        })
    };
    assert_eq!(strip(got), strip(want), "ray {ray:?}");
}

/// A solid of small nodes and voxels crowded into a random box of at most 48 voxels a
/// side, and a few large nodes elsewhere: deep trees whose rays meet many levels.
fn crowded_octree(rng: &mut Rng, domain: Domain) -> LinearOctree {
    let n = domain.resolution();
    let side = n.min(48);
    let lo = [0; 3].map(|_| rng.below(u64::from(n - side + 1)) as u32);
    let mut nodes = Vec::new();
    for _ in 0..300 {
        let k = rng.below(u64::from(domain.depth().min(3))) as u32;
        let min: [u32; 3] = std::array::from_fn(|a| (lo[a] + rng.below(u64::from(side)) as u32) >> k << k);
        nodes.push(octsolid::octree::Node { level: domain.depth() - k as u8, min, size: 1 << k });
    }
    for _ in 0..rng.below(4) {
        let k = rng.below(u64::from(domain.depth())) as u32;
        let min = [0; 3].map(|_| (rng.below(u64::from(n >> k)) as u32) << k);
        nodes.push(octsolid::octree::Node { level: domain.depth() - k as u8, min, size: 1 << k });
    }
    LinearOctree::from_nodes(domain, nodes).unwrap()
}

/// Rays aimed at the solid's own nodes (`rays`' kinds miss a small solid in a deep
/// domain): from outside or inside, to a node's centre, corner or a point of its face,
/// along axes through it, and starting inside it.
fn rays_at_nodes(rng: &mut Rng, tree: &LinearOctree, count: usize) -> Vec<(DVec3, DVec3)> {
    let nodes: Vec<_> = tree.nodes().collect();
    let n = f64::from(tree.domain().resolution());
    if nodes.is_empty() {
        return Vec::new();
    }
    (0..count)
        .map(|i| {
            let node = nodes[rng.below(nodes.len() as u64) as usize];
            let lo = DVec3::from(node.min.map(f64::from));
            let s = f64::from(node.size);
            let target = match i % 3 {
                0 => lo + DVec3::splat(0.5 * s),
                1 => lo,
                _ => lo + rng.vec(0.0, s).floor(),
            };
            match i % 5 {
                0 | 1 => {
                    let o = rng.vec(-0.2 * n, 1.2 * n);
                    (o, target - o)
                }
                2 => {
                    let mut d = DVec3::ZERO;
                    let a = rng.below(3) as usize;
                    d[a] = if rng.below(2) == 0 { 1.0 } else { -1.0 };
                    let mut o = target;
                    o[a] = if d[a] > 0.0 { -1.0 } else { n + 1.0 };
                    (o, d)
                }
                3 => (lo + rng.vec(0.0, s), rng.vec(-1.0, 1.0)),
                _ => (target - DVec3::new(1.0, 1.0, 1.0) * rng.range(1.0, 2.0 * s + 2.0), DVec3::ONE),
            }
        })
        .collect()
}

#[test]
fn tree64_matches_the_walk_and_brute_force_at_depths_1_to_12() {
    let mut rng = Rng(0x6464_6464);
    for depth in 1..=12u8 {
        let d = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
        let solids = if depth <= 6 { 6 } else { 2 };
        let count = if depth <= 6 { 400 } else { 150 };
        for i in 0..solids {
            let tree = if depth <= 5 || i % 2 == 1 { random_octree(&mut rng, d) } else { crowded_octree(&mut rng, d) };
            let n = f64::from(d.resolution());
            let mut all = rays(&mut rng, n, count);
            all.extend(rays_at_nodes(&mut rng, &tree, count));
            check_tree64(&tree, &all, &mut rng);
        }
        let n = f64::from(d.resolution());
        let few = rays(&mut rng, n, 60);
        check_tree64(&LinearOctree::full(d), &few, &mut rng);
        check_tree64(&LinearOctree::empty(d), &few, &mut rng);
    }
    let d = samples::showcase_domain(6).unwrap();
    let tree = voxelize(&samples::showcase(), d, &VoxelizeOptions::default()).unwrap();
    let mut all = rays(&mut rng, 64.0, 1500);
    all.extend(rays_at_nodes(&mut rng, &tree, 1500));
    check_tree64(&tree, &all, &mut rng);
}

#[test]
fn tree64_matches_the_walk_on_subnormal_nan_and_axis_rays() {
    let mut rng = Rng(0x5ab_0e11);
    let tiny = f64::from_bits(1); // the least subnormal
    for depth in [3u8, 4, 7, 8] {
        let d = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
        let tree = random_octree(&mut rng, d);
        let n = f64::from(d.resolution());
        let mut all = Vec::new();
        for _ in 0..300 {
            let o = match rng.below(3) {
                0 => rng.vec(0.0, n).floor(),
                1 => rng.vec(0.0, n).floor() + DVec3::splat(0.5),
                _ => rng.vec(-1.0, n + 1.0),
            };
            let pick = |rng: &mut Rng| match rng.below(6) {
                0 => 0.0,
                1 => tiny,
                2 => -tiny,
                3 => 1e-310,
                4 => -1.0,
                _ => 1.0,
            };
            let dir = DVec3::new(pick(&mut rng), pick(&mut rng), pick(&mut rng));
            if dir != DVec3::ZERO {
                all.push((o, dir));
            }
        }
        all.push((DVec3::splat(0.5), DVec3::new(f64::NAN, 1.0, 0.0)));
        all.push((DVec3::new(f64::NAN, 0.5, 0.5), DVec3::X));
        check_tree64(&tree, &all, &mut rng);
    }
}

#[test]
fn tree64_takes_no_more_bytes_than_the_traversal_octree() {
    // On a solid of many levels (the showcase at depth 8): a lowest 64-tree node, one
    // word, stands for an octree node and its inner children (8 bytes each), an upper
    // one, three words, for an octree node and its inner children above them.
    let d = samples::showcase_domain(8).unwrap();
    let tree = voxelize(&samples::showcase(), d, &VoxelizeOptions::default()).unwrap();
    let (walk, tree64) = (Traversal::new(&tree), Tree64::new(&tree));
    assert!(tree64.bytes() <= walk.bytes(), "{} against {} bytes", tree64.bytes(), walk.bytes());
}
