//! Integer arguments (`walks`, `seed`, a shard's `index` and `count`): a Python int or a NumPy
//! integer, not a bool (Python's or NumPy's, [`crate::numbers::is_bool`]). An integer that does not fit is a `ValueError` naming the argument and
//! its range, as any other bad value, not the `OverflowError` of a plain conversion; each
//! value's own range (such as [`stfit_core::walk::check_walks`]) is checked where it is used.

use pyo3::exceptions::PyOverflowError;
use pyo3::prelude::*;
use stfit_core::walk::MAX_WALKS;

use crate::errors::arg_error;

/// The integer argument `name` as a `u64`: a bool, a negative integer or one of 2^64 or more
/// is a `ValueError` stating `range`; a value that is not an integer a `TypeError`.
fn integer(name: &str, value: &Bound<'_, PyAny>, range: &str) -> PyResult<u64> {
    if crate::numbers::is_bool(value)? {
        return Err(arg_error(
            name,
            format!("expected an integer in {range}, got a bool ({value})"),
        ));
    }
    crate::numbers::refuse_masked(name, value)?;
    value.extract::<u64>().map_err(|e| {
        if e.is_instance_of::<PyOverflowError>(value.py()) {
            arg_error(name, format!("{value} is not an integer in {range}"))
        } else {
            e
        }
    })
}

/// A seed: an integer in [0, 2^64).
pub fn seed(value: &Bound<'_, PyAny>) -> PyResult<u64> {
    integer("seed", value, "[0, 2^64)")
}

/// A number of walks (its range, `[1, MAX_WALKS]` or a fit's, is checked where it is used).
pub fn walks(value: &Bound<'_, PyAny>) -> PyResult<u64> {
    integer("walks", value, &format!("[1, {MAX_WALKS}]"))
}

/// A shard's 1-based index (at most its `count`, checked with the shard).
pub fn shard_index(value: &Bound<'_, PyAny>) -> PyResult<u64> {
    integer("index", value, "[1, count]")
}

/// A number of shards.
pub fn shard_count(value: &Bound<'_, PyAny>) -> PyResult<u64> {
    integer("count", value, "[1, 2^64)")
}
