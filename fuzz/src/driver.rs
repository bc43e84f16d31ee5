//! The fuzzing loop and the process around it.
//!
//! A run of several targets is a parent process that starts one worker process a
//! target (this same binary with `--worker`), one after the other, each with its share
//! of the time and a seed of its own (the run's seed xor the FNV-1a of the target's
//! name). A worker:
//!
//! 1. loads the target's corpus (`corpus/DIR/*` for each of its folders) into the
//!    pool and runs every file once as it is;
//! 2. then, until its time or case count is up, makes a case from the pool
//!    ([`crate::mutate`]; a quarter of the cases from a seed) and runs it; a case
//!    whose outcome ([`signature`]: the words of the target's summary or error, with
//!    numbers and quoted input left out) was not seen before joins the pool (up to
//!    [`POOL_CAP`] entries besides the seeds; past that it replaces a random one), a
//!    cheap stand-in for the coverage feedback stable Rust cannot have;
//! 3. runs each case under `catch_unwind`, with the case written first to
//!    `artifacts/TARGET/.current`, the memory ceiling of [`crate::guard`] and the
//!    watchdog (its main thread; the cases run on a thread with an 8 MiB stack, as a
//!    program's main thread has).
//!
//! Findings, each saved as `artifacts/TARGET/KIND-HASH.EXT` (the FNV-1a of the input)
//! with a `.txt` beside it saying what happened:
//! - `panic`: the message, place and backtrace of the first panic at each place; the
//!   worker goes on and exits with 1 at the end;
//! - `hang`: a case running longer than the timeout; the worker exits with 3;
//! - `memory`: a case holding more than the memory limit; the worker exits with 4;
//! - `crash`: the worker died otherwise (a stack overflow, an abort); the parent
//!   saves `.current`.
//!
//! Everything but time is fixed by the seed: the same seed gives the same cases in the
//! same order, and a run stopped by `--cases` instead of `--seconds` is the same run on
//! any machine.

use std::collections::{HashMap, HashSet};
use std::fs::File;
use std::io::Write;
use std::os::unix::fs::FileExt;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use crate::guard;
use crate::mutate::Mutator;
use crate::rng::{Rng, fnv1a};
use crate::targets::Target;

/// The most pool entries a worker adds to its seeds.
pub const POOL_CAP: usize = 512;

/// How a run goes.
#[derive(Clone, Debug)]
pub struct Config {
    /// Seconds for the whole run (shared out between targets).
    pub seconds: f64,
    /// Stop each target after this many mutated cases instead (when given).
    pub cases: Option<u64>,
    /// The run's seed.
    pub seed: u64,
    /// A case running longer is a hang.
    pub timeout: Duration,
    /// A case holding more bytes is a memory blow-up.
    pub memory: usize,
    /// The longest case made.
    pub max_len: usize,
    /// The corpus root (`corpus/TARGET_DIR/*`).
    pub corpus: PathBuf,
    /// Where findings go (`artifacts/TARGET/`).
    pub artifacts: PathBuf,
    /// Print each new outcome as it is first seen (to see what the feedback keeps).
    pub print_outcomes: bool,
}

impl Default for Config {
    fn default() -> Self {
        let here = Path::new(env!("CARGO_MANIFEST_DIR"));
        Config {
            seconds: 60.0,
            cases: None,
            seed: 0,
            timeout: Duration::from_secs(2),
            memory: 1 << 30,
            max_len: 1 << 20,
            corpus: here.join("corpus"),
            artifacts: here.join("artifacts"),
            print_outcomes: false,
        }
    }
}

/// Worker exit codes.
pub mod code {
    /// No finding.
    pub const CLEAN: i32 = 0;
    /// One or more panics.
    pub const PANIC: i32 = 1;
    /// Bad arguments.
    pub const USAGE: i32 = 2;
    /// A hang.
    pub const HANG: i32 = 3;
    /// A memory blow-up.
    pub const MEMORY: i32 = 4;
}

