//! The Menger sponge, level 4: the library's [`Menger`] shape, voxelized and sliced.
//! (src/shape/menger.rs shows how little a user-defined [`Shape`] needs: a box
//! classification and a point test.)
//!
//! Run: `cargo run --release --example menger [LEVEL] [DEPTH]` (defaults 4 and 9;
//! writes example-output/menger/menger.oct and menger.png).

use octsolid::prelude::*;

mod common;

fn main() -> std::process::ExitCode {
    common::run("menger", menger)
}

fn menger(out: &std::path::Path) -> Result<()> {
    let mut args = std::env::args().skip(1).map(|a| a.parse::<u32>());
    let level = args.next().transpose().map_err(|e| Error::InvalidArgument { what: "level", reason: e.to_string() })?;
    let depth = args.next().transpose().map_err(|e| Error::InvalidArgument { what: "depth", reason: e.to_string() })?;
    let (level, depth) = (level.unwrap_or(4), depth.unwrap_or(9).min(21) as u8);

    let sponge = Menger::new(DVec3::ZERO, 2.0, level)?;
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth)?;
    let solid = voxelize(&sponge, domain, &VoxelizeOptions::default())?;
    oct::write(&solid, out.join("menger.oct"))?;
    png::write(&slice_image(&solid, Axis::Z, -0.99, 810)?, out.join("menger.png"))?;

    let exact = sponge.volume();
    println!(
        "Menger sponge level {level} at depth {depth}: {} nodes, {} voxels",
        solid.node_count(),
        solid.voxel_count()
    );
    println!(
        "volume {:.5}, analytic {:.5} ({:+.2}%; a 2^{depth} grid cannot align with thirds)",
        solid.volume(),
        exact,
        100.0 * (solid.volume() / exact - 1.0)
    );
    println!("menger.oct and menger.png (slice at z = -0.99: a Sierpinski carpet)");
    Ok(())
}
