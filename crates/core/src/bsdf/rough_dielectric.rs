//! The rough dielectric of Walter et al. 2007, generic over the NDF.

use super::microfacet::{Masking, projected_area, reflect, refract, upper};
use super::{Bsdf, BsdfSample, fresnel_dielectric};
use crate::error::{ParamError, check_eta};
use crate::math::Vec3;
use crate::ndf::Ndf;
use rand::{Rng, RngExt};

/// A rough dielectric interface: index 1 above (z > 0), `eta` below; single scattering
/// (Walter et al. 2007) with exact unpolarised Fresnel and the chosen Smith masking.
///
/// Light may arrive from either side. A direction below the surface sees the same microfacet
/// normals (all with `h.z > 0`) from underneath, and is masked by the mirrored surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughDielectric<N> {
    ndf: N,
    eta: f64,
    masking: Masking,
}

/// The generalised half vector of a pair of directions and what follows from it.
#[derive(Debug, Clone, Copy)]
struct HalfVector {
    /// The microfacet normal, `h.z > 0`.
    h: Vec3,
    /// `wi.h` and `wo.h`.
    cos_ih: f64,
    cos_oh: f64,
    /// Indices of refraction on the sides of `wi` and `wo`.
    n_i: f64,
    n_o: f64,
    reflect: bool,
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

    /// Index of refraction on the side of a direction with cosine `cos`.
    #[inline]
    fn index(&self, cos: f64) -> f64 {
        if cos > 0.0 { 1.0 } else { self.eta }
    }

    /// Walter's generalised half vector: `normalize(wi + wo)` for reflection,
    /// `-normalize(n_i wi + n_o wo)` for refraction, flipped to `h.z > 0`. `None` for grazing
    /// directions and when no facet connects the pair (either direction on the back of `h`).
    #[inline]
    fn half_vector(&self, wi: Vec3, wo: Vec3) -> Option<HalfVector> {
        let (ci, co) = (wi.z, wo.z);
        if ci == 0.0 || co == 0.0 {
            return None;
        }
        let reflect = ci * co > 0.0;
        let (n_i, n_o) = (self.index(ci), self.index(co));
        let h = if reflect {
            wi + wo
        } else {
            -(wi * n_i + wo * n_o)
        };
        let len = h.norm();
        if len == 0.0 || len.is_nan() {
            return None;
        }
        let h = if h.z < 0.0 { -h / len } else { h / len };
        let (cos_ih, cos_oh) = (wi.dot(&h), wo.dot(&h));
        // Each direction must lie on the same side of the facet as of the macro-surface.
        if cos_ih * ci <= 0.0 || cos_oh * co <= 0.0 {
            return None;
        }
        Some(HalfVector {
            h,
            cos_ih,
            cos_oh,
            n_i,
            n_o,
            reflect,
        })
    }

