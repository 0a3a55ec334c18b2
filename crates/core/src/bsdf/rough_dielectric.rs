//! The rough dielectric of Walter et al. 2007, generic over the NDF.

use super::fresnel_dielectric;
use crate::error::{ParamError, check_eta};
use crate::math::Vec3;
use crate::ndf::Ndf;

/// How the masking-shadowing term G combines the two directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Masking {
    /// `G1(wi) G1(wo)` (Walter et al. 2007; what the published fits used).
    #[default]
    Separable,
    /// Height-correlated Smith: `1/(1 + Lambda_i + Lambda_o)` for reflection and
    /// `B(1 + Lambda_i, 1 + Lambda_o)` for transmission.
    Correlated,
}

/// A rough dielectric interface: index 1 above (z > 0), `eta` below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughDielectric<N> {
    ndf: N,
    eta: f64,
    masking: Masking,
}

impl<N: Ndf> RoughDielectric<N> {
    /// A rough dielectric with the given NDF, relative index `eta = n_inside / n_outside`
    /// (finite, > 0, != 1) and masking.
    pub fn new(ndf: N, eta: f64, masking: Masking) -> Result<Self, ParamError> {
        Ok(Self {
            ndf,
            eta: check_eta(eta)?,
            masking,
        })
    }

    /// The microfacet distribution.
    pub fn ndf(&self) -> &N {
        &self.ndf
    }

    /// The relative index `n_inside / n_outside`.
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// The masking model.
    pub fn masking(&self) -> Masking {
        self.masking
    }

    /// `f(wi, wo) |wo.z|` by the single-scattering model of Walter et al. 2007 (theory section 5):
    /// reflection when `wi` and `wo` are on the same side, transmission otherwise; no radiance
    /// `1/eta^2` scaling. Zero for grazing directions and for configurations no facet connects.
    pub fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        let (ci, co) = (wi.z, wo.z);
        if ci == 0.0 || co == 0.0 {
            return 0.0;
        }
        let reflect = ci * co > 0.0;
        let (n_i, n_o) = (
            if ci > 0.0 { 1.0 } else { self.eta },
            if co > 0.0 { 1.0 } else { self.eta },
        );
        let h = if reflect {
            wi + wo
        } else {
            -(wi * n_i + wo * n_o)
        };
        let len = h.norm();
        if !(len > 0.0) {
            return 0.0;
        }
        let mut h = h / len;
        if h.z < 0.0 {
            h = -h;
        }
        let (di, d_o) = (wi.dot(&h), wo.dot(&h));
        // Each direction must lie on the same side of the facet as of the macro-surface.
        if di * ci <= 0.0 || d_o * co <= 0.0 {
            return 0.0;
        }
        let d = self.ndf.d(h);
        if d == 0.0 {
            return 0.0;
        }
        let f = fresnel_dielectric(di, self.eta);
        let g = self.g(wi, wo, reflect);
        if reflect {
            f * g * d / (4.0 * ci.abs())
        } else {
            let denom = n_i * di + n_o * d_o;
            (di * d_o).abs() / ci.abs() * n_o * n_o * (1.0 - f) * g * d / (denom * denom)
        }
    }

    /// The masking-shadowing term for the configured model.
    fn g(&self, wi: Vec3, wo: Vec3, reflect: bool) -> f64 {
        match self.masking {
            Masking::Separable => self.ndf.g1(wi) * self.ndf.g1(wo),
            Masking::Correlated => {
                let li = self.ndf.lambda(Vec3::new(wi.x, wi.y, wi.z.abs()));
                let lo = self.ndf.lambda(Vec3::new(wo.x, wo.y, wo.z.abs()));
                if reflect {
                    1.0 / (1.0 + li + lo)
                } else {
                    beta_fn(1.0 + li, 1.0 + lo)
                }
            }
        }
    }
}

/// The Beta function `B(a, b) = Gamma(a) Gamma(b) / Gamma(a + b)` for `a, b >= 1`.
fn beta_fn(a: f64, b: f64) -> f64 {
    use statrs::function::gamma::ln_gamma;
    if !a.is_finite() || !b.is_finite() {
        return 0.0;
    }
    (ln_gamma(a) + ln_gamma(b) - ln_gamma(a + b)).exp()
}
