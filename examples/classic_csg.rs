//! The classic CSG part: a cube of side 2 intersected with a sphere of radius 1.3,
//! minus three cylinders of radius 0.6 along x, y and z.
//!
//! Run: `cargo run --release --example classic_csg` (writes example-output/classic_csg/classic_csg.oct and .png).
//! With `-- --time`, also prints the time of the work itself (from the model to the
//! PNG written, timed in the process), as `examples/python/classic_part.py` prints its
//! own: `python/bench_classic.sh` sets the two against each other.

use std::f64::consts::PI;
use std::time::Instant;

use octsolid::prelude::*;

mod common;

fn main() -> std::process::ExitCode {
    common::run("classic_csg", classic_csg)
}

fn classic_csg(out: &std::path::Path) -> Result<()> {
    let started = Instant::now();
    // Model: (cube & ball) minus three bores.
    let cube = Cuboid::new(DVec3::ZERO, DVec3::splat(2.0))?;
    let ball = Sphere::new(DVec3::ZERO, 1.3)?;
    let bore = |axis| Cylinder::new(DVec3::ZERO, axis, 0.6, 3.0);
    let part = (cube & ball) - bore(Axis::X)? - bore(Axis::Y)? - bore(Axis::Z)?;

    // Voxelize into 512^3 voxels over the cube [-1, 1]^3 and save.
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 9)?;
    let solid = voxelize(&part, domain, &VoxelizeOptions::default())?;
    oct::write(&solid, out.join("classic_csg.oct"))?;
    png::write(&slice_image(&solid, Axis::Z, 0.8, 768)?, out.join("classic_csg.png"))?;
    let work = started.elapsed();

    // Analytic volume: the ball clipped by the cube loses six caps of height h = R - 1
    // (they never overlap since 2 > R^2); the three bores lie wholly inside it and
    // their union is 3 V_cyl - 3 V_bicylinder + V_tricylinder (Steinmetz solids).
    let (r_ball, r_bore) = (1.3_f64, 0.6_f64);
    let h = r_ball - 1.0;
    let clipped_ball = 4.0 / 3.0 * PI * r_ball.powi(3) - 6.0 * PI * h * h * (3.0 * r_ball - h) / 3.0;
    let bores = 3.0 * PI * r_bore.powi(2) * 2.0 - 3.0 * 16.0 / 3.0 * r_bore.powi(3)
        + 8.0 * (2.0 - 2f64.sqrt()) * r_bore.powi(3);
    let exact = clipped_ball - bores;
    println!("classic CSG part at depth 9: {} nodes, {} voxels", solid.node_count(), solid.voxel_count());
    println!("volume {:.5}, analytic {:.5} ({:+.3}%)", solid.volume(), exact, 100.0 * (solid.volume() / exact - 1.0));
    println!("classic_csg.oct and classic_csg.png (slice at z = 0.8)");
    if std::env::args().any(|a| a == "--time") {
        println!("work {:.1} ms (voxelize, the .oct, the slice's PNG)", work.as_secs_f64() * 1e3);
    }
    Ok(())
}
