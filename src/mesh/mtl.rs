//! The material libraries (`.mtl`) an OBJ names: checked, never required.
//!
//! octsolid's meshes carry no materials, so a library matters only as a sign of an
//! incomplete or damaged export: one that cannot be read, or that breaks the format
//! (a statement other tools refuse), is a [`Warning`] at the OBJ's `mtllib` line and
//! the mesh loads regardless. The check covers the statements of the MTL format
//! (Wavefront, "Alias|Wavefront Material Library", version 4.2, 1995) that carry
//! values: `newmtl` needs a name; colours `Ka Kd Ks Ke Tf` one to three numbers (or a
//! `spectral` file, or `xyz` and numbers); scalars `Ns Ni d Tr illum sharpness` and the
//! physically based `Pr Pm Ps Pc Pcr aniso anisor` a number (after options such as
//! `-halo`); texture maps a file name. Unknown statements are skipped, as other
//! readers do; every number must be finite.
//!
//! A library is looked up beside the OBJ (the name as written, spaces included) and
//! read only when it is a regular file of at most [`MAX_LIBRARY_BYTES`].

use std::io::Read;
use std::path::Path;

use crate::error::quoted;
use crate::text::Text;
use crate::warning::{Place, Warning};

/// Larger material libraries are not read (a warning says so).
pub const MAX_LIBRARY_BYTES: u64 = 16 << 20;

/// Checks the library `name` that `obj` names at `line`; pushes a warning when it
/// cannot be read or is broken.
pub(super) fn check(obj: &Path, line: usize, name: &str, warnings: &mut Vec<Warning>) {
    let warn = |message: String| Place::Line(line).warning(obj, message);
    if name.is_empty() {
        warnings.push(warn("'mtllib' names no file".into()));
        return;
    }
    let library = obj.parent().unwrap_or(Path::new("")).join(name);
    let shown = quoted(name.as_bytes());
    let bytes = match read_limited(&library) {
        Ok(bytes) => bytes,
        Err(reason) => {
            warnings.push(warn(format!("material library {shown} cannot be read ({reason}); materials are not used")));
            return;
        }
    };
    let text = Text::decode(&bytes);
    if let Some((at, problem)) = text.lines().find_map(|(n, l)| statement_problem(l).map(|p| (n, p))) {
        warnings.push(warn(format!("material library {shown}: line {at}: {problem}; materials are not used")));
    }
}

/// The bytes of a regular file of at most [`MAX_LIBRARY_BYTES`], or why not.
fn read_limited(path: &Path) -> Result<Vec<u8>, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let meta = file.metadata().map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err("not a regular file".into());
    }
    let mut bytes = Vec::new();
    file.take(MAX_LIBRARY_BYTES + 1).read_to_end(&mut bytes).map_err(|e| e.to_string())?;
    if bytes.len() as u64 > MAX_LIBRARY_BYTES {
        return Err(format!("larger than {MAX_LIBRARY_BYTES} bytes"));
    }
    Ok(bytes)
}

/// What is wrong with one line of a library, if anything.
fn statement_problem(line: &str) -> Option<String> {
    let mut words = line.split_whitespace().take_while(|w| !w.starts_with('#'));
    let keyword = words.next()?;
    let values: Vec<&str> = words.collect();
    let numbers = |values: &[&str], range: std::ops::RangeInclusive<usize>| -> Option<String> {
        let bad = values.iter().find(|v| !v.parse::<f64>().is_ok_and(f64::is_finite));
        match bad {
            Some(v) => Some(format!("{} is not a finite number", quoted(v.as_bytes()))),
            None if !range.contains(&values.len()) => {
                Some(format!("'{keyword}' needs {} to {} numbers, got {}", range.start(), range.end(), values.len()))
            }
            None => None,
        }
    };
    match keyword {
        "newmtl" if values.is_empty() => Some("'newmtl' names no material".into()),
        "Ka" | "Kd" | "Ks" | "Ke" | "Tf" => match values.first() {
            Some(&"spectral") => (values.len() < 2).then(|| format!("'{keyword} spectral' names no file")),
            Some(&"xyz") => numbers(&values[1..], 1..=3),
            _ => numbers(&values, 1..=3),
        },
        "Ns" | "Ni" | "d" | "Tr" | "illum" | "sharpness" | "Pr" | "Pm" | "Ps" | "Pc" | "Pcr" | "aniso" | "anisor" => {
            let value = values.iter().position(|v| !v.starts_with('-') || v.parse::<f64>().is_ok());
            numbers(&values[value.unwrap_or(values.len())..], 1..=1)
        }
        k if (k.starts_with("map_") || matches!(k, "bump" | "disp" | "decal" | "refl" | "norm"))
            && values.is_empty() =>
        {
            Some(format!("'{keyword}' names no file"))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::statement_problem;

    #[test]
    fn statements_other_readers_refuse_are_problems() {
        for fine in ["newmtl red", "Kd 0.8 0.8 0.8", "Ka 1", "d -halo 0.5", "Ns 10 # shiny", "map_Kd a b.png", "x y"] {
            assert_eq!(statement_problem(fine), None, "{fine}");
        }
        for broken in ["newmtl", "Kd 0.8 red 0.8", "Kd", "Ks 1 2 3 4", "Ns nan", "illum", "map_Kd", "Tf spectral"] {
            assert!(statement_problem(broken).is_some(), "{broken}");
        }
    }
}
