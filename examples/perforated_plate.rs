//! A perforated plate: 200 x 200 x 10 minus a 20 x 20 grid of through-holes of radius
//! 3 at (5 + 10 i, 5 + 10 j), one CSG tree of 401 shapes written with one pattern.
//!
//! Run: `cargo run --release --example perforated_plate [-- DEPTH... [--runs N] [--json]]`
//! (default depth 10, 3 runs). Prints, for each depth, the median voxelization time
//! and the volume against the analytic `400000 - 3600 pi * 10`, and writes
//! example-output/perforated_plate/plate.oct and plate.png (a slice through the
//! plate) at the first depth. `--json` prints one JSON line a depth instead (what
//! `benches/peers/plate_side_by_side.py` reads).
//!
//! The domain is the cube of edge 204.8 from (-2.4, -2.4, -97.2): at depth 10 its
//! voxels are 0.2 wide, so the plate's faces lie on voxel boundaries at every depth
//! from 10 on and the holes are 15 voxels in radius.

use std::f64::consts::PI;
use std::time::Instant;

use octsolid::prelude::*;

mod common;

fn main() -> std::process::ExitCode {
    common::run("perforated_plate", perforated_plate)
}

/// The plate minus the hole grid, in one line of pattern.
fn plate() -> Result<Csg> {
    let slab = Cuboid::from_corners(DVec3::ZERO, DVec3::new(200.0, 200.0, 10.0))?;
    let hole = Cylinder::new(DVec3::new(5.0, 5.0, 5.0), Axis::Z, 3.0, 12.0)?;
    Ok(slab - linear_array(hole, [20, 20, 1], DVec3::new(10.0, 10.0, 0.0))?)
}

fn perforated_plate(out: &std::path::Path) -> Result<()> {
    let (mut depths, mut runs, mut json) = (Vec::new(), 3usize, false);
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--json" => json = true,
            "--runs" => {
                let n = args.next().and_then(|n| n.parse().ok()).filter(|&n| n > 0);
                runs = n.ok_or_else(|| bad_argument("--runs", "give a positive number of runs".into()))?;
            }
            depth => depths.push(depth.parse::<u8>().map_err(|_| bad_argument("depth", format!("'{depth}'")))?),
        }
    }
    if depths.is_empty() {
        depths.push(10);
    }
    let exact = 400_000.0 - 3600.0 * PI * 10.0;
    let tree = plate()?;
    for (i, &depth) in depths.iter().enumerate() {
        let domain = Domain::new(DVec3::new(-2.4, -2.4, -97.2), 204.8, depth)?;
        let mut times = Vec::with_capacity(runs);
        let mut solid = None;
        for _ in 0..runs {
            let started = Instant::now();
            solid = Some(voxelize(
                &tree,
                domain,
                &VoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() },
            )?);
            times.push(started.elapsed().as_secs_f64());
        }
        let solid = solid.expect("at least one run");
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let error = solid.volume() / exact - 1.0;
        if json {
            println!(
                "{{\"tool\": \"octsolid\", \"model\": \"plate\", \"depth\": {depth}, \"median_s\": {median:.6}, \
                 \"runs\": {runs}, \"threads\": {}, \"nodes\": {}, \"volume\": {}, \"analytic_volume\": {exact}, \
                 \"rel_error_vs_analytic\": {error:e}}}",
                rayon::current_num_threads(),
                solid.node_count(),
                solid.volume(),
            );
        } else {
            println!(
                "plate at depth {depth}: {:.3} s (median of {runs}), {} nodes, volume {:.1}, analytic {exact:.1} ({:+.3}%)",
                median,
                solid.node_count(),
                solid.volume(),
                100.0 * error
            );
        }
        if i == 0 {
            oct::write(&solid, out.join("plate.oct"))?;
            png::write(&slice_image(&solid, Axis::Z, 5.0, 1024)?, out.join("plate.png"))?;
        }
    }
    Ok(())
}

fn bad_argument(what: &'static str, reason: String) -> Error {
    Error::InvalidArgument { what, reason }
}
