//! `stfit.Microsurface`: the multiple-scattering dielectric microsurface of `stfit-core` (the
//! height-field random walk of Heitz et al. 2016, with `stfit_core::surface` choosing the
//! estimator), its albedo and its BSDF as Monte Carlo estimates with standard errors.

use pyo3::prelude::*;
use stfit_core::ScatteringOrders;
use stfit_core::error::show;
use stfit_core::ndf::AnyNdf;
use stfit_core::surface::{NdfChoice, NdfFamily, Surface, SurfaceOptions};
use stfit_core::walk::{
    AlbedoEstimate, DEFAULT_ALBEDO_WALKS, DEFAULT_EVAL_WALKS, SideError, WalkCost, check_walks,
    defined_stderr, eval_pairs, eval_pairs_walk_count, pilot_seed,
};

use crate::arrays::{Dirs, Pairing, checked_copy, values};
use crate::errors::{arg_error, value_error};
use crate::ints;
use crate::long_run;
use crate::ndf::{self, any_ndf, ndf_object};
use crate::numbers::float_repr;

/// Parses orders: `single`, `multiple` or `all`.
pub fn orders(name: &str) -> PyResult<ScatteringOrders> {
    name.parse().map_err(|e| arg_error("orders", e))
}

#[pyclass(name = "Microsurface", module = "stfit", frozen)]
pub struct PyMicrosurface {
    ndf: AnyNdf,
    eta: f64,
    surface: Surface,
    orders: ScatteringOrders,
}

/// The walks of one estimate, in core's range ([`check_walks`]: [1, 1e9]).
fn walks_arg(walks: u64) -> PyResult<u64> {
    check_walks(walks).map_err(value_error)
}

#[pymethods]
impl PyMicrosurface {
    #[new]
    #[pyo3(signature = (ndf, eta, orders = "all"))]
    fn new(ndf: &Bound<'_, PyAny>, eta: &Bound<'_, PyAny>, orders: &str) -> PyResult<Self> {
        let n = any_ndf(ndf)?;
        let eta = crate::numbers::float("eta", eta)?;
        let family = match n {
            AnyNdf::Beckmann(_) => NdfFamily::Beckmann,
            AnyNdf::Ggx(_) => NdfFamily::Ggx,
            AnyNdf::StudentT(_) => NdfFamily::StudentT,
        };
        let options = SurfaceOptions {
            alpha: Some(n.alpha()),
            gamma: n.gamma(),
            eta: Some(eta),
            ..SurfaceOptions::new(NdfChoice::HeightField(family))
        };
        let surface = options
            .check()
            .map_err(|e| value_error(e.message(|p| p.to_string())))?;
        let orders = self::orders(orders)?;
        // What the walks need (a Student-T shape of at least 1.501) is refused here, not at the
        // first estimate.
        surface
            .estimator(orders)
            .map_err(|e| value_error(e.message(|p| p.to_string())))?;
        Ok(Self {
            ndf: n,
            eta,
            surface,
            orders,
        })
    }

    /// The relative index of refraction of the facets.
    #[getter]
    fn eta(&self) -> f64 {
        self.eta
    }

