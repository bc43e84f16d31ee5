//! Hermite data from every source (issue 38, point 2), against independent oracles:
//! a mesh solid's crossings lie on its triangles with their normals (parity, and the
//! winding rule with inner shells), and the smooth surface extracted from them follows
//! the source mesh.

mod common;

use common::mesh_distance::{MeshDistance, closest_on_triangle};
use octsolid::glam::{DAffine3, DQuat, DVec3};
use octsolid::io::ReadOptions;
use octsolid::mesh::generate::icosphere;
use octsolid::mesh::{InsideRule, MeshVoxelizeOptions, TriangleMesh, voxelize_mesh};
use octsolid::octree::{Domain, LinearOctree, voxelize};
use octsolid::shape::{Axis, Csg, Cylinder, Shape, Sphere, Transformed, mirrored, polar_array};
use octsolid::surface::{ExtractOptions, FaceKey, HermiteData, Style, extract};
use octsolid::{NoProgress, SolidFile};

/// The cube `[-1, 1]^3` at `depth`.
fn domain(depth: u8) -> Domain {
    Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap()
}

/// `mesh` voxelized in `d` under `rule`, and its crossings from its triangles.
fn mesh_solid(mesh: &TriangleMesh, d: Domain, rule: InsideRule) -> (LinearOctree, HermiteData) {
    let options = MeshVoxelizeOptions { inside: rule, ..MeshVoxelizeOptions::default() };
    let (tree, _) = voxelize_mesh(mesh, d, &options).unwrap();
    let hermite = HermiteData::from_mesh(mesh, rule, &tree);
    (tree, hermite)
}

/// The crossing of `key` as a point in space.
fn world_point(d: &Domain, key: FaceKey, t: f32) -> DVec3 {
    d.voxel_center(key.voxel()) + key.outward() * (f64::from(t) * d.voxel_size())
}

/// The triangles of a mesh binned by their boxes (grown by a tolerance) into a uniform
/// grid over `[-1, 1]^3`, for brute-force nearest-point tests of a few each.
struct TriangleBins {
    corners: Vec<[DVec3; 3]>,
    bins: Vec<Vec<usize>>,
    tolerance: f64,
}

/// Cells a side of [`TriangleBins`].
const BINS: usize = 16;

