//! Measurements of solids (`LinearOctree::measure` and its parts) against analytic
//! values of spheres, boxes and tori, against brute-force sums over voxels, and
//! against a flood fill.
//!
//! Voxelization error bound: a voxel is full when its centre is inside, so the
//! voxelized solid differs from the shape only within `delta = sqrt(3) h / 2` of its
//! surface; any integral over the solid then differs by at most the integral of the
//! integrand's magnitude over that shell.

use std::f64::consts::PI;

use glam::{DMat3, DVec3};
use octsolid::octree::{Domain, LinearOctree, Node, VoxelizeOptions, voxelize};
use octsolid::shape::{Axis, Csg, Cuboid, Shape, Sphere, Torus};
use octsolid::{Aabb, morton};

mod common;

use common::{Rng, random_octree};

fn voxelized(shape: &dyn Shape, bounds: Aabb, depth: u8) -> LinearOctree {
    let domain = Domain::around(&bounds, 0.02, depth).unwrap();
    voxelize(shape, domain, &VoxelizeOptions::default()).unwrap()
}

fn unit_sphere(depth: u8) -> LinearOctree {
    let bounds = Aabb { min: DVec3::splat(-1.0), max: DVec3::splat(1.0) };
    voxelized(&Sphere::new(DVec3::ZERO, 1.0).unwrap(), bounds, depth)
}

/// The torus of radii `major`, `minor` about z through `centre`.
fn torus(centre: DVec3, major: f64, minor: f64, depth: u8) -> LinearOctree {
    let reach = DVec3::new(major + minor, major + minor, minor);
    let shape = Torus::new(centre, Axis::Z, major, minor).unwrap();
    voxelized(&shape, Aabb { min: centre - reach, max: centre + reach }, depth)
}

/// Half-width of the band around a surface where voxelization can err.
fn band(tree: &LinearOctree) -> f64 {
    3f64.sqrt() / 2.0 * tree.domain().voxel_size()
}

/// `|a - b| <= tol` entry by entry.
fn assert_matrix_near(a: DMat3, b: DMat3, tol: f64, what: &str) {
    let d = (a - b).to_cols_array();
    assert!(d.iter().all(|e| e.abs() <= tol), "{what}: {a} vs {b} (tolerance {tol})");
}

/// Full voxels of a tree, by brute force.
fn voxels(tree: &LinearOctree) -> Vec<[u32; 3]> {
    tree.keys().iter().flat_map(|k| (k.start()..k.end()).map(morton::decode)).collect()
}

#[test]
fn a_spheres_area_estimate_converges_and_its_voxel_faces_are_one_and_a_half_times_it() {
    let exact = 4.0 * PI;
    let mut errors = Vec::new();
    for depth in [7, 8, 9] {
        let area = unit_sphere(depth).surface_area();
        let error = (area.estimate / exact - 1.0).abs();
        // The brief's 2% at depths 8 and 9, and the module doc's 0.5%.
        if depth >= 8 {
            assert!(error < 0.005, "depth {depth}: {} vs {exact}", area.estimate);
        }
        errors.push(error);
        // The staircase: the mean of |n|_1 over a sphere's normals is 3/2.
        assert!((area.voxel_faces / (1.5 * exact) - 1.0).abs() < 0.01, "depth {depth}: {}", area.voxel_faces);
    }
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "converges: {errors:?}");
}

#[test]
fn a_torus_area_estimate_is_close_to_four_pi_squared_r_r() {
    for (depth, tolerance) in [(8, 0.02), (9, 0.01)] {
        let area = torus(DVec3::new(0.3, -0.2, 0.1), 1.0, 0.25, depth).surface_area();
        let exact = 4.0 * PI * PI * 1.0 * 0.25;
        assert!((area.estimate / exact - 1.0).abs() < tolerance, "depth {depth}: {} vs {exact}", area.estimate);
    }
}

