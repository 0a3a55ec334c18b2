//! `stfit.tables`, `stfit.table_spec`, `stfit.table_shard` and `stfit.merge_table_shards`:
//! directional-albedo tables of `stfit-tables` with the options of `stfit tables`
//! (`stfit_tables::options`, the same rules and bytes), computed whole or as shards (one task
//! each, on one machine or a cluster) and merged into the table `stfit tables` writes.

use std::path::{Path, PathBuf};

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use stfit_tables::compute::compute;
use stfit_tables::format::{Format, c_header, csv, npy, shard};
use stfit_tables::grid::Axis;
use stfit_tables::options::{Choice, Naming, Output, Plan, TableOptions, write_file};
use stfit_tables::single::Quadrature;
use stfit_tables::{Shard, SpecError, Table, TableSpec};

use crate::errors::{arg_error, os_error, value_error};
use crate::ints;
use crate::long_run;
use crate::numbers::{floats, opt_float};

/// An axis option: the text of `--alpha-grid` and the like (`START:END:COUNT`,
/// `MAP:START:END:COUNT`, `v1,v2,...`) or a sequence of listed values.
fn axis(name: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Axis>> {
    let Some(value) = value else {
        return Ok(None);
    };
    if let Ok(text) = value.extract::<String>() {
        return text.parse().map(Some).map_err(|e| arg_error(name, e));
    }
    let values = floats(name, value)?.ok_or_else(|| {
        PyTypeError::new_err(format!(
            "{name}: expected an axis text such as '0.1:0.9:5' or a sequence of numbers"
        ))
    })?;
    Axis::listed(values)
        .map(Some)
        .map_err(|e| arg_error(name, e))
}

/// A named choice, as on the command line.
fn choice<T: Choice>(name: &str, value: Option<&str>) -> PyResult<Option<T>> {
    value
        .map(|v| T::parse(name, v))
        .transpose()
        .map_err(value_error)
}

/// The library's options of the keyword arguments (shared by `tables` and `table_spec`).
#[allow(clippy::too_many_arguments)]
fn options(
    ndf: &str,
    alpha_grid: Option<&Bound<'_, PyAny>>,
    gamma_grid: Option<&Bound<'_, PyAny>>,
    mu_grid: Option<&Bound<'_, PyAny>>,
    eta_grid: Option<&Bound<'_, PyAny>>,
    side: Option<&str>,
    surface: &str,
    n: Option<&Bound<'_, PyAny>>,
    k: Option<&Bound<'_, PyAny>>,
    orders: &str,
    masking: &str,
    layout: Option<&str>,
    walks: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
) -> PyResult<TableOptions> {
    Ok(TableOptions {
        ndf: Some(Choice::parse("ndf", ndf).map_err(value_error)?),
        alpha_grid: axis("alpha_grid", alpha_grid)?,
        gamma_grid: axis("gamma_grid", gamma_grid)?,
        mu_grid: axis("mu_grid", mu_grid)?,
        eta_grid: axis("eta_grid", eta_grid)?,
        side: choice("side", side)?,
        surface: Choice::parse("surface", surface).map_err(value_error)?,
        n: opt_float("n", n)?,
        k: opt_float("k", k)?,
        orders: Choice::parse("orders", orders).map_err(value_error)?,
        masking: Choice::parse("masking", masking).map_err(value_error)?,
        layout: choice("layout", layout)?,
        walks: walks.map(ints::walks).transpose()?,
        seed: seed.map(ints::seed).transpose()?,
    })
}

/// Options that cannot make a table raise `ValueError` (the computation's own failures too).
fn spec_error(e: SpecError) -> PyErr {
    value_error(e)
}

/// Computes the directional-albedo table the options describe, as `stfit tables` does with
/// the same options (the same defaults, checks and bytes), with the GIL released, on all
/// cores. Returns the `Table`, or with `shard` (`"K/N"`) the shard file's JSON text; writes
/// it to `out` when given (the format from `format` or the extension of `out`, as the
/// command line). Walks that reached the safety cap on scattering events are a warning.
#[pyfunction]
#[pyo3(signature = (ndf, *, alpha_grid = None, gamma_grid = None, mu_grid = None,
    eta_grid = None, side = None, surface = "dielectric", n = None, k = None,
    orders = "single", masking = "correlated", layout = None, format = None, shard = None,
    walks = None, seed = None, out = None))]
