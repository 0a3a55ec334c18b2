//! `stfit.RoughDielectric`: the single-scattering rough dielectric of Walter et al. 2007
//! (`stfit_core::bsdf::RoughDielectric`), evaluated, sampled and its density computed over
//! batches of direction pairs.

use pyo3::prelude::*;
use rayon::prelude::*;
use std::sync::OnceLock;
use stfit_core::bsdf::{AnalyticBsdf, Bsdf, Masking, RoughDielectric};
use stfit_core::ndf::{AnyNdf, Ndf, TabulatedStudentT, WithNdf};

use crate::arrays::{
    Dirs, Pairing, ROWS_PER_TASK, checked_copy, dir, flags, map_rows, values, vectors,
};
use crate::errors::{arg_error, value_error};
use crate::ndf::{self, any_ndf, ndf_object, stream};
use crate::numbers::float_repr;

/// Parses a masking name, `separable` or `correlated`.
pub fn masking(name: &str) -> PyResult<Masking> {
    name.parse().map_err(|e| arg_error("masking", e))
}

/// The rough dielectric; for a Student-T NDF, `eval` and `pdf` run on its
/// [`TabulatedStudentT`] (Lambda's continued fractions interpolated, to a few ulps), built on
/// first use and kept, so that every call, whatever its batch size, gives the same numbers.
#[pyclass(name = "RoughDielectric", module = "stfit", frozen)]
pub struct PyRoughDielectric(RoughDielectric<AnyNdf>, OnceLock<Option<TabulatedStudentT>>);

impl PyRoughDielectric {
    /// What makes two rough dielectrics equal (not the table, which their NDF fixes).
    fn key(&self) -> (ndf::Key, f64, Masking) {
        (ndf::key(*self.0.ndf()), self.0.eta(), self.0.masking())
    }

    /// The NDF that `eval` and `pdf` use: the tabulated form of a Student-T.
    fn pair_ndf(&self) -> Option<&TabulatedStudentT> {
        self.1
            .get_or_init(|| match self.0.ndf() {
                AnyNdf::StudentT(st) => Some(TabulatedStudentT::new(*st)),
                _ => None,
            })
            .as_ref()
    }
}

/// What [`binary`] computes for each pair.
#[derive(Clone, Copy)]
enum PairValue {
    /// `f(wi, wo) |wo.z|`.
    FCos,
    /// The density of `sample`.
    Density,
}

/// One [`PairValue`] for every pair of a batch, in a loop compiled for the concrete NDF
/// ([`AnyNdf::with`]).
struct PairLoop<'a> {
    bsdf: &'a RoughDielectric<AnyNdf>,
    value: PairValue,
    pairing: &'a Pairing,
    wi: &'a [f64],
    wo: &'a [f64],
}

impl WithNdf for PairLoop<'_> {
    type Output = Vec<f64>;

    fn run<N: Ndf>(self, ndf: N) -> Vec<f64> {
        let bsdf = self.bsdf.with_ndf(ndf);
        let pair = |k| self.pairing.pair(self.wi, self.wo, k);
        match self.value {
            PairValue::FCos => map_rows(self.pairing.n, |k| {
                let (i, o) = pair(k);
                bsdf.f_cos(i, o)
            }),
            PairValue::Density => map_rows(self.pairing.n, |k| {
                let (i, o) = pair(k);
                bsdf.density(i, o)
            }),
        }
    }
}

/// `value` over paired batches, with the GIL released.
fn binary<'py>(
    glass: &PyRoughDielectric,
    wi: &Bound<'py, PyAny>,
    wo: &Bound<'py, PyAny>,
    value: PairValue,
) -> PyResult<Bound<'py, PyAny>> {
    let py = wi.py();
    let (wi, wo) = (Dirs::new(wi, "wi")?, Dirs::new(wo, "wo")?);
    let pairing = Pairing::new(&wi, &wo, ("wi", "wo"))?;
    let (a, b) = (wi.flat()?, wo.flat()?);
    let out = py.detach(|| {
        let (a, b) = (&checked_copy(a, "wi")?, &checked_copy(b, "wo")?);
        let pairs = PairLoop {
            bsdf: &glass.0,
            value,
            pairing: &pairing,
            wi: a,
            wo: b,
        };
        Ok::<_, PyErr>(match glass.pair_ndf() {
            Some(st) => pairs.run(st.clone()),
            None => glass.0.ndf().with(pairs),
        })
    })?;
    values(py, out, &pairing.shape)
}

