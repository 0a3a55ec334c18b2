//! `stfit.StudentT`, `stfit.Ggx`, `stfit.Beckmann`: the height-field NDFs of `stfit-core`
//! (normalised by projected area, Smith Lambda on the whole sphere, exact visible-normal
//! sampling), evaluated over batches of directions.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use rand_pcg::Pcg64;
use rayon::prelude::*;
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, Ndf, StudentT, WithNdf};

use crate::arrays::{Dirs, ROWS_PER_TASK, checked_copy, dir, map_rows, values, vectors};
use crate::errors::value_error;
use crate::numbers::{float, float_repr};

/// The random-number stream of rows `[c * ROWS_PER_TASK, (c + 1) * ROWS_PER_TASK)` of a batch
/// drawn with `seed`: fixed by the seed and the rows, whatever the number of threads.
pub fn stream(seed: u64, c: usize) -> Pcg64 {
    Pcg64::new((u128::from(seed) << 64) | 0x5851_f42d_4c95_7f2d, c as u128)
}

/// What [`unary`] computes for each direction.
#[derive(Clone, Copy)]
enum DirValue {
    D,
    Lambda,
    Sigma,
    G1,
}

/// One [`DirValue`] for every direction of a batch, in a loop compiled for the concrete NDF
/// ([`AnyNdf::with`]).
struct DirLoop<'a> {
    value: DirValue,
    flat: &'a [f64],
    n: usize,
}

impl WithNdf for DirLoop<'_> {
    type Output = Vec<f64>;

    fn run<N: Ndf>(self, ndf: N) -> Vec<f64> {
        let w = |k| dir(self.flat, k);
        match self.value {
            DirValue::D => map_rows(self.n, |k| ndf.d(w(k))),
            DirValue::Lambda => map_rows(self.n, |k| ndf.lambda(w(k))),
            DirValue::Sigma => map_rows(self.n, |k| ndf.sigma(w(k))),
            DirValue::G1 => map_rows(self.n, |k| ndf.g1(w(k))),
        }
    }
}

/// `value` of `ndf` over a batch, with the GIL released.
fn unary<'py>(
    ndf: AnyNdf,
    w: &Bound<'py, PyAny>,
    name: &str,
    value: DirValue,
) -> PyResult<Bound<'py, PyAny>> {
    let py = w.py();
    let w = Dirs::new(w, name)?;
    let (flat, n) = (w.flat()?, w.len());
    let out = py.detach(|| {
        let flat = &checked_copy(flat, name)?;
        Ok::<_, PyErr>(ndf.with(DirLoop { value, flat, n }))
    })?;
    values(py, out, &w.shape)
}

/// The NDF of a Python NDF object.
pub fn any_ndf(obj: &Bound<'_, PyAny>) -> PyResult<AnyNdf> {
    if let Ok(n) = obj.cast::<PyStudentT>() {
        return Ok(n.get().0.into());
    }
    if let Ok(n) = obj.cast::<PyGgx>() {
        return Ok(n.get().0.into());
    }
    if let Ok(n) = obj.cast::<PyBeckmann>() {
        return Ok(n.get().0.into());
    }
    Err(PyTypeError::new_err(format!(
        "ndf must be a stfit.StudentT, stfit.Ggx or stfit.Beckmann, got {}",
        obj.get_type().name()?
    )))
}

/// The Python object of an NDF.
pub fn ndf_object(py: Python<'_>, ndf: AnyNdf) -> PyResult<Bound<'_, PyAny>> {
    Ok(match ndf {
        AnyNdf::StudentT(n) => Bound::new(py, PyStudentT(n))?.into_any(),
        AnyNdf::Ggx(n) => Bound::new(py, PyGgx(n))?.into_any(),
        AnyNdf::Beckmann(n) => Bound::new(py, PyBeckmann(n))?.into_any(),
    })
}

/// The parameters that make an NDF what it is: its roughness and, for a Student-T, its shape.
pub fn params(ndf: AnyNdf) -> (f64, Option<f64>) {
    (ndf.alpha(), ndf.gamma())
}

/// The Python class name of an NDF.
pub fn class_name(ndf: AnyNdf) -> &'static str {
    match ndf {
        AnyNdf::StudentT(_) => "StudentT",
        AnyNdf::Ggx(_) => "Ggx",
        AnyNdf::Beckmann(_) => "Beckmann",
    }
}

