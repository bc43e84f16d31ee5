//! Sharded outputs written by real processes at once: two writers of one `.octs`
//! leave one complete solid, one of the two, as two writers of one `.oct` leave one
//! file; the tasks of two different jobs writing one output are never joined into
//! one solid; `info` checks the shards before it says what the index says.
//! They pin issue 36's defects of concurrent `.octs` writers.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

mod common;

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("sharded-processes", name)
}

fn octsolid(dir: &Path, args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_octsolid"));
    command.current_dir(dir).args(args);
    command
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let out = octsolid(dir, args).output().unwrap();
    assert!(out.status.success(), "octsolid {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn fails(dir: &Path, args: &[&str]) -> String {
    let out = octsolid(dir, args).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "octsolid {args:?} should fail");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// Two shapes over one domain, as `shape` arguments.
const SHAPES: [&[&str]; 2] = [
    &["shape", "sphere", "--radius", "1.5", "--depth", "9", "--domain", "-2,-2,-2,4"],
    &["shape", "torus", "--radius", "1.2", "--tube", "0.5", "--depth", "9", "--domain", "-2,-2,-2,4"],
];

/// The solid of the `.oct` file at `path` as bytes, without a surface section (shards
/// carry none, so a sharded solid converted to `.oct` is compared with this).
fn solid_bytes(path: &std::path::Path) -> Vec<u8> {
    let (tree, meta) = octsolid::io::oct::read_and_metadata(path, octsolid::MemoryBudget::unlimited()).unwrap();
    octsolid::io::oct::encode_with(&tree, &meta)
}

fn args<'a>(shape: &[&'a str], more: &[&'a str]) -> Vec<&'a str> {
    shape.iter().chain(more).copied().collect()
}

#[test]
fn two_processes_writing_one_sharded_output_leave_one_complete_solid() {
    let dir = scratch("race");
    // The oracles: each shape as one file.
    for (i, shape) in SHAPES.iter().enumerate() {
        ok(&dir, &args(shape, &["-o", &format!("want{i}.oct")]));
    }
    let want: Vec<Vec<u8>> = (0..2).map(|i| solid_bytes(&dir.join(format!("want{i}.oct")))).collect();
    for round in 0..10 {
        let children: Vec<_> = SHAPES
            .iter()
            .map(|shape| {
                let mut command = octsolid(&dir, &args(shape, &["--shard-level", "2", "-o", "race.octs"]));
                command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap()
            })
            .collect();
        let outputs: Vec<Output> = children.into_iter().map(|c| c.wait_with_output().unwrap()).collect();
        for out in &outputs {
            assert!(out.status.success(), "round {round}: {}", String::from_utf8_lossy(&out.stderr));
        }
        // Every shard read and checked against the index, then compared.
        ok(&dir, &["convert", "race.octs", "got.oct"]);
        let got = std::fs::read(dir.join("got.oct")).unwrap();
        assert!(got == want[0] || got == want[1], "round {round}: the solid is neither writer's");
        let staging = dir.join("race.octs.partial");
        assert!(!staging.exists(), "round {round}: {:?} left", std::fs::read_dir(&staging).map(|d| d.count()));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tasks_of_two_jobs_writing_one_output_are_not_joined_and_info_checks_the_shards() {
    let dir = scratch("two-jobs");
    ok(&dir, &args(SHAPES[0], &["--shard-level", "2", "--cells", "0..32", "-o", "mixed.octs"]));
    ok(&dir, &args(SHAPES[1], &["--shard-level", "2", "--cells", "32..64", "-o", "mixed.octs"]));
    let e = fails(&dir, &["join", "mixed.octs"]);
    assert!(e.contains("none covers every cell"), "{e}");
    assert!(!dir.join("mixed.octs").exists());
    // The first job's other half, from another folder and spelling of the output: joined.
    ok(&dir, &args(SHAPES[0], &["--cells", "32..64", "--shard-level", "2", "--output", "mixed.octs"]));
    ok(&dir, &["join", "mixed.octs"]);
    ok(&dir, &args(SHAPES[0], &["-o", "want.oct"]));
    ok(&dir, &["convert", "mixed.octs", "got.oct"]);
    assert!(std::fs::read(dir.join("got.oct")).unwrap() == solid_bytes(&dir.join("want.oct")));
    // An index whose shard bounds are not the shard's: `info` refuses it by name.
    let solid = dir.join("mixed.octs");
    let mut index = octsolid::sharded::ShardIndex::read(&solid).unwrap();
    let i = index.shards.iter().position(|s| s.min != s.max).unwrap();
    index.shards[i].min = index.shards[i].max;
    std::fs::write(solid.join("index"), index.encode()).unwrap();
    let e = fails(&dir, &["info", "mixed.octs"]);
    assert!(e.contains(&index.layout().shard_file(index.shards[i].cell)) && e.contains("the index says"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
