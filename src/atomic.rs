//! Atomic file output: write a temporary sibling, flush it to disk, rename it over the
//! destination. A crash or a full disk never leaves a half-written file and never
//! destroys the old one.
//!
//! A bottom floor module (it imports only [`crate::error`] and [`crate::owner`]): every
//! layer that writes a file (`mesh`, `io`, `render`'s radiosity file, `sharded`, the
//! scene cache) writes through it, so none imports another just to write atomically.
//! Its public path is `octsolid::io::write_atomic`.
//!
//! The temporary file is `.NAME.octsolid-tmp-HOST-PID-RANDOM` in the destination's
//! folder, named by its writer ([`crate::owner`]: this host, this process, 64
//! unpredictable bits) and created exclusively (`O_EXCL`), so a file or symlink planted
//! under a guessed name is never written through.
//!
//! A file replaced keeps its permissions: the temporary takes them before the rename.
//!
//! A write killed before its rename leaves its temporary file behind. Every later
//! write into the same folder removes those it can prove stale: this host's whose
//! process is gone, whatever their destination. Kept: a running process's (a write in
//! progress, or a reused process id: the safe side) and another host's sharing the
//! folder, which cannot be checked from here, except that temporaries of the same
//! destination older than an hour are removed, as are those in the older name form
//! without host and process.
//!
//! Destinations that are not regular files: a symlink is followed, and its target
//! replaced atomically (the link stays); a device or fifo (`/dev/null`,
//! `/dev/stdout`) is written in place, since renaming over it would replace the
//! device with a regular file.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::error::{Error, Result};
use crate::owner::{dead_here, host_name, owned_name, owner};

/// The marker in every temporary file's name.
const TEMP_MARKER: &str = ".octsolid-tmp-";
/// Temporary files older than this are taken for leftovers of killed writes.
const STALE_AFTER: Duration = Duration::from_secs(3600);

/// Counts bytes passing through a writer.
struct Counting<W> {
    inner: W,
    bytes: u64,
}

