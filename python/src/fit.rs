//! `stfit.fit`, `stfit.FitResult`, `stfit.synth`, `stfit.report` and the fits file: the fits,
//! synthetic data and figures of `stfit-fit` and `stfit-report`, with the options and defaults
//! of the command line.

use std::path::PathBuf;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyString;
use stfit_core::ScatteringOrders;
use stfit_core::error::show;
use stfit_fit::conventions::{THETA_I_RANGE, THETA_O_RANGE, theta_i_in_range, theta_o_in_range};
use stfit_fit::options::check_fit_walks;
use stfit_fit::synth::{SynthSpec, parse_angle_list, write_file};
use stfit_fit::{
    DEFAULT_ETA, DEFAULT_LOG_FLOOR, DEFAULT_WALKS, Dataset, FitOptions, FitResult, FitsFile, Gamma,
    Grid, Loss, Model, ModelKind, ModelSpec, MultipleTerm, Optimizer, Parameter, SynthError,
    all_models, fit_dataset, fit_walk_cost,
};
use stfit_report::{ReportError, ReportOptions, YScale, fits_table, render_report};

use crate::bsdf::masking;
use crate::data::{PyDataset, dataset_of};
use crate::errors::{arg_error, fit_error, os_error, value_error};
use crate::ints;
use crate::long_run;
use crate::numbers::{self, float, float_repr, floats, opt_float};
use crate::walk::orders;

/// A parameter given as a number or `"free"` (not a bool: `scale=True`, meant as "fit it",
/// would hold it at 1).
fn parameter(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Parameter> {
    if numbers::is_bool(value)? {
        return Err(arg_error(
            name,
            format!("expected a number or 'free', got a bool ({value})"),
        ));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return match s.to_str()? {
            "free" => Ok(Parameter::Free),
            other => Err(arg_error(
                name,
                format!("expected a number or 'free', got '{other}'"),
            )),
        };
    }
    numbers::refuse_masked(name, value)?;
    value
        .extract::<f64>()
        .map(Parameter::Fixed)
        .map_err(|_| arg_error(name, "expected a number or 'free'"))
}

/// The `ValueError` of a walk option (`walks`, `seed`, ...) given where nothing walks.
fn walks_only(name: &str) -> PyErr {
    arg_error(
        name,
        "applies to orders='all' only (single scattering is analytic)",
    )
}

/// The fit options of the keyword arguments, checked together (`FitOptions::check`): `eta`
/// defaults to [`DEFAULT_ETA`] held, `scale` to free, as on the command line, and the walks of
/// an all-orders fit are checked as `--walks` is ([`check_fit_walks`]), named `walks`. As on
/// the command line, an option given where it does not apply is refused rather than ignored:
/// `walks`, `seed` and `multiple_term` apply to orders 'all' only, `log_floor` to loss 'log'.
#[allow(clippy::too_many_arguments)]
fn fit_options(
    eta: Option<&Bound<'_, PyAny>>,
    scale: Option<&Bound<'_, PyAny>>,
    loss: &str,
    log_floor: Option<f64>,
    optimizer: &str,
    masking_name: Option<&str>,
    orders_name: &str,
    walks: Option<u64>,
    seed: Option<u64>,
    multiple_term: Option<&str>,
) -> PyResult<FitOptions> {
    let orders = orders(orders_name)?;
    let loss = match loss {
        "sqrt" => Loss::Sqrt,
        "linear" => Loss::Linear,
        "log" => Loss::Log,
        other => {
            return Err(arg_error(
                "loss",
                format!("unknown loss '{other}' (expected sqrt, linear or log)"),
            ));
        }
    };
    if orders != ScatteringOrders::All {
        for (name, given) in [
            ("walks", walks.is_some()),
            ("seed", seed.is_some()),
            ("multiple_term", multiple_term.is_some()),
        ] {
            if given {
                return Err(walks_only(name));
            }
        }
    }
    if log_floor.is_some() && loss != Loss::Log {
        return Err(arg_error("log_floor", "applies to loss='log' only"));
    }
    let walks = walks.unwrap_or(DEFAULT_WALKS);
    if orders == ScatteringOrders::All {
        check_fit_walks(walks).map_err(|e| arg_error("walks", e))?;
    }
    let masking = orders
        .masking(masking_name.map(masking).transpose()?)
        .map_err(|e| arg_error("masking", e))?;
    let opts = FitOptions {
        eta: eta.map_or(Ok(Parameter::Fixed(DEFAULT_ETA)), |v| parameter("eta", v))?,
        scale: scale.map_or(Ok(Parameter::Free), |v| parameter("scale", v))?,
        loss,
        log_floor: log_floor.unwrap_or(DEFAULT_LOG_FLOOR),
        optimizer: match optimizer {
            "nelder-mead" => Optimizer::NelderMead,
            "lbfgs" => Optimizer::Lbfgs,
            other => {
                return Err(arg_error(
                    "optimizer",
                    format!("unknown optimizer '{other}' (expected nelder-mead or lbfgs)"),
                ));
            }
        },
        masking,
        orders,
        walks,
        seed: seed.unwrap_or(1),
        multiple_term: match multiple_term.unwrap_or("surrogate") {
            "surrogate" => MultipleTerm::Surrogate,
            "exact" => MultipleTerm::Exact,
            other => {
                return Err(arg_error(
                    "multiple_term",
                    format!("unknown multiple term '{other}' (expected surrogate or exact)"),
                ));
            }
        },
    };
    opts.check().map_err(value_error)?;
    Ok(opts)
}

/// The models of `model` (`beckmann`, `ggx`, `student-t` or `all`) with `gamma` held.
fn specs(model: &str, gamma: Option<f64>) -> PyResult<Vec<ModelSpec>> {
    if model == "all" {
        if gamma.is_some() {
            return Err(arg_error(
                "gamma",
                "fixes the Student-T shape; it needs model='student-t'",
            ));
        }
        return Ok(all_models().to_vec());
    }
    let kind: ModelKind = model.parse().map_err(|e| arg_error("model", e))?;
    if let Some(g) = gamma {
        stfit_core::error::check_gamma(g).map_err(|e| arg_error("gamma", e))?;
    }
    Ok(vec![
        ModelSpec::new(kind, gamma).map_err(|e| arg_error("gamma", e))?,
    ])
}

/// Warns ([`long_run::warn_if_long`]) before the all-orders fits of `specs` to `data` whose
/// walks will take long ([`fit_walk_cost`]); nothing for single scattering.
fn warn_if_fit_walks_long(
    py: Python<'_>,
    data: &Dataset,
    specs: &[ModelSpec],
    opts: &FitOptions,
) -> PyResult<()> {
    if opts.orders == ScatteringOrders::Single {
        return Ok(());
    }
    let cost = py.detach(|| fit_walk_cost(data, specs, opts));
    long_run::warn_if_long(py, cost.seconds, &cost.what(), long_run::FEWER_WALKS)
}

/// Fits models to every sample of `data` (a `Dataset`, or anything `stfit.load` reads), with the
/// options and defaults of the command line (`stfit DATA`), and returns one `FitResult` per
/// sample and model, in sample order then model order.
#[pyfunction]
#[pyo3(signature = (data, *, model = "student-t", gamma = None, sample = None, eta = None,
    scale = None, loss = "sqrt", log_floor = None, optimizer = "nelder-mead",
    masking = None, orders = "single", walks = None, seed = None, multiple_term = None))]
