//! `stfit.table_shard` and `stfit.merge_table_shards`: directional-albedo tables of
//! `stfit-tables` computed as shards (one task each, on one machine or a cluster) and merged
//! into the table `stfit tables` writes, in its formats.

use pyo3::prelude::*;
use stfit_tables::compute::compute;
use stfit_tables::format::{c_header, csv, npy, shard};
use stfit_tables::single::Quadrature;
use stfit_tables::{Shard, Table, TableSpec};

use crate::errors::{arg_error, value_error};

/// Computes shard `index` of `count` (1 <= index <= count) of the table `spec`, given as the JSON
/// text of a table specification (the `spec` of a shard file, `tables-format.md`), with the GIL
/// released, and returns the shard file's JSON text (what `stfit tables --shard K/N` writes).
#[pyfunction]
#[pyo3(signature = (spec, index = 1, count = 1))]
pub fn table_shard(py: Python<'_>, spec: &str, index: usize, count: usize) -> PyResult<String> {
    let spec: TableSpec = serde_json::from_str(spec).map_err(|e| arg_error("spec", e))?;
    let part: Shard = format!("{index}/{count}")
        .parse()
        .map_err(|e| arg_error("index/count", e))?;
    py.detach(|| {
        let lines = compute(&spec, part, &Quadrature::default(), &|_| {}).map_err(value_error)?;
        shard::write(&spec, part, &lines).map_err(value_error)
    })
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
}
