//! Library errors as Python exceptions: `ValueError` for bad parameters, `stfit.LoadError`
//! (a `ValueError`) for bad measurement data with the file, line and column, `stfit.FitError`
//! (a `ValueError`) for a fit that cannot be made, `OSError` for files that cannot be written.

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    stfit,
    LoadError,
    PyValueError,
    "Bad measurement data. Attributes: `file` (str), `line` (int or None: the 1-based line of \
     the file; for in-memory columns row k is line k + 2, the header being line 1), `column` \
     (str or None: the column's header name) and `message` (what is wrong)."
);

pyo3::create_exception!(
    stfit,
    FitError,
    PyValueError,
    "A fit that cannot be made (too few points, no signal, an optimiser that failed). \
     Attributes: `file`, `sample`, `model` and `message`."
);

/// Any displayable error as a `ValueError`.
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A `ValueError` naming the argument `name`.
pub fn arg_error(name: &str, e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{name}: {e}"))
}

/// An I/O failure as an `OSError`.
pub fn os_error(e: impl std::fmt::Display) -> PyErr {
    PyOSError::new_err(e.to_string())
}

/// A `stfit.LoadError` with its attributes.
pub fn load_error(py: Python<'_>, e: &stfit_fit::LoadError) -> PyErr {
    let err = LoadError::new_err(e.to_string());
    let set = || -> PyResult<()> {
        let v = err.value(py);
        v.setattr("file", e.file.display().to_string())?;
        v.setattr("line", e.line)?;
        v.setattr("column", e.column.clone())?;
        v.setattr("message", e.kind.to_string())
    };
    match set() {
        Ok(()) => err,
        Err(other) => other,
    }
}

/// A `stfit.FitError` with its attributes.
pub fn fit_error(py: Python<'_>, e: &stfit_fit::DatasetFitError) -> PyErr {
    let err = FitError::new_err(e.to_string());
    let set = || -> PyResult<()> {
        let v = err.value(py);
        v.setattr("file", e.file.display().to_string())?;
        v.setattr("sample", e.sample.clone())?;
        v.setattr("model", e.model.clone())?;
        v.setattr("message", e.error.to_string())
    };
    match set() {
        Ok(()) => err,
        Err(other) => other,
    }
}
