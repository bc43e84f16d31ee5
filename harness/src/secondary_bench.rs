//! Issue 41's incoherent rays measured: the primary, bounce and shadow rays of
//! [`crate::secondary_rays()`] through every contender on one thread, with the peers that
//! live outside Rust: embreex (Embree 4 from PyPI) on the source mesh, reading the rays
//! from files the harness writes ([`crate::ray_file`]), and the branch misses and
//! instructions a ray of each contender, counted by `perf stat` around `walk_one`
//! (`benches/peers/branch_misses.sh`).
//!
//! Fairness: every contender traces the same rays in the same order in a 1-thread rayon
//! pool (chunks of 256 rays a task, as the matrix); times are the CPU time of that
//! thread (`CLOCK_THREAD_CPUTIME_ID`, wall time where it cannot be read), so other
//! work on a shared machine does not count, medians of `repeats` runs after one warm-up
//! run; embreex's are its thread's CPU time too. A peer that cannot run leaves its cells "n/a" and says why in the notes; the
//! section is still written.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use super::any_contender::{Inputs, build_contender};
use super::machine::Machine;
use super::matrix::ContenderKind;
use super::ray_file::write_rays;
use super::rays::{RayKind, RaySet};
use super::scenes::voxelized_model;
use super::secondary_rays::{SEED, SecondaryRays, secondary_rays};
use octsolid::mesh::{BoundaryOptions, try_boundary_mesh};
use octsolid::render::Traversal;
use octsolid::{Error, MemoryBudget, NoProgress, Progress, Result};

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct SecondaryOptions {
    /// The model (a closed triangle mesh).
    pub model: PathBuf,
    /// Depth of its voxelization.
    pub depth: u8,
    /// Edge of the view in pixels (one primary ray a pixel).
    pub size: u32,
    /// Seed of the bounce rays.
    pub seed: u64,
    /// Timed runs a measurement, after one warm-up run.
    pub repeats: usize,
    /// The contenders, in table order (those this binary cannot build are listed as
    /// skipped).
    pub contenders: Vec<ContenderKind>,
    /// Where the ray files for the peers are written.
    pub rays_dir: PathBuf,
    /// The folder of the peer scripts (`benches/peers`).
    pub peers: PathBuf,
    /// The Python with embreex (`benches/peers/setup.sh` makes `target/peers-venv`).
    pub python: PathBuf,
    /// Count branch misses with `perf stat` (`benches/peers/branch_misses.sh`).
    pub branch_misses: bool,
    /// Memory budget for voxelizing the model.
    pub budget: MemoryBudget,
}

impl Default for SecondaryOptions {
    /// Issue 41's sitting: `models/bunny-watertight.obj` at depth 10, a 1024 x 1024
    /// view, 3 runs; the octree, the 64-tree, the BVHs over its boundary faces and Embree over the
    /// boundary faces and over the source mesh.
    fn default() -> Self {
        SecondaryOptions {
            model: PathBuf::from("models/bunny-watertight.obj"),
            depth: 10,
            size: 1024,
            seed: SEED,
            repeats: 3,
            contenders: vec![
                ContenderKind::Octree,
                ContenderKind::Tree64,
                ContenderKind::ObvhsFaces,
                ContenderKind::BvhFaces,
                ContenderKind::EmbreeFaces,
                ContenderKind::EmbreeMesh,
            ],
            rays_dir: PathBuf::from("target/issue-rays"),
            peers: PathBuf::from("benches/peers"),
            python: PathBuf::from("target/peers-venv/bin/python"),
            branch_misses: true,
            budget: MemoryBudget::default(),
        }
    }
}

/// One contender on one ray set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetResult {
    /// Which set.
    pub kind: RayKind,
    /// Rays traced a run.
    pub rays: usize,
    /// Rays that hit (closest hit found, or shadow ray occluded).
    pub hits: u64,
    /// Median seconds a run, one thread.
    pub seconds: f64,
    /// Mispredicted branches a ray (`perf stat`), when counted.
    pub branch_misses: Option<f64>,
    /// Instructions a ray (`perf stat`), when counted.
    pub instructions: Option<f64>,
}