#[allow(clippy::too_many_arguments)]
pub fn tables(
    py: Python<'_>,
    ndf: &str,
    alpha_grid: Option<&Bound<'_, PyAny>>,
    gamma_grid: Option<&Bound<'_, PyAny>>,
    mu_grid: Option<&Bound<'_, PyAny>>,
    eta_grid: Option<&Bound<'_, PyAny>>,
    side: Option<&str>,
    surface: &str,
    n: Option<&Bound<'_, PyAny>>,
    k: Option<&Bound<'_, PyAny>>,
    orders: &str,
    masking: &str,
    layout: Option<&str>,
    format: Option<&str>,
    shard: Option<&str>,
    walks: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    out: Option<PathBuf>,
) -> PyResult<Py<PyAny>> {
    let options = options(
        ndf, alpha_grid, gamma_grid, mu_grid, eta_grid, side, surface, n, k, orders, masking,
        layout, walks, seed,
    )?;
    let format: Option<Format> = choice("format", format)?;
    let part: Option<Shard> = shard
        .map(|s| s.parse().map_err(|e| arg_error("shard", e)))
        .transpose()?;
    let plan =
        Plan::new(&options, format, part, out.as_deref(), Naming::Keywords).map_err(spec_error)?;
    let is_shard = matches!(plan.output, Output::Shard(_));
    let seconds = py.detach(|| plan.walk_seconds()).map_err(spec_error)?;
    warn_if_long_table(py, seconds, &plan.spec)?;
    let (run, bytes) = py
        .detach(|| {
            let run = plan.run(&|_| {})?;
            let bytes = if out.is_some() || is_shard {
                Some(run.bytes()?)
            } else {
                None
            };
            Ok::<_, SpecError>((run, bytes))
        })
        .map_err(spec_error)?;
    if let Some(warning) = run.truncation_warning() {
        py.import("warnings")?.call_method1("warn", (warning,))?;
    }
    if let (Some(path), Some(bytes)) = (out.as_deref(), &bytes) {
        write_file(path, bytes).map_err(os_error)?;
    }
    if is_shard {
        let text = String::from_utf8(bytes.unwrap_or_default()).map_err(value_error)?;
        return Ok(text.into_pyobject(py)?.into_any().unbind());
    }
    Ok(Py::new(py, PyTable(run.table()))?.into_any())
}

/// The JSON text of the table specification the options describe (the options of
/// `stfit.tables` without `format`, `shard` and `out`), which `table_shard` takes: one task of
/// a cluster computes one shard of it.
#[pyfunction]
#[pyo3(signature = (ndf, *, alpha_grid = None, gamma_grid = None, mu_grid = None,
    eta_grid = None, side = None, surface = "dielectric", n = None, k = None,
    orders = "single", masking = "correlated", layout = None, walks = None, seed = None))]
#[allow(clippy::too_many_arguments)]
pub fn table_spec(
    ndf: &str,
    alpha_grid: Option<&Bound<'_, PyAny>>,
    gamma_grid: Option<&Bound<'_, PyAny>>,
    mu_grid: Option<&Bound<'_, PyAny>>,
    eta_grid: Option<&Bound<'_, PyAny>>,
    side: Option<&str>,
    surface: &str,
    n: Option<&Bound<'_, PyAny>>,
    k: Option<&Bound<'_, PyAny>>,
    orders: &str,
    masking: &str,
    layout: Option<&str>,
    walks: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let spec = options(
        ndf, alpha_grid, gamma_grid, mu_grid, eta_grid, side, surface, n, k, orders, masking,
        layout, walks, seed,
    )?
    .spec(Naming::Keywords)
    .map_err(spec_error)?;
    serde_json::to_string(&spec).map_err(value_error)
}