/// The files of `target`'s corpus folders, sorted by path within each folder.
#[must_use]
pub fn corpus_files(target: &Target, root: &Path) -> Vec<PathBuf> {
    let mut all = Vec::new();
    for dir in target.corpus {
        let mut files: Vec<PathBuf> = std::fs::read_dir(root.join(dir))
            .into_iter()
            .flatten()
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.is_file())
            .collect();
        files.sort();
        all.extend(files);
    }
    all
}

/// A target's outcome folded for comparison: what stands between quotes (`'`, `"`,
/// a backtick) dropped, then only the words of 1 to 12 ASCII letters kept (no
/// numbers, file names or escaped bytes), all of them for a summary and the first
/// five for an error (error messages go on to echo the input, as in "malformed header
/// line" and the line). So "line 7: 'x1' is not a number" and "line 9: 'q' is not a
/// number" are one outcome, and a checksum mismatch is one whatever the sums.
#[must_use]
pub fn signature(outcome: &octsolid::Result<String>) -> String {
    let (text, most) = match outcome {
        Ok(s) => (format!("ok {s}"), 64),
        Err(e) => (format!("err {e}"), 5),
    };
    let mut unquoted = String::new();
    let mut quote = None;
    let mut chars = text.chars();
    while let Some(c) = chars.next() {
        match quote {
            // A backslash escapes the next character (an escaped quote in the input).
            Some(_) if c == '\\' => {
                chars.next();
            }
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if matches!(c, '\'' | '"' | '`') => quote = Some(c),
            None => unquoted.push(c),
        }
    }
    let words: Vec<&str> = unquoted
        .split_whitespace()
        .map(|w| w.trim_matches(|c: char| c.is_ascii_punctuation()))
        .filter(|w| (1..=12).contains(&w.len()) && w.chars().all(|c| c.is_ascii_alphabetic()))
        .take(most)
        .collect();
    words.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signatures_leave_out_numbers_quotes_and_echoed_input() {
        let err = |reason: &str| -> octsolid::Result<String> {
            Err(octsolid::Error::Parse { path: "/tmp/x-12/case-7.obj".into(), line: 3, reason: reason.into() })
        };
        assert_eq!(signature(&err("'x1' is not a number")), signature(&err("'q' is not a number")));
        assert_eq!(signature(&err(r"'a\'b c' is not a number")), signature(&err("'q' is not a number")));
        assert_eq!(signature(&err("vertex 12 has 2 coordinates")), signature(&err("vertex 0 has 9 coordinates")));
        assert_ne!(signature(&err("'x1' is not a number")), signature(&err("'x1' is not an index")));
        assert_eq!(signature(&err("malformed header line abc def ghi")), signature(&err("malformed header line q")));
        assert_ne!(signature(&Ok("solid true closed false".into())), signature(&Ok("solid false closed false".into())));
    }
}

/// What the panic hook saw last: the place, and the report (message, place and
/// backtrace) when the place is new.
struct PanicSeen {
    place: String,
    report: Option<String>,
}

static LAST_PANIC: Mutex<Option<PanicSeen>> = Mutex::new(None);

/// Records panics instead of printing them; a backtrace is taken at a new place only.
fn install_panic_hook() {
    let places: Mutex<HashSet<String>> = Mutex::new(HashSet::new());
    std::panic::set_hook(Box::new(move |info| {
        let place = info.location().map_or_else(|| "unknown place".to_owned(), |l| l.to_string());
        let new = places.lock().unwrap_or_else(PoisonError::into_inner).insert(place.clone());
        let report = new.then(|| {
            let message = info
                .payload()
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| info.payload().downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(a panic without a message)".to_owned());
            let thread = std::thread::current().name().unwrap_or("unnamed").to_owned();
            format!(
                "panic in thread '{thread}' at {place}:\n{message}\n\nbacktrace:\n{}",
                std::backtrace::Backtrace::force_capture()
            )
        });
        *LAST_PANIC.lock().unwrap_or_else(PoisonError::into_inner) = Some(PanicSeen { place, report });
    }));
}

