//! Integer arguments: any Python integer is taken (or what converts to one losslessly,
//! by `__index__`: numpy's integers), and one the library's type cannot hold is refused
//! as an `ArgumentError` naming the argument in the library's words, as the library
//! refuses a value out of its range (pyo3's own conversion raises an `OverflowError` or
//! a `TypeError` naming no argument). Each function here is one argument's
//! `#[pyo3(from_py_with = ...)]`; the `optional_` ones take `None` too.

use std::fmt::Display;

use octsolid::render::MAX_IMAGE_SIZE;
use pyo3::prelude::*;
use pyo3::types::PyInt;

use crate::errors::invalid;

/// `obj` as a `T`, refused as `invalid {what}: {value} is outside {range}` when `T`
/// cannot hold it, or `... is not an integer`.
fn int_of<T: TryFrom<i128>>(obj: &Bound<'_, PyAny>, what: &'static str, range: impl Display) -> PyResult<T> {
    int_refused_as(obj, what, |value| format!("{value} is outside {range}"))
}

/// [`int_of`] with the reason a value `T` cannot hold is refused for.
fn int_refused_as<T: TryFrom<i128>>(
    obj: &Bound<'_, PyAny>,
    what: &'static str,
    reason: impl Fn(&str) -> String,
) -> PyResult<T> {
    let int = integer(obj).ok_or_else(|| invalid(what, format!("{} is not an integer", repr(obj))))?;
    held(&int).map_err(|value| invalid(what, reason(&value)))
}

/// `obj` as a Python integer: itself, or its `__index__` (numpy's integers); `None`
/// for anything else (a float, a string).
fn integer<'py>(obj: &Bound<'py, PyAny>) -> Option<Bound<'py, PyInt>> {
    if let Ok(int) = obj.cast::<PyInt>() {
        return Some(int.clone());
    }
    obj.call_method0("__index__").ok()?.cast_into::<PyInt>().ok()
}

/// `int` as a `T`, or the value as a refusal shows it when `T` cannot hold it (past
/// 128 bits it is outside every range here).
fn held<T: TryFrom<i128>>(int: &Bound<'_, PyInt>) -> Result<T, String> {
    let value: i128 = int.extract().map_err(|_| repr(int))?;
    T::try_from(value).map_err(|_| value.to_string())
}

/// `repr(obj)`, or "the value" when it has none.
fn repr(obj: &Bound<'_, PyAny>) -> String {
    obj.repr().map_or_else(|_| "the value".into(), |r| r.to_string())
}

/// `None` as `None`, else `read(obj)`.
fn optional<T>(obj: &Bound<'_, PyAny>, read: impl FnOnce(&Bound<'_, PyAny>) -> PyResult<T>) -> PyResult<Option<T>> {
    if obj.is_none() { Ok(None) } else { read(obj).map(Some) }
}

/// A `depth`.
pub fn depth_arg(obj: &Bound<'_, PyAny>) -> PyResult<u8> {
    int_of(obj, "depth", format_args!("1..={}", octsolid::octree::MAX_DEPTH))
}

/// An optional `depth`.
pub fn optional_depth_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<u8>> {
    optional(obj, depth_arg)
}

/// `spp`, samples a pixel side (the library's `samples`).
pub fn optional_spp_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<u32>> {
    optional(obj, |obj| int_refused_as(obj, "samples", |spp| format!("{spp} a side is outside 1..=16")))
}

/// `size=(width, height)` of a picture, refused as the library refuses an image size.
pub fn optional_size_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<(u32, u32)>> {
    optional(obj, |obj| {
        let (w, h): (Bound<'_, PyAny>, Bound<'_, PyAny>) =
            obj.extract().map_err(|_| invalid("image size", format!("{} is not (width, height)", repr(obj))))?;
        // Each side as a `u32`, or as it is shown in the refusal.
        let side = |side: &Bound<'_, PyAny>| match integer(side) {
            Some(int) => Ok(held::<u32>(&int)),
            None => Err(invalid("image size", format!("{} is not (width, height) in whole pixels", repr(obj)))),
        };
        match (side(&w)?, side(&h)?) {
            (Ok(w), Ok(h)) => Ok((w, h)),
            (w, h) => {
                let shown = |s: Result<u32, String>| s.map_or_else(|v| v, |v| v.to_string());
                Err(invalid("image size", format!("{}x{} is outside 1..={MAX_IMAGE_SIZE} a side", shown(w), shown(h))))
            }
        }
    })
}

/// A slice's `size` in pixels (`N pixels is outside 1..=16384`, as the library says).
pub fn slice_size_arg(obj: &Bound<'_, PyAny>) -> PyResult<u32> {
    int_refused_as(obj, "size", |size| format!("{size} pixels is outside 1..={}", octsolid::slice::MAX_SLICE_SIZE))
}

/// A pattern's `count` of copies (`N makes N copies; a pattern makes 1 to 100000`, as the
/// library says of a count of 0).
pub fn count_arg(obj: &Bound<'_, PyAny>) -> PyResult<u32> {
    int_refused_as(obj, "count", |n| {
        format!("{n} makes {n} copies; a pattern makes 1 to {}", octsolid::shape::MAX_COPIES)
    })
}

/// Radiosity's `max_shots`.
pub fn optional_max_shots_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<u64>> {
    optional(obj, |obj| int_of(obj, "max shots", format_args!("0..={}", u64::MAX)))
}

/// Radiosity's `max_elements`.
pub fn optional_max_elements_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<usize>> {
    optional(obj, |obj| int_of(obj, "max elements", format_args!("0..={}", usize::MAX)))
}
