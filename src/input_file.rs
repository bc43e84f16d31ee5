//! Input files read whole: regular files only.
//!
//! Every reader of a whole file (the solid formats, meshes, patches, scenes, the
//! radiosity file, a sharded solid's parts) opens it here. A path naming anything but a
//! regular file (a folder, a FIFO, a device such as `/dev/zero`, a socket) is refused
//! before a byte is read: a FIFO would block the reader forever and a device would be
//! read until memory runs out. The file is opened without blocking (`O_NONBLOCK`, which
//! a regular file ignores), so the check itself never waits on a FIFO's writer.
//!
//! A bottom floor module, like [`crate::atomic`] for outputs: it imports only
//! [`crate::error`].

use std::fs::File;
use std::io::Read;
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;

use crate::error::{Error, Result};

/// Why a path that is not a regular file is not read.
const NOT_REGULAR: &str = "not a regular file (a folder, FIFO, device or socket); not read";

/// Opens `path` for reading, refusing anything but a regular file; returns the file and
/// its length.
///
/// # Errors
/// [`Error::Io`] naming `path`: it cannot be opened, or it is not a regular file.
pub(crate) fn open_regular(path: &Path) -> Result<(File, u64)> {
    let io = |source| Error::Io { path: path.to_path_buf(), source };
    let file = std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK).open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.is_file() {
        return Err(io(std::io::Error::other(NOT_REGULAR)));
    }
    Ok((file, meta.len()))
}

/// The bytes of the regular file `path`.
///
/// # Errors
/// As [`open_regular`], or a read error naming `path`.
pub(crate) fn read(path: &Path) -> Result<Vec<u8>> {
    let (mut file, len) = open_regular(path)?;
    // The length is the file system's, not a header's: a capacity hint only (a file
    // growing meanwhile is read to its end).
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    file.read_to_end(&mut bytes).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_folders_devices_and_fifos_and_reads_files() {
        let dir = std::env::temp_dir().join(format!("octsolid-input-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.obj");
        std::fs::write(&file, b"v 0 0 0\n").unwrap();
        assert_eq!(read(&file).unwrap(), b"v 0 0 0\n");
        let fifo = dir.join("f.oct");
        let name = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
        for path in [dir.as_path(), Path::new("/dev/zero"), fifo.as_path()] {
            let message = read(path).unwrap_err().to_string();
            assert!(message.contains("not a regular file") && message.contains(path.to_str().unwrap()), "{message}");
        }
        let missing = read(&dir.join("missing.oct")).unwrap_err().to_string();
        assert!(missing.contains("missing.oct") && missing.contains("No such file"), "{missing}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
