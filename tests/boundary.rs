//! Boundary meshes of octrees against independent oracles: the dense voxel grid (exposed
//! faces, which side is full), the signed-tetrahedron volume, the directed-edge count,
//! lattice points on every edge (no T-junctions), and a round trip through every file
//! format and our loader. Random solids (nodes and voxels, random voxel sets, random
//! CSG of boxes and spheres) and hand-made tricky cases, in both modes.

mod common;

use std::collections::{HashMap, HashSet};

use common::{Rng, random_csg, random_octree};
use glam::DVec3;
use octsolid::mesh::{BoundaryOptions, PolygonTables, TriangleMesh, boundary_mesh, read_mesh, write_mesh};
use octsolid::octree::{Domain, LinearOctree, Node, VoxelizeOptions, voxelize};
use octsolid::shape::Sphere;

const MODES: [BoundaryOptions; 2] = [BoundaryOptions { unit_faces: false }, BoundaryOptions { unit_faces: true }];

/// A domain whose lattice points are exact binary fractions away from the origin.
fn domain(depth: u8) -> Domain {
    Domain::new(DVec3::new(-1.5, 0.25, 3.0), f64::from(1u32 << depth) * 0.375, depth).unwrap()
}

/// The dense voxel grid of a solid; voxels outside the domain are empty.
struct Dense {
    n: i64,
    full: Vec<bool>,
}

impl Dense {
    fn new(tree: &LinearOctree) -> Dense {
        let n = i64::from(tree.domain().resolution());
        let mut full = vec![false; (n * n * n) as usize];
        for node in tree.nodes() {
            for z in 0..node.size {
                for y in 0..node.size {
                    for x in 0..node.size {
                        let [a, b, c] = [node.min[0] + x, node.min[1] + y, node.min[2] + z].map(i64::from);
                        full[((c * n + b) * n + a) as usize] = true;
                    }
                }
            }
        }
        Dense { n, full }
    }

    fn at(&self, v: [i64; 3]) -> bool {
        v.iter().all(|&c| (0..self.n).contains(&c)) && self.full[((v[2] * self.n + v[1]) * self.n + v[0]) as usize]
    }

    /// Voxel faces between a full and an empty voxel (or the outside).
    fn exposed_faces(&self) -> u64 {
        let mut count = 0;
        for z in 0..self.n {
            for y in 0..self.n {
                for x in 0..self.n {
                    if self.at([x, y, z]) {
                        for (a, s) in [(0, -1), (0, 1), (1, -1), (1, 1), (2, -1), (2, 1)] {
                            let mut w = [x, y, z];
                            w[a] += s;
                            count += u64::from(!self.at(w));
                        }
                    }
                }
            }
        }
        count
    }
}

/// Integer lattice coordinates of a world point (exact for our domains).
fn lattice(domain: &Domain, p: DVec3) -> [i64; 3] {
    let t = (p - domain.min()) / domain.voxel_size();
    let l = t.round();
    assert_eq!(t, l, "vertex {p} is not on the lattice");
    [l.x as i64, l.y as i64, l.z as i64]
}

fn gcd(a: i64, b: i64) -> i64 {
    if b == 0 { a.abs() } else { gcd(b, a % b) }
}

/// Every property the boundary mesh promises, against the oracles.
fn check(tree: &LinearOctree, mesh: &TriangleMesh, what: &str) {
    let domain = tree.domain();
    let dense = Dense::new(tree);
    let h = domain.voxel_size();
    if tree.is_empty() {
        assert!(mesh.triangles.is_empty(), "{what}: an empty solid has no boundary");
        return;
    }
    mesh.validate().unwrap();

    // Every directed edge once, and its reverse once.
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "{what}: edge {a}->{b} used {n} times");
        assert_eq!(directed.get(&(b, a)), Some(&1), "{what}: edge {a}->{b} has no reverse");
    }
    let report = PolygonTables::new(mesh).report();
    assert!(report.watertight && report.degenerate_faces == 0, "{what}: {report:?}");
    let used: HashSet<u32> = mesh.triangles.iter().flatten().copied().collect();
    assert_eq!(used.len(), mesh.vertices.len(), "{what}: unused vertices");

    // Volume and area.
    let volume: f64 = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!((volume - tree.volume()).abs() <= 1e-9 * tree.volume(), "{what}: volume {volume} vs {}", tree.volume());
    let area = dense.exposed_faces() as f64 * h * h;
    assert!((report.area - area).abs() <= 1e-9 * area, "{what}: area {} vs {area}", report.area);

    // Axis-aligned, non-degenerate, full behind and empty in front.
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let cross = (b - a).cross(c - a);
        let axis = (0..3).find(|&i| a[i] == b[i] && b[i] == c[i]).unwrap_or_else(|| panic!("{what}: {t} tilted"));
        assert!(cross[axis] != 0.0, "{what}: triangle {t} is degenerate");
        let mut n = DVec3::ZERO;
        n[axis] = cross[axis].signum();
        let centroid = (a + b + c) / 3.0;
        let voxel = |p: DVec3| {
            let t = ((p - domain.min()) / h).floor();
            [t.x as i64, t.y as i64, t.z as i64]
        };
        assert!(dense.at(voxel(centroid - n * (h / 2.0))), "{what}: triangle {t} has no full voxel behind");
        assert!(!dense.at(voxel(centroid + n * (h / 2.0))), "{what}: triangle {t} faces a full voxel");
    }

    // No vertex strictly inside a triangle edge: every vertex is a lattice point, so
    // test the lattice points on each edge.
    let points: HashSet<[i64; 3]> = mesh.vertices.iter().map(|&p| lattice(domain, p)).collect();
    for t in &mesh.triangles {
        for k in 0..3 {
            let p = lattice(domain, mesh.vertices[t[k] as usize]);
            let q = lattice(domain, mesh.vertices[t[(k + 1) % 3] as usize]);
            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let g = gcd(gcd(d[0], d[1]), d[2]);
            for i in 1..g {
                let r = [0, 1, 2].map(|a| p[a] + d[a] / g * i);
                assert!(!points.contains(&r), "{what}: vertex {r:?} lies inside edge {p:?}-{q:?}");
            }
        }
    }
}

