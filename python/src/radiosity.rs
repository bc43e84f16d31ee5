//! `radiosity`: a scene file's diffuse interreflection solved as `octsolid radiosity`
//! solves it (the library's `scene_file::read_scene`, then `Radiosity::solve` with the
//! same options and defaults), the solution written as the same `.rad` bytes when an
//! output path is given, and the summary `--json` prints returned as a dict.

use std::path::PathBuf;

use octsolid::render::radiosity::{DEFAULT_TOLERANCE, DEFAULT_UNTIL, Radiosity, RadiosityOptions, Solver};
use octsolid::scene_file;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::budget::Budget;
use crate::errors::warn_read_past;
use crate::errors::{ToPyResult, invalid};
use crate::ints::{optional_max_elements_arg, optional_max_shots_arg};
use crate::job::Job;
use crate::progress::Want;

/// Solves a scene file's radiosity as `octsolid radiosity` does: `solver`
/// (`"shooting"`, the default, or `"gathering"`), `until` (shooting's unshot fraction),
/// `max_shots`, `tolerance` (gathering's residual), `patch_size`, `subdivide` and
/// `max_elements`; writes the solution to `output` (a `.rad` file, the CLI's bytes)
/// when given. Returns the summary `octsolid radiosity --json` prints (`solver`,
/// `patches`, `elements`, `shots`, `unshot_fraction`, `iterations`, `residual`) with
/// the energy book (`emitted`, `absorbed`, `escaped`) and `bytes` written. With
/// `progress=True`, a bar on the terminal while it solves (or a callable `f(done,
/// total)`); `memory_budget`: bytes or a size like `"2GiB"` (`--memory-budget`).
#[pyfunction]
#[pyo3(signature = (
    scene, output=None, solver="shooting", until=DEFAULT_UNTIL, max_shots=None,
    tolerance=DEFAULT_TOLERANCE, patch_size=None, subdivide=None, max_elements=None, progress=None,
    memory_budget=None
))]
#[allow(clippy::too_many_arguments)]
pub fn radiosity<'py>(
    py: Python<'py>,
    scene: PathBuf,
    output: Option<PathBuf>,
    solver: &str,
    until: f64,
    #[pyo3(from_py_with = optional_max_shots_arg)] max_shots: Option<u64>,
    tolerance: f64,
    patch_size: Option<f64>,
    subdivide: Option<f64>,
    #[pyo3(from_py_with = optional_max_elements_arg)] max_elements: Option<usize>,
    progress: Option<Want>,
    memory_budget: Option<Budget>,
) -> PyResult<Bound<'py, PyDict>> {
    let solver = Solver::ALL.into_iter().find(|s| s.name() == solver).ok_or_else(|| {
        invalid("solver", format!("{solver:?} is not one of {}", Solver::ALL.map(Solver::name).join(", ")))
    })?;
    if !(0.0..1.0).contains(&until) {
        return Err(invalid("until", format!("{until}: the unshot fraction must be at least 0 and below 1")));
    }
    if solver == Solver::Gathering && !(tolerance > 0.0 && tolerance < 1.0) {
        return Err(invalid("tolerance", format!("{tolerance}: the residual fraction must be above 0 and below 1")));
    }
    // Checked before the solve (the library's write checks it too, after the solve).
    if let Some(path) = &output {
        octsolid::FileKind::of(path, &[octsolid::FileKind::Rad]).py()?;
    }
    let job = Job::new(memory_budget, progress, "radiosity");
    let budget = job.budget;
    let options = RadiosityOptions {
        until,
        max_shots,
        patch_size,
        subdivide,
        max_elements,
        budget,
        solver,
        tolerance,
        ..RadiosityOptions::default()
    };
    let (solution, bytes, warnings) = job.run(py, |budget, progress| {
        let load = scene_file::SceneReadOptions { budget, stop: progress, ..Default::default() };
        let file = scene_file::read_scene_with(&scene, &load)?;
        let solution = Radiosity::solve(&file.scene, &options, progress)?;
        let bytes = match &output {
            Some(path) => solution.write(path)?,
            None => 0,
        };
        Ok((solution, bytes, file.warnings))
    })?;
    warn_read_past(py, &warnings)?;
    let s = solution.stats();
    let d = PyDict::new(py);
    d.set_item("solver", solver.name())?;
    d.set_item("patches", s.patches)?;
    d.set_item("elements", s.elements)?;
    d.set_item("shots", s.shots)?;
    d.set_item("unshot_fraction", s.unshot_fraction)?;
    d.set_item("iterations", s.iterations)?;
    d.set_item("residual", s.residual)?;
    d.set_item("emitted", s.emitted)?;
    d.set_item("absorbed", s.absorbed)?;
    d.set_item("escaped", s.escaped)?;
    d.set_item("bytes", bytes)?;
    Ok(d)
}