#[test]
fn axis_aligned_boxes_have_exact_areas_at_any_size_and_place() {
    let mut rng = Rng(17);
    for depth in [5u8, 7, 9, 11] {
        let domain = Domain::new(DVec3::new(-1.0, 2.0, 0.5), 2.0, depth).unwrap();
        let n = u64::from(domain.resolution());
        for _ in 0..6 {
            // Lattice-aligned corners, so the voxelized box is the box; sizes from a
            // thin plate to most of the domain, some touching the domain's faces.
            let lo: [u64; 3] = [0; 3].map(|_| rng.below(n / 2));
            let hi: [u64; 3] = std::array::from_fn(|a| lo[a] + 1 + rng.below(n - lo[a]));
            let corner = |c: [u64; 3]| domain.lattice_point(c.map(|v| v as u32));
            let shape = Cuboid::from_corners(corner(lo), corner(hi)).unwrap();
            let tree = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
            let s = corner(hi) - corner(lo);
            let exact = 2.0 * (s.x * s.y + s.y * s.z + s.z * s.x);
            let area = tree.surface_area();
            assert!((area.estimate - exact).abs() < 1e-12 * exact, "{lo:?}..{hi:?}: {} vs {exact}", area.estimate);
            assert!((area.voxel_faces - exact).abs() < 1e-12 * exact);
        }
    }
}

#[test]
fn a_concave_edge_costs_at_most_its_documented_band() {
    // An L-shaped prism: a box minus a box along one edge, with a concave edge of
    // length `l` whose faces are weighted as if the surface turned gradually.
    for (depth, axis) in [(7, Axis::Z), (8, Axis::X), (9, Axis::Y)] {
        let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
        let h = domain.voxel_size();
        let whole = Cuboid::from_corners(DVec3::splat(0.25), DVec3::splat(0.75)).unwrap();
        // The notch runs along `axis` over the quarter above 0.5 on the two others.
        let (mut lo, mut hi) = (DVec3::splat(0.5), DVec3::ONE);
        lo[axis.index()] = 0.0;
        hi[axis.index()] = 1.0;
        let shape = Csg::leaf(whole) - Cuboid::from_corners(lo, hi).unwrap();
        let tree = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
        let area = tree.surface_area();
        // Six faces of the box; the notch swaps two strips of its side faces for two
        // of its own, and cuts a quarter from the two ends.
        let exact = 6.0 * 0.25 - 2.0 * 0.25 * 0.25;
        assert!((area.voxel_faces - exact).abs() < 1e-12, "{}", area.voxel_faces);
        // Faces lose at most their whole weight, and only those within three blocks
        // (12 voxels) of the edge on either sheet: 24 h a unit of edge (3.6 to 8.1 h
        // measured, by where the edge falls in its block).
        let (edge, loss) = (0.25, exact - area.estimate);
        assert!(loss > 0.0 && loss < 24.0 * h * edge, "depth {depth}: loss {} h a unit of edge", loss / (h * edge));
    }
}

