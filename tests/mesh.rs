//! Mesh voxelization against exact mesh volumes and brute-force voxel-centre
//! classification; polygon tables; triangle-box overlap against sampling.

mod common;

use common::{Recorder, Rng};
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::mesh::generate::{box_with_hole, cuboid, icosphere, torus};
use octsolid::mesh::*;
use octsolid::morton;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions};
use octsolid::{Error, import};

fn domain_for(mesh: &TriangleMesh, depth: u8) -> Domain {
    Domain::around(&mesh.bounds(), 0.03, depth).unwrap()
}

fn closed_meshes() -> Vec<(&'static str, TriangleMesh)> {
    vec![
        ("icosphere", icosphere(DVec3::new(0.1, -0.2, 0.05), 1.0, 3)),
        ("torus", torus(1.0, 0.35, 48, 24)),
        ("box with a hole", box_with_hole(0.4, 1.0)),
    ]
}

/// Asserts two solids are equal, reporting how many voxels differ (not the lists).
/// The exact winding number of `mesh` at `p`, the oracle: every triangle's signed
/// solid angle (Van Oosterom and Strackee) summed, over `4 pi`.
fn exact_winding(mesh: &TriangleMesh, p: DVec3) -> f64 {
    let solid_angle = |t: [u32; 3]| {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize] - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        2.0 * a.dot(b.cross(c)).atan2(den)
    };
    mesh.triangles.iter().map(|&t| solid_angle(t)).sum::<f64>() / (4.0 * std::f64::consts::PI)
}

fn assert_same(a: &LinearOctree, b: &LinearOctree, what: &str) {
    let differ = (a ^ b).voxel_count();
    assert!(differ == 0, "{what}: {differ} voxels differ ({} vs {})", a.voxel_count(), b.voxel_count());
}

fn voxelize(mesh: &TriangleMesh, depth: u8, inside: InsideRule) -> (LinearOctree, MeshVoxelizeStats) {
    let options = MeshVoxelizeOptions { inside, ..Default::default() };
    let (tree, stats) = voxelize_mesh(mesh, domain_for(mesh, depth), &options).unwrap();
    tree.validate().unwrap();
    (tree, stats)
}

#[test]
fn generated_meshes_are_closed_with_known_volumes() {
    for (name, mesh) in closed_meshes() {
        let report = PolygonTables::new(&mesh).report();
        assert!(report.watertight, "{name}: {report:?}");
        assert_eq!(report.degenerate_faces, 0);
        assert!(report.volume > 0.0, "{name} is inside out");
    }
    let frame = PolygonTables::new(&box_with_hole(0.4, 1.0)).report();
    assert!((frame.volume - 3.36).abs() < 1e-12);
    assert!((frame.area - (2.0 * 3.36 + 8.0 + 3.2)).abs() < 1e-12);
    // Euler characteristic V - E + F = 2 - 2 genus: 2 for the sphere, 0 for the frame.
    let euler = |r: &MeshReport| r.vertices as i64 - r.edges as i64 + r.triangles as i64;
    assert_eq!(euler(&PolygonTables::new(&icosphere(DVec3::ZERO, 1.0, 2)).report()), 2);
    assert_eq!(euler(&frame), 0);
}

#[test]
fn a_report_holds_at_any_scale_of_the_coordinates() {
    // The frame scaled by powers of two: its area and volume scale exactly (s^2, s^3),
    // overflowing to infinity or underflowing to zero only where the true value does,
    // and no face turns degenerate. (Corners at 2^520 overflowed the squared lengths:
    // every face degenerate and a volume of NaN; at 2^-600 every face was degenerate.)
    let frame = box_with_hole(0.4, 1.0);
    let at_one = PolygonTables::new(&frame).report();
    for k in [-600, -100, 0, 100, 520, 1000] {
        let s = 2f64.powi(k);
        let mut mesh = frame.clone();
        mesh.vertices.iter_mut().for_each(|v| *v *= s);
        let report = PolygonTables::new(&mesh).report();
        assert!(report.watertight && report.degenerate_faces == 0, "2^{k}: {report:?}");
        assert_eq!(report.area, at_one.area * s * s, "2^{k}");
        assert_eq!(report.volume, at_one.volume * s * s * s, "2^{k}");
        assert_eq!(mesh.volume(), report.volume);
        assert_eq!(mesh.area(), report.area);
    }
}

