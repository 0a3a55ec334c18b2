//! The Beckmann NDF.

use super::{Ndf, cos_tan2, lambda_on_sphere};
use crate::error::{ParamError, check_alpha};
use crate::math::Vec3;
use rand::Rng;
use statrs::function::erf::{erf, erfc};
use std::f64::consts::PI;

const INV_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// Beckmann: `D(u) = exp(-tan^2 theta / alpha^2) / (pi alpha^2 u^4)`; slopes are Gaussian with
/// standard deviation `alpha / sqrt(2)` per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Beckmann {
    alpha: f64,
}

impl Beckmann {
    /// A Beckmann NDF of roughness `alpha > 0`.
    pub fn new(alpha: f64) -> Result<Self, ParamError> {
        Ok(Self {
            alpha: check_alpha(alpha)?,
        })
    }

    /// The roughness alpha.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
}

/// Beckmann Lambda for an upward direction with `a = cot(theta) / alpha > 0`:
/// `(erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))`.
#[inline]
pub(crate) fn lambda_beckmann_a(a: f64) -> f64 {
    0.5 * (INV_SQRT_PI * (-a * a).exp() / a - erfc(a))
}

/// Beckmann projected area for `cos theta = c`, `sin theta = s`, valid on the whole sphere:
/// `sigma = c (1 + erf(a)) / 2 + s alpha exp(-a^2) / (2 sqrt(pi))` with `a = c / (s alpha)`.
#[inline]
pub(crate) fn sigma_beckmann(c: f64, s: f64, alpha: f64) -> f64 {
    if s == 0.0 {
        return c.max(0.0);
    }
    let a = c / (s * alpha);
    let head = if c >= 0.0 {
        0.5 * c * (1.0 + erf(a))
    } else {
        0.5 * c * erfc(-a)
    };
    head + 0.5 * s * alpha * INV_SQRT_PI * (-a * a).exp()
}

impl Ndf for Beckmann {
    fn d(&self, wm: Vec3) -> f64 {
        let Some((u, t2)) = cos_tan2(wm) else {
            return 0.0;
        };
        let a2 = self.alpha * self.alpha;
        let u2 = u * u;
        (-t2 / a2).exp() / (PI * a2 * u2 * u2)
    }

    fn lambda(&self, w: Vec3) -> f64 {
        let alpha = self.alpha;
        lambda_on_sphere(w, |mu| lambda_beckmann_a(mu / alpha))
    }

    fn sigma(&self, w: Vec3) -> f64 {
        let (c, s) = crate::math::cos_sin_theta(w);
        sigma_beckmann(c, s, self.alpha)
    }

    fn sample_visible<R: Rng + ?Sized>(&self, _w: Vec3, _rng: &mut R) -> Vec3 {
        unimplemented!("exact Beckmann visible-normal sampling lands with the sampler commit")
    }
}
