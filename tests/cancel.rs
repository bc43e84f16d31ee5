//! Cancelling long jobs through [`Progress::cancelled`]: every job that reports
//! progress stops at a poll once asked, returns `Error::Cancelled` and writes nothing.
//! The oracle of "stopped early" is the job's own progress: a job asked to stop at its
//! first unit reports fewer units than its total (it did not run to the end and check
//! once), and the same job not asked to stop runs to its total.

mod common;

use std::sync::atomic::{AtomicU64, Ordering::SeqCst};

use common::radiosity_room::{cuboid, diffuse, tree};
use glam::DVec3;
use octsolid::io::{SolidsRef, WriteOptions};
use octsolid::mesh::generate::icosphere;
use octsolid::mesh::{MeshVoxelizeOptions, voxelize_mesh};
use octsolid::octree::{Domain, LinearOctree, OffsetOptions, VoxelizeOptions, voxelize};
use octsolid::render::radiosity::{Radiosity, RadiosityOptions, Solver};
use octsolid::render::{AntiAliasing, Camera, Material, Method, RenderOptions, Scene, render_picture};
use octsolid::shape::Sphere;
use octsolid::surface::{ExtractOptions, HermiteData, Style, extract};
use octsolid::{Error, MemoryBudget, Progress, write_solid_file};

/// Asks to stop once `after` units are reported; counts what the job reports.
struct StopAfter {
    after: u64,
    total: AtomicU64,
    done: AtomicU64,
    finished: AtomicU64,
}

impl StopAfter {
    fn new(after: u64) -> Self {
        StopAfter { after, total: AtomicU64::new(0), done: AtomicU64::new(0), finished: AtomicU64::new(0) }
    }

    /// Stops at the first unit reported.
    fn at_once() -> Self {
        Self::new(1)
    }

    /// Never stops.
    fn never() -> Self {
        Self::new(u64::MAX)
    }

    /// `(done, total)` of the last stage started.
    fn read(&self) -> (u64, u64) {
        (self.done.load(SeqCst), self.total.load(SeqCst))
    }
}

impl Progress for StopAfter {
    fn start(&self, total: u64) {
        self.total.store(total, SeqCst);
        self.done.store(0, SeqCst);
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, SeqCst);
    }
    fn finish(&self) {
        self.finished.fetch_add(1, SeqCst);
    }
    fn cancelled(&self) -> bool {
        self.done.load(SeqCst) >= self.after
    }
}

/// `result` is `Cancelled` and the job reported less than its total.
fn assert_stopped_early<T: std::fmt::Debug>(job: &str, result: octsolid::Result<T>, progress: &StopAfter) {
    match result {
        Err(Error::Cancelled) => {}
        other => panic!("{job}: want Cancelled, got {other:?}"),
    }
    let (done, total) = progress.read();
    assert!(done < total, "{job}: {done} of {total} units reported: it ran to the end");
}

fn ball(depth: u8) -> (Sphere, Domain, LinearOctree) {
    let sphere = Sphere::new(DVec3::ZERO, 0.8).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
    let tree = voxelize(&sphere, domain, &VoxelizeOptions::default()).unwrap();
    (sphere, domain, tree)
}

#[test]
fn a_voxelization_stops_when_asked_and_runs_to_its_total_when_not() {
    let (sphere, domain, tree) = ball(7);
    let stop = StopAfter::at_once();
    let result = voxelize(&sphere, domain, &VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &stop });
    assert_stopped_early("voxelize", result, &stop);
    let go = StopAfter::never();
    let done = voxelize(&sphere, domain, &VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &go });
    assert_eq!(done.unwrap(), tree);
    assert_eq!(go.read(), (512, 512));

    let mesh = icosphere(DVec3::ZERO, 0.8, 3);
    let stop = StopAfter::at_once();
    let result = voxelize_mesh(&mesh, domain, &MeshVoxelizeOptions { progress: &stop, ..Default::default() });
    assert_stopped_early("voxelize_mesh", result, &stop);
}

#[test]
fn every_renderer_stops_between_rows() {
    let (_, _, tree) = ball(6);
    let mut scene = Scene::new();
    scene.add("ball", tree, Material::default());
    let camera = Camera::look_at(DVec3::new(0.0, -3.0, 1.0), DVec3::ZERO, DVec3::Z, 40.0);
    let base = RenderOptions { width: 64, height: 64, spp: 2, ..RenderOptions::default() };
    let cases = [
        ("front to back", RenderOptions { method: Method::FrontToBack, ..base }),
        ("ray traced", RenderOptions { method: Method::Trace, ..base }),
        ("adaptive", RenderOptions { aa: AntiAliasing::Adaptive { threshold: 0.0 }, ..base }),
        ("recursive", RenderOptions { aa: AntiAliasing::Recursive { threshold: 0.0, depth: 2 }, ..base }),
    ];
    for (name, options) in cases {
        let stop = StopAfter::at_once();
        assert_stopped_early(name, render_picture(&scene, &camera, &options, &stop), &stop);
        let go = StopAfter::never();
        render_picture(&scene, &camera, &options, &go).unwrap();
        let (done, total) = go.read();
        assert!(done == total && total > 1, "{name}: {done} of {total}");
    }
}