    #[getter]
    fn ndf<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        ndf_object(py, self.ndf)
    }

    /// `single`, `multiple` or `all`.
    #[getter]
    fn orders(&self) -> &'static str {
        self.orders.name()
    }

    /// Fractions of the flux arriving from the unit direction `wi` that leave on its side
    /// (reflectance) and on the other (transmittance), from `walks` random walks (in [1, 1e9]).
    /// A `wi` on the horizon (z = 0), from which no flux arrives, is a `ValueError`.
    #[pyo3(signature = (wi, walks = DEFAULT_ALBEDO_WALKS, seed = 1))]
    fn albedo(
        &self,
        wi: &Bound<'_, PyAny>,
        #[pyo3(from_py_with = ints::walks)] walks: u64,
        #[pyo3(from_py_with = ints::seed)] seed: u64,
    ) -> PyResult<Albedo> {
        let py = wi.py();
        let wi = Dirs::new(wi, "wi")?;
        if !wi.shape.is_empty() {
            return Err(arg_error("wi", "albedo takes one direction, of shape (3,)"));
        }
        let flat = wi.flat()?;
        let walks = walks_arg(walks)?;
        let (surface, orders) = (self.surface, self.orders);
        // A pilot run (random numbers of its own, at most a sixteenth of the walks) times the
        // walks, announced when long, as `stfit albedo` does.
        let (w, cost) = py.detach(|| {
            let flat = &checked_copy(flat, "wi")?;
            let w = crate::arrays::dir(flat, 0);
            if w.z == 0.0 {
                // As `stfit albedo` refuses --theta-i 90: the walks would return 0 and 0.
                return Err(value_error(format!(
                    "wi = [{}, {}, {}]: on the horizon (z = 0): no flux arrives from it, so its \
                     albedo is undefined",
                    show(w.x),
                    show(w.y),
                    show(w.z)
                )));
            }
            let estimator = surface.estimator(orders).map_err(value_error)?;
            let cost = WalkCost::measure(estimator.as_ref(), w, walks, pilot_seed(seed));
            Ok::<_, PyErr>((w, cost))
        })?;
        long_run::warn_if_costly(py, cost, walks, walks)?;
        let a = py.detach(|| {
            let estimator = surface.estimator(orders).map_err(value_error)?;
            Ok::<_, PyErr>(estimator.albedo(w, walks, seed))
        })?;
        Ok(Albedo(a))
    }

    /// Estimates of `f(wi, wo) |wo.z|` and their standard errors, as two arrays: pairs that
    /// share a `wi` share one set of `walks` walks (in [1, 1e9]), seeded by the direction and
    /// `seed`; with dielectric or conductor facets every pair adds a quarter as many walks from
    /// its `wo` (bidirectional estimates). With 1 walk the standard errors are undefined: NaN
    /// (the empty column of `stfit eval`).
    #[pyo3(signature = (wi, wo, walks = DEFAULT_EVAL_WALKS, seed = 1))]
    fn eval<'py>(
        &self,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
        #[pyo3(from_py_with = ints::walks)] walks: u64,
        #[pyo3(from_py_with = ints::seed)] seed: u64,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let py = wi.py();
        let (wi, wo) = (Dirs::new(wi, "wi")?, Dirs::new(wo, "wo")?);
        let pairing = Pairing::new(&wi, &wo, ("wi", "wo"))?;
        let (a, b) = (wi.flat()?, wo.flat()?);
        let walks = walks_arg(walks)?;
        let (surface, orders) = (self.surface, self.orders);
        // A pilot run times the walks, announced when long, as `stfit eval` does.
        let (pairs, cost, all_walks) = py.detach(|| {
            let (a, b) = (&checked_copy(a, "wi")?, &checked_copy(b, "wo")?);
            let estimator = surface.estimator(orders).map_err(value_error)?;
            let pairs: Vec<_> = (0..pairing.n).map(|k| pairing.pair(a, b, k)).collect();
            let cost = WalkCost::measure_pairs(estimator.as_ref(), &pairs, walks, pilot_seed(seed));
            let all_walks = eval_pairs_walk_count(estimator.as_ref(), &pairs, walks);
            Ok::<_, PyErr>((pairs, cost, all_walks))
        })?;
        long_run::warn_if_costly(py, cost, walks, all_walks)?;
        let est = py.detach(|| {
            let estimator = surface.estimator(orders).map_err(value_error)?;
            Ok::<_, PyErr>(eval_pairs(estimator.as_ref(), &pairs, walks, seed))
        })?;
        let mean = est.iter().map(|e| e.mean).collect();
        let stderr = est
            .iter()
            .map(|e| defined_stderr(walks, e.stderr).unwrap_or(f64::NAN))
            .collect();
        Ok((
            values(py, mean, &pairing.shape)?,
            values(py, stderr, &pairing.shape)?,
        ))
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!(
            "stfit.Microsurface({}, eta={}, orders='{}')",
            ndf_object(py, self.ndf)?.repr()?,
            float_repr(py, self.eta)?,
            self.orders.name()
        ))
    }

    /// Equal when the NDFs are equal (class and parameters), and so are `eta` and `orders`.
    fn __eq__(&self, other: &Bound<'_, Self>) -> bool {
        let o = other.get();
        (ndf::key(self.ndf), self.eta, self.orders) == (ndf::key(o.ndf), o.eta, o.orders)
    }

    /// Consistent with `__eq__`.
    fn __hash__(&self) -> u64 {
        ndf::hash_of((ndf::hash_key(self.ndf), ndf::bits(self.eta), self.orders))
    }

    /// Pickles as its arguments: `Microsurface(ndf, eta, orders)`.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let s = slf.get();
        let args = (ndf_object(slf.py(), s.ndf)?, s.eta, s.orders.name())
            .into_pyobject(slf.py())?
            .into_any();
        Ok((slf.get_type().into_any(), args))
    }
}

