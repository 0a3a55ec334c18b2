//! `stfit.load` and `stfit.Dataset`: measurements read by `stfit-fit`'s loader from files and
//! folders, or from in-memory columns (a mapping of arrays or a pandas DataFrame) named as a
//! file's header and validated by the same rules.

use std::path::{Path, PathBuf};

use numpy::PyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList, PySlice, PyString, PyTuple};
use stfit_fit::data::Angles;
use stfit_fit::data::{Measurement, Sample};
use stfit_fit::load::{
    COL_BSDF, COL_L, COL_PHI_I, COL_PHI_O, COL_SQRT_L, COL_THETA_I, COL_THETA_O, COL_WEIGHT,
};
use stfit_fit::{Column, Dataset, load_columns, load_paths};

use crate::errors::{column_error, load_error, value_error};
use crate::numbers::first_masked;

/// Measurements: one or more named samples, each a list of points with the angles their
/// source gave, the measured value (`L` or the BSDF) and a weight.
#[pyclass(name = "Dataset", module = "stfit", frozen)]
#[derive(Clone)]
pub struct PyDataset(pub Dataset);

/// The name the file's `sample` column holds; everything else numeric unless it is not.
const SAMPLE: &str = stfit_fit::load::COL_SAMPLE;

/// A path-like object as a path, if it is one.
fn as_path(obj: &Bound<'_, PyAny>) -> Option<PathBuf> {
    if obj.is_instance_of::<PyString>() || obj.hasattr("__fspath__").unwrap_or(false) {
        obj.extract::<PathBuf>().ok()
    } else {
        None
    }
}

/// The columns a file's rows give as numbers (`data-format.md`): angles, values and weights.
const NUMBERS: [&str; 8] = [
    COL_THETA_I,
    COL_PHI_I,
    COL_THETA_O,
    COL_PHI_O,
    COL_L,
    COL_SQRT_L,
    COL_BSDF,
    COL_WEIGHT,
];

/// One in-memory column `name` of `source` (`<arrays>` or `<DataFrame>`), which must be 1-D
/// (one value per row): a column of [`NUMBERS`] as `float64` from integers or floats only (not
/// booleans, complex numbers or text, which a plain conversion would turn into numbers), the
/// `sample` column and any other as text, a missing sample name (None, NaN, pandas' NA) as
/// an empty one, which the loader refuses at its row. Values that do not convert to `float64`
/// go to the loader as text, which reports the first at its row.
fn column(source: &str, name: &str, values: &Bound<'_, PyAny>) -> PyResult<Column> {
    let py = values.py();
    if let Some(index) = first_masked(values)? {
        // The row when the column is 1-D; a masked element of another shape at the column.
        let row = (index.len() == 1).then(|| index[0]);
        return Err(column_error(
            py,
            source,
            row,
            Some(name),
            format!(
                "masked (element {index:?} of a masked array): fill the masked values \
                 (numpy.ma.filled) or drop their rows first; the values under the mask are \
                 not used"
            ),
        ));
    }
    let np = py.import("numpy")?;
    let array = np
        .call_method1("asarray", (values,))
        .map_err(|e| column_error(py, source, None, Some(name), e))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 1 {
        return Err(column_error(
            py,
            source,
            None,
            Some(name),
            format!("expected one value per row (a 1-D column), got shape {shape:?}"),
        ));
    }
    if !NUMBERS.contains(&name) {
        // The values themselves: NumPy turns a NaN among text into the text 'nan'.
        return Ok(Column::Text(texts(values, name == SAMPLE)?));
    }
    check_numeric(source, name, values, &array)?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", np.getattr("float64")?)?;
    match np.getattr("asarray")?.call((values,), Some(&kwargs)) {
        Ok(a) => Ok(Column::Numbers(a.extract::<Vec<f64>>()?)),
        Err(_) => Ok(Column::Text(texts(&array, false)?)),
    }
}

