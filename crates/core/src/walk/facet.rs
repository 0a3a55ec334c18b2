//! The BSDF of a single microfacet, as the random walk needs it: sampling at a given facet
//! normal, and the phase function toward a given direction for next-event estimation.
//!
//! Facet normals `m` are *outward*: they point to the upper medium (`m.z > 0`), and light may
//! arrive at a facet from either side. Directions are in the macro-surface frame.

use super::Microsurface;
use crate::bsdf::{Bsdf, HalfVector, fresnel_conductor, reflect, refract_with_fresnel};
use crate::error::{ParamError, check_eta, finite};
use crate::math::{Frame, Vec3, safe_sqrt};
use crate::ndf::Ndf;
use nalgebra::Complex;
use rand::{Rng, RngExt};
use std::f64::consts::{FRAC_1_PI, PI};

/// The facets a walker can hit at a scattering event, seen from its incident direction: the
/// visible-normal distribution that the phase function averages over.
///
/// Normals are outward (toward the upper medium). For the height-field walk
/// ([`HeightFieldHit`]) the density is `D_vis(m)` and integrates to 1; for a tentative collision
/// of the null-scattering walk ([`NullHit`](super::NullHit)) it integrates to the probability
/// that the collision is real, so that phase functions summed over tentative collisions
/// estimate those of the real ones.
pub trait VisibleNormals {
    /// Unit direction back toward where the light came from (`-w` for travel along `w`).
    fn wi(&self) -> Vec3;

    /// True when the walker is in the lower medium and sees the surface from below.
    fn inside(&self) -> bool;

    /// `wi` in the frame of the surface on the walker's side (mirrored through the origin from
    /// below, so that the surface seen from below has its normals up again).
    #[inline]
    fn wi_side(&self) -> Vec3 {
        if self.inside() { -self.wi() } else { self.wi() }
    }

    /// Density per unit solid angle of the outward normals `m` of the facets that scatter.
    fn density(&self, m: Vec3) -> f64;

    /// Draws an outward normal `m` and a weight `w` with `E[w g(m)] = integral density(m) g(m)
    /// dm` for every `g`.
    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> (Vec3, f64);
}

/// A hit on a height-field microsurface: visible normals `max(0, wi_side . m) D(m) /
/// sigma(wi_side)`, drawn exactly by [`Ndf::sample_visible`].
#[derive(Debug, Clone, Copy)]
pub struct HeightFieldHit<'a, N> {
    ndf: &'a N,
    wi: Vec3,
    inside: bool,
    /// The normaliser of the density: `sigma(wi_side)`, or that over `mass`.
    sigma: f64,
    /// The total of the density: 1, or the probability that a flight reached the hit.
    mass: f64,
}

impl<'a, N: Ndf> HeightFieldHit<'a, N> {
    /// A hit by light arriving from `wi` on the given side.
    pub fn new(ndf: &'a N, wi: Vec3, inside: bool) -> Self {
        let wi_side = if inside { -wi } else { wi };
        Self::with_sigma(ndf, wi, inside, ndf.sigma(wi_side))
    }

    /// As [`HeightFieldHit::new`] with `sigma(wi_side)` already known.
    #[inline]
    pub fn with_sigma(ndf: &'a N, wi: Vec3, inside: bool, sigma: f64) -> Self {
        Self {
            ndf,
            wi,
            inside,
            sigma,
            mass: 1.0,
        }
    }

    /// The visible normals of a hit that a flight reaches with probability
    /// `sigma / sigma_per_hit`, scaled by that probability: density `max(0, wi_side . m) D(m)
    /// / sigma_per_hit`, sampled with that weight. `sigma_per_hit` stays finite where `sigma`
    /// and the probability both vanish.
    #[inline]
    pub(crate) fn reached(
        ndf: &'a N,
        wi: Vec3,
        inside: bool,
        sigma: f64,
        sigma_per_hit: f64,
    ) -> Self {
        let mass = sigma / sigma_per_hit;
        Self {
            ndf,
            wi,
            inside,
            sigma: sigma_per_hit,
            mass: if mass.is_finite() { mass } else { 0.0 },
        }
    }
}

