//! The Utah teapot from its 32 bicubic Bezier patches: the surface voxelized straight
//! from the patches, and the solid (the spout and handle pierce the body, so the
//! winding rule decides inside).
//!
//! Run: `cargo run --release --example teapot` (writes example-output/teapot/teapot.oct, teapot_shell.oct, teapot.png).

use octsolid::import::{self, ImportOptions, Input};
use octsolid::patch::{tessellate, voxelize_patch_surface};
use octsolid::prelude::*;

mod common;

fn main() -> std::process::ExitCode {
    common::run("teapot", teapot)
}

fn teapot(out: &std::path::Path) -> Result<()> {
    let input = Input::read(common::model("teapot.patches"))?;
    let Input::Patches(patches) = &input else { unreachable!("a .patches file") };
    let domain = import::default_domain(&input, 9)?;

    // The shell, within half a voxel of the patches.
    let shell = voxelize_patch_surface(patches, domain, &VoxelizeOptions::default())?;
    // The solid, from a tessellation fine enough for the voxel size.
    let (solid, summary) = import::voxelize_input(&input, domain, &ImportOptions::default())?;
    oct::write(&solid, out.join("teapot.oct"))?;
    oct::write(&shell, out.join("teapot_shell.oct"))?;
    png::write(&slice_image(&solid, Axis::Y, 0.0, 768)?, out.join("teapot.png"))?;

    let reference = octsolid::mesh::PolygonTables::new(&tessellate(patches, 64)).report().volume;
    println!("teapot: {} patches; shell {} nodes ({} voxels)", patches.len(), shell.node_count(), shell.voxel_count());
    println!(
        "solid ({} rule, {} triangles): {} nodes, volume {:.4} vs {:.4} for a 64x64-a-patch tessellation ({:+.2}%)",
        summary.rule.map_or_else(|| "no".into(), |r| format!("{r:?}")),
        summary.triangles,
        solid.node_count(),
        solid.volume(),
        reference,
        100.0 * (solid.volume() / reference - 1.0)
    );
    println!("teapot.oct, teapot_shell.oct and teapot.png (slice at y = 0)");
    Ok(())
}
