//! The Lambertian (ideal diffuse) reflector.

use super::{AnalyticBsdf, Bsdf, BsdfSample};
use crate::error::{ParamError, finite};
use crate::math::{Vec3, safe_sqrt};
use rand::{Rng, RngExt};
use std::f64::consts::{FRAC_1_PI, PI};

/// Ideal diffuse reflection `f = R / pi` on the side of `wi`, with reflectance `R` in [0, 1].
/// Two-sided; nothing is transmitted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lambertian {
    reflectance: f64,
}

impl Lambertian {
    /// A Lambertian reflector of reflectance `R` (finite, in [0, 1]).
    pub fn new(reflectance: f64) -> Result<Self, ParamError> {
        let r = finite("reflectance", reflectance)?;
        if !(0.0..=1.0).contains(&r) {
            return Err(ParamError::OutOfRange {
                name: "reflectance",
                value: r,
                expected: "0 <= reflectance <= 1",
            });
        }
        Ok(Self { reflectance: r })
    }

    /// The reflectance `R`, the directional albedo for every `wi`.
    pub fn reflectance(&self) -> f64 {
        self.reflectance
    }
}

impl AnalyticBsdf for Lambertian {
    /// `R |wo.z| / pi` when `wo` is on the side of `wi`, else 0.
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        self.reflectance * self.density(wi, wo)
    }

    /// `|wo.z| / pi` on the side of `wi`.
    fn density(&self, wi: Vec3, wo: Vec3) -> f64 {
        if wi.z * wo.z > 0.0 {
            wo.z.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }
}

impl Bsdf for Lambertian {
    fn eval<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, _rng: &mut R) -> f64 {
        self.f_cos(wi, wo)
    }

    /// Cosine-weighted hemisphere on the side of `wi` (Malley's method); weight `R`. `None`
    /// for grazing `wi`, which has no side.
    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let r = rng.random::<f64>().sqrt();
        let phi = 2.0 * PI * rng.random::<f64>();
        let (sp, cp) = phi.sin_cos();
        let z = safe_sqrt(1.0 - r * r);
        if z == 0.0 {
            return None;
        }
        let wo = Vec3::new(r * cp, r * sp, z.copysign(wi.z));
        Some(BsdfSample {
            wo,
            weight: self.reflectance,
            pdf: z * FRAC_1_PI,
            delta: false,
        })
    }

    fn pdf<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, _rng: &mut R) -> f64 {
        self.density(wi, wo)
    }
}