/// An albedo estimate: `reflectance`, `transmittance` and their standard errors (None with
/// fewer than 2 walks, as `stfit albedo --json` gives null, and for a side that no walk
/// reached, which has instead the one-sided 95% upper bound `1 - 0.05^(1/walks)` in
/// `reflectance_upper_bound` / `transmittance_upper_bound`, None for a reached side), the mean number of scattering
/// events of the walks that left within the orders, `mean_bounces` (the path length, which
/// facet albedos do not change: they weight a walk; None when no walk left within the orders), the fraction `truncated` of the flux dropped by walks past the
/// safety cap, and the number of `walks`.
#[pyclass(module = "stfit", frozen)]
pub struct Albedo(AlbedoEstimate);

impl Albedo {
    /// The fields' bits, what `__eq__` and `__hash__` compare.
    fn key(&self) -> ([u64; 5], Option<u64>, u64) {
        let a = &self.0;
        let numbers = [
            a.reflectance,
            a.transmittance,
            a.reflectance_stderr,
            a.transmittance_stderr,
            a.truncated,
        ]
        .map(ndf::bits);
        (numbers, a.mean_bounces.map(ndf::bits), a.walks)
    }
}

#[pymethods]
impl Albedo {
    #[getter]
    fn reflectance(&self) -> f64 {
        self.0.reflectance
    }
    #[getter]
    fn transmittance(&self) -> f64 {
        self.0.transmittance
    }
    /// None with fewer than 2 walks, where a standard error is undefined, and when no walk was
    /// reflected (see `reflectance_upper_bound`).
    #[getter]
    fn reflectance_stderr(&self) -> Option<f64> {
        self.0.reflectance_error().stderr()
    }
    /// None with fewer than 2 walks, where a standard error is undefined, and when no walk was
    /// transmitted (see `transmittance_upper_bound`).
    #[getter]
    fn transmittance_stderr(&self) -> Option<f64> {
        self.0.transmittance_error().stderr()
    }
    /// When no walk was reflected, the one-sided 95% upper bound `1 - 0.05^(1/walks)` on the
    /// chance that a walk is; None otherwise.
    #[getter]
    fn reflectance_upper_bound(&self) -> Option<f64> {
        self.0.reflectance_error().upper_bound()
    }
    /// When no walk was transmitted, the one-sided 95% upper bound `1 - 0.05^(1/walks)` on
    /// the chance that a walk is; None otherwise.
    #[getter]
    fn transmittance_upper_bound(&self) -> Option<f64> {
        self.0.transmittance_error().upper_bound()
    }
    #[getter]
    fn mean_bounces(&self) -> Option<f64> {
        self.0.mean_bounces
    }
    #[getter]
    fn truncated(&self) -> f64 {
        self.0.truncated
    }
    #[getter]
    fn walks(&self) -> u64 {
        self.0.walks
    }
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let pm = |e: SideError| -> PyResult<String> {
            Ok(match e {
                SideError::Stderr(se) => format!(" +- {}", float_repr(py, se)?),
                SideError::UpperBound(b) => {
                    format!(" (no walk; below {} at 95%)", float_repr(py, b)?)
                }
                SideError::Undefined => String::new(),
            })
        };
        Ok(format!(
            "stfit.Albedo(reflectance={}{}, transmittance={}{}, walks={})",
            float_repr(py, self.0.reflectance)?,
            pm(self.0.reflectance_error())?,
            float_repr(py, self.0.transmittance)?,
            pm(self.0.transmittance_error())?,
            self.0.walks
        ))
    }

    /// Equal when every field is the same number (bit for bit, so an undefined standard
    /// error, NaN inside, equals itself and a pickled copy equals its original).
    fn __eq__(&self, other: &Bound<'_, Self>) -> bool {
        self.key() == other.get().key()
    }

    /// Consistent with `__eq__`.
    fn __hash__(&self) -> u64 {
        ndf::hash_of(self.key())
    }

    /// The estimate of its fields as `__reduce__` gives them (for pickle).
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    fn _from_state(
        reflectance: f64,
        transmittance: f64,
        reflectance_stderr: f64,
        transmittance_stderr: f64,
        mean_bounces: Option<f64>,
        truncated: f64,
        walks: u64,
    ) -> Self {
        Self(AlbedoEstimate {
            reflectance,
            transmittance,
            reflectance_stderr,
            transmittance_stderr,
            mean_bounces,
            truncated,
            walks,
        })
    }

    /// Pickles as its fields, every number exactly.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let a = slf.get().0;
        let state = (
            a.reflectance,
            a.transmittance,
            a.reflectance_stderr,
            a.transmittance_stderr,
            a.mean_bounces,
            a.truncated,
            a.walks,
        );
        Ok((
            slf.get_type().getattr("_from_state")?,
            state.into_pyobject(slf.py())?.into_any(),
        ))
    }
}