impl TriangleBins {
    fn new(mesh: &TriangleMesh, tolerance: f64) -> Self {
        let corners: Vec<[DVec3; 3]> = (0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect();
        let mut bins = vec![Vec::new(); BINS * BINS * BINS];
        let cell = |x: f64| (((x + 1.0) * 0.5 * BINS as f64).floor().max(0.0) as usize).min(BINS - 1);
        for (t, [a, b, c]) in corners.iter().enumerate() {
            let (lo, hi) = (a.min(*b).min(*c) - tolerance, a.max(*b).max(*c) + tolerance);
            for z in cell(lo.z)..=cell(hi.z) {
                for y in cell(lo.y)..=cell(hi.y) {
                    for x in cell(lo.x)..=cell(hi.x) {
                        bins[(z * BINS + y) * BINS + x].push(t);
                    }
                }
            }
        }
        TriangleBins { corners, bins, tolerance }
    }

    /// The triangles within the tolerance of `p`.
    fn at(&self, p: DVec3) -> Vec<usize> {
        let cell = |x: f64| (((x + 1.0) * 0.5 * BINS as f64).floor().max(0.0) as usize).min(BINS - 1);
        let bin = &self.bins[(cell(p.z) * BINS + cell(p.y)) * BINS + cell(p.x)];
        bin.iter()
            .copied()
            .filter(|&t| {
                let [a, b, c] = self.corners[t];
                closest_on_triangle(p, a, b, c).distance(p) <= self.tolerance
            })
            .collect()
    }
}

/// A triangle's own unit normal (its corners' order).
fn triangle_normal(mesh: &TriangleMesh, t: usize) -> DVec3 {
    let [a, b, c] = mesh.corners(t);
    (b - a).cross(c - a).normalize()
}

/// Checks every crossing of `hermite` lies within 1e-6 of a triangle of `mesh` whose
/// own normal it is (within 1e-5 radians); returns how many faces carry one.
fn assert_on_triangles_with_their_normals(mesh: &TriangleMesh, d: &Domain, hermite: &HermiteData) -> usize {
    let bins = TriangleBins::new(mesh, 1e-6);
    for &(key, crossing) in hermite.faces() {
        let p = world_point(d, key, crossing.t);
        let on = bins.at(p);
        assert!(!on.is_empty(), "{key:?}: the crossing {p} is on no triangle");
        let n = crossing.normal.as_dvec3();
        let best = on.iter().map(|&t| triangle_normal(mesh, t).angle_between(n)).fold(f64::INFINITY, f64::min);
        assert!(best < 1e-5, "{key:?}: normal {n} is {best} radians from its triangles' at {p}");
    }
    hermite.len()
}

/// The mean distance from the vertices and triangle centroids of `mesh` to `source`,
/// in voxels of `d`.
fn mean_distance(mesh: &TriangleMesh, source: &MeshDistance, d: &Domain) -> f64 {
    let centroids = (0..mesh.triangles.len()).map(|t| {
        let [a, b, c] = mesh.corners(t);
        (a + b + c) / 3.0
    });
    let points: Vec<DVec3> = mesh.vertices.iter().copied().chain(centroids).collect();
    points.iter().map(|&p| source.distance(p)).sum::<f64>() / points.len() as f64 / d.voxel_size()
}

#[test]
fn a_mesh_spheres_crossings_lie_on_its_triangles_and_its_surface_follows_it() {
    let mesh = icosphere(DVec3::new(0.03, -0.02, 0.01), 0.9, 4);
    assert!(mesh.triangles.len() >= 2048);
    let d = domain(7);
    let (tree, hermite) = mesh_solid(&mesh, d, InsideRule::Auto);
    let carried = assert_on_triangles_with_their_normals(&mesh, &d, &hermite);
    // Every face of a closed mesh's staircase is crossed by a triangle.
    let staircase = ExtractOptions { style: Style::Voxels, unit_faces: true, ..ExtractOptions::default() };
    let faces = extract(&tree, &HermiteData::none(), &staircase, &NoProgress).unwrap().mesh.triangles.len() / 2;
    assert_eq!(carried, faces);
    let estimate = extract(&tree, &HermiteData::none(), &ExtractOptions::default(), &NoProgress).unwrap();
    let source = MeshDistance::new(&mesh);
    let exact = extract(&tree, &hermite, &ExtractOptions::default(), &NoProgress).unwrap();
    assert!(!exact.is_estimate());
    let (from_exact, from_estimate) =
        (mean_distance(&exact.mesh, &source, &d), mean_distance(&estimate.mesh, &source, &d));
    println!("mean distance to the source: {from_exact:.4} voxel exact, {from_estimate:.4} estimated");
    assert!(from_exact < 0.02, "mean distance {from_exact} voxel");
    assert!(from_exact < from_estimate / 3.0, "{from_exact} exact, {from_estimate} estimated");
}

/// Two meshes as one (the second's vertices after the first's), the second turned
/// inside out when `reversed`.
fn joined(outer: &TriangleMesh, inner: &TriangleMesh, reversed: bool) -> TriangleMesh {
    let base = outer.vertices.len() as u32;
    let vertices = outer.vertices.iter().chain(&inner.vertices).copied().collect();
    let inner_triangles = inner.triangles.iter().map(|&[a, b, c]| {
        let t = [a + base, b + base, c + base];
        if reversed { [t[0], t[2], t[1]] } else { t }
    });
    let triangles = outer.triangles.iter().copied().chain(inner_triangles).collect();
    TriangleMesh::new(vertices, triangles).unwrap()
}

/// A hollow ball, its inner shell turned inward, under the winding rule: the crossings
/// of both shells lie on their triangles with the triangles' own normals, so those of
/// the inner shell point to the centre.
#[test]
fn a_hollow_balls_inner_shell_gives_inward_normals_under_the_winding_rule() {
    let centre = DVec3::new(0.01, 0.02, -0.03);
    let mesh = joined(&icosphere(centre, 0.9, 4), &icosphere(centre, 0.5, 4), true);
    let d = domain(7);
    let (_, hermite) = mesh_solid(&mesh, d, InsideRule::Winding);
    assert_on_triangles_with_their_normals(&mesh, &d, &hermite);
    let (mut inner, mut outer) = (0, 0);
    for &(key, crossing) in hermite.faces() {
        let from_centre = world_point(&d, key, crossing.t) - centre;
        let radial = crossing.normal.as_dvec3().dot(from_centre.normalize());
        if from_centre.length() < 0.7 {
            assert!(radial < -0.99, "{key:?}: the inner shell's normal points {radial} outward");
            inner += 1;
        } else {
            assert!(radial > 0.99, "{key:?}: the outer shell's normal points {radial} outward");
            outer += 1;
        }
    }
    assert!(inner > 10_000 && outer > 30_000, "{inner} inner and {outer} outer crossings");
}

/// Two nested shells facing out, 0.3 voxel apart, under the winding rule (2 inside the
/// inner, 1 between): the solid's surface is the outer shell, and every crossing lies
/// on it, also where a face's segment crosses both shells (its full voxel's centre
/// inside the inner one), whose first crossing does not leave the solid.
#[test]
fn nested_shells_under_the_winding_rule_cross_at_the_outer_one() {
    let d = domain(7);
    let h = d.voxel_size();
    let centre = DVec3::new(0.01, 0.02, -0.03);
    let (outer_r, inner_r) = (0.9, 0.9 - 0.3 * h);
    let (outer, inner) = (icosphere(centre, outer_r, 4), icosphere(centre, inner_r, 4));
    let mesh = joined(&outer, &inner, false);
    let (tree, hermite) = mesh_solid(&mesh, d, InsideRule::Winding);
    let outer_bins = TriangleBins::new(&outer, 1e-6);
    let inner_distance = MeshDistance::new(&inner);
    let mut both = 0;
    for &(key, crossing) in hermite.faces() {
        let p = world_point(&d, key, crossing.t);
        assert!(!outer_bins.at(p).is_empty(), "{key:?}: {p} is not on the outer shell");
        assert!(inner_distance.distance(p) > 0.1 * h, "{key:?}: {p} is on the inner shell");
        // The full voxel's centre inside the inner shell (by the analytic sphere,
        // clear of its chords): the segment crosses both.
        both += usize::from(d.voxel_center(key.voxel()).distance(centre) < inner_r - 0.05 * h);
    }
    let staircase = ExtractOptions { style: Style::Voxels, unit_faces: true, ..ExtractOptions::default() };
    let faces = extract(&tree, &HermiteData::none(), &staircase, &NoProgress).unwrap().mesh.triangles.len() / 2;
    assert_eq!(hermite.len(), faces, "every face crossed");
    assert!(both > 10_000, "{both} faces cross both shells");
}

/// A file of the reference data (`tests/data`).
fn data(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(path)
}

/// OpenVDB's level-set spheres (radius 6.3, voxel 0.5; `tests/data/vdb/shapes.json`,
/// made by OpenVDB itself): every boundary face carries a crossing from the distances,
/// within 0.05 voxel of the analytic sphere with a normal within half a degree of the
/// radius (half floats too: measured 0.010 voxel and 0.08 degrees); a fog volume
/// carries none.
#[test]
fn vdb_level_set_spheres_give_crossings_on_the_analytic_sphere() {
    let shapes: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data("vdb/shapes.json")).unwrap()).unwrap();
    let s = &shapes["sphere"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let (h, r) = (f(&s["voxel_size"]), f(&s["radius"]));
    let c = DVec3::new(f(&s["center"][0]), f(&s["center"][1]), f(&s["center"][2]));
    for (name, distance_tolerance, degrees) in [("sphere.vdb", 0.05, 0.5), ("sphere_half.vdb", 0.05, 0.5)] {
        let file = SolidFile::read(data(&format!("vdb/{name}")), &ReadOptions::default()).unwrap();
        let surface = file.surface.clone().unwrap_or_else(|| panic!("{name}: no crossings"));
        let tree = file.union();
        let d = *tree.domain();
        assert!((d.voxel_size() - h).abs() < 1e-12);
        let (mut worst, mut worst_angle) = (0.0f64, 0.0f64);
        for &(key, crossing) in surface.faces() {
            let p = world_point(&d, key, crossing.t);
            worst = worst.max(((p - c).length() - r).abs() / h);
            worst_angle = worst_angle.max(crossing.normal.as_dvec3().angle_between(p - c).to_degrees());
        }
        println!("{name}: {} crossings, {worst:.4} voxel and {worst_angle:.3} degrees at worst", surface.len());
        assert!(worst < distance_tolerance, "{name}: a crossing {worst} voxel off the sphere");
        assert!(worst_angle < degrees, "{name}: a normal {worst_angle} degrees off the radius");
        let staircase = ExtractOptions { style: Style::Voxels, unit_faces: true, ..ExtractOptions::default() };
        let faces = extract(&tree, &HermiteData::none(), &staircase, &NoProgress).unwrap().mesh.triangles.len() / 2;
        assert_eq!(surface.len(), faces, "{name}: every face crossed");
    }
    let fog = SolidFile::read(data("vdb/fog_and_mask.vdb"), &ReadOptions::default()).unwrap();
    assert!(fog.surface.is_none());
}

