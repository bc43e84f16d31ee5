//! A part for the printer: the classic CSG part (a cube and a ball intersected, three
//! bores through) voxelized with its exact crossings and exported as its true surface,
//! a closed, manifold mesh with sharp edges, in the printers' 3MF package (millimetres)
//! and as STL; the staircase of the same voxels beside it for comparison.
//!
//! Run: `cargo run --release --example printable_part` (writes
//! example-output/printable_part/part.3mf, part.stl and part-voxels.stl).

use octsolid::mesh::write_mesh;
use octsolid::prelude::*;
use octsolid::surface::{ExtractOptions, HermiteData, Style, extract};

mod common;

fn main() -> std::process::ExitCode {
    common::run("printable_part", printable_part)
}

fn printable_part(out: &std::path::Path) -> Result<()> {
    // Model, in millimetres: a 40 mm cube and a 52 mm ball, bores of 24 mm.
    let cube = Cuboid::new(DVec3::ZERO, DVec3::splat(40.0))?;
    let ball = Sphere::new(DVec3::ZERO, 26.0)?;
    let bore = |axis| Cylinder::new(DVec3::ZERO, axis, 12.0, 60.0);
    let part = (cube & ball) - bore(Axis::X)? - bore(Axis::Y)? - bore(Axis::Z)?;

    // Voxels of 0.25 mm, and where the surface crosses their faces (Hermite data).
    let domain = Domain::new(DVec3::splat(-22.0), 44.0, 8)?;
    let solid = voxelize(&part, domain, &VoxelizeOptions::default())?;
    let crossings = HermiteData::from_shape(&part, &solid);

    // The true surface: dual contouring of the crossings, closed and manifold.
    let smooth = extract(&solid, &crossings, &ExtractOptions::default(), &octsolid::NoProgress)?;
    write_mesh(&smooth.mesh, out.join("part.3mf"))?;
    write_mesh(&smooth.mesh, out.join("part.stl"))?;
    // The voxels' own boundary, the staircase, for comparison.
    let voxels = ExtractOptions { style: Style::Voxels, ..ExtractOptions::default() };
    write_mesh(&extract(&solid, &crossings, &voxels, &octsolid::NoProgress)?.mesh, out.join("part-voxels.stl"))?;
    println!(
        "{} triangles, {} vertices on creases and {} at corners; volume {:.1} mm^3 (voxels {:.1})",
        smooth.mesh.triangles.len(),
        smooth.creases,
        smooth.corners,
        smooth.mesh.volume(),
        solid.volume()
    );
    Ok(())
}
