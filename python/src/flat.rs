//! Vectors of small fixed arrays (a mesh's `Vec<DVec3>` vertices, `Vec<[u32; 3]>`
//! triangles) handed to numpy as the flat vectors of their scalars, without copying:
//! the allocation is reused, its element count times 3; and pictures as `(h, w, 3)`
//! arrays over their own buffers.

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use octsolid::glam::DVec3;
use octsolid::image::RgbImage;
use pyo3::prelude::*;

/// Vertices as their `3 * n` coordinates, x, y, z a vertex.
pub fn vertices(v: Vec<DVec3>) -> Vec<f64> {
    // SAFETY: `DVec3` is `#[repr(C)]` of three `f64`s.
    unsafe { flat_vec(v) }
}

/// Triangles as their `3 * m` corner indices.
pub fn triangles(t: Vec<[u32; 3]>) -> Vec<u32> {
    // SAFETY: `[u32; 3]` is three `u32`s.
    unsafe { flat_vec(t) }
}

/// A vector of `T` as the vector of its `3 * len` scalars, in the same allocation.
///
/// # Safety
/// Every `T` must be three `S` laid out without padding (`[S; 3]`, a `#[repr(C)]`
/// vector of three scalars); size and alignment are also asserted.
unsafe fn flat_vec<T, S>(v: Vec<T>) -> Vec<S> {
    assert!(
        std::mem::size_of::<T>() == 3 * std::mem::size_of::<S>()
            && std::mem::align_of::<T>() == std::mem::align_of::<S>(),
        "a vector of three scalars"
    );
    let mut v = std::mem::ManuallyDrop::new(v);
    let (ptr, len, cap) = (v.as_mut_ptr(), v.len(), v.capacity());
    // SAFETY: the allocation was made for `cap` values of `T`, which is `3 * cap`
    // values of `S` of the same size and alignment (asserted), so it is a valid
    // allocation of `Vec<S>`; its first `3 * len` scalars are initialized; the original
    // vector is forgotten, so the allocation has one owner.
    unsafe { Vec::from_raw_parts(ptr.cast::<S>(), 3 * len, 3 * cap) }
}

/// An 8-bit RGB picture as an `(h, w, 3)` uint8 array, its buffer not copied.
pub fn picture_array(py: Python<'_>, image: RgbImage) -> Bound<'_, PyArray3<u8>> {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let array = Array3::from_shape_vec((h, w, 3), image.into_raw()).expect("3 channels a pixel");
    array.into_pyarray(py)
}
