//! The angle conventions of measurement files (`data-format.md`), every rule once.
//!
//! - In-plane files (Walter et al. 2007, theory section 8): light comes from the air and hits
//!   the rough face in the plane of incidence at `theta_i`; `theta_o` is the direction of the
//!   transmitted light inside the glass, 180 degrees straight through; the measured quantity is
//!   `L = scale * f_t(wi, wo) * cos(theta_i) / eta^2`.
//! - General files: spherical coordinates in the surface frame, `theta` the polar angle from
//!   the outside normal (+z) in [0, 180] with 90 excluded, `phi` the azimuth; the measured
//!   quantity is `scale * f(wi, wo)`.

use stfit_core::Vec3;
use stfit_core::math::radians;

/// The relative index of refraction of the glass unless one is given (the Walter et al. 2007
/// samples: 1.51).
pub const DEFAULT_ETA: f64 = 1.51;

/// The range of `theta_i_deg`, as messages state it.
pub const THETA_I_RANGE: &str = "[0, 90)";

/// The range of `theta_o_deg`, as messages state it.
pub const THETA_O_RANGE: &str = "(90, 270)";

/// The range of a general file's polar angles, as messages state it.
pub const THETA_RANGE: &str = "[0, 180] with 90 excluded";

/// Whether a general file's polar angle (degrees) is in [`THETA_RANGE`]: 90 (grazing) has no
/// side.
pub fn theta_in_range(theta_deg: f64) -> bool {
    (0.0..=180.0).contains(&theta_deg) && theta_deg != 90.0
}

/// An azimuth in degrees reduced to [0, 360] (360 only as said below): any finite azimuth a
/// file holds means the same direction as its reduction, which then converts to radians
/// without the rounding of a huge angle. Azimuths that differ by whole turns reduce to the
/// same number, whatever their signs (`-330` and `30`, `-80` and `1e17`): the remainder of a
/// division of doubles is exact, and a negative remainder plus 360 is exact whenever another
/// double differs from it by whole turns (that double's remainder is that sum). A negative
/// azimuth too small for its sum with 360 to be exact, such as `-1e-20`, differs by whole
/// turns from no other double, and reduces to 360.
pub fn reduced_azimuth_deg(phi_deg: f64) -> f64 {
    // `+ 0.0` turns the remainder -0 of a negative whole number of turns into 0.
    phi_deg.rem_euclid(360.0) + 0.0
}

/// The unit direction of polar angle `theta_deg` from +z and azimuth `phi_deg` (any finite
/// value, [`reduced_azimuth_deg`]): `(sin theta cos phi, sin theta sin phi, cos theta)`.
pub fn spherical_from_deg(theta_deg: f64, phi_deg: f64) -> Vec3 {
    let phi = radians(reduced_azimuth_deg(phi_deg));
    stfit_core::math::spherical_direction(radians(theta_deg), phi)
}

/// The spherical angles `((theta_i, phi_i), (theta_o, phi_o))` of an in-plane configuration:
/// `wi` at azimuth 180 (the light comes from -x), `wo` at azimuth 0 when it leans forward
/// (`theta_o > 180`) and 180 otherwise.
pub fn in_plane_to_spherical(theta_i_deg: f64, theta_o_deg: f64) -> ((f64, f64), (f64, f64)) {
    let lean = theta_o_deg - 180.0;
    let phi_o = if lean > 0.0 { 0.0 } else { 180.0 };
    ((theta_i_deg, 180.0), (180.0 - lean.abs(), phi_o))
}

/// Whether an incidence angle (degrees) is in [`THETA_I_RANGE`]: light from the outside,
/// grazing excluded.
pub fn theta_i_in_range(theta_i_deg: f64) -> bool {
    (0.0..90.0).contains(&theta_i_deg)
}

/// Whether a transmitted direction (degrees) is in [`THETA_O_RANGE`]: inside the glass,
/// grazing excluded.
pub fn theta_o_in_range(theta_o_deg: f64) -> bool {
    theta_o_deg > 90.0 && theta_o_deg < 270.0
}

/// Direction toward the light for incidence `theta_i` (degrees) from the outside:
/// `wi = (-sin theta_i, 0, cos theta_i)`.
pub fn wi_from_deg(theta_i_deg: f64) -> Vec3 {
    let t = radians(theta_i_deg);
    Vec3::new(-t.sin(), 0.0, t.cos())
}

/// Transmitted direction inside the glass for `theta_o` (degrees, 180 straight through):
/// `wo = (sin(theta_o - 180), 0, -cos(theta_o - 180))`.
pub fn wo_from_deg(theta_o_deg: f64) -> Vec3 {
    let t = radians(theta_o_deg - 180.0);
    Vec3::new(t.sin(), 0.0, -t.cos())
}

/// The direction pair `(wi, wo)` of a measured configuration.
pub fn pair_from_deg(theta_i_deg: f64, theta_o_deg: f64) -> (Vec3, Vec3) {
    (wi_from_deg(theta_i_deg), wo_from_deg(theta_o_deg))
}

/// `L / (scale f)`: the measured quantity per unit BSDF value, `cos(theta_i) / eta^2` (the
/// radiance inside the glass leaves through its smooth back face into air, which divides it by
/// `eta^2`).
pub fn l_per_bsdf(wi: Vec3, eta: f64) -> f64 {
    wi.z.abs() / (eta * eta)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Azimuths that differ by whole turns give the same direction to the last bit, however
    /// large: 1e17 and 1e20 degrees are 280 degrees plus whole turns.
    #[test]
    fn whole_turns_of_azimuth_give_the_same_direction() {
        let base = spherical_from_deg(150.0, 280.0);
        for phi in [280.0 + 360.0 * 1e12, 36_000_000_000_000_280.0, 1e17, 1e20] {
            assert_eq!(spherical_from_deg(150.0, phi), base, "phi {phi}");
        }
        for phi in [-80.0, -440.0, -360.0 * 1e12 + 280.0, -1e17 - 160.0] {
            assert_eq!(spherical_from_deg(150.0, phi), base, "phi {phi}");
        }
        for (phi, reduced) in [(-330.0, 30.0), (-360.0, 0.0), (720.0, 0.0), (-1e-20, 360.0)] {
            let r = reduced_azimuth_deg(phi);
            assert_eq!(r.to_bits(), f64::to_bits(reduced), "phi {phi}: {r}");
        }
    }
}
