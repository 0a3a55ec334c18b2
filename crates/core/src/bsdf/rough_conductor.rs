//! A rough conductor: microfacet reflection with conductor Fresnel, generic over the NDF.

use super::microfacet::{HalfVector, Masking, projected_area, reflect, upper};
use super::smooth_conductor::check_conductor_index;
use super::{AnalyticBsdf, Bsdf, BsdfSample, fresnel_conductor};
use crate::error::ParamError;
use crate::math::Vec3;
use crate::ndf::Ndf;
use nalgebra::Complex;
use rand::Rng;

/// A rough conductor of complex index `n + i k`: single-scattering microfacet reflection
/// `f = F(wi.h) G D(h) / (4 |wi.z| |wo.z|)`, `h = normalize(wi + wo)`, with the exact
/// unpolarised conductor Fresnel and the chosen Smith masking. Two-sided: light from below
/// sees the mirrored surface and reflects below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughConductor<N> {
    ndf: N,
    eta: Complex<f64>,
    masking: Masking,
}

impl<N: Ndf> RoughConductor<N> {
    /// A rough conductor with the given NDF, complex index `n + i k` (finite, `n > 0`,
    /// `k >= 0`) and masking.
    pub fn new(ndf: N, n: f64, k: f64, masking: Masking) -> Result<Self, ParamError> {
        Ok(Self {
            ndf,
            eta: check_conductor_index(n, k)?,
            masking,
        })
    }

    /// The microfacet distribution.
    pub fn ndf(&self) -> &N {
        &self.ndf
    }

    /// The complex index `n + i k`.
    pub fn eta(&self) -> Complex<f64> {
        self.eta
    }

    /// The masking model.
    pub fn masking(&self) -> Masking {
        self.masking
    }

    /// The reflection half vector of a pair on one side, or `None` (see [`HalfVector::new`]).
    #[inline]
    fn half_vector(wi: Vec3, wo: Vec3) -> Option<HalfVector> {
        if wi.z * wo.z <= 0.0 {
            return None;
        }
        // Reflection: the relative index plays no role in the half vector.
        HalfVector::new(wi, wo, 2.0)
    }

    /// `D_wi(h) / (4 |wi.h|) = D(h) / (4 sigma_i)`, the density of the reflected direction.
    #[inline]
    fn density_of(&self, hv: &HalfVector, sigma_i: f64) -> f64 {
        if sigma_i <= 0.0 || sigma_i.is_nan() {
            return 0.0;
        }
        hv.cos_ih.abs() * self.ndf.d(hv.h) / sigma_i * hv.jacobian()
    }
}

impl<N: Ndf> AnalyticBsdf for RoughConductor<N> {
    /// `F G D / (4 |wi.z| |wo.z|)` times `|wo.z|`, with `h = normalize(wi + wo)`.
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some(hv) = Self::half_vector(wi, wo) else {
            return 0.0;
        };
        let d = self.ndf.d(hv.h);
        if d == 0.0 {
            return 0.0;
        }
        let a_i = projected_area(&self.ndf, wi) / wi.z.abs();
        let a_o = projected_area(&self.ndf, wo) / wo.z.abs();
        let f = fresnel_conductor(hv.cos_ih, self.eta);
        hv.walter_factor(wi.z, f) * self.masking.g_reflection(a_i, a_o) * d
    }

    fn density(&self, wi: Vec3, wo: Vec3) -> f64 {
        match Self::half_vector(wi, wo) {
            Some(hv) => self.density_of(&hv, projected_area(&self.ndf, wi)),
            None => 0.0,
        }
    }
}

impl<N: Ndf> Bsdf for RoughConductor<N> {
    /// [`AnalyticBsdf::f_cos`]; the generator is not used.
    fn eval<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, _rng: &mut R) -> f64 {
        self.f_cos(wi, wo)
    }

    /// Reflects about a visible normal drawn from the side of `wi`; weight `F G / G1(wi)`.
    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let h = self.ndf.sample_visible(upper(wi), rng);
        let wo = reflect(wi, h);
        let hv = Self::half_vector(wi, wo)?;
        let sigma_i = projected_area(&self.ndf, wi);
        let pdf = self.density_of(&hv, sigma_i);
        let a_i = sigma_i / wi.z.abs();
        let a_o = projected_area(&self.ndf, wo) / wo.z.abs();
        let weight =
            fresnel_conductor(hv.cos_ih, self.eta) * self.masking.g_reflection(a_i, a_o) * a_i;
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
        self.density(wi, wo)
    }
}