/// Computes shard `index` of `count` (1 <= index <= count) of the table `spec`, given as the JSON
/// text of a table specification (the `spec` of a shard file, `tables-format.md`), with the GIL
/// released, and returns the shard file's JSON text (what `stfit tables --shard K/N` writes).
#[pyfunction]
#[pyo3(signature = (spec, index = 1, count = 1))]
pub fn table_shard(
    py: Python<'_>,
    spec: &str,
    #[pyo3(from_py_with = ints::shard_index)] index: u64,
    #[pyo3(from_py_with = ints::shard_count)] count: u64,
) -> PyResult<String> {
    let spec: TableSpec = serde_json::from_str(spec).map_err(|e| arg_error("spec", e))?;
    let part: Shard = format!("{index}/{count}")
        .parse()
        .map_err(|e| arg_error("index/count", e))?;
    let seconds = py
        .detach(|| stfit_tables::compute::walk_seconds(&spec, part))
        .map_err(value_error)?;
    warn_if_long_table(py, seconds, &spec)?;
    py.detach(|| {
        let lines = compute(&spec, part, &Quadrature::default(), &|_| {}).map_err(value_error)?;
        shard::write(&spec, part, &lines).map_err(value_error)
    })
}

/// Warns before the walks of a table (or shard) of `spec` estimated at `seconds`, when long.
fn warn_if_long_table(py: Python<'_>, seconds: f64, spec: &TableSpec) -> PyResult<()> {
    long_run::warn_if_long(
        py,
        seconds,
        &spec.walks_description(),
        "fewer walks or fewer nodes make it shorter",
    )
}

/// Merges shard files' texts (every shard 1..N of one specification exactly once, as
/// `stfit tables merge` does) into a `Table`.
#[pyfunction]
pub fn merge_table_shards(shards: Vec<String>) -> PyResult<PyTable> {
    let named: Vec<(String, String)> = shards
        .into_iter()
        .enumerate()
        .map(|(k, text)| (format!("shard text {}", k + 1), text))
        .collect();
    shard::merge(&named).map(PyTable).map_err(value_error)
}

/// A whole directional-albedo table, in the formats of `stfit tables --format`.
#[pyclass(name = "Table", module = "stfit", frozen)]
pub struct PyTable(Table);

#[pymethods]
impl PyTable {
    /// The table's specification as JSON text.
    fn spec(&self) -> PyResult<String> {
        serde_json::to_string(&self.0.spec).map_err(value_error)
    }

    /// The `.npy` bytes (`numpy.load(io.BytesIO(t.npy()))` gives the structured array).
    fn npy<'py>(&self, py: Python<'py>) -> Bound<'py, pyo3::types::PyBytes> {
        pyo3::types::PyBytes::new(py, &npy::write(&self.0))
    }

    /// The CSV text.
    fn csv(&self) -> String {
        csv::write(&self.0)
    }

    /// The C header text (Cycles' layout).
    fn c_header(&self) -> String {
        c_header::write(&self.0)
    }

    /// Writes the table to `out` as `stfit tables merge --out OUT` does: in `format` (`csv`,
    /// `npy` or `c`), by default from the extension of `out`.
    #[pyo3(signature = (out, format = None))]
    fn write(&self, out: PathBuf, format: Option<&str>) -> PyResult<()> {
        let format: Option<Format> = choice("format", format)?;
        let format = format.unwrap_or_else(|| Format::from_path(&out));
        write_file(Path::new(&out), &format.write(&self.0)).map_err(os_error)
    }
}
