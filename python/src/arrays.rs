//! NumPy arrays of directions in, arrays of values out, and the parallel loops over them.
//!
//! A batch of directions is any array-like of shape `(..., 3)` (one direction per row of the
//! last axis) of an integer or float dtype, converted to contiguous `float64` without a copy
//! when it already is one. Values come back with the leading shape (a Python float for a
//! single direction). Every direction must be one the library takes
//! ([`stfit_fit::pairs::direction_problem`]): finite, a unit vector (|norm - 1| <= 1e-6) and
//! with a `z` that is 0 or normal (not below 2.2e-308); an accepted direction is scaled to unit
//! length ([`stfit_core::math::to_unit`]; exactly unit input is kept as it is).
//!
//! With the GIL released another Python thread may write into the caller's array, so a call
//! reads it once ([`checked_copy`]): it checks and computes on its own copy, and a direction
//! changed during the call cannot pass the check and then be evaluated as NaN.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat};
use rayon::prelude::*;
use stfit_core::Vec3;
use stfit_core::error::show;
use stfit_core::math::to_unit;
use stfit_fit::pairs::direction_problem;

use crate::numbers::{nested_bool, refuse_masked};

/// Rows per parallel task (and per random-number stream of the samplers): batches shorter
/// than this run on the calling thread.
pub const ROWS_PER_TASK: usize = 4096;

/// A batch of directions borrowed from a NumPy array.
pub struct Dirs<'py> {
    array: PyReadonlyArrayDyn<'py, f64>,
    /// The shape without its last axis (empty for a single direction).
    pub shape: Vec<usize>,
}