#[test]
fn mass_properties_equal_brute_force_sums_over_voxels() {
    let mut rng = Rng(23);
    for depth in [1u8, 3, 5] {
        for _ in 0..8 {
            let domain = Domain::new(rng.vec(-3.0, 3.0), rng.range(0.5, 4.0), depth).unwrap();
            let tree = random_octree(&mut rng, domain);
            let m = tree.mass_properties();
            let cells = voxels(&tree);
            if cells.is_empty() {
                assert_eq!((m.volume, m.centre_of_mass, m.inertia), (0.0, None, DMat3::ZERO));
                continue;
            }
            // Each voxel a cube of edge h: mass h^3, inertia h^5 / 6 on each axis about
            // its centre, moved to the centre of mass by the parallel axis theorem.
            let h = domain.voxel_size();
            let mass = h.powi(3) * cells.len() as f64;
            let centres: Vec<DVec3> = cells.iter().map(|&v| domain.voxel_center(v)).collect();
            let centre = centres.iter().sum::<DVec3>() * h.powi(3) / mass;
            let mut inertia = DMat3::ZERO;
            for c in &centres {
                let d = *c - centre;
                let parallel = DMat3::from_diagonal(DVec3::splat(d.length_squared())) - outer(d, d);
                inertia += (DMat3::IDENTITY * h * h / 6.0 + parallel) * h.powi(3);
            }
            assert!((m.volume - mass).abs() <= 1e-12 * mass);
            let scale = domain.edge();
            assert!((m.centre_of_mass.unwrap() - centre).length() <= 1e-9 * scale, "{domain}");
            let norm = inertia.to_cols_array().iter().fold(0f64, |a, e| a.max(e.abs()));
            assert_matrix_near(m.inertia, inertia, 1e-9 * norm, "brute force");
        }
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[test]
fn an_off_centre_box_has_its_centre_and_inertia_exactly() {
    let domain = Domain::new(DVec3::new(-5.0, 1.0, 2.0), 4.0, 9).unwrap();
    // Lattice-aligned, far from the domain's corner and from its centre.
    let (lo, hi) = ([301u32, 17, 64], [480u32, 90, 511]);
    let (a, b) = (domain.lattice_point(lo), domain.lattice_point(hi));
    let tree = voxelize(&Cuboid::from_corners(a, b).unwrap(), domain, &VoxelizeOptions::default()).unwrap();
    let m = tree.mass_properties();
    let s = b - a;
    let mass = s.x * s.y * s.z;
    assert!((m.volume - mass).abs() < 1e-12 * mass);
    assert!((m.centre_of_mass.unwrap() - (a + b) / 2.0).length() < 1e-12 * domain.edge());
    let want = DMat3::from_diagonal(DVec3::new(s.y * s.y + s.z * s.z, s.x * s.x + s.z * s.z, s.x * s.x + s.y * s.y))
        * (mass / 12.0);
    assert_matrix_near(m.inertia, want, 1e-11 * want.x_axis.x, "box");
}

#[test]
fn a_spheres_mass_properties_are_within_the_voxelization_bound() {
    for depth in [6, 8] {
        let tree = unit_sphere(depth);
        let m = tree.mass_properties();
        let (r, delta) = (1.0, band(&tree));
        let shell = 4.0 / 3.0 * PI * ((r + delta).powi(3) - (r - delta).powi(3));
        let mass = 4.0 / 3.0 * PI * r.powi(3);
        assert!((m.volume - mass).abs() <= shell);
        // |C - c| <= int_shell |x - c| / M, and the inertia about C differs from that
        // about c by M |C - c|^2 at most.
        let offset = (r + delta) * shell / m.volume;
        let centre = m.centre_of_mass.unwrap();
        assert!(centre.length() <= offset, "{centre}");
        let want = DMat3::IDENTITY * (0.4 * mass * r * r);
        let tolerance = (r + delta).powi(2) * shell + m.volume * offset * offset;
        assert_matrix_near(m.inertia, want, tolerance, &format!("sphere at depth {depth}"));
        // The lattice is symmetric about the sphere's centre: one moment on every axis.
        let d = m.inertia.to_cols_array();
        assert!((d[0] - d[4]).abs() < 1e-9 * d[0] && (d[0] - d[8]).abs() < 1e-9 * d[0]);
    }
}

#[test]
fn a_torus_mass_properties_are_within_the_voxelization_bound() {
    let (major, minor, centre) = (1.0, 0.3, DVec3::new(0.7, -0.4, 1.9));
    let tree = torus(centre, major, minor, 8);
    let m = tree.mass_properties();
    let delta = band(&tree);
    let shell = 2.0 * PI * PI * major * ((minor + delta).powi(2) - (minor - delta).powi(2));
    let mass = 2.0 * PI * PI * major * minor * minor;
    assert!((m.volume - mass).abs() <= shell);
    let reach = major + minor + delta;
    let offset = reach * shell / m.volume;
    assert!((m.centre_of_mass.unwrap() - centre).length() <= offset);
    // About the axis m (R^2 + 3/4 r^2), about a diameter m (R^2 / 2 + 5/8 r^2).
    let across = mass * (major * major / 2.0 + 5.0 / 8.0 * minor * minor);
    let want = DMat3::from_diagonal(DVec3::new(across, across, mass * (major * major + 0.75 * minor * minor)));
    assert_matrix_near(m.inertia, want, reach * reach * shell + m.volume * offset * offset, "torus");
}

#[test]
fn components_count_face_connected_pieces() {
    let domain = Domain::new(DVec3::ZERO, 1.0, 7).unwrap();
    let solid = |shape: &dyn Shape| voxelize(shape, domain, &VoxelizeOptions::default()).unwrap();
    let ball = |x: f64| Csg::leaf(Sphere::new(DVec3::new(x, 0.5, 0.5), 0.2).unwrap());
    assert_eq!(solid(&(ball(0.25) | ball(0.75))).components(), 2);
    assert_eq!(solid(&(ball(0.3) | ball(0.6))).components(), 1, "overlapping");
    let ring = Torus::new(DVec3::splat(0.5), Axis::X, 0.3, 0.1).unwrap();
    assert_eq!(solid(&ring).components(), 1);
    let block = |lo: f64, hi: f64| Csg::leaf(Cuboid::from_corners(DVec3::splat(lo), DVec3::splat(hi)).unwrap());
    assert_eq!(solid(&(block(0.1, 0.6) | block(0.7, 0.8))).components(), 2);
    assert_eq!(LinearOctree::empty(domain).components(), 0);
    assert_eq!(LinearOctree::full(domain).components(), 1);
    // Two cubes sharing a face, an edge, a corner: 1, 2, 2.
    let cube = |min: [u32; 3]| Node { level: 2, min, size: 32 };
    for (other, want) in [([64, 32, 32], 1), ([64, 64, 32], 2), ([64, 64, 64], 2)] {
        let tree = LinearOctree::from_nodes(domain, [cube([32, 32, 32]), cube(other)]).unwrap();
        assert_eq!(tree.components(), want, "{other:?}");
    }
    // Voxels touching along an edge, off the big nodes' lattice.
    let pair = LinearOctree::from_voxels(domain, [[5, 9, 3], [6, 10, 3]]).unwrap();
    assert_eq!(pair.components(), 2);
}

/// Brute force: flood fill of the full voxels through shared faces.
fn flood_components(tree: &LinearOctree) -> u64 {
    let n = i64::from(tree.domain().resolution());
    let index = |v: [i64; 3]| (v[0] + n * (v[1] + n * v[2])) as usize;
    let mut full = vec![false; (n * n * n) as usize];
    for v in voxels(tree) {
        full[index(v.map(i64::from))] = true;
    }
    let mut count = 0;
    for start in 0..full.len() {
        if !full[start] {
            continue;
        }
        count += 1;
        full[start] = false;
        let mut stack = vec![[start as i64 % n, start as i64 / n % n, start as i64 / (n * n)]];
        while let Some(v) = stack.pop() {
            for (a, d) in [(0, 1), (0, -1), (1, 1), (1, -1), (2, 1), (2, -1)] {
                let mut w = v;
                w[a] += d;
                if w.iter().all(|&c| (0..n).contains(&c)) && full[index(w)] {
                    full[index(w)] = false;
                    stack.push(w);
                }
            }
        }
    }
    count
}

#[test]
fn components_equal_a_flood_fill_on_random_solids() {
    let mut rng = Rng(41);
    for depth in 1..=6 {
        for _ in 0..12 {
            let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
            let tree = random_octree(&mut rng, domain);
            assert_eq!(tree.components(), flood_components(&tree), "depth {depth}");
        }
    }
}

#[test]
fn components_equal_a_flood_fill_on_large_random_solids() {
    // Near the percolation threshold of the cubic lattice (31%): clusters of every
    // size, and hundreds of thousands of keys, so the joins run in many parallel
    // chunks and cubes of voxels straddle their ends.
    let mut rng = Rng(43);
    let domain = Domain::new(DVec3::ZERO, 1.0, 7).unwrap();
    for density in [0.2, 0.3, 0.45] {
        let cells = (0..128u32).flat_map(|x| (0..128u32).flat_map(move |y| (0..128u32).map(move |z| [x, y, z])));
        let chosen: Vec<[u32; 3]> = cells.filter(|_| rng.unit() < density).collect();
        let tree = LinearOctree::from_voxels(domain, chosen).unwrap();
        assert!(tree.node_count() > 100_000);
        assert_eq!(tree.components(), flood_components(&tree), "density {density}");
    }
}

#[test]
fn measure_gathers_the_parts() {
    let tree = torus(DVec3::ZERO, 1.0, 0.25, 6);
    let all = tree.measure();
    let (mass, area) = (tree.mass_properties(), tree.surface_area());
    assert_eq!((all.volume, all.centre_of_mass, all.inertia), (mass.volume, mass.centre_of_mass, mass.inertia));
    assert_eq!((all.surface_area, all.voxel_face_area), (area.estimate, area.voxel_faces));
    assert_eq!((all.components, all.volume), (tree.components(), tree.volume()));
}
