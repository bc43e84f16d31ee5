//! Sharded jobs as tasks of Ray (`distributed/octsolid_ray.py`): a scene's solid, a
//! mesh, a shape and a streaming CSG of two of them, run on 1 worker (whose first
//! task kills its own worker process, so Ray must run it again) and on 4 worker
//! processes on 127.0.0.1, give folders bit for bit those of the jobs run in one
//! process without `--cells`. A task that fails is reported by name.
//!
//! Ray comes from `distributed/install_ray.sh` (`.venv-ray/`), so the test is ignored
//! by a plain `cargo test` (the summary says so) and run by `.ci/run`, which installs
//! Ray first (`cargo test -- --include-ignored`); run so without Ray, it fails.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::folder_files;

/// The repository's top folder (this test belongs to the cli package in `cli/`).
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("cli/ has a parent").to_path_buf()
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("distributed", name)
}

/// The Python of `.venv-ray` when Ray imports there.
fn ray_python() -> Option<PathBuf> {
    let python = repo().join(".venv-ray/bin/python");
    let ok = Command::new(&python).args(["-c", "import ray"]).output().is_ok_and(|o| o.status.success());
    ok.then_some(python)
}

/// The jobs, in order (the CSG reads two earlier outputs), with outputs in the
/// working folder.
fn jobs() -> Vec<Vec<String>> {
    let (scene, mesh) = (repo().join("scenes/classic.toml"), repo().join("models/bunny-watertight.obj"));
    let level = ["--shard-level", "2"];
    let job = |args: &[&str]| args.iter().chain(&level).map(|s| (*s).to_string()).collect::<Vec<_>>();
    vec![
        job(&["build", scene.to_str().unwrap(), "--solid", "classic part", "-o", "part.octs"]),
        job(&["voxelize", mesh.to_str().unwrap(), "--depth", "7", "-o", "bunny.octs"]),
        job(&[
            "shape",
            "sphere",
            "--radius",
            "1.2",
            "--depth",
            "9",
            "--domain",
            "-2.2,-2.2,-1.6,4.4",
            "-o",
            "ball.octs",
        ]),
        job(&["csg", "difference", "ball.octs", "part.octs", "-o", "carved.octs"]),
    ]
}

const OUTPUTS: [&str; 4] = ["part.octs", "bunny.octs", "ball.octs", "carved.octs"];

/// The driver script over `jobs` in `dir`.
fn driver(python: &Path, dir: &Path, options: &[&str], jobs: &[Vec<String>], env: &[(&str, &Path)]) -> Output {
    let mut command = Command::new(python);
    command.current_dir(dir).arg(repo().join("distributed/octsolid_ray.py"));
    command.args(["--octsolid", env!("CARGO_BIN_EXE_octsolid")]).args(options);
    for job in jobs {
        command.arg("--").args(job);
    }
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().unwrap()
}

fn succeeded(output: &Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{what} failed:\n{stdout}\n{stderr}");
    stdout
}

#[test]
#[ignore = "needs Ray: distributed/install_ray.sh, then cargo test -- --include-ignored (.ci/run does)"]
fn jobs_on_one_worker_with_a_killed_task_and_on_four_workers_equal_one_process() {
    let python = ray_python().expect("Ray is missing: run distributed/install_ray.sh (it makes .venv-ray)");
    let jobs = jobs();

    // The oracle: each job in one process, every cell, joined by the job itself.
    let one = scratch("one");
    for job in &jobs {
        let output = Command::new(env!("CARGO_BIN_EXE_octsolid")).current_dir(&one).args(job).output().unwrap();
        succeeded(&output, &format!("octsolid {job:?}"));
    }

    // One worker: 4 tasks a job, run one at a time; the first task to start kills
    // its worker process, and only Ray's retry can make its cells.
    let w1 = scratch("w1");
    let marker = w1.join("killed");
    let output = driver(&python, &w1, &["--workers", "1"], &jobs, &[("OCTSOLID_RAY_KILL_ONCE", &marker)]);
    let stdout = succeeded(&output, "the driver on 1 worker");
    assert!(stdout.contains("1 local worker on 127.0.0.1"), "a local Ray is on the loopback only:\n{stdout}");
    assert!(marker.exists(), "no task killed its worker:\n{stdout}");
    assert_eq!(stdout.matches("tasks done 4/4").count(), jobs.len(), "{stdout}");

    // Four workers: 16 tasks a job, as they come; then a job with a missing input,
    // which fails by name once its one retry fails too.
    let w4 = scratch("w4");
    let mut with_bad = jobs.clone();
    let bad: Vec<String> = ["csg", "union", "ball.octs", "missing.octs", "-o", "bad.octs", "--shard-level", "2"]
        .map(String::from)
        .to_vec();
    with_bad.push(bad);
    let output = driver(&python, &w4, &["--workers", "4", "--retries", "1"], &with_bad, &[]);
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "a job with a missing input succeeded:\n{stdout}");
    assert!(stdout.contains("4 local workers on 127.0.0.1"), "{stdout}");
    assert_eq!(stdout.matches("tasks done 16/16").count(), jobs.len(), "{stdout}\n{stderr}");
    assert!(stderr.contains("a task failed after 1 retries") && stderr.contains("missing.octs"), "{stderr}");
    assert!(!w4.join("bad.octs").exists());

    for name in OUTPUTS {
        let reference = folder_files(&one.join(name));
        assert!(reference.len() > 2, "{name}: an index and shards expected");
        assert!(folder_files(&w1.join(name)) == reference, "{name}: 1 worker differs from one process");
        assert!(folder_files(&w4.join(name)) == reference, "{name}: 4 workers differ from one process");
    }
    for dir in [one, w1, w4] {
        std::fs::remove_dir_all(dir).unwrap();
    }
}