#[allow(clippy::too_many_arguments)]
pub fn fit(
    py: Python<'_>,
    data: &Bound<'_, PyAny>,
    model: &str,
    gamma: Option<&Bound<'_, PyAny>>,
    sample: Option<&str>,
    eta: Option<&Bound<'_, PyAny>>,
    scale: Option<&Bound<'_, PyAny>>,
    loss: &str,
    log_floor: Option<&Bound<'_, PyAny>>,
    optimizer: &str,
    masking: Option<&str>,
    orders: &str,
    walks: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    multiple_term: Option<&str>,
) -> PyResult<Vec<PyFitResult>> {
    let specs = specs(model, opt_float("gamma", gamma)?)?;
    let opts = fit_options(
        eta,
        scale,
        loss,
        opt_float("log_floor", log_floor)?,
        optimizer,
        masking,
        orders,
        walks.map(ints::walks).transpose()?,
        seed.map(ints::seed).transpose()?,
        multiple_term,
    )?;
    let data = crate::data::load(data, sample)?.0;
    warn_if_fit_walks_long(py, &data, &specs, &opts)?;
    let fits = py
        .detach(|| fit_dataset(&data, &specs, &opts, &|_, _| {}))
        .map_err(|e| fit_error(py, &e))?;
    Ok(fits.into_iter().map(PyFitResult).collect())
}