/// Saves `input` as a finding of `kind` with `note` beside it; returns its path.
fn save_finding(dir: &Path, kind: &str, ext: &str, input: &[u8], note: &str) -> PathBuf {
    let _ = std::fs::create_dir_all(dir);
    let path = dir.join(format!("{kind}-{:016x}.{ext}", fnv1a(input)));
    let _ = std::fs::write(&path, input);
    let _ = std::fs::write(path.with_extension(format!("{ext}.txt")), note);
    path
}

/// What one worker did.
#[derive(Debug, Default)]
pub struct Stats {
    /// Cases run (seeds included).
    pub cases: u64,
    /// Distinct outcome signatures.
    pub outcomes: usize,
    /// Pool size at the end.
    pub pool: usize,
    /// The slowest case.
    pub slowest: Duration,
    /// The slowest case, saved when it took over a quarter of the timeout.
    pub slow: Option<PathBuf>,
    /// Panics: place, count, saved input.
    pub panics: Vec<(String, u64, PathBuf)>,
}

/// The worker's case loop (on its case thread).
fn fuzz_loop(target: &Target, config: &Config, current: &mut File) -> Stats {
    let dir = config.artifacts.join(target.name);
    let seeds: Vec<Vec<u8>> =
        corpus_files(target, &config.corpus).iter().filter_map(|p| std::fs::read(p).ok()).collect();
    let mut pool = if seeds.is_empty() { vec![Vec::new()] } else { seeds.clone() };
    let fixed = pool.len();
    let mut mutator = Mutator::new(config.seed, config.max_len);
    let mut evict = Rng::new(config.seed ^ 0x5eed);
    let mut seen: HashSet<String> = HashSet::new();
    let mut panics: HashMap<String, (u64, PathBuf)> = HashMap::new();
    let mut order: Vec<String> = Vec::new();
    let deadline = Instant::now() + Duration::from_secs_f64(config.seconds.max(0.0));
    let mut stats = Stats::default();
    let mut mutated = 0u64;
    let mut next_seed = 0;
    let mut slowest = Vec::new();
    loop {
        let input = if next_seed < seeds.len() {
            next_seed += 1;
            seeds[next_seed - 1].clone()
        } else {
            let done = match config.cases {
                Some(n) => mutated >= n,
                None => Instant::now() >= deadline,
            };
            if done {
                break;
            }
            mutated += 1;
            // A quarter of the cases start from a seed, however full the pool.
            let from = if mutator.rng.one_in(4) { &pool[..fixed] } else { &pool[..] };
            mutator.case(from)
        };
        // The case on disk first, for the watchdog and for a crash.
        let _ = current.set_len(0).and_then(|()| current.write_all_at(&input, 0));
        let t0 = Instant::now();
        guard::begin(config.memory);
        let outcome = catch_unwind(AssertUnwindSafe(|| (target.run)(&input)));
        guard::end();
        let took = t0.elapsed();
        if took > stats.slowest {
            stats.slowest = took;
            slowest = input.clone();
        }
        stats.cases += 1;
        match outcome {
            Ok(result) => {
                let outcome = signature(&result);
                if config.print_outcomes && !seen.contains(&outcome) {
                    println!("[{}] new outcome: {outcome}", target.name);
                }
                if seen.insert(outcome) && next_seed >= seeds.len() {
                    if pool.len() < fixed + POOL_CAP {
                        pool.push(input);
                    } else {
                        let i = fixed + evict.below(POOL_CAP);
                        pool[i] = input;
                    }
                }
            }
            Err(_) => {
                let seen_panic = LAST_PANIC.lock().unwrap_or_else(PoisonError::into_inner).take();
                let (place, report) = match seen_panic {
                    Some(PanicSeen { place, report }) => (place, report),
                    None => ("unknown place".to_owned(), Some("a panic the hook did not see".to_owned())),
                };
                seen.insert(format!("panic {place}"));
                match panics.get_mut(&place) {
                    Some((count, _)) => *count += 1,
                    None => {
                        let note = report.unwrap_or_default();
                        let saved = save_finding(&dir, "panic", target.ext, &input, &note);
                        let first_line = note.lines().nth(1).unwrap_or("");
                        eprintln!(
                            "[{}] PANIC at {place}: {first_line}\n  input saved to {}",
                            target.name,
                            saved.display()
                        );
                        panics.insert(place.clone(), (1, saved));
                        order.push(place);
                    }
                }
            }
        }
    }
    if stats.slowest > config.timeout / 4 {
        let note = format!("the slowest case of the run: {} ms (not a finding)", stats.slowest.as_millis());
        stats.slow = Some(save_finding(&dir, "slow", target.ext, &slowest, &note));
    }
    stats.outcomes = seen.len();
    stats.pool = pool.len();
    stats.panics = order
        .into_iter()
        .map(|place| {
            let (count, path) = panics.remove(&place).expect("every place in order was recorded");
            (place, count, path)
        })
        .collect();
    stats
}