impl SetResult {
    /// Million rays a second.
    #[must_use]
    pub fn mrays(&self) -> f64 {
        self.rays as f64 / self.seconds / 1e6
    }
}

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct SecondaryRow {
    /// The contender, `None` for a peer measured outside Rust (embreex).
    pub kind: Option<ContenderKind>,
    /// Name in the table.
    pub label: String,
    /// Why it did not run, if it did not.
    pub skipped: Option<String>,
    /// Triangles it was built over (0 for the octree).
    pub triangles: usize,
    /// Build time, milliseconds (all threads).
    pub build_ms: f64,
    /// Bytes of the structure (0 when unknown).
    pub bytes: usize,
    /// Its result on each set, in [`SecondaryRays::sets`] order.
    pub sets: Vec<SetResult>,
}

impl SecondaryRow {
    /// The result on `kind`'s set.
    #[must_use]
    pub fn set(&self, kind: RayKind) -> Option<&SetResult> {
        self.sets.iter().find(|s| s.kind == kind)
    }
}

/// Everything the section measured.
#[derive(Clone, Debug, PartialEq)]
pub struct SecondaryResults {
    /// Where and when.
    pub machine: Machine,
    /// What was run.
    pub options: SecondaryOptions,
    /// Triangles of the source mesh.
    pub mesh_triangles: usize,
    /// Triangles of the octree's boundary faces.
    pub face_triangles: usize,
    /// Rays in each set.
    pub rays: Vec<(RayKind, usize)>,
    /// One row a contender, then the peers'.
    pub rows: Vec<SecondaryRow>,
    /// Why a column or a peer is "n/a", in words.
    pub notes: Vec<String>,
}

/// Median of `times` (sorted in place).
fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    let n = times.len();
    if n % 2 == 1 { times[n / 2] } else { 0.5 * (times[n / 2 - 1] + times[n / 2]) }
}

/// Seconds of CPU the calling thread has used (`CLOCK_THREAD_CPUTIME_ID`, to the
/// nanosecond; `/proc/thread-self/schedstat` is only brought up to date at scheduler
/// ticks, too coarse for runs of tens of milliseconds), `None` where it cannot be read.
fn thread_cpu_seconds() -> Option<f64> {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `t` is a valid timespec for the call to write.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0;
    ok.then_some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
}

/// Seconds `work` takes on the calling thread: its CPU time, or wall time where that
/// cannot be read.
fn timed(work: impl FnOnce()) -> f64 {
    let (cpu, wall) = (thread_cpu_seconds(), Instant::now());
    work();
    match (cpu, thread_cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => wall.elapsed().as_secs_f64(),
    }
}

/// A rayon pool of `n` threads.
fn pool(n: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| Error::InvalidArgument { what: "threads", reason: format!("cannot start {n} threads: {e}") })
}

/// Number of progress units [`run_secondary`] reports: a build and three sets a
/// contender, and one a peer (embreex, the branch misses).
#[must_use]
pub fn work_units(options: &SecondaryOptions) -> u64 {
    4 * options.contenders.len() as u64 + 2
}

