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

pyo3::create_exception!(
    stfit,
    ExportError,
    PyValueError,
    "Some selected fits could not be exported; the others were. Attributes: `refused` (list \
     of str, one per refused fit: `sample 'x', ggx to appleseed: reason`), `written` (list of \
     pathlib.Path: the files written, empty without `out`) and `text` (str: without `out`, the \
     text of the exports made; None with `out`)."
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
    load_error_with(
        py,
        e.to_string(),
        e.file.display().to_string(),
        e.line,
        e.column.clone(),
        e.kind.to_string(),
    )
}

/// A `stfit.LoadError` found before the loader runs, about in-memory columns of `source`
/// (`<arrays>` or `<DataFrame>`): at row `row` (0-based, line `row + 2` as the loader counts)
/// of `column`, or the column as a whole, or (with neither) the columns. Displayed as the
/// loader's own errors: `<source>:<line>: column '<column>': <message>`.
pub fn column_error(
    py: Python<'_>,
    source: &str,
    row: Option<usize>,
    column: Option<&str>,
    message: impl std::fmt::Display,
) -> PyErr {
    let line = row.map(|k| k as u64 + 2);
    let mut text = source.to_owned();
    if let Some(line) = line {
        text += &format!(":{line}");
    }
    if let Some(column) = column {
        text += &format!(": column '{column}'");
    }
    text += &format!(": {message}");
    load_error_with(
        py,
        text,
        source.to_owned(),
        line,
        column.map(str::to_owned),
        message.to_string(),
    )
}

/// A `stfit.LoadError` of text `text` with its attributes.
fn load_error_with(
    py: Python<'_>,
    text: String,
    file: String,
    line: Option<u64>,
    column: Option<String>,
    message: String,
) -> PyErr {
    let err = LoadError::new_err(text);
    let set = || -> PyResult<()> {
        let v = err.value(py);
        v.setattr("file", file)?;
        v.setattr("line", line)?;
        v.setattr("column", column)?;
        v.setattr("message", message)
    };
    match set() {
        Ok(()) => err,
        Err(other) => other,
    }
}

/// A `stfit.ExportError` for a batch with refused fits: `message` (the count, and one line
/// per refusal), `refused` (the refusals' texts), `written` (the paths written) and `text`
/// (the text of the exports made, where no file was written).
pub fn export_error(
    py: Python<'_>,
    message: String,
    refused: Vec<String>,
    written: Vec<std::path::PathBuf>,
    text: Option<String>,
) -> PyErr {
    let err = ExportError::new_err(message);
    let set = || -> PyResult<()> {
        let v = err.value(py);
        v.setattr("refused", refused)?;
        v.setattr("written", written)?;
        v.setattr("text", text)
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
