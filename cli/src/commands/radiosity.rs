//! `octsolid radiosity SCENE.toml -o SOLUTION.rad [--solver shooting|gathering]
//! [--until F] [--max-shots N] [--tolerance T] [--patch-size S] [--subdivide T
//! [--max-elements N]] [--plot PLOT.png] [--json]`: solves a scene's diffuse
//! interreflection by progressive refinement (shooting) or by the chapter's
//! `[F][B] = [E]` with Gauss-Seidel (gathering) and saves the view-independent
//! solution (render it with `render --radiosity`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use octsolid::render::Scene;
use octsolid::render::radiosity::{DEFAULT_TOLERANCE, DEFAULT_UNTIL, Radiosity, RadiosityOptions, Solver};
use octsolid::{FileKind, MemoryBudget, scene_file};
use serde::Serialize;

use super::print_warnings;
use crate::output::{check_extension, check_not_an_input};
use crate::progress_bar::Bar;
use crate::values::names;

/// Arguments of `octsolid radiosity`.
#[derive(clap::Args, Debug)]
pub struct RadiosityArgs {
    /// The scene (.toml).
    pub scene: PathBuf,
    /// The solution file to write (.rad).
    #[arg(short, long)]
    pub output: PathBuf,
    /// shooting (progressive refinement, the default) or gathering (the chapter's
    /// [F][B] = [E]: the whole form-factor matrix, refused with its size above 4 GiB or
    /// the memory budget, then Gauss-Seidel sweeps to --tolerance).
    #[arg(long, default_value = "shooting", value_parser = names::<Solver>(Solver::ALL.map(Solver::name)))]
    pub solver: Solver,
    /// Gathering: stop when the largest residual is at most this fraction of the
    /// largest radiosity.
    #[arg(long, default_value_t = DEFAULT_TOLERANCE, value_parser = crate::values::parse_finite)]
    pub tolerance: f64,
    /// Shooting: stop when the unshot energy is at most this fraction of the emitted
    /// energy.
    #[arg(long, default_value_t = DEFAULT_UNTIL, value_parser = crate::values::parse_finite)]
    pub until: f64,
    /// Shooting: stop after N shots (lights included) even if --until is not reached.
    #[arg(long)]
    pub max_shots: Option<u64>,
    /// Longest patch edge in world units (default: an eighth of the scene's extent).
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub patch_size: Option<f64>,
    /// Adaptive subdivision: split an element into four where its radiosity differs
    /// from a neighbour's by more than THRESHOLD times the scene's mean radiosity (e.g.
    /// 0.5), and refine on the finer elements, up to four levels deeper (default: off,
    /// the base elements only).
    #[arg(long, value_name = "THRESHOLD", value_parser = crate::values::parse_finite)]
    pub subdivide: Option<f64>,
    /// With --subdivide: most elements to end with (default: four times the base
    /// elements).
    #[arg(long, requires = "subdivide")]
    pub max_elements: Option<usize>,
    /// Also draw the unshot energy against shots and seconds into this PNG.
    #[arg(long, value_name = "PLOT.png")]
    pub plot: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// What `octsolid radiosity --json` prints; the key names are a contract.
#[derive(Serialize)]
struct Summary {
    solver: String,
    patches: usize,
    elements: usize,
    shots: u64,
    unshot_fraction: f64,
    iterations: u64,
    residual: f64,
    seconds: f64,
}

/// Loads a scene file for radiosity, printing its warnings.
pub(crate) fn read_scene(path: &std::path::Path, budget: MemoryBudget) -> Result<scene_file::SceneFile> {
    let file = scene_file::read_scene(path, budget)?;
    print_warnings(&file.warnings);
    Ok(file)
}

/// Solves `scene` with a progress bar, the error naming `path`.
pub(crate) fn solve(scene: &Scene, options: &RadiosityOptions, path: &std::path::Path) -> Result<Radiosity> {
    let bar = Bar::new("radiosity");
    Radiosity::solve(scene, options, &bar).with_context(|| format!("{}: cannot solve radiosity", path.display()))
}

/// `octsolid radiosity SCENE.toml -o SOLUTION.rad [--until F] [--max-shots N] [--json]`
pub fn run(a: &RadiosityArgs, budget: MemoryBudget) -> Result<()> {
    FileKind::of(&a.scene, &[FileKind::Scene])?;
    check_extension(&a.output, &[FileKind::Rad])?;
    check_not_an_input(&a.output, &[&a.scene])?;
    if let Some(plot) = &a.plot {
        check_extension(plot, &[FileKind::Png])?;
        check_not_an_input(plot, &[&a.scene])?;
    }
    if a.solver == Solver::Gathering {
        if a.plot.is_some() {
            bail!("--plot draws shooting's unshot energy: it is for --solver shooting");
        }
        if a.max_shots.is_some() {
            bail!("--max-shots is for --solver shooting (gathering stops at --tolerance)");
        }
        if !(a.tolerance > 0.0 && a.tolerance < 1.0) {
            bail!("--tolerance {}: the residual fraction must be above 0 and below 1", a.tolerance);
        }
    }
    if !(0.0..1.0).contains(&a.until) {
        bail!("--until {}: the unshot fraction must be at least 0 and below 1", a.until);
    }
    let file = read_scene(&a.scene, budget)?;
    let options = RadiosityOptions {
        until: a.until,
        max_shots: a.max_shots,
        patch_size: a.patch_size,
        subdivide: a.subdivide,
        max_elements: a.max_elements,
        budget,
        solver: a.solver,
        tolerance: a.tolerance,
        ..Default::default()
    };
    let started = Instant::now();
    let solution = solve(&file.scene, &options, &a.scene)?;
    let seconds = started.elapsed().as_secs_f64();
    solution.write(&a.output)?;
    let s = solution.stats();
    if let Some(plot) = &a.plot {
        let title = a.scene.file_stem().unwrap_or_default().to_string_lossy();
        octsolid_harness::plots::convergence_plot(&s.history, solution.timeline(), &title, plot)?;
    }
    let summary = Summary {
        solver: a.solver.to_string(),
        patches: s.patches,
        elements: s.elements,
        shots: s.shots,
        unshot_fraction: s.unshot_fraction,
        iterations: s.iterations,
        residual: s.residual,
        seconds,
    };
    if a.json {
        out!("{}", serde_json::to_string(&summary)?);
        return Ok(());
    }
    if s.splits > 0 {
        out!("patches    {} ({} elements; {} split into four)", s.patches, s.elements, s.splits);
    } else {
        out!("patches    {} ({} elements)", s.patches, s.elements);
    }
    if a.solver == Solver::Gathering {
        let matrix = octsolid::render::radiosity::form_factor_matrix_bytes(s.elements, s.patches);
        out!(
            "matrix     {} x {} form factors ({:.1} MiB; {} rays)",
            s.elements,
            s.patches,
            matrix as f64 / 1048576.0,
            s.rays
        );
        out!("sweeps     {} Gauss-Seidel iterations, residual {:.2e}", s.iterations, s.residual);
    } else {
        let per_shot = 1e3 * seconds / s.shots.max(1) as f64;
        out!("shots      {} ({} rays; {per_shot:.2} ms a shot)", s.shots, s.rays);
        out!("unshot     {:.4} of the emitted energy", s.unshot_fraction);
    }
    out!("time       {seconds:.2} s");
    out!("wrote {}", a.output.display());
    Ok(())
}