/// Waits for the case thread `cases`, watching it (the calling thread is exempt from
/// the memory ceiling): on a memory blow-up or a case over the timeout, calls
/// `found(kind, exit code, note)` and ends the process with the code it returns.
fn watch<T>(cases: std::thread::JoinHandle<T>, config: &Config, found: impl Fn(&str, i32, &str) -> i32) -> T {
    guard::exempt_this_thread();
    let base = guard::live();
    while !cases.is_finished() {
        std::thread::sleep(Duration::from_millis(10));
        let finding = if let Some(live) = guard::blown() {
            Some((
                "memory",
                code::MEMORY,
                format!(
                    "memory blow-up: a case tried to hold {} MiB, past the limit of {} MiB ({} MiB were live before)",
                    live.saturating_sub(base) >> 20,
                    config.memory >> 20,
                    base >> 20
                ),
            ))
        } else {
            guard::running_for().filter(|t| *t > config.timeout).map(|t| {
                let note = format!(
                    "hang: a case has run {:.1} s (timeout {:.1} s)",
                    t.as_secs_f64(),
                    config.timeout.as_secs_f64()
                );
                ("hang", code::HANG, note)
            })
        };
        if let Some((kind, exit, note)) = finding {
            let exit = found(kind, exit, &note);
            let _ = std::io::stderr().flush();
            crate::scratch::remove();
            std::process::exit(exit);
        }
    }
    cases.join().expect("the case thread does not panic outside a case")
}

/// Runs `target` in this process as a worker (module doc) and returns its exit code;
/// a hang or memory blow-up ends the process from the watchdog instead.
#[must_use]
pub fn worker(target: &'static Target, config: &Config) -> i32 {
    let dir = config.artifacts.join(target.name);
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("cannot make {}: {e}", dir.display());
        return code::USAGE;
    }
    let current_path = dir.join(".current");
    let mut current = match File::options().create(true).truncate(true).read(true).write(true).open(&current_path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("cannot open {}: {e}", current_path.display());
            return code::USAGE;
        }
    };
    install_panic_hook();
    let started = Instant::now();
    let thread_config = config.clone();
    let cases = std::thread::Builder::new()
        .name(format!("fuzz {}", target.name))
        .stack_size(8 << 20)
        .spawn(move || fuzz_loop(target, &thread_config, &mut current))
        .expect("the case thread starts");
    let stats = watch(cases, config, |kind, exit, note| {
        let input = std::fs::read(&current_path).unwrap_or_default();
        let saved = save_finding(&dir, kind, target.ext, &input, note);
        eprintln!("[{}] {}: {note}\n  input saved to {}", target.name, kind.to_uppercase(), saved.display());
        exit
    });
    crate::scratch::remove();
    let _ = std::fs::remove_file(&current_path);
    let secs = started.elapsed().as_secs_f64();
    println!(
        "{:>16}: {} cases in {secs:.1} s ({:.0}/s), {} outcomes, pool {}, slowest case {} ms, {} panic places",
        target.name,
        stats.cases,
        stats.cases as f64 / secs.max(1e-9),
        stats.outcomes,
        stats.pool,
        stats.slowest.as_millis(),
        stats.panics.len()
    );
    if let Some(path) = &stats.slow {
        println!("{:>16}  slowest case saved to {}", "", path.display());
    }
    for (place, count, path) in &stats.panics {
        println!("{:>16}  PANIC x{count} at {place}: {}", "", path.display());
    }
    if stats.panics.is_empty() { code::CLEAN } else { code::PANIC }
}

