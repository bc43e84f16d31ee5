//! The library's [`octsolid::Error`] as a Python exception: one class a kind of
//! failure, all subclasses of `octsolid.Error` (defined in `octsolid/errors.py`, so
//! that each can also subclass the built-in exception it is a case of), carrying the
//! library's message with its file and place, and the file as `filename`.
//!
//! | library error | Python class | also a |
//! | --- | --- | --- |
//! | `Io`, `Unwritable` | `octsolid.FileError` | `OSError` |
//! | `Format`, `Parse`, `Toml`, `Scene`, `UnknownExtension`, `Undrawable` | `octsolid.FormatError` | `ValueError` |
//! | `InvalidArgument`, `DomainMismatch`, `InvalidOctree` | `octsolid.ArgumentError` | `ValueError` |
//! | `OverBudget` | `octsolid.BudgetError` | `MemoryError` |
//! | `Cancelled` | `KeyboardInterrupt` (Ctrl-C or the progress callable's exception stopped the work, `crate::job`: that exception is raised) | |
//!
//! A scene's error takes the class of its cause (a scene naming a missing file is a
//! `FileError`), with the scene's place in the message. An error with a file has it as
//! `filename`; one the operating system gave has its `errno` and `strerror` too (so
//! `e.errno == errno.ENOENT` works as for Python's own `open`).

use std::path::Path;

use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyType;

/// The Python class a library error is raised as, by name in `octsolid.errors`.
fn class_name(e: &octsolid::Error) -> &'static str {
    use octsolid::Error as E;
    match e {
        E::Io { .. } | E::Unwritable { .. } => "FileError",
        E::Scene { source, .. } => class_name(source),
        E::Undrawable { cause: Some(cause), .. } => class_name(cause),
        E::OverBudget { .. } => "BudgetError",
        E::InvalidArgument { .. } | E::DomainMismatch { .. } | E::InvalidOctree { .. } => "ArgumentError",
        _ => "FormatError",
    }
}

/// The file an error names, if any.
fn file_of(e: &octsolid::Error) -> Option<&Path> {
    use octsolid::Error as E;
    match e {
        E::Io { path, .. }
        | E::Format { path, .. }
        | E::UnknownExtension { path, .. }
        | E::Scene { path, .. }
        | E::Unwritable { path, .. }
        | E::Undrawable { path, .. }
        | E::Parse { path, .. } => Some(path),
        _ => None,
    }
}

/// The operating system's error number behind an error, if any (`errno`).
fn errno_of(e: &octsolid::Error) -> Option<i32> {
    use octsolid::Error as E;
    match e {
        E::Io { source, .. } => source.raw_os_error(),
        E::Scene { source, .. } => errno_of(source),
        E::Undrawable { cause: Some(cause), .. } => errno_of(cause),
        _ => None,
    }
}

/// The class `name` of the module `octsolid.errors`, looked up once.
fn error_class<'py>(py: Python<'py>, name: &'static str) -> PyResult<Bound<'py, PyType>> {
    static MODULE: PyOnceLock<Py<PyModule>> = PyOnceLock::new();
    let module = MODULE.get_or_try_init(py, || py.import("octsolid.errors").map(Bound::unbind))?;
    Ok(module.bind(py).getattr(name)?.cast_into::<PyType>()?)
}

/// A library error as the Python exception of its kind (see the module doc).
pub fn to_py(e: octsolid::Error) -> PyErr {
    if let octsolid::Error::Cancelled = e {
        // Only Ctrl-C cancels (`crate::job`), which raises its own exception first.
        return pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string());
    }
    Python::attach(|py| {
        let class = match error_class(py, class_name(&e)) {
            Ok(class) => class,
            Err(lookup) => return lookup,
        };
        let message = e.to_string();
        // OSError's (errno, strerror, filename) form would make the message; the
        // library's names the file already, so its parts are set as attributes and
        // `str(error)` is the library's message.
        let made = class.call1((message,)).and_then(|err| {
            if let Some(path) = file_of(&e) {
                err.setattr("filename", path.to_string_lossy().into_owned())?;
            }
            if let Some(errno) = errno_of(&e) {
                err.setattr("errno", errno)?;
                // Python's own wording (Rust's adds " (os error N)").
                err.setattr("strerror", py.import("os")?.call_method1("strerror", (errno,))?)?;
            }
            Ok(err)
        });
        match made {
            Ok(err) => PyErr::from_value(err),
            Err(failed) => failed,
        }
    })
}

/// A refused argument of the Python layer itself (a wrong array shape, an unknown
/// name), raised as `octsolid.ArgumentError` with the library's wording.
pub fn invalid(what: &'static str, reason: impl Into<String>) -> PyErr {
    to_py(octsolid::Error::InvalidArgument { what, reason: reason.into() })
}

/// `.map_err(to_py)` for library results.
pub trait ToPyResult<T> {
    /// The result with its error as the Python exception of its kind.
    fn py(self) -> PyResult<T>;
}

impl<T> ToPyResult<T> for octsolid::Result<T> {
    fn py(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}

/// Issues each warning of what a reader read past (an unknown PLY header line, a
/// missing `.mtl`) as Python's `warnings.warn(message, octsolid.InputWarning)`, as the
/// CLI prints it as `warning: FILE: line N: ...`.
pub fn warn_read_past(py: Python<'_>, warnings: &[octsolid::Warning]) -> PyResult<()> {
    for w in warnings {
        warn(py, "InputWarning", &w.to_string())?;
    }
    Ok(())
}

/// `warnings.warn(message, octsolid.<class>)`, at the caller's line.
pub fn warn(py: Python<'_>, class: &'static str, message: &str) -> PyResult<()> {
    let category = error_class(py, class)?;
    let message = std::ffi::CString::new(message.replace('\0', "\\0")).expect("no NUL left");
    PyErr::warn(py, &category, &message, 1)
}
