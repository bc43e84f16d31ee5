//! The library's one error type.
//!
//! Every fallible function returns [`Result`]. Each variant carries what went wrong,
//! where (file, byte offset, node index) and the value and limit involved, so the CLI
//! can print it as one line. Bytes quoted from an input file go through [`quoted`],
//! so a hostile file cannot put terminal escapes or line breaks into that line.

use std::path::PathBuf;

/// Result with the library's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in octsolid.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A file's content is malformed.
    #[error("{}: byte {offset}: {reason}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// Byte offset where the problem was found.
        offset: u64,
        /// What is wrong.
        reason: String,
    },
    /// A file's extension is missing or not one the reader accepts
    /// ([`crate::file_kind::FileKind::of`]).
    #[error("{}: {} (use {})", path.display(), found_extension(found), list_extensions(accepted))]
    UnknownExtension {
        /// The file.
        path: PathBuf,
        /// Its extension without the dot; empty when it has none.
        found: String,
        /// Every extension the reader accepts, without the dot.
        accepted: Vec<&'static str>,
    },
    /// A scene file could not be read or built: the cause as it was, with the scene
    /// file, the place in it the cause concerns (`file:line:column: ` when known) and,
    /// where it concerns one, the solid's name (its `name`, else `solid N`).
    #[error("{}: {}{source}", scene_place(path, place), solid.as_ref().map_or(String::new(), |s| format!("{}: ", printable(s))))]
    Scene {
        /// The scene file.
        path: PathBuf,
        /// One-based line and column (in bytes) of the value the error concerns: the
        /// refused value itself for what its reader refuses, else the solid's key that
        /// names what could not be built (`shape`, `mesh`, `oct`, `transform`,
        /// `material`) or the solid's `[[solid]]` header.
        place: Option<(usize, usize)>,
        /// The solid being built, if the error concerns one.
        solid: Option<String>,
        /// What went wrong: the I/O, format or over-budget error of a file the scene
        /// names, a refused value, ...
        source: Box<Error>,
    },
    /// A solid cannot be written as the file its path names ([`crate::write_solid_file`]:
    /// a mesh of an empty solid, a boundary the mesher refuses): the file and why.
    #[error("{}: {reason}", path.display())]
    Unwritable {
        /// The file.
        path: PathBuf,
        /// Why, with the cause.
        reason: String,
    },
    /// A file cannot be drawn ([`crate::Drawing::open`]): a mesh that cannot be
    /// voxelized, an empty solid. The file, why, and the cause when there is one.
    #[error("{}: {reason}{}", path.display(), cause.as_ref().map_or(String::new(), |c| format!(": {c}")))]
    Undrawable {
        /// The file.
        path: PathBuf,
        /// What could not be done (`cannot voxelize`, `the solid is empty`).
        reason: String,
        /// The error that stopped it, if any.
        #[source]
        cause: Option<Box<Error>>,
    },
    /// A TOML document's reader refused it: a syntax error, an unknown key or value, a
    /// value of the wrong form or out of range. The message names the value and what
    /// was expected; the place is the wrapping [`Error::Scene`]'s.
    #[error("{reason}")]
    Toml {
        /// The reader's message.
        reason: String,
    },
    /// A text file's content is malformed at a line.
    #[error("{}: line {line}: {reason}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// One-based line number.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// Two octrees that must share a domain and depth do not.
    #[error("domain mismatch: {left} vs {right}; resample one operand first")]
    DomainMismatch {
        /// The left operand's domain.
        left: String,
        /// The right operand's domain.
        right: String,
    },
    /// An argument is outside what the function accepts.
    #[error("invalid {what}: {reason}")]
    InvalidArgument {
        /// Which argument.
        what: &'static str,
        /// Why it is refused, with the given value and the limit.
        reason: String,
    },
    /// An octree breaks one of its invariants.
    #[error("invalid octree: node {index}: {reason}")]
    InvalidOctree {
        /// Index of the offending node in Morton order.
        index: usize,
        /// Which invariant is broken.
        reason: String,
    },
    /// The estimated memory of a job exceeds the budget; nothing was started.
    #[error(
        "{job} needs an estimated {} but the memory budget is {}; make the job smaller (depth, size, samples) or raise --memory-budget",
        told_apart(*estimate, *budget).0,
        told_apart(*estimate, *budget).1
    )]
    OverBudget {
        /// The refused job.
        job: String,
        /// Estimated bytes.
        estimate: u64,
        /// The budget in bytes.
        budget: u64,
    },
    /// The job was stopped by its caller ([`crate::Progress::cancelled`]) before it
    /// finished; it returned nothing and wrote nothing.
    #[error("cancelled")]
    Cancelled,
}

