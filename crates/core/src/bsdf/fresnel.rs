//! Fresnel reflectance.

/// Exact unpolarised Fresnel reflectance of a smooth dielectric interface.
///
/// `cos_i` is the cosine between the incident direction (pointing away from the interface)
/// and the interface normal; `eta = n_below / n_above` with the normal pointing above. A
/// negative `cos_i` means light arrives from below, where the relative index is `1 / eta`.
/// Returns 1 under total internal reflection.
pub fn fresnel_dielectric(cos_i: f64, eta: f64) -> f64 {
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let cos_i = cos_i.min(1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}