/// Checks the crossings `from_shape` gives `shape` (voxelized in `d`) against the
/// signed function `f` whose zero set is its surface (a distance near it): every
/// crossing within 1e-4 voxel of the zero set, and its normal along `f`'s numerical
/// gradient where that is a unit vector (off the creases); returns how many normals
/// were checked.
fn assert_on_zero_set(name: &str, shape: &dyn Shape, d: Domain, f: &dyn Fn(DVec3) -> f64) -> usize {
    let tree = voxelize(shape, d, &Default::default()).unwrap();
    let hermite = HermiteData::from_shape(shape, &tree);
    let h = d.voxel_size();
    let mut normals = 0;
    for &(key, crossing) in hermite.faces() {
        let p = world_point(&d, key, crossing.t);
        assert!(f(p).abs() < 1e-4 * h, "{name}: {key:?} at {p} is {} voxel off", f(p) / h);
        let e = 1e-6 * h;
        let g = DVec3::new(
            f(p + DVec3::X * e) - f(p - DVec3::X * e),
            f(p + DVec3::Y * e) - f(p - DVec3::Y * e),
            f(p + DVec3::Z * e) - f(p - DVec3::Z * e),
        ) / (2.0 * e);
        if (g.length() - 1.0).abs() < 1e-3 {
            let angle = crossing.normal.as_dvec3().angle_between(g);
            assert!(angle < 1e-3, "{name}: {key:?} at {p}: normal {} is {angle} radians off {g}", crossing.normal);
            normals += 1;
        }
    }
    assert!(normals * 10 > hermite.len() * 8, "{name}: {normals} of {} normals checked", hermite.len());
    normals
}