/// Checks both modes; returns the merged mesh and the unit-face one.
fn check_both(tree: &LinearOctree, what: &str) -> [TriangleMesh; 2] {
    MODES.map(|options| {
        let mesh = boundary_mesh(tree, &options);
        check(tree, &mesh, &format!("{what} ({options:?})"));
        mesh
    })
}

/// Unit segments along which exactly two diagonally opposite voxels of the four
/// around are full: there the welded mesh has four faces on one edge.
fn edge_contacts(dense: &Dense) -> usize {
    let mut count = 0;
    for d in 0..3 {
        let (b, c) = ((d + 1) % 3, (d + 2) % 3);
        for t in 0..dense.n {
            for i in 0..=dense.n {
                for j in 0..=dense.n {
                    let cell = |di: i64, dj: i64| {
                        let mut v = [0; 3];
                        v[d] = t;
                        v[b] = i - 1 + di;
                        v[c] = j - 1 + dj;
                        dense.at(v)
                    };
                    let q = [cell(0, 0), cell(1, 0), cell(1, 1), cell(0, 1)];
                    count += usize::from((q[0] && q[2] && !q[1] && !q[3]) || (q[1] && q[3] && !q[0] && !q[2]));
                }
            }
        }
    }
    count
}

#[test]
fn tricky_cases_in_both_modes() {
    let d = domain(4);
    let voxels = |v: &[[u32; 3]]| LinearOctree::from_voxels(d, v.iter().copied()).unwrap();
    let cases: Vec<(&str, LinearOctree)> = vec![
        ("empty", LinearOctree::empty(d)),
        ("whole domain", LinearOctree::full(d)),
        ("one voxel", voxels(&[[3, 5, 7]])),
        ("voxel in a corner of the domain", voxels(&[[15, 15, 15]])),
        ("edge contact", voxels(&[[4, 4, 4], [5, 5, 4]])),
        ("corner contact", voxels(&[[4, 4, 4], [5, 5, 5]])),
        ("edge contacts on every axis", voxels(&[[4, 4, 4], [5, 5, 4], [5, 4, 5], [4, 5, 5]])),
        ("three around an edge", voxels(&[[4, 4, 4], [5, 4, 4], [5, 5, 4]])),
        ("edge and corner contacts at one point", voxels(&[[4, 4, 4], [5, 5, 4], [5, 4, 5], [4, 5, 5], [5, 5, 5]])),
        ("checkerboard", {
            let c = (0..6u32).flat_map(|x| (0..6).flat_map(move |y| (0..6).map(move |z| [x + 2, y + 2, z + 2])));
            voxels(&c.filter(|v| (v[0] + v[1] + v[2]) % 2 == 0).collect::<Vec<_>>())
        }),
        ("hollow box", {
            let all = (1..13u32).flat_map(|x| (1..13).flat_map(move |y| (1..13).map(move |z| [x, y, z])));
            voxels(&all.filter(|v| v.iter().any(|&c| c == 1 || c == 12)).collect::<Vec<_>>())
        }),
        ("big node next to many small ones", {
            let big = Node { level: 1, min: [0, 0, 0], size: 8 };
            let small = (0..8u32).flat_map(|y| (0..8).map(move |z| [8, y, z])).filter(|v| (v[1] * 3 + v[2]) % 4 != 0);
            let mut nodes = vec![big, Node { level: 2, min: [8, 4, 4], size: 4 }];
            nodes.extend(small.map(|min| Node { level: 4, min, size: 1 }));
            nodes.push(Node { level: 3, min: [0, 8, 0], size: 2 });
            nodes.push(Node { level: 4, min: [3, 8, 5], size: 1 });
            LinearOctree::from_nodes(d, nodes).unwrap()
        }),
    ];
    for (what, tree) in &cases {
        let [merged, unit] = check_both(tree, what);
        assert!(merged.triangles.len() <= unit.triangles.len(), "{what}: merging made more triangles");
    }
    // Exact counts where they are plain: a cube is 12 triangles; the domain too.
    let cube = &cases[1].1;
    assert_eq!(boundary_mesh(cube, &BoundaryOptions::default()).triangles.len(), 12);
    let one = &cases[2].1;
    let mesh = boundary_mesh(one, &BoundaryOptions::default());
    assert_eq!((mesh.triangles.len(), mesh.vertices.len()), (12, 8));
    // Edge contact: the two shared corners are duplicated (8 + 8 - 2 + 2 vertices).
    let mesh = boundary_mesh(&cases[4].1, &BoundaryOptions::default());
    assert_eq!((mesh.triangles.len(), mesh.vertices.len()), (24, 16));
    // Corner contact: the shared corner is duplicated.
    let mesh = boundary_mesh(&cases[5].1, &BoundaryOptions::default());
    assert_eq!((mesh.triangles.len(), mesh.vertices.len()), (24, 16));
    // A box of 8^3 voxels as one node: 12 triangles merged, 6 * 64 * 2 as unit faces.
    let node = LinearOctree::from_nodes(d, [Node { level: 1, min: [8, 0, 8], size: 8 }]).unwrap();
    let [merged, unit] = check_both(&node, "one big node");
    assert_eq!((merged.triangles.len(), unit.triangles.len()), (12, 6 * 64 * 2));
}

