//! `stfit.load` and `stfit.Dataset`: measurements read by `stfit-fit`'s loader from files and
//! folders, or from in-memory columns (a mapping of arrays or a pandas DataFrame) named as a
//! file's header and validated by the same rules.

use std::path::{Path, PathBuf};

use numpy::PyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};
use stfit_fit::data::Angles;
use stfit_fit::{Column, Dataset, load_columns, load_paths};

use crate::errors::{load_error, value_error};

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

/// One in-memory column: numbers where they convert to `float64`, else text.
fn column(name: &str, values: &Bound<'_, PyAny>) -> PyResult<Column> {
    let py = values.py();
    let text = || -> PyResult<Column> {
        let items: Vec<String> = values
            .try_iter()?
            .map(|v| v?.str().map(|s| s.to_string()))
            .collect::<PyResult<_>>()?;
        Ok(Column::Text(items))
    };
    if name == SAMPLE {
        return text();
    }
    let np = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", np.getattr("float64")?)?;
    match np.getattr("asarray")?.call((values,), Some(&kwargs)) {
        Ok(a) => {
            let a = np.getattr("ravel")?.call1((a,))?;
            Ok(Column::Numbers(a.extract::<Vec<f64>>()?))
        }
        Err(_) => text(),
    }
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
    // A pandas DataFrame (its `columns`) or any mapping of column names to arrays.
    let (names, label): (Vec<String>, &str) = if source.hasattr("columns")?
        && source.hasattr("iloc")?
    {
        (
            source
                .getattr("columns")?
                .try_iter()?
                .map(|c| c?.str().map(|s| s.to_string()))
                .collect::<PyResult<_>>()?,
            "<DataFrame>",
        )
    } else if source.hasattr("keys")? {
        (
            source
                .call_method0("keys")?
                .try_iter()?
                .map(|c| c?.extract::<String>())
                .collect::<PyResult<_>>()?,
            "<arrays>",
        )
    } else {
        return Err(PyTypeError::new_err(format!(
            "stfit.load takes a path, a list of paths, a mapping of column names to arrays or a \
             pandas DataFrame, got {}",
            source.get_type().name()?
        )));
    };
    let columns = names
        .iter()
        .map(|n| Ok((n.clone(), column(n, &source.get_item(n)?)?)))
        .collect::<PyResult<Vec<_>>>()?;
    load_columns(Path::new(label), &columns).map_err(|e| load_error(py, &e))
}

/// Reads measurements: a measurement file or folder (CSV, in-plane or general, or pab-opto
/// files), a list of them, or in-memory columns named as a file's header (a mapping of names
/// to arrays, or a pandas DataFrame), validated by the same rules. With `sample`, keeps only
/// the sample of that name.
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

    fn __repr__(&self) -> String {
        format!(
            "stfit.Dataset(source='{}', samples={:?}, n_points={})",
            self.source(),
            self.samples(),
            self.n_points()
        )
    }
}
