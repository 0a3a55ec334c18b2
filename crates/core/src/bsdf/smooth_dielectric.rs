//! A smooth dielectric interface: two Dirac delta lobes.

use super::microfacet::refract;
use super::{AnalyticBsdf, Bsdf, BsdfSample, fresnel_dielectric};
use crate::error::{ParamError, check_eta};
use crate::math::Vec3;
use rand::{Rng, RngExt};

/// A smooth dielectric interface: index 1 above (z > 0), `eta` below. Mirror reflection with
/// the exact unpolarised Fresnel reflectance `F` and refraction with `1 - F` (no radiance
/// `1/eta^2` scaling). Both lobes are deltas: `eval` and `pdf` are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmoothDielectric {
    eta: f64,
}

impl SmoothDielectric {
    /// A smooth dielectric with relative index `eta = n_inside / n_outside` (finite, > 0,
    /// != 1).
    pub fn new(eta: f64) -> Result<Self, ParamError> {
        Ok(Self {
            eta: check_eta(eta)?,
        })
    }

    /// The relative index `n_inside / n_outside`.
    pub fn eta(&self) -> f64 {
        self.eta
    }
}

/// A delta lobe only: nothing to evaluate.
impl AnalyticBsdf for SmoothDielectric {
    fn f_cos(&self, _wi: Vec3, _wo: Vec3) -> f64 {
        0.0
    }

    fn density(&self, _wi: Vec3, _wo: Vec3) -> f64 {
        0.0
    }
}

impl Bsdf for SmoothDielectric {
    fn eval<R: Rng + ?Sized>(&self, _wi: Vec3, _wo: Vec3, _rng: &mut R) -> f64 {
        0.0
    }

    /// Reflects with probability `F(wi.z)` and refracts otherwise; each lobe's mass equals its
    /// probability, so the weight is 1 and `pdf` is the discrete probability of the lobe.
    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<BsdfSample> {
        let f = fresnel_dielectric(wi.z, self.eta);
        let mirror = Vec3::new(-wi.x, -wi.y, wi.z);
        if rng.random::<f64>() < f {
            return Some(BsdfSample {
                wo: mirror,
                weight: 1.0,
                pdf: f,
                delta: true,
            });
        }
        let wo = refract(wi, Vec3::z(), self.eta)?;
        Some(BsdfSample {
            wo,
            weight: 1.0,
            pdf: 1.0 - f,
            delta: true,
        })
    }

    fn pdf<R: Rng + ?Sized>(&self, _wi: Vec3, _wo: Vec3, _rng: &mut R) -> f64 {
        0.0
    }
}
