//! `octsolid csg OP A B [MORE...] -o OUT`: .oct files combined by a set operation.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::ValueEnum;
use octsolid::io::oct;
use octsolid::{MemoryBudget, human_bytes};

use super::print_summary;

/// Arguments of `octsolid csg`.
#[derive(clap::Args, Debug)]
pub struct CsgArgs {
    /// The operation (difference: the first minus all the others).
    pub op: CsgOp,
    /// Input .oct files (at least two), all over the same domain and depth.
    #[arg(required = true, num_args = 2..)]
    pub inputs: Vec<PathBuf>,
    /// Output .oct file.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// A set operation over files.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum CsgOp {
    /// Voxels in any input.
    Union,
    /// Voxels in every input.
    Intersect,
    /// Voxels in the first input and no other.
    Difference,
    /// Voxels in an odd number of inputs.
    Xor,
}

/// `octsolid csg OP A B [MORE...] -o OUT`
pub fn run(a: &CsgArgs, budget: MemoryBudget) -> Result<()> {
    let (op, inputs, output) = (a.op, &a.inputs, &a.output);
    let mut trees = Vec::with_capacity(inputs.len());
    for path in inputs {
        trees.push(oct::load(path, budget)?);
    }
    let started = Instant::now();
    let mut result = trees[0].clone();
    for (tree, path) in trees.iter().zip(inputs).skip(1) {
        result = match op {
            CsgOp::Union => result.union(tree),
            CsgOp::Intersect => result.intersection(tree),
            CsgOp::Difference => result.difference(tree),
            CsgOp::Xor => result.symmetric_difference(tree),
        }
        .with_context(|| format!("{}: cannot combine with {}", path.display(), inputs[0].display()))?;
    }
    out!("{op:?} of {} solids in {:.2} ms", trees.len(), started.elapsed().as_secs_f64() * 1e3);
    let bytes = oct::save(&result, output)?;
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    print_summary(&result, None);
    Ok(())
}