/// What makes two NDFs equal: the class and the parameters.
pub type Key = (&'static str, (f64, Option<f64>));

/// The [`Key`] of an NDF.
pub fn key(ndf: AnyNdf) -> Key {
    (class_name(ndf), params(ndf))
}

/// The bits of a number, equal for equal numbers (`-0.0` as `0.0`): what hashes agree on.
pub fn bits(x: f64) -> u64 {
    (x + 0.0).to_bits()
}

/// What equal NDFs hash by: [`key`] with the numbers' [`bits`].
pub fn hash_key(ndf: AnyNdf) -> (&'static str, u64, Option<u64>) {
    let (class, (alpha, gamma)) = key(ndf);
    (class, bits(alpha), gamma.map(bits))
}

/// A hash of `value` for `__hash__`.
pub fn hash_of(value: impl std::hash::Hash) -> u64 {
    use std::hash::Hasher;
    let mut h = std::collections::hash_map::DefaultHasher::new();
    value.hash(&mut h);
    h.finish()
}

/// `stfit.<class>(alpha=..., gamma=...)`, the numbers as Python's `repr(float)` writes them.
fn ndf_repr(py: Python<'_>, class: &str, ndf: AnyNdf) -> PyResult<String> {
    let alpha = float_repr(py, ndf.alpha())?;
    Ok(match ndf.gamma() {
        Some(g) => format!("stfit.{class}(alpha={alpha}, gamma={})", float_repr(py, g)?),
        None => format!("stfit.{class}(alpha={alpha})"),
    })
}

/// The methods every NDF class shares, over its inner `stfit-core` NDF `self.0`.
macro_rules! ndf_class {
    ($class:ident, $pyname:literal, $inner:ty, ($($arg:ident),*), $make:expr,
     { $($extra:tt)* }) => {
        #[pyclass(name = $pyname, module = "stfit", frozen)]
        #[derive(Clone, Copy)]
        pub struct $class(pub $inner);

        #[pymethods]
        impl $class {
            #[new]
            fn new($($arg: &Bound<'_, PyAny>),*) -> PyResult<Self> {
                $(let $arg = float(stringify!($arg), $arg)?;)*
                $make.map(Self).map_err(value_error)
            }

            /// The roughness alpha.
            #[getter]
            fn alpha(&self) -> f64 {
                self.0.alpha()
            }

            /// `D(wm)`, normalised by projected area; 0 for `wm.z <= 0`.
            fn d<'py>(&self, wm: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
                unary(self.0.into(), wm, "wm", DirValue::D)
            }

            /// Smith `Lambda(w)` on the whole sphere (`Lambda(-w) = -1 - Lambda(w)`); `inf` on the
            /// horizon (z = 0), where it diverges.
            fn lambda_<'py>(&self, w: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
                unary(self.0.into(), w, "w", DirValue::Lambda)
            }

            /// Projected area `sigma(w) = integral max(0, w.wm) D(wm) dwm`.
            fn sigma<'py>(&self, w: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
                unary(self.0.into(), w, "w", DirValue::Sigma)
            }

            /// Smith `G1(w) = 1 / (1 + Lambda(w'))`, `w'` mirrored to the upper hemisphere.
            fn g1<'py>(&self, w: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
                unary(self.0.into(), w, "w", DirValue::G1)
            }

            /// Exact visible normals: one draw per direction `w`.
            #[pyo3(signature = (w, seed = 0))]
            fn sample_visible<'py>(
                &self,
                w: &Bound<'py, PyAny>,
                #[pyo3(from_py_with = crate::ints::seed)] seed: u64,
            ) -> PyResult<Bound<'py, PyAny>> {
                sample_visible(self.0.into(), w, seed)
            }

            $($extra)*

            /// `stfit.<Class>(alpha=..., gamma=...)`, numbers as `repr(float)` writes them.
            fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
                ndf_repr(py, $pyname, self.0.into())
            }

            /// Equal when of the same class with equal parameters (another class: not
            /// implemented, so unequal).
            fn __eq__(&self, other: &Bound<'_, Self>) -> bool {
                params(self.0.into()) == params(other.get().0.into())
            }

            /// Consistent with `__eq__`: a hash of the class and the parameters.
            fn __hash__(&self) -> u64 {
                hash_of(hash_key(self.0.into()))
            }

            fn __reduce__<'py>(
                slf: &Bound<'py, Self>,
            ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
                let n: AnyNdf = slf.get().0.into();
                let args = match n.gamma() {
                    Some(g) => (n.alpha(), g).into_pyobject(slf.py())?.into_any(),
                    None => (n.alpha(),).into_pyobject(slf.py())?.into_any(),
                };
                Ok((slf.get_type().into_any(), args))
            }
        }
    };
}

ndf_class!(
    PyStudentT,
    "StudentT",
    StudentT,
    (alpha, gamma),
    StudentT::new(alpha, gamma),
    {
        /// The shape gamma (> 3/2).
        #[getter]
        fn gamma(&self) -> f64 {
            self.0.gamma()
        }
    }
);
ndf_class!(PyGgx, "Ggx", Ggx, (alpha), Ggx::new(alpha), {});
ndf_class!(
    PyBeckmann,
    "Beckmann",
    Beckmann,
    (alpha),
    Beckmann::new(alpha),
    {}
);

/// Visible normals drawn from every direction of a batch; rows of one task share a stream.
fn sample_visible<'py>(
    ndf: AnyNdf,
    w: &Bound<'py, PyAny>,
    seed: u64,
) -> PyResult<Bound<'py, PyAny>> {
    let py = w.py();
    let w = Dirs::new(w, "w")?;
    let flat = w.flat()?;
    let out = py.detach(|| {
        let flat = &checked_copy(flat, "w")?;
        let mut out = vec![0.0; flat.len()];
        // Where no normal is visible (sigma(w) = 0: straight below, or far below the horizon
        // where D's tail underflows) a draw is not a visible normal: such rows are refused.
        let hidden = out
            .par_chunks_mut(3 * ROWS_PER_TASK)
            .enumerate()
            .filter_map(|(c, chunk)| {
                let mut rng = stream(seed, c);
                let mut hidden = None;
                for (j, o) in chunk.chunks_exact_mut(3).enumerate() {
                    let k = c * ROWS_PER_TASK + j;
                    let w = dir(flat, k);
                    let wm = ndf.sample_visible(w, &mut rng);
                    if hidden.is_none() && !(w.dot(&wm) > 0.0 && wm.z > 0.0) {
                        hidden = Some(k);
                    }
                    o.copy_from_slice(&[wm.x, wm.y, wm.z]);
                }
                hidden
            })
            .min();
        if let Some(k) = hidden {
            let w = dir(flat, k);
            return Err(PyValueError::new_err(format!(
                "w[{k}] = [{}, {}, {}]: no microfacet normal is visible from it (projected \
                 area sigma(w) = {:e})",
                w.x,
                w.y,
                w.z,
                ndf.sigma(w)
            )));
        }
        Ok::<_, PyErr>(out)
    })?;
    vectors(py, out, &w.shape)
}
