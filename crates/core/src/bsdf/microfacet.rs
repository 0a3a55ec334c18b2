//! Pieces shared by the microfacet BSDFs: reflection and refraction about a facet, the side
//! convention for directions below the surface, and Smith masking-shadowing.
//!
//! Smith terms are written with `a(w) = 1 + Lambda(w') = sigma(w') / |w.z|`, where `w'` is `w`
//! flipped to the upper hemisphere ([`upper`]) and `sigma` the projected area: a direction
//! inside a dielectric is masked by the mirrored surface (Walter et al. 2007). One projected-area
//! evaluation per direction gives both the visible-normal density and G.

use crate::math::Vec3;
use crate::ndf::Ndf;

/// How the masking-shadowing term G combines the two directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Masking {
    /// `G1(wi) G1(wo)` (Walter et al. 2007; what the published fits used).
    #[default]
    Separable,
    /// Height-correlated Smith: `1/(1 + Lambda_i + Lambda_o)` for reflection and
    /// `B(1 + Lambda_i, 1 + Lambda_o)` for transmission (Heitz 2014, section 5).
    Correlated,
}

impl Masking {
    /// `G` for reflection from `a_i = 1 + Lambda(wi')` and `a_o = 1 + Lambda(wo')`.
    #[inline]
    pub fn g_reflection(self, a_i: f64, a_o: f64) -> f64 {
        match self {
            Self::Separable => 1.0 / (a_i * a_o),
            Self::Correlated => 1.0 / (a_i + a_o - 1.0),
        }
    }

    /// `G` for transmission from `a_i = 1 + Lambda(wi')` and `a_o = 1 + Lambda(wo')`.
    #[inline]
    pub fn g_transmission(self, a_i: f64, a_o: f64) -> f64 {
        match self {
            Self::Separable => 1.0 / (a_i * a_o),
            Self::Correlated => beta_fn(a_i, a_o),
        }
    }
}

/// `w` flipped to the upper hemisphere (`-w` when `w.z < 0`): the direction from which a
/// surface seen from below is seen as the same height field from above. For an isotropic NDF
/// this is equivalent to mirroring across the tangent plane.
#[inline]
pub(crate) fn upper(w: Vec3) -> Vec3 {
    if w.z < 0.0 { -w } else { w }
}

/// Projected area of the microsurface seen from the side of `w`: `sigma(upper(w))`.
#[inline]
pub(crate) fn projected_area<N: Ndf>(ndf: &N, w: Vec3) -> f64 {
    ndf.sigma(upper(w))
}

/// Mirror reflection of `w` about the unit normal `n` (either orientation).
#[inline]
pub fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    n * (2.0 * w.dot(&n)) - w
}

/// Refraction of `w` through the interface with unit normal `n` on the side of `w`
/// (`w.n >= 0`) and relative index `eta = n_transmitted / n_incident`; `None` under total
/// internal reflection. The result points away from the interface on the other side.
#[inline]
pub fn refract(w: Vec3, n: Vec3, eta: f64) -> Option<Vec3> {
    let cos_i = w.dot(&n);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-w / eta + n * (cos_i / eta - cos_t))
}

/// The Beta function `B(a, b) = Gamma(a) Gamma(b) / Gamma(a + b)` for `a, b >= 1`; zero when
/// either argument is infinite (a grazing direction).
#[inline]
fn beta_fn(a: f64, b: f64) -> f64 {
    use statrs::function::gamma::ln_gamma;
    if !a.is_finite() || !b.is_finite() {
        return 0.0;
    }
    (ln_gamma(a) + ln_gamma(b) - ln_gamma(a + b)).exp()
}
