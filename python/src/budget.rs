//! `memory_budget=`: the most memory a call may use, as the `octsolid` command's
//! `--memory-budget`: bytes as an int, or a size as a string (`"512MiB"`, `"2GiB"`,
//! parsed by the library's [`MemoryBudget`] parser, so the CLI's spellings), `None`
//! for the library's default (half the RAM). A job whose estimate exceeds it is
//! refused before it starts with `octsolid.BudgetError` (a `MemoryError`) carrying the
//! library's message (the job, its estimate and the budget).

use octsolid::MemoryBudget;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt, PyString};

use crate::errors::invalid;

/// The `memory_budget=` argument (module doc).
#[derive(Clone, Copy)]
pub struct Budget(pub MemoryBudget);

impl<'a, 'py> FromPyObject<'a, 'py> for Budget {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let obj = obj.to_owned();
        if obj.is_instance_of::<PyInt>() && !obj.is_instance_of::<PyBool>() {
            return obj
                .extract::<u64>()
                .map(|bytes| Budget(MemoryBudget(bytes)))
                .map_err(|_| invalid("memory_budget", format!("{obj} bytes is not a size of memory (0 to 2^64 - 1)")));
        }
        if let Ok(text) = obj.cast::<PyString>() {
            return text.to_cow()?.parse().map(Budget).map_err(|e: String| invalid("memory_budget", e));
        }
        let given = obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
        Err(invalid("memory_budget", format!("need bytes (an int) or a size like \"2GiB\", not a {given}")))
    }
}

/// The budget given, or the library's default.
pub fn budget_of(given: Option<Budget>) -> MemoryBudget {
    given.map_or_else(MemoryBudget::default, |b| b.0)
}