#[test]
fn plane_equations_match_the_expanded_formula() {
    let mesh = icosphere(DVec3::new(1.0, 2.0, 3.0), 2.0, 1);
    let tables = PolygonTables::new(&mesh);
    for (t, plane) in tables.planes.iter().enumerate() {
        let [p1, p2, p3] = mesh.corners(t);
        let a = p1.y * (p2.z - p3.z) + p2.y * (p3.z - p1.z) + p3.y * (p1.z - p2.z);
        let b = p1.z * (p2.x - p3.x) + p2.z * (p3.x - p1.x) + p3.z * (p1.x - p2.x);
        let c = p1.x * (p2.y - p3.y) + p2.x * (p3.y - p1.y) + p3.x * (p1.y - p2.y);
        let d = -p1.x * (p2.y * p3.z - p3.y * p2.z)
            - p2.x * (p3.y * p1.z - p1.y * p3.z)
            - p3.x * (p1.y * p2.z - p2.y * p1.z);
        for (got, want) in plane.iter().zip([a, b, c, d]) {
            assert!((got - want).abs() < 1e-9, "{plane:?} vs {:?}", [a, b, c, d]);
        }
        for p in [p1, p2, p3] {
            assert!((plane[0] * p.x + plane[1] * p.y + plane[2] * p.z + plane[3]).abs() < 1e-9);
        }
    }
    // Every edge of a closed mesh has exactly two faces.
    assert!(tables.edges.iter().all(|e| e.faces.len() == 2 && e.forward == 1));
}

#[test]
fn volumes_match_the_signed_tetrahedron_volume() {
    for (name, mesh) in closed_meshes() {
        let exact = PolygonTables::new(&mesh).report().volume;
        for rule in [InsideRule::Auto, InsideRule::Winding] {
            let (tree, stats) = voxelize(&mesh, 8, rule);
            let error = tree.volume() / exact - 1.0;
            assert!(error.abs() < 0.01, "{name} {rule:?}: {} vs {exact} ({:+.3}%)", tree.volume(), error * 100.0);
            if rule == InsideRule::Auto {
                assert_eq!(stats.rule, Some(InsideRule::Parity), "{name} is watertight");
            }
        }
    }
}

/// Regression: the torus has rings of edges in the planes `x = +-y`, which hold voxel
/// centres; with float orientations a segment along such a plane slipped between two
/// triangles and one voxel flipped. Exact predicates fixed it.
#[test]
fn voxel_centres_on_planes_of_edges_classify_as_brute_force() {
    for (name, mesh) in closed_meshes() {
        // Depth 6 for parity; depth 5 for the exact winding number (every triangle at
        // every voxel centre is slow).
        let d = domain_for(&mesh, 6);
        let d5 = domain_for(&mesh, 5);
        let grid = ParityGrid::new(&mesh);
        let all = || (0..d.voxel_total()).map(morton::decode);
        let parity_oracle =
            LinearOctree::from_voxels(d, all().filter(|v| grid.crossings(d.voxel_center(*v)) % 2 == 1)).unwrap();
        let all5 = (0..d5.voxel_total()).map(morton::decode);
        let winding_oracle =
            LinearOctree::from_voxels(d5, all5.filter(|v| exact_winding(&mesh, d5.voxel_center(*v)) >= 0.5)).unwrap();
        assert_same(&voxelize(&mesh, 6, InsideRule::Parity).0, &parity_oracle, &format!("{name} parity"));
        assert_same(&voxelize(&mesh, 6, InsideRule::Winding).0, &parity_oracle, &format!("{name} winding = parity"));
        assert_same(&voxelize(&mesh, 5, InsideRule::Winding).0, &winding_oracle, &format!("{name} winding"));
    }
}

