//! `octsolid slice FILE --axis A --at V [--size N] -o OUT.png`: a cross-section.

use std::path::PathBuf;

use anyhow::{Context, Result};
use octsolid::io::png;
use octsolid::shape::Axis;
use octsolid::{FileKind, MemoryBudget};

use crate::output::check_extension;
use crate::solid_input::{ReadFlags, read_solid_file};

/// Arguments of `octsolid slice`.
#[derive(clap::Args, Debug)]
pub struct SliceArgs {
    /// The solid file: .oct, .vox, .binvox or .vdb (several solids: their union).
    pub file: PathBuf,
    /// Axis the cutting plane is perpendicular to.
    #[arg(long, default_value = "z")]
    pub axis: Axis,
    /// World coordinate of the plane along the axis (default: the domain's middle).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::values::parse_finite)]
    pub at: Option<f64>,
    /// Image edge in pixels.
    #[arg(long, default_value_t = 768)]
    pub size: u32,
    /// Output PNG file.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// `octsolid slice FILE --axis A --at V [--size N] -o OUT.png`
pub fn run(a: &SliceArgs, budget: MemoryBudget) -> Result<()> {
    let (file, axis, size, output) = (&a.file, a.axis, a.size, &a.output);
    check_extension(output, &[FileKind::Png])?;
    budget.check(format!("a {size}x{size} slice"), octsolid::slice::estimate_bytes(size))?;
    let tree = read_solid_file(file, &a.read, budget)?.into_union();
    let d = tree.domain();
    let at = a.at.unwrap_or(d.min()[axis.index()] + 0.5 * d.edge());
    let img = octsolid::slice::slice_image(&tree, axis, at, size)
        .with_context(|| format!("{}: cannot slice", file.display()))?;
    png::write(&img, output)?;
    out!("wrote {} ({size}x{size}, {} = {})", output.display(), crate::human::axis(axis), crate::human::num(at));
    Ok(())
}