#[pymethods]
impl PyRoughDielectric {
    #[new]
    #[pyo3(signature = (ndf, eta, masking = "separable"))]
    fn new(ndf: &Bound<'_, PyAny>, eta: &Bound<'_, PyAny>, masking: &str) -> PyResult<Self> {
        let eta = crate::numbers::float("eta", eta)?;
        RoughDielectric::new(any_ndf(ndf)?, eta, self::masking(masking)?)
            .map(|b| Self(b, OnceLock::new()))
            .map_err(value_error)
    }

    /// The microfacet distribution.
    #[getter]
    fn ndf<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        ndf_object(py, *self.0.ndf())
    }

    /// The relative index of refraction `n_inside / n_outside`.
    #[getter]
    fn eta(&self) -> f64 {
        self.0.eta()
    }

    /// `separable` or `correlated`.
    #[getter]
    fn masking(&self) -> &'static str {
        self.0.masking().name()
    }

    /// `f(wi, wo) |wo.z|`, reflection or transmission by the sides of `wi` and `wo`.
    fn eval<'py>(
        &self,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        binary(self, wi, wo, PairValue::FCos)
    }

    /// The solid-angle density with which `sample` returns `wo`.
    fn pdf<'py>(
        &self,
        wi: &Bound<'py, PyAny>,
        wo: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        binary(self, wi, wo, PairValue::Density)
    }

    /// One outgoing direction per incident direction `wi`.
    #[pyo3(signature = (wi, seed = 0))]
    fn sample<'py>(
        &self,
        wi: &Bound<'py, PyAny>,
        #[pyo3(from_py_with = crate::ints::seed)] seed: u64,
    ) -> PyResult<BsdfSamples> {
        let py = wi.py();
        let wi = Dirs::new(wi, "wi")?;
        let flat = wi.flat()?;
        let n = wi.len();
        let bsdf = &self.0;
        let (wo, weight, pdf, valid) = py.detach(|| {
            let flat = &checked_copy(flat, "wi")?;
            let mut rows = vec![None; n];
            rows.par_chunks_mut(ROWS_PER_TASK)
                .enumerate()
                .for_each(|(c, chunk)| {
                    let mut rng = stream(seed, c);
                    for (j, r) in chunk.iter_mut().enumerate() {
                        *r = bsdf.sample(dir(flat, c * ROWS_PER_TASK + j), &mut rng);
                    }
                });
            let mut wo = Vec::with_capacity(3 * n);
            let (mut weight, mut pdf, mut valid) = (vec![0.0; n], vec![0.0; n], vec![false; n]);
            for (k, r) in rows.iter().enumerate() {
                match r {
                    Some(s) => {
                        wo.extend([s.wo.x, s.wo.y, s.wo.z]);
                        (weight[k], pdf[k], valid[k]) = (s.weight, s.pdf, true);
                    }
                    None => wo.extend([0.0; 3]),
                }
            }
            Ok::<_, PyErr>((wo, weight, pdf, valid))
        })?;
        Ok(BsdfSamples {
            wo: vectors(py, wo, &wi.shape)?.unbind(),
            weight: values(py, weight, &wi.shape)?.unbind(),
            pdf: values(py, pdf, &wi.shape)?.unbind(),
            valid: flags(py, valid, &wi.shape)?.unbind(),
        })
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        Ok(format!(
            "stfit.RoughDielectric({}, eta={}, masking='{}')",
            ndf_object(py, *self.0.ndf())?.repr()?,
            float_repr(py, self.0.eta())?,
            self.0.masking().name()
        ))
    }

    /// Equal when the NDFs are equal (class and parameters), and so are `eta` and `masking`.
    fn __eq__(&self, other: &Bound<'_, Self>) -> bool {
        self.key() == other.get().key()
    }

    /// Consistent with `__eq__`.
    fn __hash__(&self) -> u64 {
        ndf::hash_of((
            ndf::hash_key(*self.0.ndf()),
            ndf::bits(self.0.eta()),
            self.0.masking(),
        ))
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let b = &slf.get().0;
        let args = (ndf_object(slf.py(), *b.ndf())?, b.eta(), b.masking().name())
            .into_pyobject(slf.py())?
            .into_any();
        Ok((slf.get_type().into_any(), args))
    }
}

/// Directions drawn by `RoughDielectric.sample`: `wo` (unit vectors, zero where no direction
/// was drawn), `weight = eval / pdf`, `pdf`, and `valid` (False where the draw failed: grazing
/// `wi`, or a direction that landed on the wrong side; then weight and pdf are 0).
#[pyclass(module = "stfit", frozen, get_all)]
pub struct BsdfSamples {
    pub wo: Py<PyAny>,
    pub weight: Py<PyAny>,
    pub pdf: Py<PyAny>,
    pub valid: Py<PyAny>,
}

#[pymethods]
impl BsdfSamples {
    fn __repr__(&self) -> &'static str {
        "stfit.BsdfSamples(wo, weight, pdf, valid)"
    }
}