#[test]
fn radiosity_stops_between_shots_and_rows() {
    // A closed room whose walls glow: the hollow between two boxes.
    let room = tree(&(cuboid([-0.75; 3], [0.75; 3]) - cuboid([-0.5; 3], [0.5; 3])));
    let mut scene = Scene::new();
    scene.add("room", room, diffuse(0.5, 1.0));
    for solver in [Solver::Shooting, Solver::Gathering] {
        let options = RadiosityOptions { patch_size: Some(0.25), until: 1e-6, solver, ..RadiosityOptions::default() };
        let stop = StopAfter::at_once();
        assert_stopped_early(&format!("{solver:?}"), Radiosity::solve(&scene, &options, &stop), &stop);
    }
}

#[test]
fn a_surface_and_its_file_stop_and_nothing_is_written() {
    let (sphere, _, tree) = ball(7);
    let hermite = HermiteData::from_shape(&sphere, &tree);
    let options = ExtractOptions { style: Style::Smooth, tolerance: 0.1, ..ExtractOptions::default() };
    let stop = StopAfter::new(2);
    assert_stopped_early("extract", extract(&tree, &hermite, &options, &stop), &stop);

    let dir = common::scratch_dir("cancel", "surface_file");
    let path = dir.join("ball.glb");
    let stop = StopAfter::at_once();
    let result = write_solid_file(&path, &SolidsRef::of_file(&path, &tree), &WriteOptions::default(), &stop);
    assert_stopped_early("write .glb", result, &stop);
    assert_eq!(common::folder_files(&dir), Vec::new(), "a cancelled write leaves no file");
}

#[test]
fn an_offset_stops_between_passes() {
    let (_, _, tree) = ball(7);
    let stop = StopAfter::at_once();
    let options = OffsetOptions { progress: &stop, ..OffsetOptions::default() };
    assert_stopped_early("shell", tree.shell(4.0, true, &options), &stop);
}

#[test]
fn a_drawing_stopped_while_voxelizing_its_mesh_says_cancelled_not_undrawable() {
    let dir = common::scratch_dir("cancel", "drawing");
    let path = dir.join("ball.obj");
    octsolid::mesh::write_mesh(&icosphere(DVec3::ZERO, 0.8, 3), &path).unwrap();
    let stop = StopAfter::at_once();
    let options = octsolid::DrawingOptions { depth: Some(7), progress: &stop, ..Default::default() };
    assert_stopped_early("drawing", octsolid::Drawing::open(&path, &options).map(|_| ()), &stop);
}

/// A scene file of one shape solid, a ball at depth 7, in a scratch folder of `test`.
fn ball_scene(test: &str) -> std::path::PathBuf {
    let path = common::scratch_dir("cancel", test).join("ball.toml");
    let scene = "[domain]\nmin = [-1, -1, -1]\nedge = 2\ndepth = 7\n\n[[solid]]\n\
                 shape = { sphere = { center = [0, 0, 0], radius = 0.8 } }\n";
    std::fs::write(&path, scene).unwrap();
    path
}

#[test]
fn a_scene_stopped_while_building_its_solids_says_cancelled() {
    let path = ball_scene("scene");
    let read = |stop: &dyn Progress| {
        let options = octsolid::scene_file::SceneReadOptions { stop, ..Default::default() };
        octsolid::scene_file::read_scene_with(&path, &options)
    };
    // Asked to stop from the start: the scene reports nothing to it, only asks.
    match read(&StopAfter::new(0)) {
        Err(Error::Cancelled) => {}
        other => panic!("want Cancelled, got {:?}", other.map(|_| ())),
    }
    assert_eq!(read(&StopAfter::never()).unwrap().scene.solids.len(), 1);
}

#[test]
fn radiosity_stops_while_making_a_shape_solids_patches() {
    let path = ball_scene("patches");
    let scene = octsolid::scene_file::read_scene(&path, MemoryBudget::unlimited()).unwrap().scene;
    for solver in [Solver::Shooting, Solver::Gathering] {
        let stop = StopAfter::new(0);
        match Radiosity::solve(&scene, &RadiosityOptions { solver, ..RadiosityOptions::default() }, &stop) {
            Err(Error::Cancelled) => {}
            other => panic!("{solver:?}: want Cancelled, got {:?}", other.map(|_| ())),
        }
        // Stopped before the solver started: its progress never began.
        assert_eq!(stop.read(), (0, 0), "{solver:?}");
    }
}

#[test]
fn the_crossings_of_a_shape_stop_when_asked_and_report_every_face_otherwise() {
    // Depth 8: about 200,000 boundary faces, blocks of 65,536. (The CLI's `shape` and `build`
    // ignored Ctrl-C while they found them.)
    let (sphere, _, tree) = ball(8);
    let progress = StopAfter::at_once();
    assert_stopped_early("crossings", HermiteData::from_shape_with(&sphere, &tree, &progress), &progress);
    let progress = StopAfter::never();
    let data = HermiteData::from_shape_with(&sphere, &tree, &progress).unwrap();
    assert_eq!(progress.read(), (data.len() as u64, data.len() as u64));
    assert!(data.len() > 2 << 16, "{} faces: not several blocks", data.len());
    assert_eq!(data, HermiteData::from_shape(&sphere, &tree));
}
