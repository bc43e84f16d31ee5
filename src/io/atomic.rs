//! Atomic file output: write a temporary sibling, flush it to disk, rename it over the
//! destination. A crash or a full disk never leaves a half-written file and never
//! destroys the old one.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

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

/// A temporary path next to `path`, unique to this process and call.
fn temporary_sibling(path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path.file_name().map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()))
}

/// Writes a file through `write`, atomically; returns the bytes written.
///
/// On any error the temporary file is removed and the destination is untouched; the
/// error names the destination.
pub fn write_atomic(path: impl AsRef<Path>, write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<u64> {
    let path = path.as_ref();
    let temp = temporary_sibling(path);
    let result = (|| {
        let file = File::create(&temp)?;
        let mut out = Counting { inner: BufWriter::new(file), bytes: 0 };
        write(&mut out)?;
        out.flush()?;
        let bytes = out.bytes;
        let file = out.inner.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&temp, path)?;
        Ok(bytes)
    })();
    result.map_err(|source| {
        let _ = std::fs::remove_file(&temp);
        Error::Io { path: path.to_path_buf(), source }
    })
}