/// Patterns, transforms and CSG trees are shapes: their exact crossings come from
/// their distances through the placements and set operations (`HermiteData::from_shape`),
/// on the analytic surfaces with their normals.
#[test]
fn patterns_transforms_and_csg_trees_give_exact_crossings() {
    let d = domain(6);
    // Five spheres about z.
    let ring =
        polar_array(Sphere::new(DVec3::new(0.5, 0.0, 0.1), 0.25).unwrap(), Axis::Z, DVec3::ZERO, 5, None).unwrap();
    let centres: Vec<DVec3> =
        (0..5).map(|i| DQuat::from_rotation_z(f64::from(i) * 72f64.to_radians()) * DVec3::new(0.5, 0.0, 0.1)).collect();
    let ring_f = |p: DVec3| centres.iter().map(|c| p.distance(*c) - 0.25).fold(f64::INFINITY, f64::min);
    assert_on_zero_set("polar array", &ring, d, &ring_f);
    // A sphere and its mirror image.
    let pair =
        mirrored(Sphere::new(DVec3::new(0.3, 0.2, 0.1), 0.3).unwrap(), DVec3::new(1.0, 1.0, 0.0), DVec3::ZERO).unwrap();
    let pair_f =
        |p: DVec3| (p.distance(DVec3::new(0.3, 0.2, 0.1)) - 0.3).min(p.distance(DVec3::new(-0.2, -0.3, 0.1)) - 0.3);
    assert_on_zero_set("mirror", &pair, d, &pair_f);
    // A cylinder turned 30 degrees about x and moved, and a ball with it bored out.
    let to_world = DAffine3::from_translation(DVec3::new(0.05, -0.02, 0.03))
        * DAffine3::from_rotation_x(std::f64::consts::FRAC_PI_6);
    let bore = Transformed::new(Cylinder::new(DVec3::ZERO, Axis::Z, 0.3, 1.2).unwrap(), to_world).unwrap();
    let bore_f = |p: DVec3| {
        let q = to_world.inverse().transform_point3(p);
        (q.x.hypot(q.y) - 0.3).max(q.z.abs() - 0.6)
    };
    assert_on_zero_set("turned cylinder", &bore, d, &bore_f);
    let bored = Csg::from(Sphere::new(DVec3::ZERO, 0.8).unwrap()) - bore.clone();
    let bored_f = |p: DVec3| (p.length() - 0.8).max(-bore_f(p));
    assert_on_zero_set("ball minus cylinder", &bored, d, &bored_f);
}

