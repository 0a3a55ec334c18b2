//! A smooth conductor: one Dirac delta lobe.

use super::{AnalyticBsdf, Bsdf, BsdfSample, fresnel_conductor};
use crate::error::ParamError;
use crate::math::Vec3;
use nalgebra::Complex;
use rand::Rng;

/// Validates a conductor's complex index `n + i k` ([`crate::error::check_conductor`]).
pub(crate) fn check_conductor_index(n: f64, k: f64) -> Result<Complex<f64>, ParamError> {
    let (n, k) = crate::error::check_conductor(n, k)?;
    Ok(Complex::new(n, k))
}

/// A smooth conductor with complex index `n + i k` relative to the outside medium: mirror
/// reflection with the exact unpolarised conductor Fresnel reflectance. Two-sided: light from
/// below reflects below, as from above. `eval` and `pdf` are zero (delta lobe).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmoothConductor {
    eta: Complex<f64>,
}

impl SmoothConductor {
    /// A smooth conductor of complex index `n + i k` (finite, `n > 0`, `k >= 0`).
    pub fn new(n: f64, k: f64) -> Result<Self, ParamError> {
        Ok(Self {
            eta: check_conductor_index(n, k)?,
        })
    }

    /// The complex index `n + i k`.
    pub fn eta(&self) -> Complex<f64> {
        self.eta
    }
}

/// A delta lobe only: nothing to evaluate.
impl AnalyticBsdf for SmoothConductor {
    fn f_cos(&self, _wi: Vec3, _wo: Vec3) -> f64 {
        0.0
    }

    fn density(&self, _wi: Vec3, _wo: Vec3) -> f64 {
        0.0
    }
}

impl Bsdf for SmoothConductor {
    fn eval<R: Rng + ?Sized>(&self, _wi: Vec3, _wo: Vec3, _rng: &mut R) -> f64 {
        0.0
    }

    /// Always the mirror direction: probability 1, weight `F(wi.z)`.
    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, _rng: &mut R) -> Option<BsdfSample> {
        Some(BsdfSample {
            wo: Vec3::new(-wi.x, -wi.y, wi.z),
            weight: fresnel_conductor(wi.z, self.eta),
            pdf: 1.0,
            delta: true,
        })
    }

    fn pdf<R: Rng + ?Sized>(&self, _wi: Vec3, _wo: Vec3, _rng: &mut R) -> f64 {
        0.0
    }
}
