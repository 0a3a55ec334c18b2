//! BSDFs behind one trait, for light on either side of the surface.
//!
//! Convention: z > 0 is the outside (index 1), z < 0 the inside (index `eta`, which may be
//! above or below 1). `eval(wi, wo)` returns `f(wi, wo) |wo.z|` with no radiance `1/eta^2`
//! scaling (importance transport, as Mitsuba's importance mode).
//!
//! - Smooth facets: [`SmoothDielectric`], [`SmoothConductor`] (delta lobes, reported by
//!   [`BsdfSample::delta`]; their `eval` and `pdf` are zero).
//! - [`Lambertian`] reflection.
//! - Microfacet models generic over the NDF, with [`Masking`] chosen per instance:
//!   [`RoughDielectric`] (Walter et al. 2007) and [`RoughConductor`]. They sample visible
//!   normals from the side of `wi`; the weight is `G / G1(wi)` times the Fresnel factor the
//!   lobe choice did not absorb.
//!
//! Conductors and the Lambertian are two-sided: light from below reflects below.

mod fresnel;
mod lambertian;
mod microfacet;
mod rough_conductor;
mod rough_dielectric;
mod smooth_conductor;
mod smooth_dielectric;

pub(crate) use fresnel::fresnel_dielectric_fraction;
pub use fresnel::{fresnel_conductor, fresnel_dielectric};
pub use lambertian::Lambertian;
pub use microfacet::{Masking, reflect, refract};
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