impl<N: Ndf> VisibleNormals for HeightFieldHit<'_, N> {
    #[inline]
    fn wi(&self) -> Vec3 {
        self.wi
    }

    #[inline]
    fn inside(&self) -> bool {
        self.inside
    }

    #[inline]
    fn density(&self, m: Vec3) -> f64 {
        let c = self.wi_side().dot(&m);
        if c <= 0.0 || self.sigma.is_nan() || self.sigma <= 0.0 {
            return 0.0;
        }
        // 1/sigma does not depend on m: its division runs beside D's instead of after it.
        let inv_sigma = 1.0 / self.sigma;
        c * inv_sigma * self.ndf.d(m)
    }

    #[inline]
    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> (Vec3, f64) {
        (self.ndf.sample_visible(self.wi_side(), rng), self.mass)
    }
}

/// A direction scattered by a facet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FacetSample {
    /// Outgoing unit direction, macro-surface frame.
    pub wo: Vec3,
    /// `f(wi, wo; m) |wo . m| / pdf`: the facet's throughput for this sample.
    pub weight: f64,
}

/// The scattering of light by one microfacet of outward normal `m`.
///
/// `phase` is the phase function of the microsurface at a hit: the density per unit solid angle
/// of `wo` of light scattered from `wi`, averaged over the visible facets,
/// `p(wi -> wo) = integral D_vis(m) f(wi, wo; m) |wo . m| [wo leaves on wo's side] dm`, where only
/// scattering that leaves the facet on the side of the macro-surface that `wo` points to counts
/// (other light cannot reach `wo` without scattering again). Smooth facets evaluate it in closed
/// form through the half vector; others may return an unbiased Monte Carlo estimate.
pub trait Facet: Send + Sync {
    /// Scatters light arriving from `wi` (either side of the facet) at a facet of outward normal
    /// `m`; `None` if the light is absorbed.
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, m: Vec3, rng: &mut R) -> Option<FacetSample>;

    /// The phase function `p(wi -> wo)` at a hit (see the trait documentation), or an unbiased
    /// estimate of it.
    fn phase<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64;

    /// The density with which a hit followed by [`Facet::scatter`] sends light to `wo` (on `wo`'s
    /// side of the macro-surface), or an unbiased estimate of it: `phase` with the facet's
    /// sampling density in place of `f |wo . m|`.
    fn phase_pdf<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64;

    /// The density with which a hit followed by [`Facet::scatter`] sends the walker along `wo`
    /// on the lower side of the interface if `o_inside` (else the upper), in closed form, or
    /// `None` for facets that only estimate their phase function. The side is given rather
    /// than read off `wo.z`: a walker refracted into the lower medium may travel upward in it.
    /// Bidirectional estimation ([`Estimator`](super::Estimator) on a
    /// [`Microsurface`]) weights paths by these densities.
    fn side_pdf<V: VisibleNormals>(&self, _vis: &V, _wo: Vec3, _o_inside: bool) -> Option<f64> {
        None
    }

    /// The index of refraction below the interface relative to the one above it: 1 for a facet
    /// that never transmits. The walk is reciprocal with it:
    /// `f(wi, wo) / n_o^2 = f(wo, wi) / n_i^2`.
    fn relative_index(&self) -> f64 {
        1.0
    }
}

/// A smooth dielectric facet: index 1 above, `eta` below (`eta` may be below 1). Light is
/// reflected with the exact Fresnel probability and refracted otherwise; sample weights are 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DielectricFacet {
    eta: f64,
    /// `1 / eta`.
    inv_eta: f64,
}

impl DielectricFacet {
    /// A dielectric facet with relative index `eta = n_below / n_above` (finite, > 0, != 1).
    pub fn new(eta: f64) -> Result<Self, ParamError> {
        let eta = check_eta(eta)?;
        Ok(Self {
            eta,
            inv_eta: 1.0 / eta,
        })
    }

    /// The relative index `n_below / n_above`.
    pub fn eta(&self) -> f64 {
        self.eta
    }
}

