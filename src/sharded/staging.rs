//! The staging folder of a sharded output and how a finished solid replaces the old
//! one: every writer stages in a folder of its own and publishes with one atomic
//! rename, so two writers of one output give one complete solid (the last one
//! published), as two writers of a single file do.
//!
//! `OUT.partial/` (beside the output) holds:
//! - `run-HOST-PID-RANDOM/`: the folder of one process writing a whole job (no
//!   `--cells`), or of one join assembling the solid; it becomes the output;
//! - `job-ID/`: the shards and part files of the tasks of job `ID` ([`super::JobId`]),
//!   which many processes on many machines add to; `join.lock` in it while a join of
//!   the job runs;
//! - `old-HOST-PID-RANDOM/`: an earlier solid moved aside (only where the atomic
//!   exchange is missing), removed right after.
//!
//! The staging folder and a job's folder must be plain folders (not symbolic links)
//! of the user running octsolid, or nothing is written into or removed from them.
//!
//! Publishing: `renameat2(RENAME_EXCHANGE)` swaps the finished folder with the
//! output in one step, then the old solid (now in the finished folder's place) is
//! removed; with no output yet, `RENAME_NOREPLACE`. Where `renameat2` is missing
//! (not Linux, or a file system without it) the old solid is renamed aside to `old-`
//! and the new one renamed into place: a reader may then, for an instant, find no
//! solid, but never a mixed one.
//!
//! Leftovers of killed processes: a `run-` or `old-` folder whose owner (HOST and PID
//! in its name) is this host and a process that no longer exists is removed by any
//! later writer or join of the same output, as is a `join.lock` of a dead join. A
//! folder of another host, or of a PID now reused, is left alone (nothing proves it
//! stale); so are a job's folder (its tasks may run anywhere, at any time: a later
//! `join` of the job finishes and removes it) and the `NAME.octs.old-PID` folders of
//! octsolid before this layout.

use std::io::{ErrorKind, Read};
use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

use super::job::JobId;
use crate::error::{Error, Result};
use crate::owner::{dead_here, owned_name, owner};

/// The prefix of a writer's own folder.
const RUN_PREFIX: &str = "run-";
/// The prefix of an earlier solid moved aside.
const OLD_PREFIX: &str = "old-";
/// The prefix of a job's folder.
const JOB_PREFIX: &str = "job-";
/// The join lock's file name in a job's folder.
const LOCK_FILE: &str = "join.lock";

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Io { path: path.to_path_buf(), source }
}

/// The staging folder of output `out`: `OUT.partial` beside it.
#[must_use]
pub(crate) fn staging_dir(out: &Path) -> PathBuf {
    let mut name = out.file_name().map(std::ffi::OsStr::to_os_string).unwrap_or_default();
    name.push(".partial");
    out.with_file_name(name)
}

/// The folder of job `job` in staging folder `root`.
pub(crate) fn job_dir(root: &Path, job: JobId) -> PathBuf {
    root.join(format!("{JOB_PREFIX}{job}"))
}

/// The job of a folder named `job-ID`.
pub(crate) fn job_of(name: &str) -> Option<JobId> {
    name.strip_prefix(JOB_PREFIX).and_then(JobId::parse)
}