#[test]
fn winding_survives_holes_parity_does_not_need_to() {
    let closed = icosphere(DVec3::ZERO, 1.0, 4);
    let exact = PolygonTables::new(&closed).report().volume;
    let mut open = closed.clone();
    let mut rng = Rng(2024);
    open.retain_triangles(|_| rng.below(100) >= 5);
    let report = PolygonTables::new(&open).report();
    assert!(!report.watertight && report.boundary_edges > 100, "{report:?}");
    let d = domain_for(&closed, 7);
    let options = MeshVoxelizeOptions::default();
    let (tree, stats) = voxelize_mesh(&open, d, &options).unwrap();
    assert_eq!(stats.rule, Some(InsideRule::Winding), "auto picks winding for an open mesh");
    let error = tree.volume() / exact - 1.0;
    assert!(error.abs() < 0.02, "winding on the open mesh: {:+.3}%", error * 100.0);
}

#[test]
fn winding_number_is_one_inside_zero_outside() {
    let mesh = torus(1.0, 0.35, 40, 20);
    let w = WindingNumber::new(&mesh);
    for (p, want) in [
        (DVec3::new(1.0, 0.0, 0.0), 1.0),
        (DVec3::ZERO, 0.0),
        (DVec3::new(0.0, -1.1, 0.1), 1.0),
        (DVec3::splat(3.0), 0.0),
    ] {
        assert!((exact_winding(&mesh, p) - want).abs() < 1e-9, "exact at {p}");
        assert!((w.at(p) - want).abs() < 0.02, "fast at {p}: {}", w.at(p));
    }
}

#[test]
fn surface_shells_cover_the_surface_and_thin_is_6_separating() {
    let mesh = icosphere(DVec3::ZERO, 1.0, 3);
    let d = domain_for(&mesh, 6);
    let thick = voxelize_surface(&mesh, d, SurfaceKind::Conservative, &VoxelizeOptions::default()).unwrap();
    let thin = voxelize_surface(&mesh, d, SurfaceKind::Thin, &VoxelizeOptions::default()).unwrap();
    thick.validate().unwrap();
    assert!(thin.voxel_count() < thick.voxel_count() && (&thin - &thick).is_empty());
    // Every vertex lies in a shell voxel.
    assert!(mesh.vertices.iter().all(|v| thick.contains_point(*v)));
    // 6-separating: no face-neighbour pair of voxels crosses from solid inside to
    // outside without a thin-shell voxel on one side.
    let solid = voxelize(&mesh, 6, InsideRule::Parity).0;
    let n = d.resolution();
    for code in 0..d.voxel_total() {
        let v = morton::decode(code);
        for a in 0..3 {
            let mut w = v;
            w[a] += 1;
            if w[a] >= n {
                continue;
            }
            if solid.contains_voxel(v) != solid.contains_voxel(w) {
                assert!(thin.contains_voxel(v) || thin.contains_voxel(w), "leak between {v:?} and {w:?}");
            }
        }
    }
}

#[test]
fn quick_watertight_check_agrees_with_the_tables() {
    let mut rng = Rng(8);
    for (name, mesh) in closed_meshes() {
        assert!(mesh.is_watertight(), "{name}");
        let mut open = mesh.clone();
        open.retain_triangles(|_| rng.below(50) != 0);
        assert_eq!(open.is_watertight(), PolygonTables::new(&open).report().watertight, "{name} opened");
        let mut flipped = mesh.clone();
        flipped.triangles[3].swap(0, 1);
        assert!(!flipped.is_watertight() && !PolygonTables::new(&flipped).report().watertight, "{name} flipped");
        // Every edge twice each way: each reverse is there, but edges repeat.
        let mut doubled = mesh.clone();
        doubled.triangles.extend_from_within(..);
        assert!(!doubled.is_watertight() && !PolygonTables::new(&doubled).report().watertight, "{name} doubled");
    }
}

#[test]
fn same_octree_for_any_thread_count() {
    let mesh = torus(1.0, 0.35, 48, 24);
    let mut open = mesh.clone();
    open.retain_triangles(|t| t % 17 != 0);
    for (m, rule) in [(&mesh, InsideRule::Parity), (&open, InsideRule::Winding)] {
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| voxelize(m, 8, rule).0)
        };
        let one = run(1);
        assert_same(&one, &run(2), "1 vs 2 threads");
        assert_same(&one, &run(3), "1 vs 3 threads");
    }
}