impl<'py> Dirs<'py> {
    /// The batch in `obj`, named `name` in errors: an array of an integer or float dtype
    /// (booleans, complex numbers, text and objects are refused, not converted: a plain
    /// conversion drops an imaginary part and parses text; so is a bool in nested lists, which
    /// NumPy would make 1 or 0 among numbers, and a masked array with a masked element,
    /// [`refuse_masked`]).
    pub fn new(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Self> {
        let py = obj.py();
        refuse_masked(name, obj)?;
        let np = py.import("numpy")?;
        let not_numbers =
            |e: PyErr| PyValueError::new_err(format!("{name}: not an array of numbers: {e}"));
        let array = np.call_method1("asarray", (obj,)).map_err(not_numbers)?;
        let dtype = array.getattr("dtype")?;
        let kind: String = dtype.getattr("kind")?.extract()?;
        if !matches!(kind.as_str(), "i" | "u" | "f") {
            return Err(PyValueError::new_err(format!(
                "{name}: not an array of numbers (an integer or float dtype), got dtype {dtype}"
            )));
        }
        // Bools among numbers in lists, which NumPy made numbers.
        if let Some((index, shown)) = nested_bool(obj)? {
            return Err(PyValueError::new_err(format!(
                "{name}: the element at index {index:?} is a bool ({shown}), not a number"
            )));
        }
        // The shape before the conversion, which makes a 0-d array 1-d.
        let full: Vec<usize> = array.getattr("shape")?.extract()?;
        if full.last() != Some(&3) {
            return Err(PyValueError::new_err(format!(
                "{name}: expected directions of shape (..., 3), got shape {full:?}"
            )));
        }
        let kwargs = PyDict::new(py);
        kwargs.set_item("dtype", np.getattr("float64")?)?;
        let converted = np
            .getattr("ascontiguousarray")?
            .call((array,), Some(&kwargs))
            .map_err(not_numbers)?;
        let array: PyReadonlyArrayDyn<'py, f64> = converted.extract()?;
        let shape = full[..full.len() - 1].to_vec();
        Ok(Self { array, shape })
    }

    /// The coordinates, three per direction.
    pub fn flat(&self) -> PyResult<&[f64]> {
        Ok(self.array.as_slice()?)
    }

    /// The number of directions.
    pub fn len(&self) -> usize {
        self.shape.iter().product()
    }
}

/// Direction `k` of a flat coordinate slice.
#[inline]
pub fn dir(flat: &[f64], k: usize) -> Vec3 {
    Vec3::new(flat[3 * k], flat[3 * k + 1], flat[3 * k + 2])
}

/// True for a direction (three coordinates) that the library does not take
/// ([`direction_problem`]).
#[inline]
fn refused(c: &[f64]) -> bool {
    direction_problem(Vec3::new(c[0], c[1], c[2])).is_some()
}

/// The coordinates of `flat` copied and checked (in parallel, with the GIL released): what a
/// call computes on. `flat` borrows the caller's array, which another Python thread may
/// change while the GIL is released; the copy is what was checked, so a direction changed
/// during the call cannot pass the check and then be evaluated. The first direction that the
/// library does not take ([`direction_problem`]: not finite, not a unit vector, or a subnormal
/// `z`) is a `ValueError` naming `name` and the row. Each block of [`ROWS_PER_TASK`] rows is
/// checked as it is copied, while it is in cache.
pub fn checked_copy(flat: &[f64], name: &str) -> PyResult<Vec<f64>> {
    let block = 3 * ROWS_PER_TASK;
    let mut copy = vec![0.0; flat.len()];
    let bad = copy
        .par_chunks_mut(block)
        .zip(flat.par_chunks(block))
        .enumerate()
        .filter_map(|(b, (to, from))| {
            to.copy_from_slice(from);
            let j = to.chunks_exact(3).position(refused);
            if j.is_none() {
                // Accepted within the unit tolerance: scaled to unit length.
                for c in to.chunks_exact_mut(3) {
                    let w = to_unit(Vec3::new(c[0], c[1], c[2]));
                    c.copy_from_slice(&[w.x, w.y, w.z]);
                }
            }
            let j = j?;
            Some(b * ROWS_PER_TASK + j)
        })
        .min();
    let Some(k) = bad else {
        return Ok(copy);
    };
    let w = dir(&copy, k);
    let problem = direction_problem(w).expect("the row was refused");
    Err(PyValueError::new_err(format!(
        "{name}[{k}] = [{}, {}, {}]: {problem}",
        show(w.x),
        show(w.y),
        show(w.z)
    )))
}

/// Two batches paired row by row: equal shapes, or one a single direction paired with every
/// row of the other. Returns the index maps and the result shape.
pub struct Pairing {
    pub shape: Vec<usize>,
    pub n: usize,
    a_single: bool,
    b_single: bool,
}

impl Pairing {
    pub fn new(a: &Dirs<'_>, b: &Dirs<'_>, names: (&str, &str)) -> PyResult<Self> {
        let (a_single, b_single) = (a.shape.is_empty(), b.shape.is_empty());
        let shape = if a.shape == b.shape || b_single {
            a.shape.clone()
        } else if a_single {
            b.shape.clone()
        } else {
            return Err(PyValueError::new_err(format!(
                "{} and {} must have the same shape, or one be a single direction: got {:?} and \
                 {:?} (each with a last axis of 3)",
                names.0, names.1, a.shape, b.shape
            )));
        };
        let n = shape.iter().product();
        Ok(Self {
            shape,
            n,
            a_single,
            b_single,
        })
    }

    /// The pair of row `k`.
    #[inline]
    pub fn pair(&self, a: &[f64], b: &[f64], k: usize) -> (Vec3, Vec3) {
        (
            dir(a, if self.a_single { 0 } else { k }),
            dir(b, if self.b_single { 0 } else { k }),
        )
    }
}

/// `f(k)` for every row `k < n`, in parallel for large batches.
pub fn map_rows(n: usize, f: impl Fn(usize) -> f64 + Send + Sync) -> Vec<f64> {
    (0..n)
        .into_par_iter()
        .with_min_len(ROWS_PER_TASK)
        .map(f)
        .collect()
}

/// Values with the given leading shape: a float for a single direction, else an array.
pub fn values<'py>(py: Python<'py>, v: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    if shape.is_empty() {
        return Ok(PyFloat::new(py, v[0]).into_any());
    }
    Ok(PyArray1::from_vec(py, v)
        .reshape(shape.to_vec())?
        .into_any())
}

/// Directions (three coordinates per row) with the given leading shape.
pub fn vectors<'py>(py: Python<'py>, v: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    let mut full = shape.to_vec();
    full.push(3);
    Ok(PyArray1::from_vec(py, v).reshape(full)?.into_any())
}

/// Booleans with the given leading shape.
pub fn flags<'py>(py: Python<'py>, v: Vec<bool>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    if shape.is_empty() {
        return Ok(pyo3::types::PyBool::new(py, v[0]).to_owned().into_any());
    }
    Ok(PyArray1::from_vec(py, v)
        .reshape(shape.to_vec())?
        .into_any())
}