/// Refuses a numeric column (`array`, from `values`) whose dtype is not integer, float or
/// object, or that holds a boolean, complex number or text: its row when an element shows it.
fn check_numeric(
    source: &str,
    name: &str,
    values: &Bound<'_, PyAny>,
    array: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let py = values.py();
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "i" | "u" | "f" | "O") {
        return Err(column_error(
            py,
            source,
            None,
            Some(name),
            format!("expected numbers (an integer or float dtype), got dtype {dtype}"),
        ));
    }
    // A list mixing booleans with numbers converts to floats: its elements show them.
    let items = if kind == "O" {
        array.clone()
    } else if values.is_instance_of::<PyList>() || values.is_instance_of::<PyTuple>() {
        values.clone()
    } else {
        return Ok(());
    };
    let np = py.import("numpy")?;
    let builtins = py.import("builtins")?;
    let not_numbers = PyTuple::new(
        py,
        [
            builtins.getattr("str")?,
            builtins.getattr("bytes")?,
            builtins.getattr("bool")?,
            np.getattr("bool_")?,
            builtins.getattr("complex")?,
            np.getattr("complexfloating")?,
        ],
    )?;
    for (k, v) in items.try_iter()?.enumerate() {
        let v = v?;
        if v.is_instance(&not_numbers)? {
            return Err(column_error(
                py,
                source,
                Some(k),
                Some(name),
                format!(
                    "{} is a {}, not a number (give integers or floats)",
                    v.repr()?,
                    v.get_type().name()?
                ),
            ));
        }
    }
    Ok(())
}

/// The elements of a 1-D column as text; with `names`, a missing one (None, NaN, pandas' NA
/// or NaT) as the empty text.
fn texts(values: &Bound<'_, PyAny>, names: bool) -> PyResult<Vec<String>> {
    values
        .try_iter()?
        .map(|v| {
            let v = v?;
            if names && missing(&v)? {
                Ok(String::new())
            } else {
                Ok(v.str()?.to_string())
            }
        })
        .collect()
}

/// Whether a value is missing: None, a NaN, or what pandas (when loaded) calls missing.
fn missing(v: &Bound<'_, PyAny>) -> PyResult<bool> {
    if v.is_none() {
        return Ok(true);
    }
    if v.is_instance_of::<PyString>() {
        return Ok(false);
    }
    if v.extract::<f64>().is_ok_and(f64::is_nan) {
        return Ok(true);
    }
    let modules = v.py().import("sys")?.getattr("modules")?;
    match modules.get_item("pandas") {
        Ok(pandas) => Ok(pandas
            .call_method1("isna", (v,))?
            .extract::<bool>()
            .unwrap_or(false)),
        Err(_) => Ok(false),
    }
}

/// A column's key and its values, as a mapping or a DataFrame holds them.
type Keyed<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>);

/// The columns of a pandas DataFrame (by position, so that a repeated name reaches the
/// loader, which refuses it) or of a mapping of column names to arrays, with the source's
/// label (`<DataFrame>`, `<arrays>`).
fn keyed_columns<'py>(source: &Bound<'py, PyAny>) -> PyResult<(Vec<Keyed<'py>>, &'static str)> {
    if source.hasattr("columns")? && source.hasattr("iloc")? {
        let iloc = source.getattr("iloc")?;
        let all = PySlice::full(source.py());
        let columns = source
            .getattr("columns")?
            .try_iter()?
            .enumerate()
            .map(|(i, c)| Ok((c?, iloc.get_item((&all, i))?)))
            .collect::<PyResult<_>>()?;
        return Ok((columns, "<DataFrame>"));
    }
    if source.hasattr("keys")? {
        let columns = source
            .call_method0("keys")?
            .try_iter()?
            .map(|c| {
                let c = c?;
                let values = source.get_item(&c)?;
                Ok((c, values))
            })
            .collect::<PyResult<_>>()?;
        return Ok((columns, "<arrays>"));
    }
    Err(PyTypeError::new_err(format!(
        "stfit.load takes a path, a list of paths, a mapping of column names to arrays or a \
         pandas DataFrame, got {}",
        source.get_type().name()?
    )))
}

/// A column's name: its key, which must be a string as a file's header is.
fn column_name(source: &str, key: &Bound<'_, PyAny>) -> PyResult<String> {
    key.extract().map_err(|_| {
        let what = match (key.repr(), key.get_type().name()) {
            (Ok(r), Ok(n)) => format!("{r} ({n})"),
            _ => "a key that is not a string".to_owned(),
        };
        column_error(
            key.py(),
            source,
            None,
            None,
            format!("column names must be strings, as in a file's header; got {what}"),
        )
    })
}

