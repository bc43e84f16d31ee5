//! The merge of two large solids: two overlapping spheres voxelized at depth 12
//! (25,802,344 and 18,952,452 nodes, the `merge/spheres_12_*` cases of
//! `benches/csg_many.rs`), then their union or difference, timed.
//!
//! Run: `cargo run --release --example sphere_merge [-- union|difference [--threads T]
//! [--runs N]]` (default: union, on 1 and then 2 threads, 5 runs). Prints the median
//! and the fastest merge, and the time to free the result (about 240 MB, which a
//! merge's time includes in the bench, as it does for any caller). `--runs 0` only
//! voxelizes: under `perf stat -e task-clock`, the CPU time of `--runs N` less that of
//! `--runs 0`, over N, is the CPU time of one merge and its result's free.

use std::process::ExitCode;
use std::time::Instant;

use octsolid::prelude::*;

fn main() -> ExitCode {
    match sphere_merge() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("sphere_merge: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn sphere_merge() -> Result<()> {
    let (mut op, mut threads, mut runs) = (SetOp::Union, vec![1, 2], 5usize);
    let mut args = std::env::args().skip(1);
    let number = |flag: &'static str, value: Option<String>| {
        value.and_then(|n| n.parse().ok()).ok_or_else(|| bad_argument(flag, "give a number".into()))
    };
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "union" => op = SetOp::Union,
            "difference" => op = SetOp::Difference,
            "--threads" => threads = vec![number("--threads", args.next())?],
            "--runs" => runs = number("--runs", args.next())?,
            other => return Err(bad_argument("argument", format!("'{other}'"))),
        }
    }
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 12)?;
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    let a = voxelize(&Sphere::new(DVec3::new(-0.2, 0.0, 0.0), 0.7)?, domain, &options)?;
    let b = voxelize(&Sphere::new(DVec3::new(0.25, 0.1, 0.05), 0.6)?, domain, &options)?;
    let inputs = a.node_count() + b.node_count();
    println!("spheres at depth 12: {} + {} = {inputs} input nodes", a.node_count(), b.node_count());
    for &t in &threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .map_err(|e| bad_argument("--threads", e.to_string()))?;
        let (mut merges, mut frees, mut nodes) = (Vec::new(), Vec::new(), 0);
        for _ in 0..runs {
            let started = Instant::now();
            let merged = pool.install(|| a.combine(&b, op))?;
            merges.push(started.elapsed().as_secs_f64() * 1e3);
            nodes = merged.node_count();
            let started = Instant::now();
            drop(merged);
            frees.push(started.elapsed().as_secs_f64() * 1e3);
        }
        if runs == 0 {
            continue;
        }
        merges.sort_by(f64::total_cmp);
        frees.sort_by(f64::total_cmp);
        let median = merges[runs / 2];
        println!(
            "{op:?} on {t} thread{}: {nodes} nodes; merge {median:.1} ms (median of {runs}, fastest {:.1} ms, \
             {:.0} M input nodes/s), free {:.1} ms",
            if t == 1 { "" } else { "s" },
            merges[0],
            inputs as f64 / median / 1e3,
            frees[runs / 2],
        );
    }
    Ok(())
}

fn bad_argument(what: &'static str, reason: String) -> Error {
    Error::InvalidArgument { what, reason }
}
