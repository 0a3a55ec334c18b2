//! Numeric arguments, read the one way every call reads them: a number is a Python int or
//! float, or a NumPy integer or float (a 0-d array included), never a bool. `True` is an int to
//! Python and NumPy's `bool_` converts to 1.0, so a plain conversion would take `alpha=True` as
//! 1.0 and `[0.3, True]` as `[0.3, 1.0]`; here a bool is a `ValueError` naming the argument. A
//! NumPy masked array with a masked element is refused ([`refuse_masked`]): converting it would
//! use the values under the mask.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt, PyString};

/// Whether `value` is a bool: Python's, NumPy's `bool_`, or a NumPy array of dtype bool.
pub fn is_bool(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    if value.is_instance_of::<PyBool>() {
        return Ok(true);
    }
    if value.is_exact_instance_of::<PyFloat>() || value.is_exact_instance_of::<PyInt>() {
        return Ok(false);
    }
    let np = value.py().import("numpy")?;
    if value.is_instance(&np.getattr("bool_")?)? {
        return Ok(true);
    }
    if value.is_instance(&np.getattr("ndarray")?)? {
        let kind: String = value.getattr("dtype")?.getattr("kind")?.extract()?;
        return Ok(kind == "b");
    }
    Ok(false)
}

/// The index of the first masked element of `value` when it is a NumPy masked array with a
/// masked element (empty for a 0-d one such as `numpy.ma.masked`), else None.
pub fn first_masked(value: &Bound<'_, PyAny>) -> PyResult<Option<Vec<usize>>> {
    if value.is_exact_instance_of::<PyFloat>()
        || value.is_instance_of::<PyInt>()
        || value.is_instance_of::<PyString>()
    {
        return Ok(None);
    }
    let np = value.py().import("numpy")?;
    let ma = np.getattr("ma")?;
    if !ma.call_method1("isMaskedArray", (value,))?.is_truthy()? {
        return Ok(None);
    }
    let mask = ma.call_method1("getmaskarray", (value,))?;
    if !mask.call_method0("any")?.is_truthy()? {
        return Ok(None);
    }
    let first = np.call_method1("argwhere", (mask,))?.get_item(0)?;
    Ok(Some(first.call_method0("tolist")?.extract()?))
}

/// A masked array without masked elements passes (its data are its values); one with any is a
/// `ValueError` naming the argument `name` and the first masked index.
pub fn refuse_masked(name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
    match first_masked(value)? {
        None => Ok(()),
        Some(index) => Err(PyValueError::new_err(format!(
            "{name}: a masked array with masked elements (the first at index {index:?}): \
             fill them (numpy.ma.filled) or drop them (compressed) first; the values under \
             the mask are not used"
        ))),
    }
}

/// The number `value` of the argument `name`: a bool is a `ValueError`, a value that is not a
/// number a `TypeError`, both naming the argument.
pub fn float(name: &str, value: &Bound<'_, PyAny>) -> PyResult<f64> {
    if value.is_exact_instance_of::<PyFloat>() {
        return value.extract();
    }
    if is_bool(value)? {
        return Err(PyValueError::new_err(format!(
            "{name}: expected a number, got a bool ({value})"
        )));
    }
    refuse_masked(name, value)?;
    if value.is_instance_of::<PyString>() {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a number, got str {}",
            value.repr()?
        )));
    }
    value.extract::<f64>().map_err(|_| {
        let type_name = value
            .get_type()
            .name()
            .map_or_else(|_| "?".to_owned(), |n| n.to_string());
        PyTypeError::new_err(format!("{name}: expected a number, got {type_name}"))
    })
}

/// An optional number ([`float`]); None stays None.
pub fn opt_float(name: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    value
        .filter(|v| !v.is_none())
        .map(|v| float(name, v))
        .transpose()
}

/// A sequence of numbers (a list, a tuple or a 1-D array): each element as [`float`], named
/// `name[k]`; a masked array with a masked element is refused ([`refuse_masked`]), as text is.
/// None when `value` is not iterable (the caller says what it takes).
pub fn floats(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Option<Vec<f64>>> {
    if value.is_instance_of::<PyString>() {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a sequence of numbers, got str {}",
            value.repr()?
        )));
    }
    refuse_masked(name, value)?;
    let Ok(items) = value.try_iter() else {
        return Ok(None);
    };
    items
        .enumerate()
        .map(|(k, v)| float(&format!("{name}[{k}]"), &v?))
        .collect::<PyResult<Vec<_>>>()
        .map(Some)
}

/// The first bool among the elements of nested lists and tuples `value` (what NumPy converts
/// to 1 or 0 when they also hold numbers), with its index; None when there is none or `value`
/// is not a list or tuple.
pub fn nested_bool(value: &Bound<'_, PyAny>) -> PyResult<Option<(Vec<usize>, String)>> {
    use pyo3::types::{PyList, PyTuple};
    if !(value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>()) {
        return Ok(None);
    }
    for (k, item) in value.try_iter()?.enumerate() {
        let item = item?;
        if is_bool(&item)? {
            return Ok(Some((vec![k], item.repr()?.to_string())));
        }
        if let Some((mut index, shown)) = nested_bool(&item)? {
            index.insert(0, k);
            return Ok(Some((index, shown)));
        }
    }
    Ok(None)
}

/// Extractors of named number arguments, for `#[pyo3(from_py_with = ...)]` (which takes a
/// function of the value alone) on arguments with a default.
pub mod arg {
    use super::float;
    use pyo3::prelude::*;

    macro_rules! named {
        ($($name:ident),*) => {$(
            #[doc = concat!("The number argument `", stringify!($name), "` ([`float`]).")]
            pub fn $name(value: &Bound<'_, PyAny>) -> PyResult<f64> {
                float(stringify!($name), value)
            }
        )*};
    }

    named!(scale, noise, eta);
}

/// `x` as Python's `repr(float)` writes it, the shortest text that reads back to it (`0.3`,
/// `1.0`, `1e-08`, `1e+300`, `inf`): how every `__repr__` of the package shows a number.
pub fn float_repr(py: Python<'_>, x: f64) -> PyResult<String> {
    Ok(PyFloat::new(py, x).repr()?.to_string())
}
