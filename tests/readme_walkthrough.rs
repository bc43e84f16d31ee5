//! README.md's walkthrough, run as written: every command of the first `sh` block
//! under "## Use", in order, in a fresh folder holding the repository's `models/`
//! and a copy of its `scenes/` (nothing is written into the checkout). Each must succeed, and no command may overwrite what an earlier one
//! wrote (every output name, given by `-o` or implied by `render`, is new), so the
//! walkthrough cannot silently break again.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("cli/ has a parent").to_path_buf()
}

/// The walkthrough's commands, comments stripped, split into arguments.
fn walkthrough() -> Vec<Vec<String>> {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let usage = &readme[readme.find("## Use").expect("a Use section")..];
    let block = &usage[usage.find("```sh\n").expect("an sh block") + 6..];
    let block = &block[..block.find("```").expect("a closed block")];
    block
        .lines()
        .map(|line| line.split(" #").next().unwrap().split_whitespace().map(String::from).collect::<Vec<_>>())
        .filter(|words| !words.is_empty())
        .collect()
}

/// Where a command writes: its `-o`, or for `render` without one the input's stem
/// with `.png`.
fn output_of(args: &[String]) -> Option<String> {
    if let Some(i) = args.iter().position(|a| a == "-o") {
        return args.get(i + 1).cloned();
    }
    (args[1] == "render").then(|| format!("{}.png", Path::new(&args[2]).file_stem().unwrap().to_string_lossy()))
}

/// `octsolid view ...` serves until stopped: it must print its loopback address and
/// serve its page there; then it is stopped.
fn serves_its_page(dir: &Path, args: &[String]) {
    use std::io::{BufRead, BufReader, Read, Write};
    let mut child = Command::new(env!("CARGO_BIN_EXE_octsolid"))
        .current_dir(dir)
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let address = line.split("http://").nth(1).and_then(|s| s.split('/').next()).unwrap_or_default().to_string();
    let mut page = Vec::new();
    if let Ok(mut stream) = std::net::TcpStream::connect(&address) {
        write!(stream, "GET / HTTP/1.0\r\n\r\n").unwrap();
        stream.read_to_end(&mut page).unwrap();
    }
    let _ = child.kill();
    let _ = child.wait();
    assert!(address.starts_with("127.0.0.1:"), "README command {args:?} printed {line}");
    // An HTTP/1.1 server answers a 1.0 request in 1.1 (RFC 9110, 2.5).
    assert!(page.starts_with(b"HTTP/1.1 200 OK"), "README command {args:?} serves no page at {address}");
}

#[test]
fn every_readme_command_runs_in_order() {
    let commands = walkthrough();
    assert!(commands.len() >= 10, "the walkthrough has its commands: {commands:?}");
    let dir = common::scratch_dir("readme", "walkthrough");
    // The models linked; the scenes copied, so their solid caches (written beside a
    // scene) stay out of the checkout.
    std::os::unix::fs::symlink(repo().join("models"), dir.join("models")).unwrap();
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    for entry in std::fs::read_dir(repo().join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() {
            std::fs::copy(&path, dir.join("scenes").join(path.file_name().unwrap())).unwrap();
        }
    }
    let mut written = BTreeSet::new();
    for args in &commands {
        assert_eq!(args[0], "octsolid", "a walkthrough line is an octsolid command: {args:?}");
        if let Some(out) = output_of(args) {
            assert!(written.insert(out.clone()), "{args:?} overwrites {out}, written by an earlier command");
        }
        if args[1] == "view" {
            serves_its_page(&dir, &args[1..]);
            continue;
        }
        let out = Command::new(env!("CARGO_BIN_EXE_octsolid")).current_dir(&dir).args(&args[1..]).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "README command {args:?} failed: {stderr}");
        assert!(!stderr.contains("warning"), "README command {args:?} warns: {stderr}");
    }
    for out in &written {
        assert!(dir.join(out).metadata().is_ok_and(|m| m.len() > 0), "{out} was not written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
