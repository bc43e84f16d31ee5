//! `octsolid._octsolid`: the library's modeler and renderer as a Python extension
//! module (PyO3, abi3 for Python 3.9 on), re-exported by the package `octsolid`
//! (`octsolid/__init__.py`, which adds `Solid.to_trimesh`). Thin: every function is
//! the library calls the matching `octsolid` command makes (see [`solid`]), with
//! numpy arrays at its edges and the GIL released while the library works.
//!
//! Rooms: [`shapes`] (`Shape` and the primitives, the patterns), [`solid`] (`Solid`,
//! `voxelize`, `from_mesh`, `load_mesh`, `load`), [`surface`] (a solid's surface data,
//! made when needed), [`render`] (`render`, `Solid._repr_png_`), [`radiosity`]
//! (`radiosity`), [`errors`] (the library's errors as `octsolid.Error`s), [`flat`] (mesh
//! buffers as numpy's), and the arguments long calls share: [`budget`]
//! (`memory_budget=`), [`progress`] (`progress=`: a bar on the terminal or a callable),
//! and [`job`] (both made ready and the work run without the GIL).

mod budget;
mod errors;
mod flat;
mod ints;
mod job;
mod progress;
mod radiosity;
mod render;
mod shapes;
mod solid;
mod surface;

use pyo3::prelude::*;

/// The extension module: the classes and functions `octsolid` re-exports.
#[pymodule]
fn _octsolid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<shapes::Shape>()?;
    m.add_class::<shapes::Sphere>()?;
    m.add_class::<shapes::Ellipsoid>()?;
    m.add_class::<shapes::Cuboid>()?;
    m.add_class::<shapes::Cylinder>()?;
    m.add_class::<shapes::Cone>()?;
    m.add_class::<shapes::Torus>()?;
    m.add_class::<shapes::HalfSpace>()?;
    m.add_class::<solid::Solid>()?;
    m.add_function(wrap_pyfunction!(shapes::linear_array, m)?)?;
    m.add_function(wrap_pyfunction!(shapes::polar_array, m)?)?;
    m.add_function(wrap_pyfunction!(solid::voxelize, m)?)?;
    m.add_function(wrap_pyfunction!(solid::from_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(solid::load_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(solid::load, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::write_png, m)?)?;
    m.add_function(wrap_pyfunction!(radiosity::radiosity, m)?)?;
    Ok(())
}