/// The result of fitting one model to one sample: every field of a record of the fits JSON
/// (`fits-format.md`) as an attribute of the same name.
#[pyclass(name = "FitResult", module = "stfit", frozen)]
#[derive(Clone)]
pub struct PyFitResult(pub FitResult);

#[pymethods]
impl PyFitResult {
    /// The sample's name.
    #[getter]
    fn sample(&self) -> &str {
        &self.0.sample
    }
    /// The NDF family: `beckmann`, `ggx` or `student-t`.
    #[getter]
    fn model(&self) -> &'static str {
        self.0.model.kind.name()
    }
    #[getter]
    fn alpha(&self) -> f64 {
        self.0.model.alpha
    }
    /// The Student-T shape (None for Beckmann and GGX).
    #[getter]
    fn gamma(&self) -> Option<f64> {
        self.0.model.gamma.value()
    }
    /// True when gamma was held at its value.
    #[getter]
    fn gamma_fixed(&self) -> bool {
        self.0.model.gamma.is_fixed()
    }
    #[getter]
    fn scale(&self) -> f64 {
        self.0.model.scale
    }
    #[getter]
    fn eta(&self) -> f64 {
        self.0.model.eta
    }
    #[getter]
    fn masking(&self) -> &'static str {
        self.0.model.masking.name()
    }
    #[getter]
    fn orders(&self) -> &'static str {
        self.0.model.orders.name()
    }
    #[getter]
    fn walks(&self) -> Option<u64> {
        self.0.model.walks
    }
    #[getter]
    fn seed(&self) -> Option<u64> {
        self.0.model.seed
    }
    #[getter]
    fn eta_fixed(&self) -> bool {
        self.0.eta_fixed
    }
    #[getter]
    fn scale_fixed(&self) -> bool {
        self.0.scale_fixed
    }
    #[getter]
    fn loss(&self) -> &'static str {
        self.0.loss.name()
    }
    #[getter]
    fn log_floor(&self) -> Option<f64> {
        self.0.log_floor
    }
    #[getter]
    fn optimizer(&self) -> &'static str {
        self.0.optimizer.name()
    }
    /// For an all-orders fit, how the search computed the orders >= 2 term: `surrogate` or
    /// `exact` (None for single scattering).
    #[getter]
    fn multiple_term(&self) -> Option<&'static str> {
        self.0.multiple_term.map(|t| t.name())
    }
    /// What the fitted points measure: `L`, `bsdf` or `L+bsdf`.
    #[getter]
    fn measured(&self) -> PyResult<String> {
        serde_json::to_value(self.0.measured)
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .ok_or_else(|| value_error("unnamed measured quantity"))
    }
    /// Root-mean-square residual of the square root of the measured quantity.
    #[getter]
    fn rmse_sqrt_l(&self) -> f64 {
        self.0.rmse_sqrt_l
    }
    #[getter]
    fn n_points(&self) -> usize {
        self.0.n_points
    }
    #[getter]
    fn alpha_stderr(&self) -> Option<f64> {
        self.0.alpha_stderr
    }
    #[getter]
    fn gamma_stderr(&self) -> Option<f64> {
        self.0.gamma_stderr
    }
    #[getter]
    fn eta_stderr(&self) -> Option<f64> {
        self.0.eta_stderr
    }
    #[getter]
    fn scale_stderr(&self) -> Option<f64> {
        self.0.scale_stderr
    }
    #[getter]
    fn iterations(&self) -> u64 {
        self.0.iterations
    }
    /// The data file (None for data not read from a file).
    #[getter]
    fn data(&self) -> Option<&str> {
        self.0.data.as_deref()
    }
    /// Why the fit cannot be trusted as it stands: one dict per reason, with its `kind` and
    /// details, as in the fits JSON (`fits-format.md`); empty for a sound fit, and a fit with
    /// any warning has no standard errors.
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.0.warnings).map_err(value_error)?;
        py.import("json")?.call_method1("loads", (text,))
    }
    #[getter]
    fn stfit_version(&self) -> &str {
        &self.0.stfit_version
    }

    /// The fit as named in messages, such as `sample 'frosted', student-t (gamma = 3)`.
    fn label(&self) -> String {
        self.0.label()
    }

    /// The fitted model's value at in-plane configurations (`L`, the data convention):
    /// arrays of `theta_i_deg` in [0, 90) and `theta_o_deg` in (90, 270), the ranges of
    /// `data-format.md`; an angle outside them (NaN included) is a `ValueError` naming it.
    fn predict(
        &self,
        py: Python<'_>,
        theta_i_deg: &Bound<'_, PyAny>,
        theta_o_deg: &Bound<'_, PyAny>,
    ) -> PyResult<Vec<f64>> {
        let sequence = |name: &str, v| {
            floats(name, v)?.ok_or_else(|| {
                PyTypeError::new_err(format!("{name}: expected a sequence of numbers"))
            })
        };
        let theta_i_deg = sequence("theta_i_deg", theta_i_deg)?;
        let theta_o_deg = sequence("theta_o_deg", theta_o_deg)?;
        if theta_i_deg.len() != theta_o_deg.len() {
            return Err(value_error(
                "theta_i_deg and theta_o_deg must have the same length",
            ));
        }
        check_angles("theta_i_deg", &theta_i_deg, THETA_I_RANGE, theta_i_in_range)?;
        check_angles("theta_o_deg", &theta_o_deg, THETA_O_RANGE, theta_o_in_range)?;
        let angles: Vec<(f64, f64)> = theta_i_deg.into_iter().zip(theta_o_deg).collect();
        let model = self.0.model;
        py.detach(|| model.predict(&angles)).map_err(value_error)
    }

    /// The record as JSON text, exactly as in the fits file.
    fn to_json(&self) -> String {
        serde_json::to_string(&self.0).expect("fits are plain data and serialise")
    }

    /// The record as a dict with the keys of the fits JSON.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (self.to_json(),))
    }

    /// A record from its JSON text (`to_json`), checked as a fits file checks each of its
    /// records ([`FitResult::from_json`]: no unknown key, every number in its documented range).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        FitResult::from_json(text).map(Self).map_err(value_error)
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<Self>().is_ok_and(|o| o.get().0 == self.0)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        Ok((slf.get_type().getattr("from_json")?, (slf.get().to_json(),)))
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!(
            "stfit.FitResult({}, alpha={}, rmse_sqrt_l={})",
            self.0.label(),
            float_repr(py, self.0.model.alpha)?,
            float_repr(py, self.0.rmse_sqrt_l)?
        ))
    }
}

