//! Places in the scene text: the line and column of a byte offset, the `[[solid]]` a
//! place lies in (from the spans of the parsed document), and the first float that is
//! not finite (checked once over the whole document, since the reader takes `nan` and
//! `inf`). Errors name their place with these.

use std::ops::Range;

/// The first float of the TOML `text` that is not finite (`nan`, `inf`, or a literal
/// past `f64`'s range such as `1e400`): its span, dotted key and literal. Every float
/// of a scene is a coordinate, size, angle or coefficient, none of which may be
/// infinite, so the whole document is checked once here rather than field by field.
pub(super) fn first_non_finite(text: &str) -> Option<(Range<usize>, String, String)> {
    use toml::de::{DeTable, DeValue};
    pub(super) fn walk(value: &toml::Spanned<DeValue>, key: &str) -> Option<(Range<usize>, String, String)> {
        match value.get_ref() {
            DeValue::Float(f) => {
                let literal = f.as_str();
                let finite = literal.replace('_', "").parse::<f64>().is_ok_and(f64::is_finite);
                (!finite).then(|| (value.span(), key.to_owned(), literal.to_owned()))
            }
            DeValue::Array(items) => items.iter().enumerate().find_map(|(i, item)| walk(item, &format!("{key}[{i}]"))),
            DeValue::Table(table) => table.iter().find_map(|(k, v)| {
                let name = if key.is_empty() { k.get_ref().to_string() } else { format!("{key}.{}", k.get_ref()) };
                walk(v, &name)
            }),
            _ => None,
        }
    }
    let doc = DeTable::parse(text).ok()?;
    doc.get_ref().iter().find_map(|(k, v)| walk(v, k.get_ref()))
}

/// One-based line and column (in bytes) of byte `offset` in `text`.
pub(super) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text.as_bytes()[..offset.min(text.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = before.iter().rposition(|&b| b == b'\n').map_or(before.len(), |i| before.len() - i - 1) + 1;
    (line, column)
}

/// The name of the `[[solid]]` whose header, keys or values hold byte `offset` of
/// `text` (its `name`, else `solid N`); `None` when the place lies in no solid or
/// `text` is not TOML.
pub(super) fn solid_at(text: &str, offset: usize) -> Option<String> {
    use toml::de::{DeTable, DeValue};
    let doc = DeTable::parse(text).ok()?;
    let DeValue::Array(solids) = doc.get_ref().get("solid")?.get_ref() else { return None };
    solids.iter().enumerate().find_map(|(i, solid)| {
        let mut region = solid.span();
        let mut name = None;
        if let DeValue::Table(table) = solid.get_ref() {
            for (key, value) in table.iter() {
                region = region.start.min(key.span().start)..region.end.max(value.span().end);
            }
            name = table.get("name").and_then(|v| v.get_ref().as_str()).map(str::to_owned);
        }
        region.contains(&offset).then(|| name.unwrap_or_else(|| format!("solid {}", i + 1)))
    })
}
