//! The lines of an ASCII-structured text file (OBJ, ASCII STL and PLY, `.patches`),
//! whatever encoding its names and comments are in.
//!
//! These formats are ASCII keywords and numbers; only names and comments may hold other
//! characters, in whatever encoding the exporter used. So a file is read line by line:
//! a line that is UTF-8 is taken as it is (borrowed, no copy), any other line as
//! Latin-1, every byte one character (nothing is lost, a Latin-1 name reads right, a
//! Windows-1252 one nearly). A file that starts with a UTF-16 byte-order mark (little
//! or big endian) is transcoded first, lossily: unpaired surrogates become U+FFFD and
//! an odd last byte is dropped. A UTF-8 byte-order mark is skipped. Lines end at
//! `\n`, `\r\n` or a lone `\r`.
//!
//! Deviation from a charset library (`encoding_rs`): no guessing beyond this. UTF-16
//! without a byte-order mark reads as Latin-1 with NUL bytes, which no keyword matches,
//! so such a file is refused at its first line rather than misread.

use std::borrow::Cow;
use std::path::Path;

use crate::warning::{Place, Warning};

/// The byte order of a UTF-16 file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Utf16 {
    /// Little endian, byte-order mark `FF FE`.
    Le,
    /// Big endian, byte-order mark `FE FF`.
    Be,
}

/// A file's text as lines, with how it was decoded.
pub(crate) struct Text<'a> {
    /// The lines, without their line ends.
    lines: Vec<Cow<'a, str>>,
    /// One-based numbers of the lines read as Latin-1 (not UTF-8).
    latin1: Vec<usize>,
    /// Lines before the text's first (of a text that starts inside a file).
    lines_before: usize,
    /// Whether a UTF-16 file had an odd byte at its end (dropped).
    odd_byte: bool,
}

impl<'a> Text<'a> {
    /// Decodes `bytes` as described in the module docs.
    pub(crate) fn decode(bytes: &'a [u8]) -> Text<'a> {
        let utf16 = match bytes {
            [0xff, 0xfe, ..] => Some(Utf16::Le),
            [0xfe, 0xff, ..] => Some(Utf16::Be),
            _ => None,
        };
        let Some(order) = utf16 else {
            let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
            let mut latin1 = Vec::new();
            let lines = split_lines(bytes)
                .enumerate()
                .map(|(i, line)| match std::str::from_utf8(line) {
                    Ok(s) => Cow::Borrowed(s),
                    Err(_) => {
                        latin1.push(i + 1);
                        Cow::Owned(line.iter().map(|&b| char::from(b)).collect())
                    }
                })
                .collect();
            return Text { lines, latin1, lines_before: 0, odd_byte: false };
        };
        let units = bytes[2..].chunks_exact(2).map(|p| match order {
            Utf16::Le => u16::from_le_bytes([p[0], p[1]]),
            Utf16::Be => u16::from_be_bytes([p[0], p[1]]),
        });
        let text: String = char::decode_utf16(units).map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER)).collect();
        let lines = split_lines(text.as_bytes())
            .map(|line| Cow::Owned(String::from_utf8(line.to_vec()).expect("split at ASCII line ends")))
            .collect();
        Text { lines, latin1: Vec::new(), lines_before: 0, odd_byte: bytes.len() % 2 == 1 }
    }

    /// The same text numbered as if `lines_before` lines came first (the body of a
    /// file after its header).
    pub(crate) fn after_lines(self, lines_before: usize) -> Text<'a> {
        Text { lines_before, ..self }
    }

    /// `(one-based line number, line)` for every line.
    pub(crate) fn lines(&self) -> impl Iterator<Item = (usize, &str)> + '_ {
        self.lines.iter().enumerate().map(|(i, l)| (self.lines_before + i + 1, l.as_ref()))
    }

    /// The number of the last line (at least 1, for errors about the end of the file).
    pub(crate) fn last_line(&self) -> usize {
        self.lines_before + self.lines.len().max(1)
    }

    /// Warnings about the decoding: lines that were not UTF-8, a dropped odd byte.
    pub(crate) fn warnings(&self, path: &Path) -> Vec<Warning> {
        let mut out = Vec::new();
        if let Some(first) = self.latin1.first() {
            let message = format!("lines that are not UTF-8, read as Latin-1: {}", self.latin1.len());
            out.push(Place::Line(self.lines_before + first).warning(path, message));
        }
        if self.odd_byte {
            out.push(Place::File.warning(path, "UTF-16 text with an odd number of bytes; the last byte is ignored"));
        }
        out
    }
}

/// The lines of `bytes`, split at `\n`, `\r\n` and a lone `\r`, without their ends;
/// no empty last line after a final line end.
fn split_lines(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    let mut rest = bytes;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let Some(end) = rest.iter().position(|&b| b == b'\n' || b == b'\r') else {
            return Some(std::mem::take(&mut rest));
        };
        let line = &rest[..end];
        let skip = if rest[end] == b'\r' && rest.get(end + 1) == Some(&b'\n') { 2 } else { 1 };
        rest = &rest[end + skip..];
        Some(line)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(text: &Text) -> Vec<String> {
        text.lines().map(|(_, l)| l.to_string()).collect()
    }

    #[test]
    fn every_line_end_and_encoding_reads_the_same_lines() {
        let want = ["v 1 2 3", "", "g caf\u{e9}"];
        let utf8 = "v 1 2 3\n\ng caf\u{e9}\n";
        assert_eq!(lines(&Text::decode(utf8.as_bytes())), want);
        assert_eq!(lines(&Text::decode(b"v 1 2 3\r\n\r\ng caf\xe9")), want);
        assert_eq!(lines(&Text::decode(b"\xef\xbb\xbfv 1 2 3\r\rg caf\xc3\xa9\r")), want);
        let le: Vec<u8> = [0xfeff].into_iter().chain(utf8.encode_utf16()).flat_map(u16::to_le_bytes).collect();
        let be: Vec<u8> = [0xfeff].into_iter().chain(utf8.encode_utf16()).flat_map(u16::to_be_bytes).collect();
        assert_eq!(lines(&Text::decode(&le)), want);
        assert_eq!(lines(&Text::decode(&be)), want);
        assert!(Text::decode(&le[..le.len() - 1]).warnings(Path::new("x.obj"))[0].message.contains("odd"));
    }

    #[test]
    fn latin1_lines_are_counted_in_one_warning() {
        let text = Text::decode(b"# \xe9\nv 0 0 0\ng \xe0\n");
        let w = text.warnings(Path::new("x.obj"));
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].place, Place::Line(1));
        assert!(w[0].message.ends_with(": 2"), "{}", w[0]);
        assert!(Text::decode(b"plain\n").warnings(Path::new("x.obj")).is_empty());
    }
}