    /// `f(wi, wo) |wo.z|` by the single-scattering model of Walter et al. 2007 (theory section 5):
    /// reflection when `wi` and `wo` are on the same side, transmission otherwise; no radiance
    /// `1/eta^2` scaling. Zero for grazing directions and for configurations no facet connects.
    ///
    /// `f_r = F G D / (4 |wi.z| |wo.z|)`,
    /// `f_t = |wi.h| |wo.h| n_o^2 (1 - F) G D / (|wi.z| |wo.z| (n_i wi.h + n_o wo.h)^2)`.
    pub fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some(hv) = self.half_vector(wi, wo) else {
            return 0.0;
        };
        let d = self.ndf.d(hv.h);
        if d == 0.0 {
            return 0.0;
        }
        let f = fresnel_dielectric(hv.cos_ih, self.eta);
        let a_i = projected_area(&self.ndf, wi) / wi.z.abs();
        let a_o = projected_area(&self.ndf, wo) / wo.z.abs();
        if hv.reflect {
            f * self.masking.g_reflection(a_i, a_o) * d / (4.0 * wi.z.abs())
        } else {
            let g = self.masking.g_transmission(a_i, a_o);
            let denom = hv.n_i * hv.cos_ih + hv.n_o * hv.cos_oh;
            (hv.cos_ih * hv.cos_oh).abs() / wi.z.abs() * hv.n_o * hv.n_o * (1.0 - f) * g * d
                / (denom * denom)
        }
    }

    /// Solid-angle density of `wo` under [`Bsdf::sample`] given the half vector, the
    /// projected area `sigma_i` seen from the side of `wi` and the Fresnel reflectance
    /// `f = F(wi.h)`: `D_wi(h) |dh/dwo| (F or 1 - F)` with `D_wi(h) = |wi.h| D(h) / sigma_i`.
    #[inline]
    fn pdf_half(&self, hv: &HalfVector, sigma_i: f64, f: f64) -> f64 {
        let d = self.ndf.d(hv.h);
        if d == 0.0 || sigma_i <= 0.0 || sigma_i.is_nan() {
            return 0.0;
        }
        let d_visible = hv.cos_ih.abs() * d / sigma_i;
        if hv.reflect {
            d_visible / (4.0 * hv.cos_ih.abs()) * f
        } else {
            let denom = hv.n_i * hv.cos_ih + hv.n_o * hv.cos_oh;
            d_visible * hv.n_o * hv.n_o * hv.cos_oh.abs() / (denom * denom) * (1.0 - f)
        }
    }
}

impl<N: Ndf> Bsdf for RoughDielectric<N> {
    /// [`RoughDielectric::f_cos`].
    fn eval<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, _rng: &mut R) -> f64 {
        self.f_cos(wi, wo)
    }

    /// Draws a visible normal `h` from the side of `wi` (from `upper(wi)`), then reflects with
    /// probability `F(wi.h)` and refracts otherwise. The weight is `G / G1(wi)`. Returns `None`
    /// for grazing `wi` and when the scattered direction lands on the wrong side.
    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let h = self.ndf.sample_visible(upper(wi), rng);
        let cos_ih = wi.dot(&h);
        let f = fresnel_dielectric(cos_ih, self.eta);
        let reflect_lobe = rng.random::<f64>() < f;
        let wo = if reflect_lobe {
            reflect(wi, h)
        } else {
            // The facet normal on the side of wi.
            let facing = if cos_ih < 0.0 { -h } else { h };
            refract(wi, facing, self.index(-wi.z) / self.index(wi.z))?
        };
        if (wo.z * wi.z > 0.0) != reflect_lobe || wo.z == 0.0 {
            return None;
        }
        // Recompute the half vector from (wi, wo), so that the returned pdf and weight are
        // exactly those of pdf(wi, wo) and eval(wi, wo): rounding can move a facet sampled at
        // h.z ~ 0, where D may diverge (Student-T, gamma < 2), to h.z <= 0.
        let hv = self.half_vector(wi, wo)?;
        let sigma_i = projected_area(&self.ndf, wi);
        let pdf = self.pdf_half(&hv, sigma_i, fresnel_dielectric(hv.cos_ih, self.eta));
        let a_i = sigma_i / wi.z.abs();
        let a_o = projected_area(&self.ndf, wo) / wo.z.abs();
        let g = if reflect_lobe {
            self.masking.g_reflection(a_i, a_o)
        } else {
            self.masking.g_transmission(a_i, a_o)
        };
        let weight = g * a_i;
        if !(pdf > 0.0 && pdf.is_finite() && weight.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight,
            pdf,
            delta: false,
        })
    }

    fn pdf<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, _rng: &mut R) -> f64 {
        match self.half_vector(wi, wo) {
            Some(hv) => self.pdf_half(
                &hv,
                projected_area(&self.ndf, wi),
                fresnel_dielectric(hv.cos_ih, self.eta),
            ),
            None => 0.0,
        }
    }
}
