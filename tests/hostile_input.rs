//! Hostile input: each test pins one way a crafted or extreme input used to panic,
//! hang, allocate without asking the memory budget, or compute with non-finite
//! numbers, and checks the clean refusal or the right answer that replaced it; each is
//! named for the defect it pins (every limit and its error: docs/LIMITS.md). The file
//! began with issue 15 (hardening: no panic, no hang, no unbounded memory); issues 35
//! and 36 added to it.
//!
//! The other items of the hardening work have their tests beside the code they pin:
//!
//! | item | test |
//! |---|---|
//! | frame index overflow, `--spp 16` budget, `--max-depth 3000` | `render.rs`: `pictures_over_the_budget_and_endless_mirrors_are_refused_before_work` |
//! | PLY element with zero properties and a huge count | `loaders.rs`: `ply_zero_property_element_is_refused_quickly` |
//! | `--fill surface`/`thin` budget | `mesh.rs`: `one_triangle_surface_at_depth_14_is_refused_under_a_small_budget` (and `patches.rs` for patch surfaces) |
//! | OBJ coordinates in single precision | `loaders.rs`: `obj_coordinates_keep_double_precision` |
//! | 1000-vertex face | `loaders.rs`: `thousand_vertex_face_triangulates_to_n_minus_2_triangles_with_its_area` |
//! | control characters in messages | `loaders.rs`: `error_messages_escape_control_characters` |
//! | temporary files: exclusive, unpredictable, stale ones removed; devices and symlinks | `src/atomic.rs` unit tests |
//! | output that is an input, `info > /dev/full` | `first_hour.rs`: `outputs_never_replace_inputs_and_stdout_failures_are_errors` |
//! | every parser under mutation | the fuzz crate (`fuzz/`) and its corpus replay test |

mod common;

use std::path::Path;

use glam::DVec3;
use octsolid::import::{Fill, ImportOptions, Input, voxelize_input};
use octsolid::io::oct;
use octsolid::mesh::generate::cuboid;
use octsolid::mesh::{
    InsideRule, MeshVoxelizeOptions, ParityGrid, SurfaceKind, TriangleMesh, voxelize_mesh, voxelize_surface,
};
use octsolid::octree::{Domain, EDGE_RANGE, LinearOctree, MAX_COORDINATE, VoxelizeOptions, voxelize};
use octsolid::patch::{BezierPatch, estimate_tessellation_bytes, tessellate};
use octsolid::render::polygon::{Interpolation, MeshRenderOptions, MeshScene, fragments, render_mesh};
use octsolid::render::{Camera, Material, Projection, RenderOptions, Scene, render};
use octsolid::scene_file::read_scene;
use octsolid::shape::Cuboid;
use octsolid::{Error, MemoryBudget, NoProgress};

fn scratch(test: &str) -> std::path::PathBuf {
    common::scratch_dir("hardening", test)
}

/// `copies` pairs of the same large triangle, one of each pair turned over: closed
/// (every edge used twice each way), enclosing nothing, and every triangle covering
/// the whole `yz` extent.
fn stacked_triangles(copies: usize) -> TriangleMesh {
    let mut mesh = TriangleMesh {
        vertices: vec![DVec3::ZERO, DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 1.0), DVec3::new(0.3, 1.0, 1.0)],
        ..TriangleMesh::default()
    };
    for _ in 0..copies {
        mesh.triangles.push([1, 2, 3]);
        mesh.triangles.push([1, 3, 2]);
    }
    mesh
}

#[test]
fn parity_grid_of_many_large_triangles_stays_linear_and_counts_like_brute_force() {
    // 70,000 triangles that each span every cell: a sqrt(n)-sided grid would list
    // 70,000 x 1024^2 entries, past u32 (the old panic) and 290 GB.
    let mesh = stacked_triangles(35_000);
    let grid = ParityGrid::new(&mesh);
    let n = mesh.triangles.len();
    assert!(grid.bytes() <= ParityGrid::max_bytes(n), "{} > {}", grid.bytes(), ParityGrid::max_bytes(n));
    assert!(ParityGrid::max_bytes(n) < 200 * n as u64 + (16 << 20));
    // Brute force: the + x ray from p crosses every copy at once or none; both
    // orientations count, so the answer is n or 0.
    for (p, crosses) in
        [(DVec3::new(-1.0, 0.8, 0.7), true), (DVec3::new(-1.0, 0.2, 0.3), false), (DVec3::new(0.5, 0.8, 0.7), false)]
    {
        assert_eq!(grid.crossings(p), if crosses { n as u32 } else { 0 }, "{p}");
    }
}

