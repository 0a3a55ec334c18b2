//! BSDFs behind one trait, for light on either side of the surface.
//!
//! # Convention
//!
//! z > 0 is the outside (index 1), z < 0 the inside (index `eta`, which may be above or below
//! 1). `wi` points toward the light and `wo` toward the viewer or detector, both away from the
//! surface. `eval(wi, wo)` returns `f(wi, wo) |wo.z|`, where `f` is the BSDF of Walter et al.
//! 2007 (eqs. 20 and 21, with `n_o^2` in the transmission term): the radiance leaving toward
//! `wo`, in `wo`'s medium, per unit irradiance arriving from `wi`. Integrated over `wo` it
//! gives the fraction of the incident flux scattered (a lossless dielectric conserves energy
//! with no extra factor); integrated over `wi` against incident radiance, the radiance a
//! detector sees, which inside glass is up to `eta^2` times the incident radiance. This is the
//! value Mitsuba 3's rough dielectric returns in importance mode with `si.wi = wi`. Renderers
//! that call their BSDF with the first direction toward the camera in radiance mode (Mitsuba
//! 3) need the adjoint value, [`radiance_scale`] times this one.
//!
//! # Types
//!
//! - Smooth facets: [`SmoothDielectric`], [`SmoothConductor`] (delta lobes, reported by
//!   [`BsdfSample::delta`]; their `eval` and `pdf` are zero).
//! - [`Lambertian`] reflection.
//! - Microfacet models generic over the NDF, with [`Masking`] chosen per instance:
//!   [`RoughDielectric`] (Walter et al. 2007) and [`RoughConductor`]. They sample visible
//!   normals from the side of `wi`; the weight is `G / G1(wi)` times the Fresnel factor the
//!   lobe choice did not absorb.
//! - The random walks of [`crate::walk`] are BSDFs too, with stochastic `eval` and `pdf`.
//!
//! The closed-form BSDFs also implement [`AnalyticBsdf`], which evaluates without a random
//! generator. Conductors and the Lambertian are two-sided: light from below reflects below.

mod fresnel;
mod lambertian;
mod microfacet;
mod rough_conductor;
mod rough_dielectric;
mod smooth_conductor;
mod smooth_dielectric;

pub use fresnel::{fresnel_conductor, fresnel_dielectric};
pub(crate) use fresnel::{
    fresnel_dielectric_fraction, reflectance_fraction, reflectance_fraction_sin2, sin2_from_cos,
};
pub use lambertian::Lambertian;
pub(crate) use microfacet::refract_with_fresnel;
pub use microfacet::{HalfVector, Masking, SmithTerm, reflect, refract};
pub use rough_conductor::RoughConductor;
pub use rough_dielectric::RoughDielectric;
pub use smooth_conductor::SmoothConductor;
pub use smooth_dielectric::SmoothDielectric;

use crate::math::Vec3;
use rand::Rng;

/// A direction drawn by [`Bsdf::sample`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample {
    /// The sampled outgoing direction (unit length).
    pub wo: Vec3,
    /// `eval(wi, wo) / pdf` for a continuous lobe; for a delta lobe the lobe's
    /// `f |wo.z|` mass divided by the probability of choosing it.
    pub weight: f64,
    /// Solid-angle density of `wo` for a continuous lobe; for a delta lobe the discrete
    /// probability of having chosen it.
    pub pdf: f64,
    /// True when `wo` comes from a Dirac delta lobe (a smooth interface), which `eval` and
    /// `pdf` do not contain.
    pub delta: bool,
}

/// A bidirectional scattering distribution function in the local frame.
///
/// Stochastic BSDFs (random walks) draw from `rng` in `eval` and `pdf` and return unbiased
/// estimates; analytic BSDFs ignore it.
pub trait Bsdf: Send + Sync {
    /// `f(wi, wo) |wo.z|` for unit `wi`, `wo`, excluding delta lobes.
    fn eval<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, rng: &mut R) -> f64;

    /// Draws an outgoing direction for light arriving from `wi`, or `None` if the draw was
    /// absorbed or failed.
    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<BsdfSample>;

    /// Solid-angle density with which [`Bsdf::sample`] returns `wo` from a continuous lobe.
    fn pdf<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, rng: &mut R) -> f64;
}

/// A BSDF in closed form: its value and its sampling density are deterministic functions of
/// the two directions, so they need no random generator (its [`Bsdf::eval`] and
/// [`Bsdf::pdf`] return the same numbers and ignore theirs).
///
/// ```
/// use stfit_core::Vec3;
/// use stfit_core::bsdf::{AnalyticBsdf, Masking, RoughDielectric};
/// use stfit_core::ndf::Ggx;
///
/// let glass = RoughDielectric::new(Ggx::new(0.3)?, 1.5, Masking::Separable)?;
/// let wi = Vec3::new(-0.5, 0.0, 0.75_f64.sqrt()); // light from air, 30 degrees
/// let wo = Vec3::new(0.2, 0.0, -(0.96_f64).sqrt()); // transmitted into the glass
/// assert!(glass.f_cos(wi, wo) > 0.0);
/// assert!(glass.density(wi, wo) > 0.0);
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
pub trait AnalyticBsdf: Bsdf {
    /// `f(wi, wo) |wo.z|` for unit `wi`, `wo`, excluding delta lobes.
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64;

    /// Solid-angle density with which [`Bsdf::sample`] returns `wo` from a continuous lobe.
    fn density(&self, wi: Vec3, wo: Vec3) -> f64;
}

/// The factor that turns `f(wi, wo)` of this crate's convention (`wi` toward the light, see the
/// [module documentation](self)) into the BSDF with the roles of the directions exchanged,
/// `f(wo, wi) = f(wi, wo) (n_wi / n_wo)^2` (generalised reciprocity, Veach 1997, eq. 5.14):
/// `(n_wi / n_wo)^2` for transmission, 1 for reflection, with `n = 1` above the surface and
/// `eta` below. For light from air into glass of index `eta` it is `1 / eta^2`.
///
/// A renderer whose BSDF takes the direction toward the camera first (Mitsuba 3's `si.wi` in
/// radiance mode) multiplies `eval(camera, light)` by `radiance_scale(camera, light, eta)` to
/// get the radiance it transports; tracing importance from the lights, or with `wi` toward the
/// light as here, no factor is needed.
///
/// ```
/// use stfit_core::Vec3;
/// use stfit_core::bsdf::radiance_scale;
///
/// let up = Vec3::new(0.0, 0.0, 1.0);
/// assert_eq!(radiance_scale(up, -up, 1.5), 1.0 / 2.25);
/// assert_eq!(radiance_scale(-up, up, 1.5), 2.25);
/// assert_eq!(radiance_scale(up, up, 1.5), 1.0);
/// ```
pub fn radiance_scale(wi: Vec3, wo: Vec3, eta: f64) -> f64 {
    match (wi.z > 0.0, wo.z > 0.0) {
        (true, false) => 1.0 / (eta * eta),
        (false, true) => eta * eta,
        _ => 1.0,
    }
}
