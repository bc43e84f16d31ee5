//! The Stanford bunny, voxelized and carved by CSG: hollowed out by a shrunken copy of
//! itself, then bored through by a cylindrical tunnel. And the closed (watertight)
//! bunny as a shape in a CSG expression before any voxelizing: `bunny - cylinder`.
//!
//! Run: `cargo run --release --example bunny_csg` (writes example-output/bunny_csg/bunny_csg.oct and .png).

use glam::DAffine3;
use octsolid::mesh::{MeshVoxelizeOptions, read_mesh, voxelize_mesh};
use octsolid::prelude::*;

mod common;

fn main() -> std::process::ExitCode {
    common::run("bunny_csg", bunny_csg)
}

fn bunny_csg(out: &std::path::Path) -> Result<()> {
    // The scan is open at the base; the default `auto` rule picks the winding number.
    let mesh = read_mesh(common::model("stanford-bunny.obj"))?;
    let domain = Domain::around(&mesh.bounds(), 0.02, 9)?;
    let (bunny, stats) = voxelize_mesh(&mesh, domain, &MeshVoxelizeOptions::default())?;

    // Hollow: remove the bunny shrunk to 75% about its body's centre (an exact
    // octree resample through a scale).
    let body = DVec3::new(-0.015, 0.09, 0.0);
    let shrink =
        DAffine3::from_translation(body) * DAffine3::from_scale(DVec3::splat(0.75)) * DAffine3::from_translation(-body);
    let cavity = bunny.resample(shrink, domain, &VoxelizeOptions::default())?;

    // Tunnel: a cylinder along x through the body.
    let tunnel = voxelize(&Cylinder::new(body, Axis::X, 0.015, 0.4)?, domain, &VoxelizeOptions::default())?;

    let carved = &(&bunny - &cavity) - &tunnel;
    oct::write(&carved, out.join("bunny_csg.oct"))?;
    png::write(&slice_image(&carved, Axis::Z, 0.0, 768)?, out.join("bunny_csg.png"))?;

    println!(
        "bunny at depth 9 ({} rule): {} nodes, volume {:.4e}",
        stats.rule.map_or_else(|| "no".into(), |r| format!("{r:?}")),
        bunny.node_count(),
        bunny.volume()
    );
    println!(
        "cavity {:.4e} (0.75^3 = 42.2% of the bunny: {:.1}%)",
        cavity.volume(),
        100.0 * cavity.volume() / bunny.volume()
    );
    println!("carved: {} nodes, volume {:.4e}", carved.node_count(), carved.volume());

    // A closed mesh is a Shape: carve the watertight bunny by a cylinder first, then
    // voxelize the expression once.
    let closed = read_mesh(common::model("bunny-watertight.obj"))?;
    let b = closed.bounds();
    let (centre, size) = (b.center(), b.size());
    let bore = Cylinder::new(centre, Axis::X, 0.12 * size.y, 1.2 * size.x)?;
    let expression = MeshShape::new(&closed)? - bore;
    let bored = voxelize(&expression, Domain::around(&b, 0.02, 8)?, &VoxelizeOptions::default())?;
    oct::write(&bored, out.join("bunny_bored.oct"))?;
    png::write(&slice_image(&bored, Axis::Z, centre.z, 768)?, out.join("bunny_bored.png"))?;
    println!("closed bunny minus a bore, as one shape: {} nodes, volume {:.4e}", bored.node_count(), bored.volume());
    println!("bunny_csg.oct, bunny_csg.png (slice at z = 0), bunny_bored.oct and bunny_bored.png");
    Ok(())
}
