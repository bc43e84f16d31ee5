//! Draws the worked large example's time and peak memory against depth (log axes)
//! from the CSV `benches/large/large_part.py` writes.
//!
//! `cargo run --release -p octsolid-harness --example plot_large -- TABLE.csv OUT.png [BUDGET_BYTES]`

use std::path::PathBuf;

use octsolid_harness::plots::{LargeStep, large_plot};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [table, out, rest @ ..] = args.as_slice() else {
        return Err("usage: plot_large TABLE.csv OUT.png [BUDGET_BYTES]".into());
    };
    let budget: f64 = rest.first().map_or(Ok(2.0 * f64::from(1u32 << 30)), |b| b.parse())?;
    let text = std::fs::read_to_string(table)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().ok_or("empty table")?.split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).ok_or(format!("no column {name}"));
    let (depth, step, seconds, peak) = (column("depth")?, column("step")?, column("seconds")?, column("peak_bytes")?);
    let mut steps = Vec::new();
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        let cell = |c: usize| cells.get(c).copied().ok_or(format!("{table}: row {}: too few columns", i + 2));
        steps.push(LargeStep {
            depth: cell(depth)?.parse()?,
            step: cell(step)?.to_owned(),
            seconds: cell(seconds)?.parse()?,
            peak_bytes: cell(peak)?.parse()?,
        });
    }
    large_plot(&steps, budget, &PathBuf::from(out))?;
    Ok(())
}