impl Facet for DielectricFacet {
    #[inline(always)]
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, m: Vec3, rng: &mut R) -> Option<FacetSample> {
        // Under total internal reflection the Fresnel reflectance is 1: no choice to draw.
        // Refract with probability 1 - F, decided without dividing for F.
        let wo = match refract_with_fresnel(wi, m, self.eta, self.inv_eta) {
            Some((wt, (num, den))) if rng.random::<f64>() * den >= num => wt,
            _ => reflect(wi, m),
        };
        Some(FacetSample { wo, weight: 1.0 })
    }

    /// Closed form (Walter et al. 2007 through the visible-normal density): with `h` the
    /// (generalised) half vector, reflection gives `F D_vis(h) / (4 |wi.h|)` and transmission
    /// `(1 - F) D_vis(h) |wo.h| n_o^2 / (n_i wi.h + n_o wo.h)^2`
    /// (`HalfVector::dielectric_weight`).
    ///
    /// The geometric checks need only the signs of `wi.v` and `wo.v` for the unnormalised half
    /// vector `v = |v| h`, so the normalisation (whose square root and division run side by
    /// side) waits until they pass; for many directions they do not.
    #[inline(always)]
    fn phase<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, _rng: &mut R) -> f64 {
        self.phase_to_side(vis, wo, wo.z < 0.0)
    }

    /// Sample weights are 1, so the sampling density is the phase function.
    fn phase_pdf<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        self.phase(vis, wo, rng)
    }

    fn side_pdf<V: VisibleNormals>(&self, vis: &V, wo: Vec3, o_inside: bool) -> Option<f64> {
        Some(self.phase_to_side(vis, wo, o_inside))
    }

    fn relative_index(&self) -> f64 {
        self.eta
    }
}

impl DielectricFacet {
    /// [`Facet::phase`] toward `wo` leaving into the lower medium if `o_inside`, whatever the
    /// sign of `wo.z` ([`Facet::side_pdf`]). Inlined into the loops over target directions
    /// of next-event estimation, where what depends on the hit alone is then computed once
    /// per hit.
    #[inline(always)]
    fn phase_to_side<V: VisibleNormals>(&self, vis: &V, wo: Vec3, o_inside: bool) -> f64 {
        let wi = vis.wi();
        let n_i = if vis.inside() { self.eta } else { 1.0 };
        let n_o = if o_inside { self.eta } else { 1.0 };
        let reflection = o_inside == vis.inside();
        let v = HalfVector::unnormalised(wi, wo, n_i, n_o, reflection);
        let n2 = v.norm_squared();
        let (v, n2) = if n2 > 1e-300 && n2 < 1e300 {
            // Oriented to the walker's side, as `HalfVector::of_pair` would.
            (if vis.wi_side().dot(&v) < 0.0 { -v } else { v }, n2)
        } else {
            // Degenerate (measure zero) or astronomically large half vectors: normalise first.
            match HalfVector::of_pair(wi, wo, n_i, n_o, reflection, vis.wi_side()) {
                Some(hv) => (hv.h, 1.0),
                None => return 0.0,
            }
        };
        let side = if vis.inside() { -1.0 } else { 1.0 };
        // |v| times wi.h and wo.h.
        let (vi, vo) = (wi.dot(&v), wo.dot(&v));
        // The facet must face the walker, and wo must leave it on the right side.
        if side * vi <= 0.0 || (side * vo > 0.0) != reflection {
            return 0.0;
        }
        // 1/|v| = sqrt(n2) / n2: the root and the division run side by side.
        let inv_len = n2.sqrt() * (1.0 / n2);
        let hv = HalfVector::from_scaled(v, vi, vo, inv_len, n_i, n_o, reflection);
        let d_vis = vis.density(hv.h);
        if d_vis == 0.0 {
            return 0.0;
        }
        d_vis * hv.dielectric_weight(self.eta, self.inv_eta)
    }
}

/// A smooth two-sided mirror facet: a perfect mirror, a constant reflectance, or a Fresnel
/// conductor of complex index `n + i k` ([`fresnel_conductor`]). Opaque: the walker never
/// crosses the interface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConductorFacet {
    reflectance: Reflectance,
}

/// How a [`ConductorFacet`] reflects.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Reflectance {
    Constant(f64),
    Fresnel(Complex<f64>),
}

impl ConductorFacet {
    /// A perfect mirror (reflectance 1).
    pub fn mirror() -> Self {
        Self {
            reflectance: Reflectance::Constant(1.0),
        }
    }

