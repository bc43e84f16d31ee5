//! What a loader read past without refusing the file: warnings as values.
//!
//! The library never prints. A loader that skips something (an unknown PLY header
//! line, a missing `.mtl`, lines that are not UTF-8) pushes a [`Warning`] naming the
//! file and the [`Place`], and returns them beside what it read
//! ([`crate::mesh::read_mesh_and_warnings`], [`crate::import::Input::read_and_warnings`]);
//! the CLI prints each as `warning: FILE: line N: ...`.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::error::Error;

/// Where in a file something was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    /// The file as a whole.
    File,
    /// A one-based line of a text file.
    Line(usize),
    /// A byte offset into a binary file.
    Byte(u64),
}

impl Place {
    /// The error `reason` at this place of `path`: [`Error::Parse`] at a line,
    /// [`Error::Format`] at a byte offset (offset 0 for the whole file).
    pub(crate) fn error(self, path: &Path, reason: impl Into<String>) -> Error {
        let (path, reason) = (path.to_path_buf(), reason.into());
        match self {
            Place::Line(line) => Error::Parse { path, line, reason },
            Place::Byte(offset) => Error::Format { path, offset, reason },
            Place::File => Error::Format { path, offset: 0, reason },
        }
    }

    /// The warning `message` at this place of `path`.
    pub(crate) fn warning(self, path: &Path, message: impl Into<String>) -> Warning {
        Warning { path: path.to_path_buf(), place: self, message: message.into() }
    }
}

impl fmt::Display for Place {
    /// `line N`, `byte N`, or nothing for the whole file.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::File => Ok(()),
            Place::Line(n) => write!(f, "line {n}"),
            Place::Byte(n) => write!(f, "byte {n}"),
        }
    }
}

/// Something a loader read past: the file, the place and what it did about it.
/// Displays as `FILE: line N: message` (or `byte N`, or no place).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// The file.
    pub path: PathBuf,
    /// Where in it.
    pub place: Place,
    /// What was found and what the loader did (bytes from the file are quoted with
    /// their control characters escaped).
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.place {
            Place::File => write!(f, "{}: {}", self.path.display(), self.message),
            place => write!(f, "{}: {place}: {}", self.path.display(), self.message),
        }
    }
}

/// Things of one kind a loader skipped, for one warning instead of one each: how many,
/// and where the first was.
#[derive(Default)]
pub(crate) struct Tally {
    count: usize,
    first: Option<Place>,
}

impl Tally {
    /// Counts one more, at `place`.
    pub(crate) fn add(&mut self, place: Place) {
        self.first.get_or_insert(place);
        self.count += 1;
    }

    /// `message(count)` at the first place, when there were any.
    pub(crate) fn warning(&self, path: &Path, message: impl Fn(usize) -> String) -> Option<Warning> {
        self.first.map(|place| place.warning(path, message(self.count)))
    }
}