/// Runs the section: voxelizes the model, makes and writes the rays, measures every
/// contender and the peers; `progress` receives [`work_units`] units.
pub fn run_secondary(options: &SecondaryOptions, progress: &dyn Progress) -> Result<SecondaryResults> {
    if options.size == 0 {
        return Err(Error::InvalidArgument { what: "size", reason: "the view needs at least one pixel".into() });
    }
    progress.start(work_units(options));
    let (one, all) = (pool(1)?, pool(std::thread::available_parallelism().map_or(1, usize::from))?);
    let (tree, mesh) = all.install(|| voxelized_model(&options.model, options.depth, options.budget))?;
    let rays = all.install(|| secondary_rays(&Traversal::new(&tree), &mesh.bounds(), options.size, options.seed));
    std::fs::create_dir_all(&options.rays_dir)
        .map_err(|source| Error::Io { path: options.rays_dir.clone(), source })?;
    for set in rays.sets() {
        write_rays(&options.rays_dir.join(format!("{}.rays", set.kind.name())), &set.rays)?;
    }
    let faces = all.install(|| try_boundary_mesh(&tree, &BoundaryOptions::default(), options.budget, &NoProgress))?;
    let inputs = Inputs { tree: &tree, faces: &faces, mesh: Some(&mesh) };
    let mut rows = Vec::new();
    for &kind in &options.contenders {
        let triangles = match kind {
            ContenderKind::Octree | ContenderKind::Tree64 => 0,
            ContenderKind::ObvhsMesh
            | ContenderKind::BvhMesh
            | ContenderKind::EmbreeMesh
            | ContenderKind::EmbreePacketsMesh => mesh.triangles.len(),
            _ => faces.triangles.len(),
        };
        rows.push(measure(kind, triangles, inputs, &rays, &one, &all, options.repeats));
        progress.advance(4);
    }
    let mut notes = Vec::new();
    match embreex(options, mesh.triangles.len()) {
        Ok(row) => rows.push(row),
        Err(why) => notes.push(format!("embreex: n/a, {why}")),
    }
    progress.advance(1);
    if options.branch_misses {
        if let Err(why) = branch_misses(options, &mut rows) {
            notes.push(format!("branch misses: n/a, {why}"));
        }
    } else {
        notes.push("branch misses: not counted (--no-perf)".into());
    }
    progress.advance(1);
    progress.finish();
    Ok(SecondaryResults {
        machine: Machine::current(),
        options: options.clone(),
        mesh_triangles: mesh.triangles.len(),
        face_triangles: faces.triangles.len(),
        rays: rays.sets().iter().map(|s| (s.kind, s.rays.len())).collect(),
        rows,
        notes,
    })
}

/// Builds `kind` (all threads, median of `repeats` builds) and traces the three sets on
/// one thread.
fn measure(
    kind: ContenderKind,
    triangles: usize,
    inputs: Inputs<'_>,
    rays: &SecondaryRays,
    one: &rayon::ThreadPool,
    all: &rayon::ThreadPool,
    repeats: usize,
) -> SecondaryRow {
    let row = |skipped, build_ms, bytes, sets| SecondaryRow {
        kind: Some(kind),
        label: kind.label().to_string(),
        skipped,
        triangles,
        build_ms,
        bytes,
        sets,
    };
    let mut builds = Vec::new();
    let mut built = None;
    for _ in 0..repeats.max(1) {
        let started = Instant::now();
        match all.install(|| build_contender(kind, inputs)) {
            Ok(c) => built = Some(c),
            Err(why) => return row(Some(why), 0.0, 0, Vec::new()),
        }
        builds.push(started.elapsed().as_secs_f64() * 1e3);
    }
    let structure = built.expect("built at least once");
    let sets = rays
        .sets()
        .into_iter()
        .map(|set: &RaySet| {
            let hits = one.install(|| structure.trace_set(set));
            let mut times: Vec<f64> = (0..repeats.max(1))
                .map(|_| {
                    one.install(|| {
                        timed(|| {
                            structure.trace_set(set);
                        })
                    })
                })
                .collect();
            SetResult {
                kind: set.kind,
                rays: set.rays.len(),
                hits,
                seconds: median(&mut times),
                branch_misses: None,
                instructions: None,
            }
        })
        .collect();
    row(None, median(&mut builds), structure.structure_bytes(), sets)
}