/// The first of the angles `values` (degrees) outside `range` (`in_range`, the data format's
/// rule) as a `ValueError` naming the argument `name` and the index.
fn check_angles(
    name: &str,
    values: &[f64],
    range: &str,
    in_range: fn(f64) -> bool,
) -> PyResult<()> {
    match values.iter().position(|&v| !in_range(v)) {
        None => Ok(()),
        Some(k) => Err(value_error(format!(
            "{name}[{k}] = {} is out of range; must be in {range} degrees",
            show(values[k])
        ))),
    }
}

/// The fits of a list of `FitResult`s.
fn results(fits: &Bound<'_, PyAny>) -> PyResult<Vec<FitResult>> {
    fits.try_iter()?
        .map(|f| {
            let f = f?;
            f.cast::<PyFitResult>()
                .map(|r| r.get().0.clone())
                .map_err(|_| PyTypeError::new_err("expected a list of stfit.FitResult"))
        })
        .collect()
}

/// The fits as the text table `stfit DATA` prints.
#[pyfunction]
pub fn table(fits: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(fits_table(&results(fits)?))
}

/// The fits as the text of a fits file (`fits-format.md`, what `stfit DATA --json` prints).
#[pyfunction]
pub fn fits_json(fits: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(FitsFile::new(results(fits)?).to_json())
}

/// The fits stored in a fits file (`stfit DATA --out FILE`).
#[pyfunction]
pub fn read_fits(path: PathBuf) -> PyResult<Vec<PyFitResult>> {
    let file = FitsFile::read(&path).map_err(|e| match e {
        stfit_fit::FitsFileError::Io { .. } => os_error(e),
        other => value_error(other),
    })?;
    Ok(file.fits.into_iter().map(PyFitResult).collect())
}

/// An angle list: a sequence of numbers, or the command line's text form
/// (`"0,30,60"`, `"106:254:2"`).
fn angle_list(name: &str, value: Option<&Bound<'_, PyAny>>, default: &str) -> PyResult<Vec<f64>> {
    match value {
        None => parse_angle_list(default).map_err(|e| arg_error(name, e)),
        Some(v) => match v.cast::<PyString>() {
            Ok(s) => parse_angle_list(s.to_str()?).map_err(|e| arg_error(name, e)),
            Err(_) => floats(name, v)?
                .ok_or_else(|| arg_error(name, "expected a sequence of numbers or a text list")),
        },
    }
}

