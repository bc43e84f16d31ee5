//! The fuzzer's command line:
//!
//! ```text
//! cargo run --release -p octsolid-fuzz -- [TARGET|all] [--seconds N] [--seed S]
//!     [--cases N] [--timeout SECS] [--memory MIB] [--max-len BYTES]
//!     [--corpus DIR] [--artifacts DIR] [--print-outcomes]
//! cargo run --release -p octsolid-fuzz -- TARGET --replay FILE_OR_DIR...
//! cargo run --release -p octsolid-fuzz -- --write-corpus
//! cargo run --release -p octsolid-fuzz -- --list
//! ```
//!
//! Exit status: 0 when nothing was found, 1 when something was (each finding named,
//! its input saved under `fuzz/artifacts/TARGET/`), 2 for bad arguments.

use std::path::{Path, PathBuf};
use std::time::Duration;

use octsolid_fuzz::driver::{self, Config, code};
use octsolid_fuzz::guard::CountingAlloc;
use octsolid_fuzz::targets::{self, TARGETS, Target};

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc;

/// What the command line asks for.
enum Mode {
    Fuzz,
    Worker,
    Replay(Vec<PathBuf>),
    WriteCorpus,
    List,
}

fn usage(message: &str) -> i32 {
    eprintln!(
        "{message}\nusage: octsolid-fuzz [TARGET|all] [--seconds N] [--seed S] [--cases N] [--timeout SECS] [--memory MIB] [--max-len BYTES] [--corpus DIR] [--artifacts DIR] [--print-outcomes]"
    );
    eprintln!("       octsolid-fuzz TARGET --replay FILE_OR_DIR...");
    eprintln!("       octsolid-fuzz --write-corpus | --list");
    code::USAGE
}

fn main() {
    std::process::exit(real_main());
}

fn real_main() -> i32 {
    let mut config = Config::default();
    let mut mode = Mode::Fuzz;
    let mut target_name: Option<String> = None;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = |name: &str| args.next().ok_or_else(|| format!("{name} needs a value"));
        let parsed: Result<(), String> = (|| {
            match arg.as_str() {
                "--seconds" => config.seconds = number(&value("--seconds")?)?,
                "--seed" => config.seed = number(&value("--seed")?)?,
                "--cases" => config.cases = Some(number(&value("--cases")?)?),
                "--timeout" => config.timeout = Duration::from_secs_f64(number(&value("--timeout")?)?),
                "--memory" => config.memory = number::<usize>(&value("--memory")?)? << 20,
                "--max-len" => config.max_len = number(&value("--max-len")?)?,
                "--corpus" => config.corpus = PathBuf::from(value("--corpus")?),
                "--artifacts" => config.artifacts = PathBuf::from(value("--artifacts")?),
                "--worker" => mode = Mode::Worker,
                "--print-outcomes" => config.print_outcomes = true,
                "--write-corpus" => mode = Mode::WriteCorpus,
                "--list" => mode = Mode::List,
                "--replay" => mode = Mode::Replay(Vec::new()),
                s if s.starts_with("--") => return Err(format!("unknown option {s}")),
                s => match &mut mode {
                    Mode::Replay(files) => files.push(PathBuf::from(s)),
                    _ if target_name.is_none() => target_name = Some(s.to_owned()),
                    _ => return Err(format!("unexpected argument {s}")),
                },
            }
            Ok(())
        })();
        if let Err(e) = parsed {
            return usage(&e);
        }
    }
    let chosen: Vec<&'static Target> = match target_name.as_deref() {
        None | Some("all") => TARGETS.iter().collect(),
        Some(name) => match targets::by_name(name) {
            Some(t) => vec![t],
            None => return usage(&format!("no target {name:?}; --list names them")),
        },
    };
    match mode {
        Mode::List => {
            for t in TARGETS {
                println!("{:>16}  corpus {:<28}  {}", t.name, t.corpus.join(","), t.about);
            }
            code::CLEAN
        }
        Mode::WriteCorpus => {
            let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
            match octsolid_fuzz::corpus::write(&config.corpus, &repo) {
                Ok(files) => {
                    for (name, len) in &files {
                        println!("{len:>8}  {name}");
                    }
                    octsolid_fuzz::scratch::remove();
                    code::CLEAN
                }
                Err(e) => {
                    eprintln!("cannot write the corpus: {e}");
                    code::PANIC
                }
            }
        }
        Mode::Worker => match chosen.as_slice() {
            [one] => driver::worker(one, &config),
            _ => usage("--worker runs one target"),
        },
        Mode::Replay(paths) => {
            let [one] = chosen.as_slice() else { return usage("--replay needs one target") };
            let mut files = Vec::new();
            for p in paths {
                if p.is_dir() {
                    // A folder: its files, less the notes and the running case of an artifact folder.
                    let mut inside: Vec<PathBuf> = std::fs::read_dir(&p)
                        .into_iter()
                        .flatten()
                        .flatten()
                        .map(|e| e.path())
                        .filter(|p| p.is_file())
                        .filter(|p| {
                            !p.to_string_lossy().ends_with(".txt") && p.file_name() != Some(".current".as_ref())
                        })
                        .collect();
                    inside.sort();
                    files.extend(inside);
                } else {
                    files.push(p);
                }
            }
            if driver::replay(one, &files, &config) { code::CLEAN } else { code::PANIC }
        }
        Mode::Fuzz => {
            println!(
                "fuzzing {} target(s) for {} s in all, seed {}, timeout {:.1} s, memory limit {} MiB",
                chosen.len(),
                config.seconds,
                config.seed,
                config.timeout.as_secs_f64(),
                config.memory >> 20
            );
            let findings = driver::run(&chosen, &config);
            if findings.is_empty() {
                println!("no findings");
                code::CLEAN
            } else {
                println!("{} finding(s):", findings.len());
                for (target, what, path) in &findings {
                    match path {
                        Some(p) => println!("  {target}: {what}: {}", p.display()),
                        None => println!("  {target}: {what}"),
                    }
                }
                println!("reproduce one with: cargo run --release -p octsolid-fuzz -- TARGET --replay FILE");
                code::PANIC
            }
        }
    }
}

/// A number argument.
fn number<T: std::str::FromStr>(s: &str) -> Result<T, String> {
    s.parse().map_err(|_| format!("{s:?} is not a valid number here"))
}
