//! Normal distributions on the whole sphere, for porous, granular and volumetric surfaces
//! (d'Eon 2023, section 3; theory section 7).
//!
//! A [`SphereNdf`] is isotropic about z and bounded. Its projected area `sigma(w)` has no
//! closed form in general: it is the integral of `D` against the projected area of a ring of
//! facets at one inclination (the cross section of a delta NDF), computed by Gauss-Legendre
//! quadrature in the facet inclination. Height-field NDFs are special cases (zero below the
//! horizon), seen on the sphere through [`HeightField`], and the quadrature reproduces their
//! closed-form Smith `sigma`.
//!
//! Only the shape of `D` matters to a random walk in a half-space (a common factor rescales
//! height), but the NDFs here keep the projected-area normalisation `integral D wm.z dwm = 1`
//! wherever it is defined.

mod heightfield;
mod porous;
mod vmf;

pub use heightfield::HeightField;
pub use porous::Porous;
pub use vmf::VonMisesFisher;

use crate::math::Vec3;
use crate::quadrature::GaussLegendre;
use std::f64::consts::PI;

/// An isotropic, bounded normal distribution on the whole sphere.
pub trait SphereNdf: Clone + Send + Sync {
    /// `D` as a function of `u = cos theta_m` in [-1, 1].
    fn d_cos(&self, u: f64) -> f64;

    /// A constant majorant `Dbar >= D(wm)` for every `wm` on the sphere.
    fn majorant(&self) -> f64;

    /// The angular width (radians) of the NDF's narrowest feature near the pole; it sets the
    /// quadrature panels of [`SphereNdf::sigma`].
    fn angular_width(&self) -> f64;

    /// Whether `D` vanishes below the horizon (`u <= 0`), as for height fields. The
    /// null-scattering walk then takes its majorant on the upper hemisphere only.
    fn is_height_field(&self) -> bool {
        false
    }

    /// Projected area `sigma(w) = integral max(0, w.wm) D(wm) dwm`; by default by quadrature
    /// of `D` against the delta-NDF cross section [`ring_cross_section`]
    /// ([`sigma_by_quadrature`]).
    fn sigma(&self, w: Vec3) -> f64 {
        sigma_by_quadrature(|u| self.d_cos(u), w.z, self.angular_width())
    }
}

/// Projected area seen from a direction with `cos theta = c` of a ring of unit-area facets
/// spread uniformly in azimuth at inclination `cos theta_m = u`:
/// `K(c, u) = integral_0^{2 pi} max(0, c u + s sm cos phi) dphi` with `s`, `sm` the sines.
/// This is the Smith projected area of a Dirac delta NDF (the Green's function of `sigma`).
pub fn ring_cross_section(c: f64, u: f64) -> f64 {
    let s = (1.0 - c * c).max(0.0).sqrt();
    let sm = (1.0 - u * u).max(0.0).sqrt();
    let a = c * u;
    let b = s * sm;
    if a >= b {
        2.0 * PI * a
    } else if a <= -b {
        0.0
    } else {
        let r = (-a / b).clamp(-1.0, 1.0);
        let phi1 = r.acos();
        2.0 * (a * phi1 + b * (1.0 - r * r).sqrt())
    }
}

/// `integral_0^pi D(cos theta_m) K(c, cos theta_m) sin theta_m d theta_m`, with panels refined
/// geometrically near the pole (down to `width / 8`), split at the horizon and at the kinks of
/// `K` (`theta_m = pi/2 -+ theta` for `w` in the upper hemisphere, where `K` behaves like a power 3/2 of the distance); panels
/// touching a kink are integrated with a substitution that removes the singularity.
pub fn sigma_by_quadrature(d_cos: impl Fn(f64) -> f64, c: f64, width: f64) -> f64 {
    // K switches form where |c u| = s sm: at theta_m = pi/2 -+ theta' with theta' the angle
    // between w and the nearer pole.
    let theta = c.abs().min(1.0).acos();
    let half_pi = 0.5 * PI;
    let kinks: Vec<f64> = [half_pi - theta, half_pi + theta]
        .into_iter()
        .filter(|k| *k > 0.0 && *k < PI)
        .collect();
    let mut edges = pole_refined_edges(width);
    edges.extend(&kinks);
    // Midpoints between consecutive edges keep every panel touching at most one kink.
    edges.sort_by(f64::total_cmp);
    edges.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let mids: Vec<f64> = edges.windows(2).map(|e| 0.5 * (e[0] + e[1])).collect();
    edges.extend(mids);
    edges.sort_by(f64::total_cmp);
    let integrand = |tm: f64| {
        let (st, ct) = tm.sin_cos();
        d_cos(ct) * ring_cross_section(c, ct) * st
    };
    let rule = rule();
    let is_kink = |x: f64| kinks.iter().any(|k| (k - x).abs() < 1e-12);
    edges
        .windows(2)
        .filter(|e| e[1] > e[0])
        .map(|e| {
            if is_kink(e[0]) {
                rule.integrate_endpoint_singular(e[0], e[1], integrand)
            } else if is_kink(e[1]) {
                rule.integrate_endpoint_singular(e[1], e[0], integrand)
            } else {
                rule.integrate(e[0], e[1], integrand)
            }
        })
        .sum()
}

/// Panel edges on [0, pi]: the horizon and a geometric sequence from `width / 8` upward.
fn pole_refined_edges(width: f64) -> Vec<f64> {
    let mut edges = vec![0.0, 0.5 * PI, PI];
    let mut e = (width / 8.0).clamp(1e-6, 0.5);
    while e < PI {
        edges.push(e);
        e *= 2.0;
    }
    edges
}

/// `integral D(wm) dwm` over the sphere: the total microfacet area per unit macro area.
pub fn total_area(d_cos: impl Fn(f64) -> f64, width: f64) -> f64 {
    let mut edges = pole_refined_edges(width);
    edges.sort_by(f64::total_cmp);
    edges.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    2.0 * PI * rule().integrate_panels(&edges, |tm| d_cos(tm.cos()) * tm.sin())
}

/// The rule used per panel (built per call: cheap next to the integrand evaluations).
fn rule() -> GaussLegendre {
    GaussLegendre::new(32)
}