/// Synthetic measurements of known truth (`stfit synth`): the model's values on an angle grid
/// with multiplicative noise `max(0, v (1 + noise z))`, as a `Dataset` of one sample, also
/// written as a CSV file to `out` when given.
#[pyfunction]
#[pyo3(signature = (model, alpha, gamma = None, *, scale = 1.0, noise = 0.0, seed = 1,
    grid = "in-plane", theta_i = None, phi_i = None, theta_o = None, phi_o = None,
    eta = DEFAULT_ETA, masking = None, orders = "single", walks = None,
    sample = "synthetic", out = None))]
#[allow(clippy::too_many_arguments)]
pub fn synth(
    py: Python<'_>,
    model: &str,
    alpha: &Bound<'_, PyAny>,
    gamma: Option<&Bound<'_, PyAny>>,
    #[pyo3(from_py_with = numbers::arg::scale)] scale: f64,
    #[pyo3(from_py_with = numbers::arg::noise)] noise: f64,
    #[pyo3(from_py_with = ints::seed)] seed: u64,
    grid: &str,
    theta_i: Option<&Bound<'_, PyAny>>,
    phi_i: Option<&Bound<'_, PyAny>>,
    theta_o: Option<&Bound<'_, PyAny>>,
    phi_o: Option<&Bound<'_, PyAny>>,
    #[pyo3(from_py_with = numbers::arg::eta)] eta: f64,
    masking: Option<&str>,
    orders: &str,
    walks: Option<&Bound<'_, PyAny>>,
    sample: &str,
    out: Option<PathBuf>,
) -> PyResult<PyDataset> {
    let kind: ModelKind = model.parse().map_err(|e| arg_error("model", e))?;
    let (alpha, gamma) = (float("alpha", alpha)?, opt_float("gamma", gamma)?);
    let grid = match grid {
        "in-plane" => {
            for (given, name) in [(phi_i, "phi_i"), (phi_o, "phi_o")] {
                if given.is_some() {
                    return Err(arg_error(name, "applies only to grid='general'"));
                }
            }
            Grid::InPlane {
                theta_i_deg: angle_list("theta_i", theta_i, "0,30,60,80")?,
                theta_o_deg: angle_list("theta_o", theta_o, "106:254:2")?,
            }
        }
        "general" => Grid::Spherical {
            theta_i_deg: angle_list("theta_i", theta_i, "0,30,60,120,150")?,
            phi_i_deg: angle_list("phi_i", phi_i, "0")?,
            theta_o_deg: angle_list("theta_o", theta_o, "5:175:10")?,
            phi_o_deg: angle_list("phi_o", phi_o, "0:340:20")?,
        },
        other => {
            return Err(arg_error(
                "grid",
                format!("unknown grid '{other}' (expected in-plane or general)"),
            ));
        }
    };
    let orders = self::orders(orders)?;
    let masking = orders
        .masking(masking.map(crate::bsdf::masking).transpose()?)
        .map_err(|e| arg_error("masking", e))?;
    let all = orders == ScatteringOrders::All;
    let walks = match walks.map(ints::walks).transpose()? {
        Some(_) if !all => return Err(walks_only("walks")),
        given => given.unwrap_or(DEFAULT_WALKS),
    };
    let spec = SynthSpec {
        model: Model {
            kind,
            alpha,
            gamma: gamma.map_or(Gamma::NotApplicable, Gamma::Fixed),
            scale,
            eta,
            masking,
            orders,
            walks: all.then_some(walks),
            seed: all.then_some(seed),
        },
        grid,
        noise,
        seed,
        name: sample.to_owned(),
    };
    if all {
        let seconds = py.detach(|| spec.walk_seconds()).map_err(value_error)?;
        long_run::warn_if_long(
            py,
            seconds,
            &spec.walks_description(),
            long_run::FEWER_WALKS,
        )?;
    }
    let points = py.detach(|| spec.sample()).map_err(value_error)?;
    let comment = format!(
        "stfit {} synth (Python): model {}, alpha {alpha}, gamma {gamma:?}, scale {scale}, \
         noise {noise}, seed {seed}, eta {eta}, masking {}, orders {}{}",
        env!("CARGO_PKG_VERSION"),
        kind.name(),
        masking.name(),
        orders.name(),
        if all {
            format!(", walks {walks}")
        } else {
            String::new()
        }
    );
    if let Some(path) = &out {
        write_file(path, std::slice::from_ref(&points), Some(&comment), false).map_err(
            |e| match e {
                SynthError::Io { .. } => os_error(e),
                other => value_error(other),
            },
        )?;
    }
    Ok(PyDataset(stfit_fit::Dataset {
        source: out.unwrap_or_else(|| PathBuf::from("<synth>")),
        samples: vec![points],
    }))
}