/// Reads the regular file `path` whole, after checking that its length is `want`
/// (`what` names the source of `want` in the error).
pub(crate) fn read_exact_len(path: &Path, want: u64, what: &str) -> Result<Vec<u8>> {
    let (file, len) = crate::input_file::open_regular(path)?;
    if len != want {
        return Err(Error::Format {
            path: path.to_path_buf(),
            offset: 0,
            reason: format!("the file is {len} bytes, {what} says {want}"),
        });
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(len).read_to_end(&mut bytes).map_err(io_error(path))?;
    if bytes.len() as u64 != len {
        return Err(Error::Format { path: path.to_path_buf(), offset: 0, reason: "the file shrank while read".into() });
    }
    Ok(bytes)
}

/// Reads the regular file `path`, whose length `length_of` finds from its first
/// `head` bytes (checking them), after checking that length against the file's.
pub(crate) fn read_checked_len(
    path: &Path,
    head: usize,
    length_of: impl FnOnce(&[u8]) -> Result<u64>,
) -> Result<Vec<u8>> {
    let (file, len) = crate::input_file::open_regular(path)?;
    let mut bytes = Vec::with_capacity(head.min(len as usize));
    let mut file = file;
    (&mut file).take(head as u64).read_to_end(&mut bytes).map_err(io_error(path))?;
    let want = length_of(&bytes)?;
    if want != len {
        return Err(Error::Format {
            path: path.to_path_buf(),
            offset: 0,
            reason: format!("the header makes the file {want} bytes, it is {len}"),
        });
    }
    bytes.reserve_exact((len as usize).saturating_sub(bytes.len()));
    file.take(len - bytes.len() as u64).read_to_end(&mut bytes).map_err(io_error(path))?;
    if bytes.len() as u64 != len {
        return Err(Error::Format { path: path.to_path_buf(), offset: 0, reason: "the file shrank while read".into() });
    }
    Ok(bytes)
}

/// Checks that `path` is a folder (not a symbolic link to one) of this user.
pub(crate) fn check_own_folder(path: &Path) -> Result<()> {
    let meta = std::fs::symlink_metadata(path).map_err(io_error(path))?;
    // SAFETY: geteuid has no preconditions and cannot fail.
    let me = unsafe { libc::geteuid() };
    if !meta.file_type().is_dir() || meta.uid() != me {
        let what = if meta.file_type().is_symlink() {
            "a symbolic link".to_owned()
        } else if !meta.is_dir() {
            "not a folder".to_owned()
        } else {
            format!("a folder of user {}, not this user's ({me})", meta.uid())
        };
        return Err(Error::invalid(
            "staging folder",
            format!(
                "{}: {what}; a staging folder must be a plain folder of one's own: nothing written or removed there",
                path.display()
            ),
        ));
    }
    Ok(())
}

/// Makes the folder `path` if it is missing, then checks it ([`check_own_folder`]).
pub(crate) fn own_folder(path: &Path) -> Result<()> {
    match std::fs::create_dir(path) {
        Ok(()) => {}
        Err(e) if e.kind() == ErrorKind::AlreadyExists => {}
        Err(e) => return Err(io_error(path)(e)),
    }
    check_own_folder(path)
}

/// Makes a new `run-` folder of this process in staging folder `root` (made if
/// missing, and checked).
pub(crate) fn new_run_folder(root: &Path) -> Result<PathBuf> {
    // Another writer may remove an empty staging folder between the two steps.
    for _ in 0..8 {
        own_folder(root)?;
        let run = root.join(owned_name(RUN_PREFIX));
        match std::fs::create_dir(&run) {
            Ok(()) => return Ok(run),
            Err(e) if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::AlreadyExists) => {}
            Err(e) => return Err(io_error(&run)(e)),
        }
    }
    Err(Error::invalid("staging folder", format!("{}: could not make a folder of this process in it", root.display())))
}