    /// A mirror of constant reflectance in `[0, 1]`.
    pub fn with_reflectance(reflectance: f64) -> Result<Self, ParamError> {
        let reflectance = check_unit("reflectance", reflectance)?;
        Ok(Self {
            reflectance: Reflectance::Constant(reflectance),
        })
    }

    /// A smooth conductor with the exact unpolarised Fresnel reflectance of the complex index
    /// `n + i k` in the supported range ([`crate::error::check_conductor`]).
    pub fn fresnel(n: f64, k: f64) -> Result<Self, ParamError> {
        Ok(Self {
            reflectance: {
                let (n, k) = crate::error::check_conductor(n, k)?;
                Reflectance::Fresnel(Complex::new(n, k))
            },
        })
    }

    /// The reflectance at incidence cosine `cos_i` (either side).
    #[inline]
    pub fn reflectance(&self, cos_i: f64) -> f64 {
        match self.reflectance {
            Reflectance::Constant(r) => r,
            Reflectance::Fresnel(eta) => fresnel_conductor(cos_i, eta),
        }
    }
}

impl Facet for ConductorFacet {
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, m: Vec3, _rng: &mut R) -> Option<FacetSample> {
        Some(FacetSample {
            wo: reflect(wi, m),
            weight: self.reflectance(wi.dot(&m)),
        })
    }

    /// `R(wi.h) D_vis(h) / (4 |wi.h|)` with `h` the reflection half vector.
    fn phase<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        let pdf = self.phase_pdf(vis, wo, rng);
        if pdf == 0.0 {
            return 0.0;
        }
        let h = (vis.wi() + wo).normalize();
        self.reflectance(vis.wi().dot(&h)) * pdf
    }

    fn phase_pdf<V: VisibleNormals, R: Rng + ?Sized>(
        &self,
        vis: &V,
        wo: Vec3,
        _rng: &mut R,
    ) -> f64 {
        self.reflection_pdf(vis, wo, wo.z < 0.0)
    }

    fn side_pdf<V: VisibleNormals>(&self, vis: &V, wo: Vec3, o_inside: bool) -> Option<f64> {
        Some(self.reflection_pdf(vis, wo, o_inside))
    }
}

impl ConductorFacet {
    /// The density of reflected directions `wo` on the lower side if `o_inside`:
    /// `D_vis(h) / (4 |wo.h|)`, 0 on the other side of the interface, which reflection never
    /// reaches.
    #[inline]
    fn reflection_pdf<V: VisibleNormals>(&self, vis: &V, wo: Vec3, o_inside: bool) -> f64 {
        if o_inside != vis.inside() {
            return 0.0;
        }
        let Some(hv) = HalfVector::of_pair(vis.wi(), wo, 1.0, 1.0, true, vis.wi_side()) else {
            return 0.0;
        };
        let d_vis = vis.density(hv.h);
        if d_vis == 0.0 {
            return 0.0;
        }
        d_vis * hv.jacobian()
    }
}

/// A two-sided Lambertian facet of albedo in `[0, 1]`: light leaves on the side it came from
/// with density `|wo . m| / pi`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LambertianFacet {
    albedo: f64,
}

impl LambertianFacet {
    /// A Lambertian facet with albedo in `[0, 1]`.
    pub fn new(albedo: f64) -> Result<Self, ParamError> {
        Ok(Self {
            albedo: check_unit("albedo", albedo)?,
        })
    }

    /// The albedo.
    pub fn albedo(&self) -> f64 {
        self.albedo
    }

    /// Cosine-weighted density of `wo` around the facet side that `wi` is on.
    #[inline]
    fn cos_density(wi: Vec3, wo: Vec3, m: Vec3) -> f64 {
        let (ci, co) = (wi.dot(&m), wo.dot(&m));
        if ci * co > 0.0 {
            co.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }
}

impl Facet for LambertianFacet {
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, m: Vec3, rng: &mut R) -> Option<FacetSample> {
        let n = if wi.dot(&m) >= 0.0 { m } else { -m };
        let (u1, u2): (f64, f64) = (rng.random(), rng.random());
        let r = u1.sqrt();
        let (sp, cp) = (2.0 * PI * u2).sin_cos();
        let local = Vec3::new(r * cp, r * sp, safe_sqrt(1.0 - u1));
        Some(FacetSample {
            wo: Frame::from_normal(n).to_world(local),
            weight: self.albedo,
        })
    }

