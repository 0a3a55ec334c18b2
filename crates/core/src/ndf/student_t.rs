//! The Student-T NDF of Ribardiere et al. 2017 in d'Eon's (alpha, gamma) parameterisation.

use super::{Ndf, cos_tan2, lambda_on_sphere};
use crate::error::{ParamError, check_alpha, check_gamma};
use crate::math::Vec3;
use rand::Rng;
use statrs::function::beta::beta_reg;
use statrs::function::gamma::ln_gamma;
use std::f64::consts::PI;

/// Student-T: `D(u) = (g-1)^g alpha^(2g-2) / (pi u^4 (alpha^2 (g-1) + tan^2 theta)^g)` with
/// shape `g = gamma > 3/2`. Slopes along one axis are `(alpha/sqrt 2) T_nu`, `nu = 2g - 2`.
/// `gamma = 2` is GGX; `gamma -> inf` tends to Beckmann with the same alpha.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudentT {
    alpha: f64,
    gamma: f64,
    /// `ln((g-1)^g alpha^(2g-2) / pi)`, the log of D's numerator.
    ln_d_norm: f64,
    /// Degrees of freedom `nu = 2g - 2` of the 1D slope distribution.
    nu: f64,
    /// Normalisation of the Student t pdf: `Gamma((nu+1)/2) / (sqrt(nu pi) Gamma(nu/2))`.
    t_norm: f64,
}

impl StudentT {
    /// A Student-T NDF with roughness `alpha > 0` and shape `gamma > 3/2`.
    pub fn new(alpha: f64, gamma: f64) -> Result<Self, ParamError> {
        let alpha = check_alpha(alpha)?;
        let gamma = check_gamma(gamma)?;
        let nu = 2.0 * gamma - 2.0;
        let ln_d_norm = gamma * (gamma - 1.0).ln() + (2.0 * gamma - 2.0) * alpha.ln() - PI.ln();
        let t_norm = (ln_gamma(0.5 * (nu + 1.0)) - ln_gamma(0.5 * nu)).exp() / (nu * PI).sqrt();
        Ok(Self {
            alpha,
            gamma,
            ln_d_norm,
            nu,
            t_norm,
        })
    }

    /// The roughness alpha.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The shape gamma.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// Student t pdf `f_nu(k)`.
    #[inline]
    fn t_pdf(&self, k: f64) -> f64 {
        self.t_norm * (1.0 + k * k / self.nu).powf(-0.5 * (self.nu + 1.0))
    }

    /// Upper tail `S_nu(k) = P(T_nu > k)` for `k >= 0`, a regularised incomplete beta.
    #[inline]
    fn t_upper_tail(&self, k: f64) -> f64 {
        let x = self.nu / (self.nu + k * k);
        0.5 * beta_reg(0.5 * self.nu, 0.5, x)
    }

    /// `g(k) = (nu + k^2)/(nu - 1) f_nu(k) - k S_nu(k)` for `k >= 0`: `E[(T - k)+]`, so that
    /// `Lambda = (s/mu) g(mu/s)` with `s = alpha/sqrt 2`.
    #[inline]
    fn excess(&self, k: f64) -> f64 {
        (self.nu + k * k) / (self.nu - 1.0) * self.t_pdf(k) - k * self.t_upper_tail(k)
    }
}

impl Ndf for StudentT {
    fn d(&self, wm: Vec3) -> f64 {
        let Some((u, t2)) = cos_tan2(wm) else {
            return 0.0;
        };
        let g = self.gamma;
        let e = self.alpha * self.alpha * (g - 1.0) + t2;
        let u2 = u * u;
        (self.ln_d_norm - g * e.ln()).exp() / (u2 * u2)
    }

    /// Closed form with the regularised incomplete beta function (theory section 3).
    fn lambda(&self, w: Vec3) -> f64 {
        let s = self.alpha * std::f64::consts::FRAC_1_SQRT_2;
        lambda_on_sphere(w, |mu| s / mu * self.excess(mu / s))
    }

    fn sigma(&self, w: Vec3) -> f64 {
        let (c, sin) = crate::math::cos_sin_theta(w);
        if sin == 0.0 {
            return c.max(0.0);
        }
        let s = self.alpha * std::f64::consts::FRAC_1_SQRT_2;
        let k = c.abs() / (sin * s);
        let tail = sin * s * self.excess(k);
        if c > 0.0 { c + tail } else { tail }
    }

    fn sample_visible<R: Rng + ?Sized>(&self, _w: Vec3, _rng: &mut R) -> Vec3 {
        unimplemented!("exact Student-T visible-normal sampling lands with the sampler commit")
    }
}
