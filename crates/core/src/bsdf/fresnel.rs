//! Fresnel reflectance.

use nalgebra::Complex;

/// Exact unpolarised Fresnel reflectance of a smooth dielectric interface.
///
/// `cos_i` is the cosine between the incident direction (pointing away from the interface)
/// and the interface normal; `eta = n_below / n_above` with the normal pointing above. A
/// negative `cos_i` means light arrives from below, where the relative index is `1 / eta`.
/// Returns 1 under total internal reflection.
pub fn fresnel_dielectric(cos_i: f64, eta: f64) -> f64 {
    let (num, den) = reflectance_fraction(cos_i, eta, 1.0 / eta);
    num / den
}

/// [`fresnel_dielectric`] as a fraction `(num, den)`, `den > 0`, with the inverse index
/// `inv_eta = 1 / eta` precomputed: `(1, 1)` under total internal reflection, otherwise
/// [`fresnel_dielectric_fraction`] of the incident cosine and the transmitted cosine from
/// Snell's law, with `sin^2` of the incident angle free of cancellation ([`sin2_from_cos`]). For
/// callers that fold the division into their own or compare `u * den < num` for a sampling
/// choice.
#[inline]
pub(crate) fn reflectance_fraction(cos_i: f64, eta: f64, inv_eta: f64) -> (f64, f64) {
    reflectance_fraction_sin2(cos_i, sin2_from_cos(cos_i.abs().min(1.0)), eta, inv_eta)
}

/// [`reflectance_fraction`] given also `sin2_i`, the incident `sin^2` (`1 - cos_i^2`), for
/// callers that have it more accurately than from `cos_i` (from a cross product).
#[inline]
pub(crate) fn reflectance_fraction_sin2(
    cos_i: f64,
    sin2_i: f64,
    eta: f64,
    inv_eta: f64,
) -> (f64, f64) {
    let (cos_i, eta_t, inv_eta_t) = if cos_i >= 0.0 {
        (cos_i.min(1.0), eta, inv_eta)
    } else {
        ((-cos_i).min(1.0), inv_eta, eta)
    };
    let sin2_t = sin2_i * (inv_eta_t * inv_eta_t);
    if sin2_t >= 1.0 {
        return (1.0, 1.0);
    }
    fresnel_dielectric_fraction(cos_i, (1.0 - sin2_t).sqrt(), eta_t)
}

/// `sin^2 = 1 - c^2` as `(1 - c)(1 + c)`, for `0 <= c <= 1`: `1 - c` is exact for `c >= 1/2`,
/// so the result keeps its relative accuracy near normal incidence, where `1 - c*c` loses the
/// rounding of `c*c` (relative `1e-16 / sin^2`: with eta 100 the critical angle has `sin^2 =
/// 1e-4`, and near it the transmitted cosine `sqrt(1 - sin^2 / eta_t^2)` multiplied that into
/// 3.5e-7 of the reflectance).
#[inline]
pub(crate) fn sin2_from_cos(c: f64) -> f64 {
    (1.0 - c) * (1.0 + c)
}

/// The unpolarised dielectric Fresnel reflectance `(rs^2 + rp^2) / 2 = num / den` (`den > 0`)
/// from the incident and transmitted cosines `cos_i, cos_t >= 0` and the relative index `eta`
/// of the transmission side over the incident side: `rs = (cos_i - eta cos_t) / (cos_i + eta
/// cos_t)`, `rp = (eta cos_i - cos_t) / (eta cos_i + cos_t)` over their common denominator.
/// For callers that know `cos_t` anyway (refraction, transmission) and can fold the division
/// into their own, or compare `u * den < num` for a sampling choice.
#[inline]
pub(crate) fn fresnel_dielectric_fraction(cos_i: f64, cos_t: f64, eta: f64) -> (f64, f64) {
    let (s_num, s_den) = (cos_i - eta * cos_t, cos_i + eta * cos_t);
    let (p_num, p_den) = (eta * cos_i - cos_t, eta * cos_i + cos_t);
    let (s2, p2) = (s_den * s_den, p_den * p_den);
    (0.5 * (s_num * s_num * p2 + p_num * p_num * s2), s2 * p2)
}

/// Exact unpolarised Fresnel reflectance of a smooth conductor, relative complex index
/// `eta = n + i k` (the metal's index over the outside medium's).
///
/// `cos_i` is the cosine between the incident direction and the interface normal; conductors
/// are two-sided, so its sign is ignored. The transmitted cosine is the principal complex
/// square root of `1 - sin^2 theta_i / eta^2` (pbrt-v4 `FrComplex`). With `k = 0` this equals
/// [`fresnel_dielectric`].
pub fn fresnel_conductor(cos_i: f64, eta: Complex<f64>) -> f64 {
    let cos_i = cos_i.abs().min(1.0);
    if cos_i == 0.0 {
        // Both amplitudes are -1 at grazing incidence; the formulas below would give 0/0 for
        // a real index of 1.
        return 1.0;
    }
    let sin2_i = super::sin2_from_cos(cos_i);
    let sin2_t = Complex::new(sin2_i, 0.0) / (eta * eta);
    let cos_t = (Complex::new(1.0, 0.0) - sin2_t).sqrt();
    let ci = Complex::new(cos_i, 0.0);
    let r_parallel = (eta * ci - cos_t) / (eta * ci + cos_t);
    let r_perpendicular = (ci - eta * cos_t) / (ci + eta * cos_t);
    (0.5 * (r_parallel.norm_sqr() + r_perpendicular.norm_sqr())).min(1.0)
}