#[test]
fn mesh_estimate_counts_the_parity_grid() {
    // Under a budget just below the parity grid's bound, the parity rule is refused
    // and the winding rule (no grid) runs.
    let mesh = cuboid(DVec3::splat(0.5), DVec3::ONE);
    let domain = Domain::new(DVec3::splat(-0.25), 1.5, 4).unwrap();
    let budget = MemoryBudget(ParityGrid::max_bytes(mesh.triangles.len()) - 1);
    let run = |inside| voxelize_mesh(&mesh, domain, &MeshVoxelizeOptions { inside, budget, ..Default::default() });
    assert!(matches!(run(InsideRule::Parity), Err(Error::OverBudget { .. })));
    assert!(matches!(run(InsideRule::Auto), Err(Error::OverBudget { .. })));
    let (tree, _) = run(InsideRule::Winding).unwrap();
    assert!((tree.volume() - 1.0).abs() < 0.3, "{}", tree.volume());
}

/// A flat patch over the unit square at height `z`.
fn flat_patch(z: f64) -> BezierPatch {
    BezierPatch { p: std::array::from_fn(|i| std::array::from_fn(|j| DVec3::new(i as f64 / 3.0, j as f64 / 3.0, z))) }
}

#[test]
fn patch_tessellation_is_estimated_and_refused_before_it_is_made() {
    // The estimate covers what a tessellation holds (24 bytes a vertex, 12 a
    // triangle, counted on the mesh made).
    let patches: Vec<BezierPatch> = (0..8).map(|k| flat_patch(f64::from(k))).collect();
    for n in [4, 16, 64] {
        let mesh = tessellate(&patches, n);
        let held = 24 * mesh.vertices.len() as u64 + 12 * mesh.triangles.len() as u64;
        let unwelded = 24 * u64::from((n + 1) * (n + 1)) * 8;
        assert!(estimate_tessellation_bytes(8, n) >= held.max(unwelded), "n = {n}");
    }
    // 2,000 patches (a 78 KB file) at a fine voxel: refused under 256 MiB before any
    // triangle is made, with the tessellation named.
    let many = Input::Patches((0..2000).map(|k| flat_patch(f64::from(k) * 1e-3)).collect());
    let domain = Domain::new(DVec3::splat(-0.5), 3.0, 10).unwrap();
    let options = ImportOptions { fill: Fill::Solid, budget: MemoryBudget(256 << 20), ..ImportOptions::default() };
    let e = voxelize_input(&many, domain, &options).unwrap_err();
    assert!(matches!(&e, Error::OverBudget { job, .. } if job.contains("tessellating")), "{e}");
    assert!(many.report(MemoryBudget(256 << 20)).is_err());
}

#[test]
fn meshes_beyond_the_supported_scale_are_refused_with_the_range_and_small_ones_inside_it_voxelize() {
    for scale in [1e-200, 1e300] {
        let mesh = cuboid(DVec3::splat(scale), DVec3::splat(scale));
        let e = octsolid::import::default_domain(&Input::Mesh(mesh), 6).unwrap_err().to_string();
        assert!(e.contains("outside the supported"), "{scale}: {e}");
    }
    // Inside the range the estimate is finite and the answer is the cube's volume.
    for scale in [EDGE_RANGE.start() * 10.0, 1e40] {
        let mesh = cuboid(DVec3::splat(scale), DVec3::splat(scale));
        let input = Input::Mesh(mesh);
        let domain = octsolid::import::default_domain(&input, 6).unwrap();
        let (tree, _) = voxelize_input(&input, domain, &ImportOptions::default()).unwrap();
        let relative = tree.volume() / scale.powi(3);
        assert!((relative - 1.0).abs() < 0.1, "{scale}: {relative}");
    }
}

