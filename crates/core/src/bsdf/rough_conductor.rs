//! A rough conductor: microfacet reflection with conductor Fresnel, generic over the NDF.

use super::microfacet::{Masking, projected_area, reflect, upper};
use super::smooth_conductor::check_conductor_index;
use super::{Bsdf, BsdfSample, fresnel_conductor};
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

    /// The half vector `normalize(wi + wo)` flipped to `h.z > 0`, or `None` when the pair is
    /// not a reflection on one side, is grazing, or no facet connects it.
    #[inline]
    fn half_vector(wi: Vec3, wo: Vec3) -> Option<Vec3> {
        if wi.z * wo.z <= 0.0 {
            return None;
        }
        let h = upper(wi + wo);
        let len = h.norm();
        if len == 0.0 || len.is_nan() {
            return None;
        }
        let h = h / len;
        if wi.dot(&h) * wi.z <= 0.0 || wo.dot(&h) * wo.z <= 0.0 {
            return None;
        }
        Some(h)
    }

    /// `D_wi(h) / (4 |wi.h|) = D(h) / (4 sigma_i)`, the density of the reflected direction.
    #[inline]
    fn pdf_half(&self, h: Vec3, sigma_i: f64) -> f64 {
        if sigma_i <= 0.0 || sigma_i.is_nan() {
            return 0.0;
        }
        self.ndf.d(h) / (4.0 * sigma_i)
    }
}

impl<N: Ndf> Bsdf for RoughConductor<N> {
    fn eval<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, _rng: &mut R) -> f64 {
        let Some(h) = Self::half_vector(wi, wo) else {
            return 0.0;
        };
        let d = self.ndf.d(h);
        if d == 0.0 {
            return 0.0;
        }
        let a_i = projected_area(&self.ndf, wi) / wi.z.abs();
        let a_o = projected_area(&self.ndf, wo) / wo.z.abs();
        let f = fresnel_conductor(wi.dot(&h), self.eta);
        f * self.masking.g_reflection(a_i, a_o) * d / (4.0 * wi.z.abs())
    }

    /// Reflects about a visible normal drawn from the side of `wi`; weight `F G / G1(wi)`.
    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<BsdfSample> {
        if wi.z == 0.0 {
            return None;
        }
        let h = self.ndf.sample_visible(upper(wi), rng);
        let wo = reflect(wi, h);
        let h = Self::half_vector(wi, wo)?;
        let sigma_i = projected_area(&self.ndf, wi);
        let pdf = self.pdf_half(h, sigma_i);
        let a_i = sigma_i / wi.z.abs();
        let a_o = projected_area(&self.ndf, wo) / wo.z.abs();
        let weight =
            fresnel_conductor(wi.dot(&h), self.eta) * self.masking.g_reflection(a_i, a_o) * a_i;
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
        match Self::half_vector(wi, wo) {
            Some(h) => self.pdf_half(h, projected_area(&self.ndf, wi)),
            None => 0.0,
        }
    }
}
