//! Little-endian fields read one after another from a file's bytes, each error naming
//! the file, the byte offset and the field (the binary readers' shared cursor: OpenVDB
//! files, radiosity solutions). Reading past the end is an error, never a panic; a
//! count read from the file must be checked against [`Fields::left`] before it sizes
//! anything.
//!
//! A bottom floor module: it imports only [`crate::error`], so `io` and `render` (the
//! radiosity file) both read through it without one importing the other.

use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};

/// A cursor over `bytes`, the contents (or the head) of the file at `path`.
pub(crate) struct Fields<'a> {
    pub(crate) path: &'a Path,
    pub(crate) bytes: &'a [u8],
    /// The offset of the next field.
    pub(crate) pos: usize,
}

impl<'a> Fields<'a> {
    /// A cursor at offset `pos` of `bytes`.
    pub(crate) fn new(path: &'a Path, bytes: &'a [u8], pos: usize) -> Self {
        Fields { path, bytes, pos }
    }

    /// The format error `reason` at byte `at` of the file.
    pub(crate) fn err(&self, at: usize, reason: impl Into<String>) -> Error {
        Error::Format { path: self.path.to_path_buf(), offset: at as u64, reason: reason.into() }
    }

    /// Bytes after the cursor.
    pub(crate) fn left(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next `n` bytes, the field `what`.
    pub(crate) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        if n > self.left() {
            return Err(self.err(self.pos, format!("truncated: {what} needs {n} bytes, {} left", self.left())));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// The next `N` bytes, the field `what`.
    pub(crate) fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        Ok(self.take(N, what)?.try_into().expect("N bytes"))
    }

    pub(crate) fn u32(&mut self, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn u64(&mut self, what: &str) -> Result<u64> {
        Ok(u64::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn i64(&mut self, what: &str) -> Result<i64> {
        Ok(i64::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn f64(&mut self, what: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }

    /// Three `f64`s: x, y, z.
    pub(crate) fn vec3(&mut self, what: &str) -> Result<DVec3> {
        Ok(DVec3::new(self.f64(what)?, self.f64(what)?, self.f64(what)?))
    }

    /// A `u32` length, then that many bytes of UTF-8.
    pub(crate) fn string(&mut self, what: &str) -> Result<String> {
        let n = self.u32(what)? as usize;
        let at = self.pos;
        let s = self.take(n, what)?;
        String::from_utf8(s.to_vec()).map_err(|_| self.err(at, format!("{what} is not UTF-8")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_read_in_order_and_a_short_file_is_refused_where_it_ends() {
        let mut bytes = 7u32.to_le_bytes().to_vec();
        bytes.extend_from_slice(&(-2i64).to_le_bytes());
        bytes.extend_from_slice(&[2, 0, 0, 0, b'o', b'k', 1, 2]);
        let mut f = Fields::new(Path::new("x.bin"), &bytes, 0);
        assert_eq!(f.u32("count").unwrap(), 7);
        assert_eq!(f.i64("offset").unwrap(), -2);
        assert_eq!(f.string("name").unwrap(), "ok");
        assert_eq!(f.left(), 2);
        let e = f.u32("size").unwrap_err().to_string();
        assert!(e.contains("x.bin") && e.contains("size needs 4 bytes, 2 left") && e.contains("18"), "{e}");
        assert_eq!(f.pos, 18, "a refused field moves nothing");
    }
}