/// The Utah teapot's patches (winding rule: its spout and handle pierce the body) at
/// depth 7: its crossings moved onto the patches lie on a fine tessellation (128
/// segments a side) far nearer than those of the coarse tessellation it is voxelized
/// as (measured: mean 0.0007 voxel against 0.0092, 0.4% over 0.02 voxel against 5.5%:
/// where Newton's method gives up, the tessellation's crossing stays, and the fine
/// tessellation's own chords are a hundredth of a voxel at the knob and spout).
#[test]
fn a_patch_sets_crossings_lie_on_its_patches() {
    let patches =
        octsolid::patch::read_patches(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/teapot.patches"))
            .unwrap();
    let input = octsolid::import::Input::Patches(patches.clone());
    let d = octsolid::import::default_domain(&input, 7).unwrap();
    let (tree, summary) = octsolid::import::voxelize_input(&input, d, &Default::default()).unwrap();
    let exact = octsolid::import::surface_of_input(&input, &tree, &summary, Default::default()).unwrap().unwrap();
    let coarse = input.triangles(d.voxel_size(), Default::default()).unwrap();
    let tessellated = HermiteData::from_mesh(&coarse, summary.rule.unwrap(), &tree);
    assert_eq!(exact.len(), tessellated.len());
    let fine = MeshDistance::new(&octsolid::patch::tessellate(&patches, 128));
    let off = |h: &HermiteData| {
        let distances: Vec<f64> =
            h.faces().iter().map(|&(key, c)| fine.distance(world_point(&d, key, c.t)) / d.voxel_size()).collect();
        let far = distances.iter().filter(|&&x| x > 0.02).count() as f64 / distances.len() as f64;
        (distances.iter().sum::<f64>() / distances.len() as f64, far)
    };
    let ((mean, far), (coarse_mean, coarse_far)) = (off(&exact), off(&tessellated));
    println!(
        "on the patches: mean {mean:.5} voxel, {:.3}% over 0.02; the tessellation's {coarse_mean:.5}, {:.3}%",
        far * 100.0,
        coarse_far * 100.0
    );
    assert!(far < 0.01 && far * 5.0 < coarse_far, "{far} of the crossings over 0.02 voxel off ({coarse_far})");
    assert!(mean * 5.0 < coarse_mean, "{mean} against the tessellation's {coarse_mean}");
}