/// Regression: `--fill surface` of one triangle across the domain at depth 14 went
/// straight to work and allocated gigabytes (about 2.6e8 surface voxels), because the
/// surface voxelizers had no memory estimate. Both kinds must be refused, before any
/// work, under a small budget, through the library call and the import path the CLI
/// takes.
#[test]
fn one_triangle_surface_at_depth_14_is_refused_under_a_small_budget() {
    let corners = vec![DVec3::ZERO, DVec3::X, DVec3::new(0.0, 1.0, 1.0)];
    let mesh = TriangleMesh::new(corners, vec![[0, 1, 2]]).unwrap();
    let domain = domain_for(&mesh, 14);
    let budget = MemoryBudget(256 << 20);
    for kind in [SurfaceKind::Conservative, SurfaceKind::Thin] {
        let progress = Recorder::default();
        let err = voxelize_surface(&mesh, domain, kind, &VoxelizeOptions { budget, progress: &progress }).unwrap_err();
        // Area 0.71 in (1.06 / 2^14)^2 voxel faces: about 1.7e8, so gigabytes of keys.
        assert!(matches!(err, Error::OverBudget { estimate, .. } if estimate > 2 << 30), "{kind:?}: {err}");
        assert!(err.to_string().contains("depth 14"), "{err}");
        assert_eq!(progress.read().0, 0, "{kind:?}: work started before the budget check");
    }
    let input = import::Input::Mesh(mesh);
    for fill in [import::Fill::Surface, import::Fill::Thin] {
        let result =
            import::voxelize_input(&input, domain, &import::ImportOptions { fill, budget, ..Default::default() });
        assert!(matches!(result, Err(Error::OverBudget { .. })), "{fill:?} passed the import path");
    }
}

#[test]
fn surface_shells_are_the_same_on_any_thread_count() {
    let mesh = torus(1.0, 0.35, 48, 24);
    let d = domain_for(&mesh, 8);
    for kind in [SurfaceKind::Conservative, SurfaceKind::Thin] {
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| voxelize_surface(&mesh, d, kind, &VoxelizeOptions::default()).unwrap())
        };
        let one = run(1);
        assert!(one.voxel_count() > 10_000, "{kind:?}: {} voxels", one.voxel_count());
        assert_eq!(one, run(2), "{kind:?}: 1 vs 2 threads");
        assert_eq!(one, run(3), "{kind:?}: 1 vs 3 threads");
    }
}

#[test]
fn mesh_voxelizations_report_progress_adding_up_to_their_total() {
    // Depth 4 is one level below the parallel ones, where the solid's 2-voxel nodes
    // once reported nothing.
    let mesh = icosphere(DVec3::new(0.1, -0.2, 0.05), 1.0, 3);
    for depth in 1..=7 {
        let d = domain_for(&mesh, depth);
        let total = 1 << (3 * u32::from(depth.min(3)));
        let solid = Recorder::default();
        let options = MeshVoxelizeOptions { progress: &solid, ..Default::default() };
        voxelize_mesh(&mesh, d, &options).unwrap();
        assert_eq!(solid.read(), (1, total, total, 1), "solid at depth {depth}");
        for kind in [SurfaceKind::Conservative, SurfaceKind::Thin] {
            let shell = Recorder::default();
            let options = VoxelizeOptions { budget: MemoryBudget::default(), progress: &shell };
            voxelize_surface(&mesh, d, kind, &options).unwrap();
            assert_eq!(shell.read(), (1, total, total, 1), "{kind:?} at depth {depth}");
        }
    }
}

/// The box with corners `lo` and `hi` as a closed mesh: [`cuboid`]'s triangles, each
/// corner `lo` or `hi` on each axis exactly (no arithmetic on the coordinates).
fn box_mesh(lo: DVec3, hi: DVec3) -> TriangleMesh {
    let unit = cuboid(DVec3::splat(0.5), DVec3::ONE);
    let pick = |v: DVec3| DVec3::select(v.cmpgt(DVec3::splat(0.5)), hi, lo);
    TriangleMesh::new(unit.vertices.iter().map(|&v| pick(v)).collect(), unit.triangles).unwrap()
}

