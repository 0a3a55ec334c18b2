//! The von Mises-Fisher lobe about the macro normal.

use super::SphereNdf;
use crate::error::{ParamError, finite};
use std::f64::consts::PI;

/// A von Mises-Fisher NDF with concentration `kappa > 0` about +z: `D(u) proportional to
/// exp(kappa u)` on the whole sphere, normalised by projected area
/// (`integral D wm.z dwm = 1`): `D(u) = kappa exp(kappa (u - 1)) / (2 pi (1 - exp(-2 kappa))
/// (coth kappa - 1/kappa))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VonMisesFisher {
    kappa: f64,
    /// `D(1)`, the maximum.
    peak: f64,
}

impl VonMisesFisher {
    /// A vMF NDF with concentration `kappa` in [0.1, 1e4]: below, `D` (normalised by
    /// projected area) grows like `1/kappa` and walks lengthen; above, the null walk's majorant
    /// makes walks crawl.
    pub fn new(kappa: f64) -> Result<Self, ParamError> {
        let kappa = finite("kappa", kappa)?;
        if !(0.1..=1e4).contains(&kappa) {
            return Err(ParamError::OutOfRange {
                name: "kappa",
                value: kappa,
                expected: "kappa must be in [0.1, 1e4]",
            });
        }
        let one_minus = -(-2.0 * kappa).exp_m1();
        let mean_cos = mean_cosine(kappa);
        let peak = kappa / (2.0 * PI * one_minus * mean_cos);
        Ok(Self { kappa, peak })
    }

    /// The concentration kappa.
    pub fn kappa(&self) -> f64 {
        self.kappa
    }
}

/// `coth(kappa) - 1/kappa`, the mean of `wm.z` under the vMF density (series for small kappa).
fn mean_cosine(kappa: f64) -> f64 {
    if kappa < 1e-3 {
        kappa / 3.0 - kappa.powi(3) / 45.0
    } else {
        1.0 / kappa.tanh() - 1.0 / kappa
    }
}

impl SphereNdf for VonMisesFisher {
    fn d_cos(&self, u: f64) -> f64 {
        self.peak * (self.kappa * (u - 1.0)).exp()
    }

    fn majorant(&self) -> f64 {
        self.peak
    }

    fn angular_width(&self) -> f64 {
        (1.0 / self.kappa.sqrt()).min(1.0)
    }
}