/// The dataset of `source`: a path, a list of paths, a mapping of columns or a DataFrame.
pub fn dataset_of(source: &Bound<'_, PyAny>) -> PyResult<Dataset> {
    if let Ok(d) = source.cast::<PyDataset>() {
        return Ok(d.get().0.clone());
    }
    let py = source.py();
    if let Some(path) = as_path(source) {
        return py
            .detach(|| load_paths(&[path]))
            .map_err(|e| load_error(py, &e));
    }
    if source.is_instance_of::<PyList>() || source.is_instance_of::<PyTuple>() {
        let paths = source
            .try_iter()?
            .map(|p| {
                as_path(&p?).ok_or_else(|| {
                    PyTypeError::new_err("a list given to stfit.load must hold paths")
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        if paths.is_empty() {
            return Err(value_error("stfit.load: no paths given"));
        }
        return py
            .detach(|| load_paths(&paths))
            .map_err(|e| load_error(py, &e));
    }
    let (keyed, label) = keyed_columns(source)?;
    let columns = keyed
        .iter()
        .map(|(key, values)| {
            let name = column_name(label, key)?;
            let values = column(label, &name, values)?;
            Ok((name, values))
        })
        .collect::<PyResult<Vec<_>>>()?;
    load_columns(Path::new(label), &columns).map_err(|e| load_error(py, &e))
}

/// Reads measurements: a measurement file or folder (CSV, in-plane or general, or pab-opto
/// files), a list of them, or in-memory columns named as a file's header (a mapping of names
/// to arrays, or a pandas DataFrame), validated by the same rules (and, for columns, string
/// names, 1-D columns, numbers of an integer or float dtype: see [`column`]). With `sample`,
/// keeps only the sample of that name.
#[pyfunction]
#[pyo3(signature = (source, *, sample = None))]
pub fn load(source: &Bound<'_, PyAny>, sample: Option<&str>) -> PyResult<PyDataset> {
    let py = source.py();
    let mut data = dataset_of(source)?;
    if let Some(name) = sample {
        let one = data.sample(name).map_err(|e| load_error(py, &e))?.clone();
        data.samples = vec![one];
    }
    Ok(PyDataset(data))
}

#[pymethods]
impl PyDataset {
    /// Where the data came from: the file, the paths joined by `, `, `<arrays>` or
    /// `<DataFrame>`.
    #[getter]
    fn source(&self) -> String {
        self.0.source.display().to_string()
    }

    /// The sample names, in order of first appearance (`""` for a file without a sample
    /// column).
    #[getter]
    fn samples(&self) -> Vec<String> {
        self.0.samples.iter().map(|s| s.name.clone()).collect()
    }

    /// The number of measured points of every sample together.
    #[getter]
    fn n_points(&self) -> usize {
        self.0.samples.iter().map(|s| s.points.len()).sum()
    }

    /// The dataset restricted to the sample `name` (a `stfit.LoadError` if it has none).
    fn sample(&self, py: Python<'_>, name: &str) -> PyResult<Self> {
        let one = self.0.sample(name).map_err(|e| load_error(py, &e))?.clone();
        Ok(Self(Dataset {
            source: self.0.source.clone(),
            samples: vec![one],
        }))
    }

    /// The points as columns named as a file's header, in sample order: `sample`,
    /// `theta_i_deg`, `theta_o_deg`, `L`, `weight` for in-plane data; `sample`,
    /// `theta_i_deg`, `phi_i_deg`, `theta_o_deg`, `phi_o_deg`, `bsdf`, `weight` for general
    /// data. `stfit.load(d.columns())` reads them back to the same dataset.
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let points = || {
            self.0
                .samples
                .iter()
                .flat_map(|s| s.points.iter().map(move |p| (s.name.as_str(), p)))
        };
        let in_plane = points().all(|(_, p)| matches!(p.angles, Angles::InPlane { .. }));
        let general = points().all(|(_, p)| matches!(p.angles, Angles::Spherical { .. }));
        if !in_plane && !general {
            return Err(value_error(
                "the dataset mixes in-plane and general points: no one header holds both",
            ));
        }
        let out = PyDict::new(py);
        let names: Vec<&str> = points().map(|(n, _)| n).collect();
        out.set_item(SAMPLE, names)?;
        let col = |f: &dyn Fn(&Angles) -> f64| -> Vec<f64> {
            points().map(|(_, p)| f(&p.angles)).collect()
        };
        let add = |name: &str, v: Vec<f64>| out.set_item(name, PyArray1::from_vec(py, v));
        if in_plane {
            add(
                "theta_i_deg",
                col(&|a| match *a {
                    Angles::InPlane { theta_i_deg, .. } => theta_i_deg,
                    Angles::Spherical { .. } => f64::NAN,
                }),
            )?;
            add(
                "theta_o_deg",
                col(&|a| match *a {
                    Angles::InPlane { theta_o_deg, .. } => theta_o_deg,
                    Angles::Spherical { .. } => f64::NAN,
                }),
            )?;
            add("L", points().map(|(_, p)| p.value).collect())?;
        } else {
            let sph = |a: &Angles| match *a {
                Angles::Spherical {
                    theta_i_deg,
                    phi_i_deg,
                    theta_o_deg,
                    phi_o_deg,
                } => [theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg],
                Angles::InPlane { .. } => [f64::NAN; 4],
            };
            for (i, name) in ["theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg"]
                .into_iter()
                .enumerate()
            {
                add(name, col(&|a| sph(a)[i]))?;
            }
            add("bsdf", points().map(|(_, p)| p.value).collect())?;
        }
        add("weight", points().map(|(_, p)| p.weight).collect())?;
        Ok(out)
    }

    fn __len__(&self) -> usize {
        self.0.samples.len()
    }

    /// Equal when the source and every sample's name and points (angles, value, weight) are.
    fn __eq__(&self, other: &Bound<'_, Self>) -> bool {
        self.0 == other.get().0
    }

    /// Unhashable: datasets compare by their (possibly many) points.
    #[classattr]
    const __hash__: Option<Py<PyAny>> = None;

    /// A dataset from the state `__reduce__` gives: the source and, per sample, its name, one
    /// byte per point (0 in-plane, 1 general) and the points' numbers as little-endian
    /// `float64` bytes (theta_i, theta_o, value, weight in-plane; theta_i, phi_i, theta_o,
    /// phi_o, value, weight general).
    #[staticmethod]
    fn _from_state<'py>(
        source: PathBuf,
        samples: Vec<(String, Bound<'py, PyBytes>, Bound<'py, PyBytes>)>,
    ) -> PyResult<Self> {
        let bad = || value_error("Dataset._from_state: not a state of Dataset.__reduce__");
        let samples = samples
            .into_iter()
            .map(|(name, kinds, bytes)| {
                let (kinds, bytes) = (kinds.as_bytes(), bytes.as_bytes());
                if bytes.len() % 8 != 0 {
                    return Err(bad());
                }
                let numbers: Vec<f64> = bytes
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                    .collect();
                let mut rest = numbers.as_slice();
                let mut points = Vec::with_capacity(kinds.len());
                for &kind in kinds {
                    let n = match kind {
                        0 => 4,
                        1 => 6,
                        _ => return Err(bad()),
                    };
                    if rest.len() < n {
                        return Err(bad());
                    }
                    let (p, r) = rest.split_at(n);
                    rest = r;
                    points.push(match *p {
                        [ti, to, v, w] => Measurement::in_plane(ti, to, v, w),
                        [ti, pi, to, po, v, w] => Measurement::spherical((ti, pi), (to, po), v, w),
                        _ => unreachable!("4 or 6 numbers"),
                    });
                }
                if !rest.is_empty() {
                    return Err(bad());
                }
                Ok(Sample { name, points })
            })
            .collect::<PyResult<_>>()?;
        Ok(Self(Dataset { source, samples }))
    }

    /// Pickles as its points, every number exactly ([`PyDataset::_from_state`]).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let py = slf.py();
        let d = &slf.get().0;
        let samples = d
            .samples
            .iter()
            .map(|s| {
                let mut kinds = Vec::with_capacity(s.points.len());
                let mut bytes = Vec::new();
                for p in &s.points {
                    let numbers: Vec<f64> = match p.angles {
                        Angles::InPlane {
                            theta_i_deg,
                            theta_o_deg,
                        } => {
                            kinds.push(0u8);
                            vec![theta_i_deg, theta_o_deg]
                        }
                        Angles::Spherical {
                            theta_i_deg,
                            phi_i_deg,
                            theta_o_deg,
                            phi_o_deg,
                        } => {
                            kinds.push(1u8);
                            vec![theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg]
                        }
                    };
                    for x in numbers.into_iter().chain([p.value, p.weight]) {
                        bytes.extend_from_slice(&x.to_le_bytes());
                    }
                }
                (
                    s.name.clone(),
                    PyBytes::new(py, &kinds),
                    PyBytes::new(py, &bytes),
                )
            })
            .collect::<Vec<_>>();
        let state = (d.source.clone(), samples).into_pyobject(py)?.into_any();
        Ok((slf.get_type().getattr("_from_state")?, state))
    }

    fn __repr__(&self) -> String {
        format!(
            "stfit.Dataset(source='{}', samples={:?}, n_points={})",
            self.source(),
            self.samples(),
            self.n_points()
        )
    }
}