/// Draws the report of `stfit report` into the folder `out` (created if missing): the
/// comparison figures (SVG and PNG) and `fits.md`. `fits` are the fits to draw (each with its
/// own model); without them the four models of `model='all'` are fitted first, with the fit
/// options given. Returns the paths written; non-fatal findings become Python warnings.
#[pyfunction]
#[pyo3(signature = (data, fits = None, *, out, y_axis = "sqrt", eta = None, scale = None,
    loss = None, log_floor = None, optimizer = None, masking = None, orders = None,
    walks = None, seed = None, multiple_term = None))]
#[allow(clippy::too_many_arguments)]
pub fn report(
    py: Python<'_>,
    data: &Bound<'_, PyAny>,
    fits: Option<&Bound<'_, PyAny>>,
    out: PathBuf,
    y_axis: &str,
    eta: Option<&Bound<'_, PyAny>>,
    scale: Option<&Bound<'_, PyAny>>,
    loss: Option<&str>,
    log_floor: Option<&Bound<'_, PyAny>>,
    optimizer: Option<&str>,
    masking: Option<&str>,
    orders: Option<&str>,
    walks: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
    multiple_term: Option<&str>,
) -> PyResult<Vec<PathBuf>> {
    // Stored fits carry the options they were fitted with: fit options given with them would
    // be ignored, so they are refused (as `stfit report --fits` does).
    let given = [
        ("eta", eta.is_some()),
        ("scale", scale.is_some()),
        ("loss", loss.is_some()),
        ("log_floor", log_floor.is_some()),
        ("optimizer", optimizer.is_some()),
        ("masking", masking.is_some()),
        ("orders", orders.is_some()),
        ("walks", walks.is_some()),
        ("seed", seed.is_some()),
        ("multiple_term", multiple_term.is_some()),
    ];
    if let (Some(_), Some((name, _))) = (fits, given.iter().find(|(_, g)| *g)) {
        return Err(arg_error(
            name,
            "does not apply with fits: stored fits carry the model and options they were \
             fitted with",
        ));
    }
    let opts = ReportOptions {
        y_scale: match y_axis {
            "sqrt" => YScale::Sqrt,
            "linear" => YScale::Linear,
            other => {
                return Err(arg_error(
                    "y_axis",
                    format!("unknown axis '{other}' (expected sqrt or linear)"),
                ));
            }
        },
    };
    let data = dataset_of(data)?;
    let fits = match fits {
        // As `stfit report --fits` refuses a fits file with no fit: a report without models.
        Some(f) => match results(f)? {
            none if none.is_empty() => {
                return Err(arg_error(
                    "fits",
                    "holds no fit; give at least one, or None to fit the four models first",
                ));
            }
            some => some,
        },
        None => {
            let fit_opts = fit_options(
                eta,
                scale,
                loss.unwrap_or("sqrt"),
                opt_float("log_floor", log_floor)?,
                optimizer.unwrap_or("nelder-mead"),
                masking,
                orders.unwrap_or("single"),
                walks.map(ints::walks).transpose()?,
                seed.map(ints::seed).transpose()?,
                multiple_term,
            )?;
            let (specs, opts) = (all_models(), &fit_opts);
            warn_if_fit_walks_long(py, &data, &specs, opts)?;
            py.detach(|| fit_dataset(&data, &specs, opts, &|_, _| {}))
                .map_err(|e| fit_error(py, &e))?
        }
    };
    // The walks of the all-orders fits run again to draw them.
    let seconds = py.detach(|| stfit_report::walk_seconds(&data, &fits, &opts));
    long_run::warn_if_long(
        py,
        seconds,
        stfit_report::WALKS_DESCRIPTION,
        "fits with fewer walks make it shorter",
    )?;
    let report = py
        .detach(|| render_report(&data, &fits, &opts))
        .map_err(|e| value_error(format!("{}: {e}", data.source.display())))?;
    let warn = py.import("warnings")?;
    for w in &report.warnings {
        warn.call_method1("warn", (w,))?;
    }
    py.detach(|| report.write_to(&out)).map_err(|e| match e {
        ReportError::Io { .. } => os_error(e),
        other => value_error(other),
    })
}
