//! Integer arguments: any Python integer is taken, and one the library's type cannot
//! hold is refused as an `ArgumentError` naming the argument in the library's words, as
//! the library refuses a value out of its range (pyo3's own conversion raises an
//! `OverflowError` or a `TypeError` naming no argument). Each function here is one
//! argument's `#[pyo3(from_py_with = ...)]`; the `optional_` ones take `None` too.

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
    let given = || obj.repr().map_or_else(|_| "the value".into(), |r| r.to_string());
    if !obj.is_instance_of::<PyInt>() {
        return Err(invalid(what, format!("{} is not an integer", given())));
    }
    let outside = |value: String| invalid(what, reason(&value));
    // Past 128 bits it is outside every range here.
    let value: i128 = obj.extract().map_err(|_| outside(given()))?;
    T::try_from(value).map_err(|_| outside(value.to_string()))
}

/// `None` as `None`, else [`int_of`].
fn optional_int_of<T: TryFrom<i128>>(
    obj: &Bound<'_, PyAny>,
    what: &'static str,
    range: impl Display,
) -> PyResult<Option<T>> {
    if obj.is_none() { Ok(None) } else { int_of(obj, what, range).map(Some) }
}

/// A `depth`.
pub fn depth_arg(obj: &Bound<'_, PyAny>) -> PyResult<u8> {
    int_of(obj, "depth", format_args!("1..={}", octsolid::octree::MAX_DEPTH))
}

/// An optional `depth`.
pub fn optional_depth_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<u8>> {
    optional_int_of(obj, "depth", format_args!("1..={}", octsolid::octree::MAX_DEPTH))
}

/// `spp`, samples a pixel side (the library's `samples`).
pub fn optional_spp_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<u32>> {
    if obj.is_none() {
        return Ok(None);
    }
    int_refused_as(obj, "samples", |spp| format!("{spp} a side is outside 1..=16")).map(Some)
}

/// `size=(width, height)` of a picture, refused as the library refuses an image size.
pub fn optional_size_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<(u32, u32)>> {
    if obj.is_none() {
        return Ok(None);
    }
    let given = || obj.repr().map_or_else(|_| "the value".into(), |r| r.to_string());
    let (w, h): (Bound<'_, PyAny>, Bound<'_, PyAny>) =
        obj.extract().map_err(|_| invalid("image size", format!("{} is not (width, height)", given())))?;
    let side = |side: &Bound<'_, PyAny>| -> PyResult<Result<u32, String>> {
        if !side.is_instance_of::<PyInt>() {
            return Err(invalid("image size", format!("{} is not (width, height) in whole pixels", given())));
        }
        Ok(side.extract::<i128>().map_or_else(|_| Err(given()), |v| u32::try_from(v).map_err(|_| v.to_string())))
    };
    match (side(&w)?, side(&h)?) {
        (Ok(w), Ok(h)) => Ok(Some((w, h))),
        (w, h) => {
            let shown = |s: Result<u32, String>| s.map_or_else(|v| v, |v| v.to_string());
            Err(invalid("image size", format!("{}x{} is outside 1..={MAX_IMAGE_SIZE} a side", shown(w), shown(h))))
        }
    }
}

/// A slice's `size` in pixels.
pub fn slice_size_arg(obj: &Bound<'_, PyAny>) -> PyResult<u32> {
    int_of(obj, "size", format_args!("1..={} pixels", octsolid::slice::MAX_SLICE_SIZE))
}

/// A pattern's `count` of copies.
pub fn count_arg(obj: &Bound<'_, PyAny>) -> PyResult<u32> {
    int_of(obj, "count", format_args!("1..={} copies", octsolid::shape::MAX_COPIES))
}

/// Radiosity's `max_shots`.
pub fn optional_max_shots_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<u64>> {
    optional_int_of(obj, "max shots", format_args!("0..={}", u64::MAX))
}

/// Radiosity's `max_elements`.
pub fn optional_max_elements_arg(obj: &Bound<'_, PyAny>) -> PyResult<Option<usize>> {
    optional_int_of(obj, "max elements", format_args!("0..={}", usize::MAX))
}