/// Runs `targets` one after the other, each in a worker process with its share of the
/// time; returns the findings (target, what, saved input), empty when clean.
#[must_use]
pub fn run(targets: &[&'static Target], config: &Config) -> Vec<(String, String, Option<PathBuf>)> {
    let exe = std::env::current_exe().expect("the fuzzer knows its own path");
    let share = config.seconds / targets.len().max(1) as f64;
    let mut findings = Vec::new();
    for target in targets {
        let seed = config.seed ^ fnv1a(target.name.as_bytes());
        let mut cmd = std::process::Command::new(&exe);
        cmd.arg(target.name)
            .arg("--worker")
            .args(["--seconds", &share.to_string(), "--seed", &seed.to_string()])
            .args(["--timeout", &config.timeout.as_secs_f64().to_string()])
            .args(["--memory", &(config.memory >> 20).to_string(), "--max-len", &config.max_len.to_string()])
            .arg("--corpus")
            .arg(&config.corpus)
            .arg("--artifacts")
            .arg(&config.artifacts);
        if let Some(n) = config.cases {
            cmd.args(["--cases", &n.to_string()]);
        }
        if config.print_outcomes {
            cmd.arg("--print-outcomes");
        }
        let status = match cmd.status() {
            Ok(s) => s,
            Err(e) => {
                findings.push((target.name.to_owned(), format!("the worker did not start: {e}"), None));
                continue;
            }
        };
        let dir = config.artifacts.join(target.name);
        match status.code() {
            Some(code::CLEAN) => {}
            Some(code::PANIC) => findings.push((target.name.to_owned(), "panics (listed above)".into(), None)),
            Some(code::HANG) => findings.push((target.name.to_owned(), "a hang (above)".into(), None)),
            Some(code::MEMORY) => findings.push((target.name.to_owned(), "a memory blow-up (above)".into(), None)),
            _ => {
                let input = std::fs::read(dir.join(".current")).unwrap_or_default();
                let note = format!(
                    "crash: the worker ended with {status} (a stack overflow or an abort; its last words are above)"
                );
                let saved = save_finding(&dir, "crash", target.ext, &input, &note);
                eprintln!("[{}] CRASH: {note}\n  input saved to {}", target.name, saved.display());
                findings.push((target.name.to_owned(), note, Some(saved)));
            }
        }
        let _ = std::fs::remove_file(dir.join(".current"));
    }
    findings
}

/// Replays `files` through `target` in this process, on a case thread under the
/// memory limit and the timeout (a blow-up or a hang is reported and ends the
/// process; the default panic hook prints a panic, `RUST_BACKTRACE=1` its
/// backtrace); returns whether none panicked.
#[must_use]
pub fn replay(target: &'static Target, files: &[PathBuf], config: &Config) -> bool {
    let files = files.to_vec();
    let memory = config.memory;
    let cases = std::thread::Builder::new()
        .name(format!("replay {}", target.name))
        .stack_size(8 << 20)
        .spawn(move || {
            let mut clean = true;
            for file in &files {
                let Ok(bytes) = std::fs::read(file) else {
                    eprintln!("{}: cannot be read", file.display());
                    clean = false;
                    continue;
                };
                let t0 = Instant::now();
                guard::begin(memory);
                let outcome = catch_unwind(AssertUnwindSafe(|| (target.run)(&bytes)));
                guard::end();
                let secs = t0.elapsed().as_secs_f64();
                match outcome {
                    Ok(Ok(summary)) => println!("{}: ok ({secs:.3} s): {summary}", file.display()),
                    Ok(Err(e)) => println!("{}: refused ({secs:.3} s): {e}", file.display()),
                    Err(_) => {
                        println!("{}: PANIC (above)", file.display());
                        clean = false;
                    }
                }
            }
            clean
        })
        .expect("the case thread starts");
    let clean = watch(cases, config, |kind, exit, note| {
        println!("{}: {note}", kind.to_uppercase());
        exit
    });
    crate::scratch::remove();
    clean
}