/// Runs `program` with `args`; its standard output, or why it failed.
fn run(program: &Path, args: &[&str]) -> std::result::Result<String, String> {
    let out =
        Command::new(program).args(args).output().map_err(|e| format!("cannot run {}: {e}", program.display()))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("").trim();
        return Err(format!("{} {} failed ({}): {last}", program.display(), args.join(" "), out.status));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Numbers of a whitespace-separated line `words`, `None` for `n/a`.
fn numbers(words: &[&str]) -> std::result::Result<Vec<Option<f64>>, String> {
    words
        .iter()
        .map(|w| if *w == "n/a" { Ok(None) } else { w.parse().map(Some).map_err(|_| format!("not a number: {w}")) })
        .collect()
}

/// The set kind of a ray file's stem.
fn set_kind(name: &str) -> Option<RayKind> {
    [RayKind::Primary, RayKind::Bounce, RayKind::Shadow].into_iter().find(|k| k.name() == name)
}

/// embreex on the source mesh through `embreex_ray_files.py`, whose output is a line
/// `embreex VERSION EMBREE_VERSION BUILD_MS`, then `SET RAYS HITS SECONDS` a set.
fn embreex(options: &SecondaryOptions, triangles: usize) -> std::result::Result<SecondaryRow, String> {
    if !options.python.exists() {
        return Err(format!("no {} (benches/peers/setup.sh makes it)", options.python.display()));
    }
    let script = options.peers.join("embreex_ray_files.py");
    let (model, dir, runs) = (options.model.to_string_lossy(), options.rays_dir.to_string_lossy(), options.repeats);
    let out = run(&options.python, &[&script.to_string_lossy(), &model, &dir, "--runs", &runs.to_string()])?;
    let mut lines = out.lines().map(|l| l.split_whitespace().collect::<Vec<_>>());
    let head = lines.next().ok_or("embreex_ray_files.py printed nothing")?;
    let [_, version, embree, build_ms] = head[..] else { return Err(format!("unexpected first line {head:?}")) };
    let mut sets = Vec::new();
    for words in lines {
        let [name, ref values @ ..] = words[..] else { continue };
        let kind = set_kind(name).ok_or_else(|| format!("unknown ray set {name}"))?;
        let [Some(rays), Some(hits), Some(seconds)] = numbers(values)?[..] else {
            return Err(format!("unexpected line for {name}: {words:?}"));
        };
        sets.push(SetResult {
            kind,
            rays: rays as usize,
            hits: hits as u64,
            seconds,
            branch_misses: None,
            instructions: None,
        });
    }
    Ok(SecondaryRow {
        kind: None,
        label: format!("embreex {version} (Embree {embree}), original mesh"),
        skipped: None,
        triangles,
        build_ms: build_ms.parse().unwrap_or(f64::NAN),
        bytes: 0,
        sets,
    })
}

/// Branch misses and instructions a ray of every contender that ran, through
/// `branch_misses.sh MODEL DEPTH SIZE SEED CONTENDER...`, whose output is a line
/// `CONTENDER SET RAYS BRANCH_MISSES INSTRUCTIONS` a contender and set (each a ray,
/// `n/a` when perf cannot count them).
fn branch_misses(options: &SecondaryOptions, rows: &mut [SecondaryRow]) -> std::result::Result<(), String> {
    let slugs: Vec<&str> =
        rows.iter().filter(|r| r.skipped.is_none()).filter_map(|r| r.kind.map(|k| k.slug())).collect();
    let script = options.peers.join("branch_misses.sh");
    let (model, depth, size, seed) = (
        options.model.to_string_lossy().into_owned(),
        options.depth.to_string(),
        options.size.to_string(),
        options.seed.to_string(),
    );
    let mut args = vec![script.to_str().unwrap_or("branch_misses.sh"), &model, &depth, &size, &seed];
    args.extend(&slugs);
    let out = run(Path::new("bash"), &args)?;
    let mut counted = false;
    let mut why = None;
    for line in out.lines() {
        if let Some(reason) = line.strip_prefix('#') {
            why.get_or_insert_with(|| reason.trim().to_string());
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        let [slug, set, ref values @ ..] = words[..] else { continue };
        let (Some(kind), Some(set)) = (ContenderKind::from_slug(slug), set_kind(set)) else { continue };
        let [_, misses, instructions] = numbers(values)?[..] else { return Err(format!("unexpected line {line:?}")) };
        let Some(result) =
            rows.iter_mut().find(|r| r.kind == Some(kind)).and_then(|r| r.sets.iter_mut().find(|s| s.kind == set))
        else {
            continue;
        };
        result.branch_misses = misses;
        result.instructions = instructions;
        counted |= misses.is_some();
    }
    match (counted, why) {
        (true, _) => Ok(()),
        (false, Some(why)) => Err(why),
        (false, None) => Err("branch_misses.sh counted nothing".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder of its own under the system's temporary folder.
    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("octsolid-secondary-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A row of `kind` with 1,000 rays of each set.
    fn row(kind: ContenderKind) -> SecondaryRow {
        let set = |kind| SetResult { kind, rays: 1000, hits: 1, seconds: 1.0, branch_misses: None, instructions: None };
        SecondaryRow {
            kind: Some(kind),
            label: kind.label().into(),
            skipped: None,
            triangles: 0,
            build_ms: 1.0,
            bytes: 1,
            sets: vec![set(RayKind::Primary), set(RayKind::Bounce), set(RayKind::Shadow)],
        }
    }

    #[test]
    fn the_peer_scripts_output_lands_in_its_rows_and_a_reason_explains_n_a() {
        let peers = scratch("peers");
        let script = peers.join("branch_misses.sh");
        // Echoes its arguments back, so the test sees what the harness passed.
        std::fs::write(
            &script,
            "echo \"# args $*\"\necho 'octree primary 1000 12.50 800.00'\necho 'octree bounce 1000 n/a n/a'\n\
             echo 'embree-mesh shadow 1000 3.25 410.5'\n",
        )
        .unwrap();
        let options = SecondaryOptions { peers: peers.clone(), ..SecondaryOptions::default() };
        let mut rows = vec![row(ContenderKind::Octree), row(ContenderKind::EmbreeMesh)];
        branch_misses(&options, &mut rows).unwrap();
        assert_eq!(rows[0].set(RayKind::Primary).unwrap().branch_misses, Some(12.5));
        assert_eq!(rows[0].set(RayKind::Primary).unwrap().instructions, Some(800.0));
        assert_eq!(rows[0].set(RayKind::Bounce).unwrap().branch_misses, None);
        assert_eq!(rows[1].set(RayKind::Shadow).unwrap().branch_misses, Some(3.25));
        assert_eq!(rows[1].set(RayKind::Primary).unwrap().branch_misses, None);

        std::fs::write(&script, "echo '# no hardware counters'\necho 'octree primary n/a n/a n/a'\n").unwrap();
        let why = branch_misses(&options, &mut [row(ContenderKind::Octree)]).unwrap_err();
        assert_eq!(why, "no hardware counters");

        // embreex: a stand-in "python" printing the script's lines.
        let python = peers.join("python");
        std::fs::write(&python, "#!/bin/sh\necho 'embreex 9.9 4.4.0 12.5'\necho 'bounce 400 37 0.0002'\n").unwrap();
        std::process::Command::new("chmod").arg("+x").arg(&python).status().unwrap();
        let options = SecondaryOptions { python, ..options };
        let peer = embreex(&options, 3700).unwrap();
        assert_eq!(peer.label, "embreex 9.9 (Embree 4.4.0), original mesh");
        let bounce = peer.set(RayKind::Bounce).unwrap();
        assert_eq!((bounce.rays, bounce.hits), (400, 37));
        assert!((bounce.mrays() - 2.0).abs() < 1e-9);
        let missing = SecondaryOptions { python: peers.join("nowhere"), ..options };
        assert!(embreex(&missing, 3700).unwrap_err().contains("setup.sh"));
        std::fs::remove_dir_all(&peers).unwrap();
    }
}