/// Brute force over voxel centres with the voxelizer's tie rule for points on the
/// surface (the point a hair toward +x, then +y, then +z decides): a centre is in the
/// box `[lo, hi]` iff `lo <= c < hi` on each axis.
fn box_by_centres(domain: Domain, lo: DVec3, hi: DVec3) -> LinearOctree {
    let inside = |c: DVec3| c.cmpge(lo).all() && c.cmplt(hi).all();
    let voxels = (0..domain.voxel_total()).map(morton::decode).filter(|&v| inside(domain.voxel_center(v)));
    LinearOctree::from_voxels(domain, voxels).unwrap()
}

fn voxelize_in(mesh: &TriangleMesh, domain: Domain, inside: InsideRule) -> LinearOctree {
    let options = MeshVoxelizeOptions { inside, ..Default::default() };
    let (tree, _) = voxelize_mesh(mesh, domain, &options).unwrap();
    tree.validate().unwrap();
    tree
}

/// Regression: faces, edges and corners on voxel planes put node centres on the
/// surface (at depth 3 in `[-0.5, 1.5]^3` the centres of the eight depth-1 nodes are
/// the cube's corners), where crossings were counted by vertex indices: the whole
/// domain, volume 5 instead of 1.
#[test]
fn axis_aligned_cube_on_voxel_planes_voxelizes_exactly() {
    let cube = cuboid(DVec3::splat(0.5), DVec3::ONE);
    // Domains in which 0 and 1 lie on voxel planes at every depth from 2.
    let domains =
        [(DVec3::splat(-0.5), 2.0), (DVec3::ZERO, 1.0), (DVec3::splat(-1.0), 4.0), (DVec3::new(-1.0, -3.0, -2.0), 4.0)];
    for (min, edge) in domains {
        for depth in 2..=7 {
            let domain = Domain::new(min, edge, depth).unwrap();
            let want = box_by_centres(domain, DVec3::ZERO, DVec3::ONE);
            assert_eq!(want.volume(), 1.0, "brute force in {min} edge {edge} depth {depth}");
            for rule in [InsideRule::Parity, InsideRule::Winding] {
                let tree = voxelize_in(&cube, domain, rule);
                let what = format!("{rule:?} in {min} edge {edge} depth {depth}");
                assert_eq!(tree.volume(), 1.0, "{what}");
                assert_same(&tree, &want, &what);
            }
        }
    }
}

/// Random boxes with corners on the voxel lattice (faces on voxel planes, the exact
/// answer the voxels of the index range) and at voxel centres (faces through a layer
/// of centres on each side, decided by the tie rule of [`box_by_centres`]).
#[test]
fn boxes_on_voxel_planes_and_through_voxel_centres_match_brute_force() {
    let mut rng = Rng(41);
    for case in 0..60 {
        let depth = 2 + rng.below(5) as u8;
        let domain = Domain::new(rng.vec(-2.0, 2.0), rng.range(0.5, 3.0), depth).unwrap();
        let res = u64::from(domain.resolution());
        let through_centres = case % 2 == 1;
        // Index ranges lo..hi on each axis, at least one voxel wide.
        let top = if through_centres { res - 1 } else { res };
        let mut lo = [0u32; 3];
        let mut hi = [0u32; 3];
        for a in 0..3 {
            let (x, y) = (rng.below(top), rng.below(top));
            (lo[a], hi[a]) = (x.min(y) as u32, (x.max(y) + 1).min(top) as u32);
        }
        let corner = |c: [u32; 3]| if through_centres { domain.voxel_center(c) } else { domain.lattice_point(c) };
        let (a, b) = (corner(lo), corner(hi));
        let want = box_by_centres(domain, a, b);
        let count: u64 = (0..3).map(|i| u64::from(hi[i] - lo[i])).product();
        assert_eq!(want.voxel_count(), count, "brute force, case {case}");
        for rule in [InsideRule::Parity, InsideRule::Winding] {
            let what = format!("case {case}: {rule:?} box {a}..{b} depth {depth}");
            assert_same(&voxelize_in(&box_mesh(a, b), domain, rule), &want, &what);
        }
    }
}