    /// Monte Carlo over one visible facet normal.
    fn phase<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        self.albedo * self.phase_pdf(vis, wo, rng)
    }

    fn phase_pdf<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        if (wo.z < 0.0) != vis.inside() {
            return 0.0;
        }
        let (m, weight) = vis.sample(rng);
        weight * Self::cos_density(vis.wi(), wo, m)
    }
}

/// Any [`Bsdf`] used as the facet BSDF, in the facet's frame (`z` along the outward normal).
/// The phase function is a one-normal Monte Carlo estimate, so delta lobes of the inner BSDF are
/// missed by next-event estimation: use [`DielectricFacet`] or [`ConductorFacet`] for smooth
/// facets. For bi-scale roughness use a [`Microsurface`] as the facet directly (it implements
/// [`Facet`] without the pdf walk that [`Bsdf::sample`] adds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfFacet<B>(pub B);

/// Draws a visible facet for a one-normal Monte Carlo phase estimate and returns its frame and
/// weight, or `None` if `wo` cannot leave that facet on `wo`'s side of the macro-surface.
#[inline]
fn visible_frame<V: VisibleNormals, R: Rng + ?Sized>(
    vis: &V,
    wo: Vec3,
    rng: &mut R,
) -> Option<(Frame, f64)> {
    let (m, weight) = vis.sample(rng);
    ((wo.dot(&m) < 0.0) == (wo.z < 0.0) && weight > 0.0).then(|| (Frame::from_normal(m), weight))
}

impl<B: Bsdf> Facet for BsdfFacet<B> {
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, m: Vec3, rng: &mut R) -> Option<FacetSample> {
        let frame = Frame::from_normal(m);
        let s = self.0.sample(frame.to_local(wi), rng)?;
        Some(FacetSample {
            wo: frame.to_world(s.wo),
            weight: s.weight,
        })
    }

    fn phase<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        match visible_frame(vis, wo, rng) {
            Some((fr, w)) => w * self.0.eval(fr.to_local(vis.wi()), fr.to_local(wo), rng),
            None => 0.0,
        }
    }

    fn phase_pdf<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        match visible_frame(vis, wo, rng) {
            Some((fr, w)) => w * self.0.pdf(fr.to_local(vis.wi()), fr.to_local(wo), rng),
            None => 0.0,
        }
    }
}

/// A microsurface as the facet BSDF of a larger-scale microsurface: bi-scale roughness. Sampling
/// is one inner walk in the facet's frame; the phase function is a one-normal Monte Carlo
/// estimate with an inner `eval` (or `pdf`) walk.
impl<M: Ndf, F: Facet> Facet for Microsurface<M, F> {
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, m: Vec3, rng: &mut R) -> Option<FacetSample> {
        let frame = Frame::from_normal(m);
        let s = self.sample_walk(frame.to_local(wi), rng)?;
        Some(FacetSample {
            wo: frame.to_world(s.wo),
            weight: s.weight,
        })
    }

    fn phase<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        match visible_frame(vis, wo, rng) {
            Some((fr, w)) => w * self.eval(fr.to_local(vis.wi()), fr.to_local(wo), rng),
            None => 0.0,
        }
    }

    fn phase_pdf<V: VisibleNormals, R: Rng + ?Sized>(&self, vis: &V, wo: Vec3, rng: &mut R) -> f64 {
        match visible_frame(vis, wo, rng) {
            Some((fr, w)) => w * self.pdf(fr.to_local(vis.wi()), fr.to_local(wo), rng),
            None => 0.0,
        }
    }
}

/// Validates a quantity in `[0, 1]`.
fn check_unit(name: &'static str, value: f64) -> Result<f64, ParamError> {
    let value = finite(name, value)?;
    if (0.0..=1.0).contains(&value) {
        Ok(value)
    } else {
        Err(ParamError::OutOfRange {
            name,
            value,
            expected: "in [0, 1]",
        })
    }
}