impl Error {
    /// Shorthand for [`Error::InvalidArgument`].
    pub(crate) fn invalid(what: &'static str, reason: impl Into<String>) -> Self {
        Error::InvalidArgument { what, reason: reason.into() }
    }

    /// `wrap(self)`, the error as the caller names it (its file, its scene), except
    /// [`Error::Cancelled`], which stays itself: a stop is no fault of what the wrapper
    /// names, and its callers match it.
    pub(crate) fn wrapped(self, wrap: impl FnOnce(Error) -> Error) -> Error {
        match self {
            Error::Cancelled => self,
            e => wrap(e),
        }
    }
}

/// `file:line:column`, or just `file` when the place is not known.
fn scene_place(path: &std::path::Path, place: &Option<(usize, usize)>) -> String {
    match place {
        Some((line, column)) => format!("{}:{line}:{column}", path.display()),
        None => path.display().to_string(),
    }
}

/// `unexpected extension '.ext'`, or `no extension` for an empty one.
fn found_extension(found: &str) -> String {
    if found.is_empty() { "no extension".into() } else { format!("unexpected extension '.{found}'") }
}

/// `.a, .b or .c`.
fn list_extensions(extensions: &[&str]) -> String {
    let dotted: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
    match dotted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// Longest run of characters [`quoted`] shows before it cuts with `...`.
const QUOTE_LIMIT: usize = 80;

/// `bytes` from an input file as a single-quoted string that is safe to print on one
/// line: printable characters as they are; `\'` and `\\` escaped; tab, line feed and
/// carriage return as `\t`, `\n`, `\r`; other control characters and the invisible
/// format characters that reorder or hide text (bidirectional overrides, zero-width
/// characters, the byte-order mark) as `\x1b` (ASCII) or `\u{202e}`; bytes that are not
/// UTF-8 as `\xff`. More than [`QUOTE_LIMIT`] characters are cut, ending in `...`.
#[must_use]
pub(crate) fn quoted(bytes: &[u8]) -> String {
    let mut out = String::from("'");
    let mut shown = 0;
    for chunk in bytes.utf8_chunks() {
        for c in chunk.valid().chars() {
            if shown == QUOTE_LIMIT {
                return out + "...'";
            }
            push_escaped(&mut out, c);
            shown += 1;
        }
        for b in chunk.invalid() {
            if shown == QUOTE_LIMIT {
                return out + "...'";
            }
            out += &format!("\\x{b:02x}");
            shown += 1;
        }
    }
    out + "'"
}

/// One character of [`quoted`].
fn push_escaped(out: &mut String, c: char) {
    match c {
        '\'' => out.push_str("\\'"),
        '\\' => out.push_str("\\\\"),
        c => push_printable(out, c),
    }
}

/// Whether [`printable`] escapes `c`: control characters and the invisible format
/// characters that reorder or hide text (bidirectional overrides, zero-width
/// characters, the byte-order mark).
fn is_unprintable(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}' | '\u{2060}'..='\u{2069}' | '\u{feff}')
}

/// One character of [`printable`].
fn push_printable(out: &mut String, c: char) {
    match c {
        '\t' => out.push_str("\\t"),
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        c if c.is_ascii_control() => out.push_str(&format!("\\x{:02x}", c as u32)),
        c if is_unprintable(c) => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
        c => out.push(c),
    }
}

/// A name or message that came from a file (a solid's or a grid's name, a TOML
/// reader's message quoting a value), safe to print on one line: tab, line feed and
/// carriage return as `\t`, `\n`, `\r`, other control characters and the invisible
/// format characters that reorder or hide text as `\x1b` or `\u{202e}`, as messages
/// quote bytes from files; no quotes are added and nothing is cut, so an ordinary name
/// prints as it is.
#[must_use]
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(is_unprintable) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    text.chars().for_each(|c| push_printable(&mut out, c));
    std::borrow::Cow::Owned(out)
}