/// A 2 KB OBJ whose one face visits 5 vertices 1,000 times: fanned, 998 triangles,
/// most with a repeated corner or cancelled by a copy facing the other way, the rest
/// copies of a few sets of corners. A node pays for the distinct triangles, not the
/// 998 (it took 13 s at depth 8), and the solid is that of the triangles that bound
/// something, each as many times as it is copied, built here by hand.
#[test]
fn a_face_that_revisits_its_corners_costs_a_node_its_distinct_triangles() {
    let mut rng = Rng(31);
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\nv 0.5 0.5 1\nf");
    for _ in 0..1000 {
        obj.push_str(&format!(" {}", 1 + rng.below(5)));
    }
    obj.push('\n');
    let (mesh, _) = mesh_from_bytes(obj.as_bytes(), std::path::Path::new("revisits.obj")).unwrap();
    assert_eq!(mesh.triangles.len(), 998);
    // By hand: each set of corners with its signed count (+1 for an even order of the
    // corners, -1 for an odd one), repeated corners dropped.
    let mut net: std::collections::BTreeMap<[u32; 3], i32> = Default::default();
    for &[a, b, c] in &mesh.triangles {
        if a != b && b != c && a != c {
            let odd = (a > b) ^ (b > c) ^ (a > c);
            let mut k = [a, b, c];
            k.sort_unstable();
            *net.entry(k).or_default() += if odd { -1 } else { 1 };
        }
    }
    let facing = |[a, b, c]: [u32; 3], n: i32| if n > 0 { [a, b, c] } else { [a, c, b] };
    let bounding: Vec<[u32; 3]> =
        net.iter().flat_map(|(&k, &n)| std::iter::repeat_n(facing(k, n), n.unsigned_abs() as usize)).collect();
    let distinct: Vec<[u32; 3]> = net.iter().filter(|(_, n)| **n != 0).map(|(&k, &n)| facing(k, n)).collect();
    let (kept, void) = mesh.solid_boundary();
    assert_eq!((kept.triangles.len(), void), (bounding.len(), 998 - bounding.len()));
    assert!(void > 500 && distinct.len() <= 10, "{void} left out, {} distinct", distinct.len());
    let by_hand = TriangleMesh::new(mesh.vertices.clone(), bounding).unwrap();
    let once = TriangleMesh::new(mesh.vertices.clone(), distinct).unwrap();
    for rule in [InsideRule::Winding, InsideRule::Parity] {
        let (tree, stats) = voxelize_in_with_stats(&mesh, domain_for(&mesh, 7), rule);
        let (want, _) = voxelize_in_with_stats(&by_hand, domain_for(&mesh, 7), rule);
        assert_same(&tree, &want, &format!("{rule:?}"));
        assert_eq!(stats.void_triangles, void);
        let (_, single) = voxelize_in_with_stats(&once, domain_for(&mesh, 7), rule);
        assert!(stats.triangle_box_tests <= single.triangle_box_tests, "{stats:?} against {single:?}");
    }
}

fn voxelize_in_with_stats(
    mesh: &TriangleMesh,
    domain: Domain,
    inside: InsideRule,
) -> (LinearOctree, MeshVoxelizeStats) {
    let options = MeshVoxelizeOptions { inside, ..Default::default() };
    voxelize_mesh(mesh, domain, &options).unwrap()
}

/// Copies of a closed mesh's triangles count as many times as they are copied, and
/// triangles that bound nothing not at all: three copies of each, with a triangle
/// with a repeated corner and a pair facing both ways after each, bound the same
/// solid under both rules (winding 3, an odd number of crossings), exactly.
#[test]
fn copied_triangles_count_their_copies_under_both_rules() {
    for (name, mesh) in closed_meshes() {
        let mut tripled = mesh.clone();
        tripled.triangles = mesh
            .triangles
            .iter()
            .flat_map(|&[a, b, c]| [[a, b, c], [a, b, c], [b, c, a], [a, a, b], [a, c, b], [c, a, b]])
            .collect();
        for rule in [InsideRule::Parity, InsideRule::Winding] {
            assert_same(&voxelize(&tripled, 6, rule).0, &voxelize(&mesh, 6, rule).0, &format!("{name} {rule:?}"));
        }
    }
}