#[test]
fn random_nodes_and_voxel_sets() {
    let mut rng = Rng(0x5eed_b0da);
    for round in 0..24 {
        let depth = 3 + (round % 3) as u8;
        let tree = random_octree(&mut rng, domain(depth));
        check_both(&tree, &format!("random nodes {round}"));
    }
    for round in 0..24 {
        let d = domain(3);
        let fill = rng.range(0.1, 0.9);
        let voxels: Vec<[u32; 3]> = (0..8u32)
            .flat_map(|x| (0..8).flat_map(move |y| (0..8).map(move |z| [x, y, z])))
            .filter(|_| rng.unit() < fill)
            .collect();
        let tree = LinearOctree::from_voxels(d, voxels).unwrap();
        check_both(&tree, &format!("random voxels {round} (fill {fill:.2})"));
    }
}

/// Where the random CSG trees' primitives are centred, on each axis.
const CENTRES: (f64, f64) = (0.2, 0.8);

#[test]
fn random_csg_of_boxes_and_spheres() {
    let mut rng = Rng(0xc5c5_1234);
    for round in 0..16 {
        let depth = 4 + (round % 2) as u8;
        let d = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
        let tree = voxelize(&random_csg(&mut rng, 3, CENTRES), d, &VoxelizeOptions::default()).unwrap();
        check_both(&tree, &format!("random csg {round}"));
    }
}

#[test]
fn same_mesh_for_any_thread_count() {
    let tree = random_octree(&mut Rng(77), domain(6));
    for options in MODES {
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let single = one.install(|| boundary_mesh(&tree, &options));
        assert_eq!(single, boundary_mesh(&tree, &options), "{options:?}");
    }
}

#[test]
fn files_reload_with_the_same_volume() {
    let dir = common::scratch_dir("boundary", "reload");
    let d = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
    let ball = voxelize(&Sphere::new(DVec3::new(0.1, 0.0, -0.05), 0.8).unwrap(), d, &VoxelizeOptions::default());
    let contacts = LinearOctree::from_voxels(d, [[4, 4, 4], [5, 5, 4], [9, 9, 9], [10, 10, 10]]).unwrap();
    let mut rng = Rng(4242);
    let mut cases = vec![("ball", ball.unwrap()), ("contacts", contacts)];
    cases.extend((0..4).map(|i| ("random", random_octree(&mut rng, domain(4 + i % 2)))));
    assert!(cases.iter().all(|(what, t)| *what == "ball" || edge_contacts(&Dense::new(t)) > 0));
    for (what, tree) in &cases {
        for options in MODES {
            let mesh = boundary_mesh(tree, &options);
            for ext in ["obj", "stl", "ply"] {
                let path = dir.join(format!("{what}.{ext}"));
                write_mesh(&mesh, &path).unwrap();
                let loaded = read_mesh(&path).unwrap();
                let report = PolygonTables::new(&loaded).report();
                let volume = tree.volume();
                // STL moves the copies by a thousandth of an edge: a few 10^-4 voxel
                // volumes each (the bound is checked in tests/stl_export.rs).
                let tolerance = if ext == "stl" { 1e-3 } else { 1e-6 };
                assert!((report.volume - volume).abs() <= tolerance * volume, "{what}.{ext}: {}", report.volume);
                // OBJ and PLY keep the mesh's indices. STL has none: the loader welds
                // equal positions, so the copies the mesh keeps where voxels touch only
                // along an edge or at a corner are written moved apart
                // (mesh::separate_sheets, tested in tests/stl_export.rs) and come back
                // as they were.
                assert!(loaded.is_watertight() && report.watertight, "{what}.{ext} {options:?}: {report:?}");
                assert_eq!(report.non_manifold_edges + report.boundary_edges + report.misoriented_edges, 0);
                assert_eq!(
                    (loaded.vertices.len(), loaded.triangles.len()),
                    (mesh.vertices.len(), mesh.triangles.len())
                );
            }
        }
    }
}