/// A number as an error message shows it: as Rust writes it (`0.25`, `400`) where that
/// is short, in scientific notation (`1e300`, `2.5e-9`) where plain digits would run to
/// hundreds (Rust's `Display` of `1e300` is 301 characters).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Number(pub f64);

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let x = self.0;
        if x == 0.0 || !x.is_finite() || (1e-5..1e16).contains(&x.abs()) {
            std::fmt::Display::fmt(&x, f)
        } else {
            std::fmt::LowerExp::fmt(&x, f)
        }
    }
}

/// A point or vector as an error message shows it: `[x, y, z]`, each a [`Number`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Vector(pub glam::DVec3);

impl std::fmt::Display for Vector {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [x, y, z] = self.0.to_array().map(Number);
        write!(f, "[{x}, {y}, {z}]")
    }
}

/// A distance in voxels as a job's name shows it: to a thousandth of a voxel (a world
/// distance over the voxel size runs to 17 digits), in scientific notation past a
/// billion.
pub(crate) fn in_voxels(d: f64) -> String {
    if d.abs() >= 1e9 {
        return format!("{d:e}");
    }
    let text = format!("{d:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// Two byte counts in [`human_bytes`], or in whole bytes where those read the same (an
/// estimate just over the budget read "needs an estimated 1.0 GiB but the memory budget
/// is 1.0 GiB").
fn told_apart(a: u64, b: u64) -> (String, String) {
    let (ha, hb) = (human_bytes(a), human_bytes(b));
    if ha != hb || a == b { (ha, hb) } else { (format!("{a} bytes"), format!("{b} bytes")) }
}

/// Formats a byte count with a binary unit, e.g. `1.5 GiB`.
#[must_use]
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut v = bytes as f64;
    let mut unit = 0;
    while v >= 1024.0 && unit + 1 < UNITS.len() {
        v /= 1024.0;
        unit += 1;
    }
    if unit == 0 { format!("{bytes} B") } else { format!("{v:.1} {}", UNITS[unit]) }
}

#[cfg(test)]
mod tests {
    use super::{Number, Vector, printable, quoted};

    #[test]
    fn numbers_too_long_for_plain_digits_are_shown_in_scientific_notation() {
        assert_eq!(Number(400.0).to_string(), "400");
        assert_eq!(Number(-0.25).to_string(), "-0.25");
        assert_eq!(Number(0.0).to_string(), "0");
        assert_eq!(Number(1e300).to_string(), "1e300");
        assert_eq!(Number(-2.5e-9).to_string(), "-2.5e-9");
        assert_eq!(Number(f64::NAN).to_string(), "NaN");
        assert_eq!(Number(f64::INFINITY).to_string(), "inf");
        assert_eq!(Vector(glam::DVec3::new(1.0, 1e308, -3.5)).to_string(), "[1, 1e308, -3.5]");
        assert_eq!(super::in_voxels(2016492.3076923075), "2016492.308");
        assert_eq!(super::in_voxels(2.0), "2");
        assert_eq!(super::in_voxels(-0.5), "-0.5");
        assert_eq!(super::in_voxels(3e12), "3e12");
        assert_eq!(super::told_apart(3 << 30, 1 << 30), ("3.0 GiB".into(), "1.0 GiB".into()));
        assert_eq!(super::told_apart((1 << 30) + 9, 1 << 30), ("1073741833 bytes".into(), "1073741824 bytes".into()));
    }

    #[test]
    fn quoted_escapes_what_a_terminal_would_act_on() {
        assert_eq!(quoted(b"solid x"), "'solid x'");
        assert_eq!(quoted(b"a\x1b[31mred\x07\n"), "'a\\x1b[31mred\\x07\\n'");
        assert_eq!(quoted("it's a\\b\tc\r".as_bytes()), "'it\\'s a\\\\b\\tc\\r'");
        assert_eq!(quoted(b"caf\xe9 \xff"), "'caf\\xe9 \\xff'");
        assert_eq!(quoted("Größe \u{202e}txt\u{85}".as_bytes()), "'Größe \\u{202e}txt\\u{85}'");
        let long = quoted(&[b'a'; 200]);
        assert!(long.ends_with("...'") && long.len() == 1 + 80 + 4, "{long}");
    }

    #[test]
    fn printable_escapes_control_characters_and_leaves_names_alone() {
        assert_eq!(printable("gear's \\ part"), "gear's \\ part");
        assert_eq!(printable("a\x1b[2Jb\u{7}\n\u{202e}"), "a\\x1b[2Jb\\x07\\n\\u{202e}");
        assert_eq!(printable(&"x".repeat(200)).len(), 200);
    }
}
