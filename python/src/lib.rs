//! `stfit._stfit`, the Python extension of stfit (imported as `stfit`): thin conversions between
//! NumPy arrays or Python values and the library crates (`stfit-core`, `stfit-fit`,
//! `stfit-report`, `stfit-tables`, `stfit-export`), which hold every formula and rule. Batches run with the GIL released, on
//! rayon's threads when they are large.

mod arrays;
mod bsdf;
mod data;
mod errors;
mod export;
mod fit;
mod ints;
mod long_run;
mod ndf;
mod numbers;
mod tables;
mod walk;

use pyo3::prelude::*;

#[pymodule]
fn _stfit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("LoadError", m.py().get_type::<errors::LoadError>())?;
    m.add("FitError", m.py().get_type::<errors::FitError>())?;
    m.add("ExportError", m.py().get_type::<errors::ExportError>())?;
    m.add(
        "LongRunWarning",
        m.py().get_type::<long_run::LongRunWarning>(),
    )?;
    m.add_class::<ndf::PyStudentT>()?;
    m.add_class::<ndf::PyGgx>()?;
    m.add_class::<ndf::PyBeckmann>()?;
    m.add_class::<bsdf::PyRoughDielectric>()?;
    m.add_class::<bsdf::BsdfSamples>()?;
    m.add_class::<walk::PyMicrosurface>()?;
    m.add_class::<walk::Albedo>()?;
    m.add_class::<data::PyDataset>()?;
    m.add_class::<fit::PyFitResult>()?;
    m.add_function(wrap_pyfunction!(data::load, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(fit::table, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fits_json, m)?)?;
    m.add_function(wrap_pyfunction!(fit::read_fits, m)?)?;
    m.add_function(wrap_pyfunction!(fit::synth, m)?)?;
    m.add_function(wrap_pyfunction!(fit::report, m)?)?;
    m.add_function(wrap_pyfunction!(export::export, m)?)?;
    m.add_class::<tables::PyTable>()?;
    m.add_function(wrap_pyfunction!(tables::tables, m)?)?;
    m.add_function(wrap_pyfunction!(tables::table_spec, m)?)?;
    m.add_function(wrap_pyfunction!(tables::table_shard, m)?)?;
    m.add_function(wrap_pyfunction!(tables::merge_table_shards, m)?)?;
    Ok(())
}
