//! The viewer's moving frame on one thread, for profiles (BENCHMARKS.md and
//! docs/benchmark-log/2026-12.md, "The viewer's moving frame"): the bunny at depth 10, 1280x720, the front-to-back display, 1 sample
//! a pixel, axis normals, no shadows, encoded as PNG, `N` times (`view_frame N`).
//! Under callgrind, collect only the frames:
//! `valgrind --tool=callgrind --toggle-collect='view_frame::frame*'`.
use octsolid::io::png;
use octsolid::mesh::{MeshVoxelizeOptions, read_mesh, voxelize_mesh};
use octsolid::octree::Domain;
use octsolid::render::{Camera, Method, Normals, RenderOptions, Scene, ShadeOptions};
use octsolid::shape::Axis;
use octsolid::{MemoryBudget, NoProgress};

#[inline(never)]
fn frame(scene: &Scene, camera: &Camera, options: &RenderOptions) -> usize {
    png::render_png(scene, camera, options, &NoProgress).unwrap().0.len()
}

fn main() {
    let n: usize = std::env::args().nth(1).map_or(1, |a| a.parse().expect("N: a count of frames"));
    let mesh = read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/../models/stanford-bunny.obj")).unwrap();
    let options = MeshVoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    let tree = voxelize_mesh(&mesh, Domain::around(&mesh.bounds(), 0.02, 10).unwrap(), &options).unwrap().0;
    let bounds = tree.bounds().unwrap();
    let scene = Scene::from_solid(tree);
    let camera = Camera::frame(&bounds, Camera::default_view(Axis::Y), Axis::Y.unit(), 1280.0 / 720.0);
    let options = RenderOptions {
        width: 1280,
        height: 720,
        spp: 1,
        shade: ShadeOptions { shadows: false, normals: Normals::Axis, ..ShadeOptions::default() },
        method: Method::FrontToBack,
        ..RenderOptions::default()
    };
    let bytes: usize = (0..n).map(|_| frame(&scene, &camera, &options)).sum();
    println!("{n} frames, {bytes} PNG bytes");
}