impl<W: Write> Write for Counting<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.bytes += n as u64;
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// Creates a new temporary sibling of `path`, exclusively.
fn create_temporary(path: &Path) -> std::io::Result<(File, PathBuf)> {
    let name = path.file_name().map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    loop {
        let temp = path.with_file_name(format!(".{name}{}", owned_name(TEMP_MARKER)));
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => return Ok((file, temp)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
}

/// Removes the temporary files in `path`'s folder that are provably stale (module
/// doc); best effort.
fn remove_stale_temporaries(path: &Path) {
    let own_prefix = path.file_name().map(|n| format!(".{}{TEMP_MARKER}", n.to_string_lossy()));
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let Ok(entries) = std::fs::read_dir(folder) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some((_, suffix)) = name.split_once(TEMP_MARKER).filter(|_| name.starts_with('.')) else { continue };
        let Some(meta) = entry.metadata().ok().filter(std::fs::Metadata::is_file) else { continue };
        let stale = match owner(suffix, "") {
            Some((host, pid)) if dead_here(host, pid) => true,
            Some((host, _)) if host == host_name() => false,
            _ => {
                let old = meta.modified().ok().and_then(|t| t.elapsed().ok()).is_some_and(|age| age > STALE_AFTER);
                old && own_prefix.as_ref().is_some_and(|p| name.starts_with(p.as_str()))
            }
        };
        if stale {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Writes a file through `write`, atomically; returns the bytes written.
///
/// On any error the temporary file is removed and the destination is untouched; the
/// error names the destination. See the module doc for symlinks and devices.
pub fn write_atomic(path: impl AsRef<Path>, write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<u64> {
    let path = path.as_ref();
    let io_error = |source| Error::Io { path: path.to_path_buf(), source };
    let target = match destination(path)? {
        Destination::File(target) => target,
        Destination::Device(device) => return write_in_place(&device, write).map_err(io_error),
    };
    replace(path, &target, |file| {
        let mut out = Counting { inner: BufWriter::new(file), bytes: 0 };
        write(&mut out)?;
        out.flush()?;
        let bytes = out.bytes;
        Ok((out.inner.into_inner().map_err(|e| e.into_error())?, bytes))
    })
}

/// [`write_atomic`] for a file whose head is known only once its body is written (a
/// binary STL's triangle count): `write` gets the temporary file itself, buffered, and
/// may seek back into what it wrote. A destination that is a device or fifo is
/// refused, as it cannot seek. Returns the file's length.
pub(crate) fn write_atomic_seekable(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<u64> {
    let path = path.as_ref();
    let target = match destination(path)? {
        Destination::File(target) => target,
        Destination::Device(_) => {
            let source = std::io::Error::other("not a regular file: this format is written by seeking back");
            return Err(Error::Io { path: path.to_path_buf(), source });
        }
    };
    replace(path, &target, |file| {
        let mut out = BufWriter::new(file);
        write(&mut out)?;
        out.flush()?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        let bytes = file.metadata()?.len();
        Ok((file, bytes))
    })
}

/// Where a write to a path lands: a file replaced by renaming (the path itself, or
/// the file its symbolic link leads to), or a device or fifo written in place.
enum Destination {
    File(PathBuf),
    Device(PathBuf),
}

/// The [`Destination`] of a write to `path`; errors name `path`.
fn destination(path: &Path) -> Result<Destination> {
    let io_error = |source| Error::Io { path: path.to_path_buf(), source };
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(Destination::File(path.to_path_buf()));
    };
    let target =
        if meta.file_type().is_symlink() { std::fs::canonicalize(path).map_err(io_error)? } else { path.to_path_buf() };
    let followed = std::fs::metadata(&target).map_err(io_error)?;
    Ok(if followed.is_file() || followed.is_dir() { Destination::File(target) } else { Destination::Device(target) })
}

/// Writes `target`'s new contents into a temporary file beside it with `body` (which
/// returns the file and the count to report), makes them durable and renames the
/// temporary over `target`. On any error the temporary is removed and `target` is
/// untouched; the error names `path` (what the caller was asked to write).
fn replace(path: &Path, target: &Path, body: impl FnOnce(File) -> std::io::Result<(File, u64)>) -> Result<u64> {
    let io_error = |source| Error::Io { path: path.to_path_buf(), source };
    remove_stale_temporaries(target);
    let (file, temp) = create_temporary(target).map_err(io_error)?;
    let result = (|| {
        let (file, bytes) = body(file)?;
        // A file replaced keeps its permissions (the temporary was made 0666 less the
        // umask).
        if let Some(old) = std::fs::metadata(target).ok().filter(std::fs::Metadata::is_file) {
            file.set_permissions(old.permissions())?;
        }
        file.sync_all()?;
        std::fs::rename(&temp, target)?;
        Ok(bytes)
    })();
    result.map_err(|source| {
        let _ = std::fs::remove_file(&temp);
        io_error(source)
    })
}

/// Writes into an existing device or fifo.
fn write_in_place(path: &Path, write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> std::io::Result<u64> {
    let file = OpenOptions::new().write(true).open(path)?;
    let mut out = Counting { inner: BufWriter::new(file), bytes: 0 };
    write(&mut out)?;
    out.flush()?;
    Ok(out.bytes)
}

/// Whether `a` and `b` name the same existing file (the same device and inode, so
/// also through links and different spellings). An output that is one of the inputs
/// is refused by the command line with this.
#[must_use]
pub fn same_file(a: impl AsRef<Path>, b: impl AsRef<Path>) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use std::time::SystemTime;

    use super::*;

    /// An empty folder of the temporary directory, removed when the test passes (kept to
    /// be looked at when it fails).
    struct Scratch(PathBuf);

    impl std::ops::Deref for Scratch {
        type Target = Path;
        fn deref(&self) -> &Path {
            &self.0
        }
    }

    impl AsRef<Path> for Scratch {
        fn as_ref(&self) -> &Path {
            &self.0
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            if !std::thread::panicking() {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
    }

    fn scratch(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("octsolid-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    #[test]
    fn a_planted_file_under_the_temporary_name_is_never_written_through() {
        // Names are unpredictable (`owner::unpredictable`), so a planted symlink cannot
        // be guessed; and creation is exclusive, so even a clash fails safe.
        let dir = scratch("planted");
        let victim = dir.join("victim");
        std::fs::write(&victim, b"keep").unwrap();
        let out = dir.join("out.oct");
        write_atomic(&out, |w| w.write_all(b"new")).unwrap();
        assert_eq!(std::fs::read(&victim).unwrap(), b"keep");
        assert_eq!(std::fs::read(&out).unwrap(), b"new");
        let leftovers = std::fs::read_dir(&dir)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().contains(TEMP_MARKER));
        assert_eq!(leftovers.count(), 0);
    }

    #[test]
    fn a_replaced_file_keeps_its_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch("permissions");
        let out = dir.join("kept.oct");
        std::fs::write(&out, b"old").unwrap();
        for mode in [0o600, 0o640, 0o400] {
            std::fs::set_permissions(&out, std::fs::Permissions::from_mode(mode)).unwrap();
            write_atomic(&out, |w| w.write_all(b"new")).unwrap();
            assert_eq!(std::fs::metadata(&out).unwrap().permissions().mode() & 0o777, mode);
            assert_eq!(std::fs::read(&out).unwrap(), b"new");
        }
    }

    #[test]
    fn symlinks_keep_pointing_and_devices_stay_devices() {
        let dir = scratch("links");
        let real = dir.join("real.oct");
        std::fs::write(&real, b"old").unwrap();
        let link = dir.join("link.oct");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_atomic(&link, |w| w.write_all(b"new")).unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        assert_eq!(write_atomic("/dev/null", |w| w.write_all(b"gone")).unwrap(), 4);
        assert!(!std::fs::metadata("/dev/null").unwrap().is_file());
        assert!(same_file(&link, &real) && same_file(dir.join("./real.oct"), &real));
        assert!(!same_file(&real, dir.join("missing")));
    }

    #[test]
    fn stale_temporaries_are_removed_and_young_ones_kept() {
        let dir = scratch("stale");
        let out = dir.join("big.oct");
        let old = dir.join(format!(".big.oct{TEMP_MARKER}0000000000000001"));
        let young = dir.join(format!(".big.oct{TEMP_MARKER}0000000000000002"));
        for p in [&old, &young] {
            std::fs::write(p, b"partial").unwrap();
        }
        let two_hours_ago = SystemTime::now() - Duration::from_secs(7200);
        File::options().write(true).open(&old).unwrap().set_modified(two_hours_ago).unwrap();
        write_atomic(&out, |w| w.write_all(b"done")).unwrap();
        assert!(!old.exists() && young.exists());
    }

    #[test]
    fn temporaries_of_a_killed_writer_are_removed_at_once_and_a_running_ones_kept() {
        let dir = scratch("killed");
        // A process that has ended: its id names no running process (until reused,
        // when its temporary is kept, the safe side).
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let host = host_name();
        let name =
            |dest: &str, host: &str, pid: u32| dir.join(format!(".{dest}{TEMP_MARKER}{host}-{pid}-00000000000000ab"));
        // A killed write of another file in the folder: fresh, yet provably stale.
        let killed = name("other.vdb", &host, dead);
        // A write in progress (this process), hours old: kept.
        let running = name("big.oct", &host, std::process::id());
        // Another host's, fresh: cannot be checked, kept.
        let remote = name("big.oct", "elsewhere.example", dead);
        for p in [&killed, &running, &remote] {
            std::fs::write(p, b"partial").unwrap();
        }
        let two_hours_ago = SystemTime::now() - Duration::from_secs(7200);
        File::options().write(true).open(&running).unwrap().set_modified(two_hours_ago).unwrap();
        write_atomic(dir.join("big.oct"), |w| w.write_all(b"done")).unwrap();
        assert!(!killed.exists() && running.exists() && remote.exists());
    }
}