#[test]
fn oct_files_whose_domain_reaches_past_the_supported_range_are_refused_at_the_header() {
    let d = Domain::new(DVec3::ZERO, 1.0, 3).unwrap();
    let tree =
        voxelize(&Cuboid::new(DVec3::splat(0.5), DVec3::splat(0.5)).unwrap(), d, &VoxelizeOptions::default()).unwrap();
    let good = oct::encode(&tree);
    let with = |min: f64, edge: f64| {
        let mut b = good.clone();
        b[16..24].copy_from_slice(&min.to_le_bytes());
        b[40..48].copy_from_slice(&edge.to_le_bytes());
        oct::decode(&b, Path::new("x.oct"), MemoryBudget::default())
    };
    assert!(with(0.0, 1.0).is_ok());
    // Edge to infinity; a corner past the coordinate limit; a domain so far out that
    // neighbouring voxel corners round together; NaN and infinite fields.
    for (min, edge) in
        [(0.0, 1e308), (MAX_COORDINATE, 1.0), (1e12, 1e-3), (f64::NAN, 1.0), (0.0, f64::INFINITY), (-1e308, 1.7e308)]
    {
        let e = with(min, edge).unwrap_err().to_string();
        assert!(e.starts_with("x.oct: byte 16: invalid domain"), "{min} {edge}: {e}");
    }
    // A domain far out but with room for its voxels round-trips with finite bounds.
    let far = Domain::new(DVec3::splat(1e6), 1.0, 3).unwrap();
    let tree = LinearOctree::full(far);
    let back = oct::decode(&oct::encode(&tree), Path::new("far.oct"), MemoryBudget::default()).unwrap();
    let b = back.bounds().unwrap();
    assert!(b.min.is_finite() && b.max.is_finite() && back.volume() == 1.0);
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn non_finite_and_out_of_range_camera_values_are_refused_with_their_place() {
    let dir = scratch("camera");
    let scene = |camera: &str| {
        format!(
            "[image]\nsize = [32, 24]\n\n[camera]\n{camera}\n\n[[solid]]\nname = \"ball\"\n\
             shape = {{ sphere = {{ center = [0, 0, 0], radius = 1 }} }}\n"
        )
    };
    let err = |camera: &str| {
        let path = write(&dir, "s.toml", &scene(camera));
        read_scene(&path, MemoryBudget::default()).map(|_| ()).unwrap_err().to_string()
    };
    // Any float of the file that is not finite: named with its key, line and column.
    let e = err("eye = [4, 3, 2]\nfov = nan");
    assert!(e.ends_with("s.toml:6:7: camera.fov = nan is not a finite number"), "{e}");
    let e = err("eye = [4, inf, 2]");
    assert!(e.contains("s.toml:5:") && e.contains("camera.eye[1] = inf"), "{e}");
    let e = err("eye = [4, 3, 2]\nfov = 1e400");
    assert!(e.contains("s.toml:6:7: "), "{e}");
    // Values out of their range: refused where they are read, at their place.
    for (camera, says) in [
        ("eye = [4, 3, 2]\nfov = 400", "s.toml:6:7: field of view 400 must be between 0 and 180 degrees"),
        ("eye = [4, 3, 2]\nfov = 0", "s.toml:6:7: field of view 0 must be"),
        ("projection = \"orthographic\"\nheight = -1", "s.toml:6:10: orthographic height -1 must be positive"),
        ("eye = [4, 3, 2]\nup = [0, 0, 0]", "s.toml:6:6: the direction [0, 0, 0] points nowhere"),
        ("view = [0, 0, 0]", "s.toml:5:8: the direction [0, 0, 0] points nowhere"),
    ] {
        let e = err(camera);
        assert!(e.contains(says), "{camera}: {e}");
    }
    // Finite but unusable cameras, found once the solids' bounds are known: blamed on
    // the camera's table.
    for (camera, says) in [
        ("eye = [4, 3, 2]\ntarget = [4, 3, 2]", "is at the target"),
        ("eye = [0, 0, 5]\ntarget = [0, 0, 0]\nup = [0, 0, 1]", "along the line of sight"),
        ("eye = [0, 0, 5]\nup = [0, 0, -2]", "along the line of sight"),
    ] {
        let e = err(camera);
        assert!(e.contains("s.toml:4:1: ") && e.contains("invalid camera") && e.contains(says), "{camera}: {e}");
    }
    // The same check guards the library's render for cameras built in code.
    let mut scene = Scene::new();
    let d = Domain::new(DVec3::splat(-1.0), 2.0, 3).unwrap();
    let tree = voxelize(&Cuboid::new(DVec3::ZERO, DVec3::splat(0.5)).unwrap(), d, &VoxelizeOptions::default()).unwrap();
    scene.add("box", tree, Material::default());
    let nan = Camera {
        eye: DVec3::new(3.0, 2.0, 1.0),
        target: DVec3::ZERO,
        up: DVec3::Z,
        projection: Projection::Perspective { fov_y: f64::NAN },
    };
    let options = RenderOptions { width: 16, height: 16, spp: 1, ..RenderOptions::default() };
    let e = render(&scene, &nan, &options, &NoProgress).unwrap_err().to_string();
    assert!(e.contains("field of view NaN"), "{e}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn facing_mirrors_at_the_deepest_recursion_render_on_the_worker_threads() {
    // Two parallel mirrors and an eye between them looking nearly along their normal:
    // every primary ray bounces MAX_RAY_DEPTH times. The recursion must fit the
    // worker threads' stacks (the old SIGABRT); the picture must show the mirrors'
    // light, not the background everywhere.
    let dir = scratch("mirrors");
    let path = write(
        &dir,
        "mirrors.toml",
        "[image]\nsize = [48, 32]\nsamples = 1\nmax_depth = 64\n\n\
         [camera]\neye = [0, 0.5, 0]\ntarget = [0, -1, 0.05]\nup = [0, 0, 1]\n\n\
         [[solid]]\nname = \"left\"\nmaterial = { color = [0.9, 0.2, 0.2], reflectance = 0.9 }\n\
         shape = { box = { center = [0, 2, 0], size = [8, 0.2, 8] } }\n\n\
         [[solid]]\nname = \"right\"\nmaterial = { color = [0.2, 0.2, 0.9], reflectance = 0.9 }\n\
         shape = { box = { center = [0, -2, 0], size = [8, 0.2, 8] } }\n\n\
         [[light]]\ntype = \"point\"\nposition = [0, 0, 3]\n",
    );
    let file = read_scene(&path, MemoryBudget::default()).unwrap();
    assert_eq!(file.options.shade.max_depth, octsolid::render::MAX_RAY_DEPTH);
    let (img, stats) = render(&file.scene, &file.camera, &file.options, &NoProgress).unwrap();
    assert!(stats.secondary_rays > 10 * u64::from(img.width() * img.height()), "{stats:?}");
    let background = file.scene.background.to_array().map(octsolid::render::to_srgb8);
    assert!(img.pixels().filter(|p| p.0 != background).count() > img.pixels().len() / 2);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn polygon_pictures_are_checked_for_size_and_memory_before_drawing() {
    let mesh = cuboid(DVec3::ZERO, DVec3::ONE);
    let scene = MeshScene {
        mesh: &mesh,
        material: Material::default(),
        lights: Scene::default_lights(&mesh.bounds()),
        ambient: DVec3::ONE,
        background: DVec3::ZERO,
    };
    let camera = Camera::look_at(DVec3::new(3.0, -2.0, 2.0), DVec3::ZERO, DVec3::Z, 35.0);
    let options = |width, height, spp, budget| MeshRenderOptions {
        width,
        height,
        spp,
        interpolation: Interpolation::Flat,
        budget: MemoryBudget(budget),
        exposure: 0.0,
    };
    let e = render_mesh(&scene, &camera, &options(60_000, 100, 1, u64::MAX)).unwrap_err().to_string();
    assert!(e.contains("60000x100 is outside"), "{e}");
    // 8000 x 8000 at 16 x 16 samples would be 16 G samples: refused by the estimate.
    let e = render_mesh(&scene, &camera, &options(8000, 8000, 16, 1 << 30)).unwrap_err();
    assert!(matches!(e, Error::OverBudget { .. }), "{e}");
    assert!(render_mesh(&scene, &camera, &options(64, 48, 2, 64 << 20)).is_ok());
    // The rows' triangle lists: 20,000 triangles that each cross all 4,000 rows need
    // 640 MB of entries, refused under 256 MiB once counted, before being listed.
    let tall = TriangleMesh {
        vertices: vec![DVec3::new(-1.0, 0.0, -3.0), DVec3::new(1.0, 0.0, -3.0), DVec3::new(0.0, 0.0, 3.0)],
        triangles: vec![[0, 1, 2]; 20_000],
        ..TriangleMesh::default()
    };
    let front = Camera::look_at(DVec3::new(0.0, -10.0, 0.0), DVec3::ZERO, DVec3::Z, 35.0);
    let e = fragments(&tall, &front, 100, 4000, MemoryBudget(256 << 20)).unwrap_err();
    assert!(matches!(&e, Error::OverBudget { job, .. } if job.contains("rows")), "{e}");
    let seen = fragments(&tall, &front, 100, 40, MemoryBudget(256 << 20)).unwrap();
    assert!(seen.iter().any(Option::is_some));
}

#[test]
fn a_zero_size_triangle_keeps_only_the_voxels_at_its_point() {
    // A triangle whose three corners are one point, beside a real one: the surface
    // keeps the voxels that touch the point (8 at a lattice corner, 1 inside a voxel)
    // plus the real triangle's, never the whole domain.
    let domain = Domain::new(DVec3::ZERO, 1.0, 9).unwrap();
    let h = domain.voxel_size();
    for (point, touching) in [(DVec3::splat(0.5), 8), (DVec3::splat(0.5 + h / 3.0), 1)] {
        let mesh = TriangleMesh { vertices: vec![point; 3], triangles: vec![[0, 1, 2]], ..TriangleMesh::default() };
        for kind in [SurfaceKind::Conservative, SurfaceKind::Thin] {
            let tree = voxelize_surface(&mesh, domain, kind, &VoxelizeOptions::default()).unwrap();
            let count = tree.voxel_count();
            match kind {
                SurfaceKind::Conservative => {
                    assert_eq!(count, touching, "{point}");
                    assert!(tree.contains_voxel(domain.voxel_of(point).unwrap()), "{point}");
                }
                SurfaceKind::Thin => assert!(count <= touching, "{point}: {count}"),
            }
        }
    }
}