/// Removes the `run-` and `old-` folders in staging folder `root` whose owner is
/// provably gone (module doc); best effort, and nothing when `root` is not a plain
/// folder of this user. Returns how many were removed.
pub(crate) fn remove_stale(root: &Path) -> usize {
    if check_own_folder(root).is_err() {
        return 0;
    }
    let Ok(entries) = std::fs::read_dir(root) else { return 0 };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let stale = [RUN_PREFIX, OLD_PREFIX]
            .iter()
            .find_map(|p| owner(&name, p))
            .is_some_and(|(host, pid)| dead_here(host, pid));
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        if stale && is_dir && std::fs::remove_dir_all(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Removes staging folder `root` if it is empty (another writer may be using it).
pub(crate) fn remove_if_empty(root: &Path) {
    let _ = std::fs::remove_dir(root);
}

/// The join lock of a job's folder: a file naming this host and process, made
/// exclusively; removed when dropped. A lock of a dead join on this host is taken
/// over.
pub(crate) struct JoinLock(PathBuf);

impl JoinLock {
    pub(crate) fn acquire(job: &Path) -> Result<JoinLock> {
        let path = job.join(LOCK_FILE);
        let mine = format!("{}\n", owned_name(""));
        for _ in 0..2 {
            let created = std::fs::OpenOptions::new().write(true).create_new(true).mode(0o644).open(&path);
            match created {
                Ok(mut file) => {
                    std::io::Write::write_all(&mut file, mine.as_bytes()).map_err(io_error(&path))?;
                    return Ok(JoinLock(path));
                }
                Err(e) if e.kind() == ErrorKind::AlreadyExists => {
                    let held = std::fs::read_to_string(&path).unwrap_or_default();
                    match owner(held.trim(), "") {
                        Some((host, pid)) if dead_here(host, pid) => {
                            let _ = std::fs::remove_file(&path);
                        }
                        _ => {
                            return Err(Error::invalid(
                                "join",
                                format!(
                                    "{}: another join of this job is running ({}); if none is, remove this file",
                                    path.display(),
                                    held.trim()
                                ),
                            ));
                        }
                    }
                }
                Err(e) => return Err(io_error(&path)(e)),
            }
        }
        Err(Error::invalid("join", format!("{}: the join lock could not be taken", path.display())))
    }
}

impl Drop for JoinLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// Whether `path` may be replaced by a sharded solid: a folder (not a link) holding
/// an index, or empty.
fn replaceable(path: &Path) -> Result<bool> {
    let meta = std::fs::symlink_metadata(path).map_err(io_error(path))?;
    if !meta.file_type().is_dir() {
        return Ok(false);
    }
    let index = std::fs::symlink_metadata(path.join(super::INDEX_FILE)).is_ok_and(|m| m.is_file());
    Ok(index || std::fs::read_dir(path).map_err(io_error(path))?.next().is_none())
}

/// `renameat2(from, to, flags)`; `None` when the system or file system lacks it.
fn rename2(from: &Path, to: &Path, flags: libc::c_uint) -> Option<std::io::Result<()>> {
    use std::os::unix::ffi::OsStrExt as _;
    let c = |p: &Path| std::ffi::CString::new(p.as_os_str().as_bytes()).map_err(|_| ErrorKind::InvalidInput);
    let (Ok(from), Ok(to)) = (c(from), c(to)) else {
        return Some(Err(ErrorKind::InvalidInput.into()));
    };
    // SAFETY: both are NUL-terminated paths; AT_FDCWD resolves them as open(2) does.
    let r = unsafe { libc::renameat2(libc::AT_FDCWD, from.as_ptr(), libc::AT_FDCWD, to.as_ptr(), flags) };
    if r == 0 {
        return Some(Ok(()));
    }
    let e = std::io::Error::last_os_error();
    match e.raw_os_error() {
        Some(libc::ENOSYS | libc::EINVAL | libc::ENOTSUP) => None,
        _ => Some(Err(e)),
    }
}

/// Puts the finished folder `from` (in staging folder `root`) in place of `to` in one
/// atomic step, replacing an earlier sharded solid there (refusing to replace
/// anything else), and removes the earlier one (module doc).
pub(crate) fn publish(from: &Path, to: &Path, root: &Path) -> Result<()> {
    let refuse =
        || Error::invalid("output", format!("{}: exists and is not a sharded solid; not replaced", to.display()));
    // Another writer may publish between any two steps: try again (bounded).
    for _ in 0..16 {
        let exists = std::fs::symlink_metadata(to).is_ok();
        if exists && !replaceable(to)? {
            return Err(refuse());
        }
        let flags = if exists { libc::RENAME_EXCHANGE } else { libc::RENAME_NOREPLACE };
        match rename2(from, to, flags) {
            Some(Ok(())) => {
                if exists {
                    // `from` now holds the earlier solid.
                    std::fs::remove_dir_all(from).map_err(io_error(from))?;
                }
                return Ok(());
            }
            Some(Err(e)) if matches!(e.kind(), ErrorKind::NotFound | ErrorKind::AlreadyExists) => continue,
            Some(Err(e)) => return Err(io_error(to)(e)),
            None => {}
        }
        // Without renameat2: the earlier solid aside, then the new one in.
        let old = root.join(owned_name(OLD_PREFIX));
        if exists {
            match std::fs::rename(to, &old) {
                Ok(()) => {}
                Err(e) if e.kind() == ErrorKind::NotFound => continue,
                Err(e) => return Err(io_error(to)(e)),
            }
        }
        match std::fs::rename(from, to) {
            Ok(()) => {
                if exists {
                    std::fs::remove_dir_all(&old).map_err(io_error(&old))?;
                }
                return Ok(());
            }
            // Another writer's solid appeared in between (renaming onto a folder that
            // is not empty fails): the next round replaces it.
            Err(e) if matches!(e.kind(), ErrorKind::DirectoryNotEmpty | ErrorKind::AlreadyExists) => {}
            Err(e) => return Err(io_error(from)(e)),
        }
    }
    Err(Error::invalid("output", format!("{}: other writers kept replacing it; not published", to.display())))
}
