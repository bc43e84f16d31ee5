//! Issue 38's surface-quality table: meshes (OBJ, PLY, STL, read by
//! `octsolid::mesh::read_mesh`) measured against the exact surface of an analytic
//! solid, one Markdown table row a mesh. The oracle and the measurement are the tests'
//! (tests/common/exact_surface.rs: area-weighted samples, distance to the exact surface
//! RMS / max in voxels, the triangle normals' angle to the exact normal, median and
//! share within 5 degrees, away from creases); this program only reads, measures and
//! prints. It times nothing: the time column is what `--time` says (the scripts time
//! whole commands, benches/peers/surface.sh).
//!
//! ```text
//! cargo bench --bench surface_quality -- [--solid classic] [--voxel 0.004296875]
//!     [--samples 200000] [--seed 1] [--header] [--label TEXT] [--time TEXT] MESH ...
//! cargo bench --bench surface_quality -- --reference SOURCE.obj --voxel V MESH ...
//! ```
//!
//! `--label` and `--time` apply to the next mesh only (the label defaults to the file's
//! name). Meshes may also come from the environment variable `SURFACE_QUALITY_MESHES`
//! (paths separated by whitespace) when none is given. Solids: `classic` (default:
//! the classic CSG part, voxel 2.2 / 512 by default, its depth 9 in [-1.1, 1.1]^3),
//! `sphere`, `torus`, `cube`, `sphere-minus-cube` (`ExactSolid::by_name`).
//!
//! The second mode, `--reference SOURCE`, measures the distance from each mesh's
//! samples to another mesh (the source a solid was voxelized from; a bounding-box
//! hierarchy over its triangles, tests/common/mesh_distance.rs): mean, median, RMS and
//! max in voxels; the same away from the source's holes (where the source is open and
//! the solid closed, the samples whose nearest source point lies on the source's open
//! boundary are the closing surface's: their share of the area is given, and the mean
//! and max of the others); and back, from as many samples of the source to the mesh
//! (mean and max), one row a mesh.

#[path = "../tests/common/exact_surface.rs"]
mod exact_surface;
#[path = "../tests/common/mesh_distance.rs"]
mod mesh_distance;

use std::process::ExitCode;

use exact_surface::{DEFAULT_SAMPLES, ExactSolid, measure_with, par_map, sample_mesh};
use mesh_distance::MeshDistance;

/// One mesh to measure, with its row's label and time.
struct Job {
    path: String,
    label: Option<String>,
    time: Option<String>,
}

struct Options {
    solid: String,
    voxel: f64,
    samples: usize,
    seed: u64,
    header: bool,
    reference: Option<String>,
    jobs: Vec<Job>,
}

fn parse(args: Vec<String>) -> Result<Options, String> {
    let mut o = Options {
        solid: "classic".into(),
        voxel: 2.2 / 512.0,
        samples: DEFAULT_SAMPLES,
        seed: 1,
        header: false,
        reference: None,
        jobs: Vec::new(),
    };
    let (mut label, mut time) = (None, None);
    let mut it = args.into_iter();
    while let Some(arg) = it.next() {
        let mut value = || it.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            // What `cargo bench` passes to every bench target.
            "--bench" => {}
            "--solid" => o.solid = value()?,
            "--voxel" => o.voxel = value()?.parse().map_err(|e| format!("--voxel: {e}"))?,
            "--samples" => o.samples = value()?.parse().map_err(|e| format!("--samples: {e}"))?,
            "--seed" => o.seed = value()?.parse().map_err(|e| format!("--seed: {e}"))?,
            "--header" => o.header = true,
            "--reference" => o.reference = Some(value()?),
            "--label" => label = Some(value()?),
            "--time" => time = Some(value()?),
            flag if flag.starts_with("--") => return Err(format!("unknown option {flag}")),
            _ => o.jobs.push(Job { path: arg, label: label.take(), time: time.take() }),
        }
    }
    if o.jobs.is_empty()
        && let Ok(list) = std::env::var("SURFACE_QUALITY_MESHES")
    {
        o.jobs = list.split_whitespace().map(|p| Job { path: p.into(), label: None, time: None }).collect();
    }
    Ok(o)
}

fn label(job: &Job) -> String {
    job.label.clone().unwrap_or_else(|| {
        let name = std::path::Path::new(&job.path).file_name().map_or(job.path.clone(), |n| n.to_string_lossy().into());
        format!("`{name}`")
    })
}

/// Mean, median, RMS and maximum of distances.
struct Stats {
    mean: f64,
    median: f64,
    rms: f64,
    max: f64,
}

impl Stats {
    fn of(mut d: Vec<f64>) -> Self {
        if d.is_empty() {
            return Stats { mean: f64::NAN, median: f64::NAN, rms: f64::NAN, max: f64::NAN };
        }
        d.sort_by(f64::total_cmp);
        let n = d.len() as f64;
        Stats {
            mean: d.iter().sum::<f64>() / n,
            median: d[d.len() / 2],
            rms: (d.iter().map(|x| x * x).sum::<f64>() / n).sqrt(),
            max: d[d.len() - 1],
        }
    }
}

/// `1234567` as `1,234,567`.
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, ch) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(ch);
    }
    out
}

fn run(o: &Options) -> Result<(), String> {
    if o.jobs.is_empty() {
        return Err("no mesh given (arguments or SURFACE_QUALITY_MESHES)".into());
    }
    if let Some(reference) = &o.reference {
        let source = octsolid::mesh::read_mesh(reference).map_err(|e| e.to_string())?;
        let to_source = MeshDistance::new(&source);
        let source_samples = sample_mesh(&source, o.samples, o.seed);
        if o.header {
            println!(
                "| mesh | triangles | to the source mesh, mean / median / RMS / max | the same away from the source's holes, mean / max (area over them) | from the source mesh, mean / max | time |"
            );
            println!("|---|---:|---|---|---|---:|");
        }
        for job in &o.jobs {
            let mesh = octsolid::mesh::read_mesh(&job.path).map_err(|e| e.to_string())?;
            let samples = sample_mesh(&mesh, o.samples, o.seed);
            let nearest = par_map(&samples, |s| to_source.nearest(s.point));
            let there = Stats::of(nearest.iter().map(|n| n.distance / o.voxel).collect());
            let away: Vec<f64> =
                nearest.iter().filter(|n| !n.over_open_boundary).map(|n| n.distance / o.voxel).collect();
            let over_holes = 1.0 - away.len() as f64 / nearest.len() as f64;
            let away = Stats::of(away);
            let to_mesh = MeshDistance::new(&mesh);
            let back = Stats::of(par_map(&source_samples, |s| to_mesh.distance(s.point) / o.voxel));
            println!(
                "| {} | {} | {:.3} / {:.3} / {:.3} / {:.2} voxel | {:.3} / {:.2} voxel ({:.2}%) | {:.3} / {:.2} voxel | {} |",
                label(job),
                thousands(mesh.triangles.len()),
                there.mean,
                there.median,
                there.rms,
                there.max,
                away.mean,
                away.max,
                100.0 * over_holes,
                back.mean,
                back.max,
                job.time.as_deref().unwrap_or("")
            );
        }
        return Ok(());
    }
    let solid = ExactSolid::by_name(&o.solid).ok_or(format!("unknown solid {}", o.solid))?;
    if o.header {
        println!(
            "| mesh | triangles | distance to the true surface, RMS / max | face normals off, median | share of area within 5 degrees | time |"
        );
        println!("|---|---:|---|---:|---:|---:|");
    }
    for job in &o.jobs {
        let mesh = octsolid::mesh::read_mesh(&job.path).map_err(|e| e.to_string())?;
        let q = measure_with(&mesh, &solid, o.voxel, o.samples, o.seed);
        println!(
            "| {} | {} | {:.3} / {:.2} voxel | {:.3} | {:.1}% | {} |",
            label(job),
            thousands(q.triangles),
            q.rms,
            q.max,
            q.median_normal_deg,
            100.0 * q.share_within_5deg_away_from_edges,
            job.time.as_deref().unwrap_or("")
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    let result = parse(std::env::args().skip(1).collect()).and_then(|o| run(&o));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("surface_quality: {e}");
            ExitCode::FAILURE
        }
    }
}
