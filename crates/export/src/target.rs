//! The renderers' own rough-dielectric BSDFs, implemented after their sources, so that a fit
//! can be translated into them and the translation's error measured.
//!
//! Every renderer here evaluates Walter et al. 2007's microfacet dielectric: the same half
//! vector, Fresnel term, Jacobian and `n_o^2` factor as stfit-core's
//! [`RoughDielectric`](stfit_core::bsdf::RoughDielectric) for light `wi`, so a target BSDF is
//! `f |wo.z| = walter_factor * G * D(h)` with stfit-core's
//! [`HalfVector::walter_factor`] (the formula exists once) and the renderer's own NDF `D` and
//! masking-shadowing `G` ([`RendererMicrofacet`]; each source is cited at its variant).

use stfit_core::Vec3;
use stfit_core::bsdf::HalfVector;
use stfit_core::error::check_eta;
use stfit_core::ndf::{AnyNdf, Ndf};

use crate::ExportError;
use crate::gtr::VRayGtr;

/// The masking-shadowing term G of a renderer whose NDF is one of stfit's (Beckmann, GGX,
/// Student-T), in terms of `a = 1 + Lambda(w')` (`w'` the direction mirrored to the upper
/// hemisphere, as in Walter et al. 2007).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Smith {
    /// `G1(wi) G1(wo)` with the exact Smith G1 (stfit's `--masking separable`).
    Separable,
    /// Mitsuba 3 `MicrofacetDistribution::G` = `smith_g1(wi) smith_g1(wo)`, where Beckmann's
    /// `smith_g1` is the rational approximation `(3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577
    /// a^2)` for `a = 1/(alpha tan theta) < 1.6`, 1 above (GGX exact); from
    /// mitsuba-renderer/mitsuba3, include/mitsuba/render/microfacet.h.
    MitsubaSeparable,
    /// `1 / (1 + Lambda(wi) + Lambda(wo))` for reflection and transmission alike, exact
    /// Lambda: the height-correlated form of reflection, used for transmission too. pbrt-v4
    /// `TrowbridgeReitzDistribution::G` (mmp/pbrt-v4, src/pbrt/util/scattering.h, used by
    /// `DielectricBxDF::f`, src/pbrt/bxdfs.h), appleseed `GGXMDF::G`
    /// (appleseedhq/appleseed, src/appleseed/foundation/math/microfacet.cpp, used by
    /// `GlassBSDF`, src/appleseed/renderer/modeling/bsdf/glassbsdf.cpp), and the OpenPBR
    /// viewer's `ggx_G2`.
    LambdaSum,
    /// Cycles `bsdf_G` = `1 / (1 + lambdaI + lambdaO)` for reflection and transmission, where
    /// Beckmann's Lambda is the rational approximation
    /// `((0.396 a - 1.259) a + 1) / ((2.181 a + 3.535) a)` for `a < 1.6`, 0 above (GGX exact);
    /// from blender/blender, intern/cycles/kernel/closure/bsdf_microfacet.h (Blender 4; Blender
    /// 3 multiplied two G1 instead).
    Cycles,
}

/// Mitsuba 3's Beckmann `smith_g1` for `a = 1 / (alpha tan theta)`.
fn mitsuba_beckmann_g1(a: f64) -> f64 {
    if a >= 1.6 {
        1.0
    } else {
        (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
    }
}

/// Cycles' Beckmann Lambda for `a = 1 / (alpha tan theta)`.
fn cycles_beckmann_lambda(a: f64) -> f64 {
    if a >= 1.6 {
        0.0
    } else {
        ((0.396 * a - 1.259) * a + 1.0) / ((2.181 * a + 3.535) * a)
    }
}

/// `a = 1 / (alpha tan theta)` of a direction (any side), infinite at normal incidence.
fn beckmann_a(alpha: f64, w: Vec3) -> f64 {
    let sin = (w.x * w.x + w.y * w.y).sqrt();
    if sin == 0.0 {
        return f64::INFINITY;
    }
    w.z.abs() / (sin * alpha)
}

/// A renderer's microfacet model of a rough interface: its NDF and its masking-shadowing term.
pub trait RendererMicrofacet: Sync {
    /// `D(h)` for a unit half vector with `h.z > 0`.
    fn d(&self, h: Vec3) -> f64;
    /// `G(wi, wo)` of a pair that a facet of normal `h` connects (reflection or transmission).
    fn g(&self, wi: Vec3, wo: Vec3, h: Vec3, reflect: bool) -> f64;
}

/// A renderer with one of stfit's NDFs and its own masking term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoreMicrofacet {
    pub ndf: AnyNdf,
    pub smith: Smith,
}

impl CoreMicrofacet {
    /// `1 + Lambda(w')` of the exact Smith function.
    fn a(&self, w: Vec3) -> f64 {
        let up = if w.z < 0.0 { -w } else { w };
        1.0 + self.ndf.lambda(up)
    }
}

impl RendererMicrofacet for CoreMicrofacet {
    fn d(&self, h: Vec3) -> f64 {
        self.ndf.d(h)
    }

    fn g(&self, wi: Vec3, wo: Vec3, _h: Vec3, _reflect: bool) -> f64 {
        let beckmann_alpha = match self.ndf {
            AnyNdf::Beckmann(b) => Some(b.alpha()),
            _ => None,
        };
        match (self.smith, beckmann_alpha) {
            (Smith::Separable, _) | (Smith::MitsubaSeparable, None) => {
                1.0 / (self.a(wi) * self.a(wo))
            }
            (Smith::LambdaSum, _) | (Smith::Cycles, None) => 1.0 / (self.a(wi) + self.a(wo) - 1.0),
            (Smith::MitsubaSeparable, Some(alpha)) => {
                mitsuba_beckmann_g1(beckmann_a(alpha, wi))
                    * mitsuba_beckmann_g1(beckmann_a(alpha, wo))
            }
            (Smith::Cycles, Some(alpha)) => {
                let li = cycles_beckmann_lambda(beckmann_a(alpha, wi));
                let lo = cycles_beckmann_lambda(beckmann_a(alpha, wo));
                1.0 / (1.0 + li + lo)
            }
        }
    }
}

impl RendererMicrofacet for VRayGtr {
    fn d(&self, h: Vec3) -> f64 {
        VRayGtr::d(self, h.z)
    }

    /// V-Ray's separable `G1(wi) G1(wo)` ([`VRayGtr::g1`]); a direction inside the glass is
    /// masked by the mirrored surface (its cosine taken as `|w.z|`), as in Walter et al.
    fn g(&self, wi: Vec3, wo: Vec3, _h: Vec3, _reflect: bool) -> f64 {
        self.g1(wi.z.abs()) * self.g1(wo.z.abs())
    }
}

/// A renderer's rough dielectric interface: index 1 above, `eta` below, with the renderer's
/// microfacet model `M`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetDielectric<M> {
    micro: M,
    eta: f64,
}

impl<M: RendererMicrofacet> TargetDielectric<M> {
    /// A target BSDF with the given microfacet model and relative index.
    pub fn new(micro: M, eta: f64) -> Result<Self, ExportError> {
        Ok(Self {
            micro,
            eta: check_eta(eta)?,
        })
    }

    /// The microfacet model.
    pub fn micro(&self) -> &M {
        &self.micro
    }

    /// `f_cos(wi, wo)` of the renderer's BSDF for light `wi`: `walter_factor * G * D(h)`.
    pub fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        let Some(hv) = HalfVector::new(wi, wo, self.eta) else {
            return 0.0;
        };
        let d = self.micro.d(hv.h);
        if d == 0.0 {
            return 0.0;
        }
        let f = hv.dielectric_fresnel(self.eta);
        let v = hv.walter_factor(wi.z, f) * self.micro.g(wi, wo, hv.h, hv.reflect) * d;
        if v.is_finite() { v } else { 0.0 }
    }
}

/// A linear mixture of two target BSDFs, `(1 - w) a + w b` (OpenPBR's specular haze), applied
/// to reflection only (`haze_transmits` false: the transmitted light takes lobe `a` alone) or
/// to the whole BSDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mixture<M> {
    pub a: TargetDielectric<M>,
    pub b: TargetDielectric<M>,
    pub weight: f64,
    pub haze_transmits: bool,
}

impl<M: RendererMicrofacet> Mixture<M> {
    /// `f_cos(wi, wo)` of the mixture.
    pub fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        let reflect = wi.z * wo.z > 0.0;
        if reflect || self.haze_transmits {
            (1.0 - self.weight) * self.a.f_cos(wi, wo) + self.weight * self.b.f_cos(wi, wo)
        } else {
            self.a.f_cos(wi, wo)
        }
    }
}

/// Anything that evaluates `f_cos(wi, wo)` for light `wi`.
pub trait Scatter: Sync {
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64;
}

impl<M: RendererMicrofacet> Scatter for TargetDielectric<M> {
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        TargetDielectric::f_cos(self, wi, wo)
    }
}

impl<M: RendererMicrofacet> Scatter for Mixture<M> {
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        Mixture::f_cos(self, wi, wo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stfit_core::bsdf::{AnalyticBsdf, Masking, RoughDielectric};
    use stfit_core::ndf::{Beckmann, Ggx};

    fn target(ndf: AnyNdf, smith: Smith) -> TargetDielectric<CoreMicrofacet> {
        TargetDielectric::new(CoreMicrofacet { ndf, smith }, 1.5).unwrap()
    }

    /// With separable exact masking the target BSDF is stfit-core's, and with the Lambda-sum
    /// form it equals the height-correlated reflection lobe of stfit-core (whose reflection G
    /// is `1/(1 + Lambda_i + Lambda_o)`).
    #[test]
    fn target_masking_forms_reduce_to_core_where_they_coincide() {
        let ndf: AnyNdf = Ggx::new(0.3).unwrap().into();
        let sep = RoughDielectric::new(ndf, 1.5, Masking::Separable).unwrap();
        let cor = RoughDielectric::new(ndf, 1.5, Masking::Correlated).unwrap();
        let t_sep = target(ndf, Smith::Separable);
        let t_sum = target(ndf, Smith::LambdaSum);
        let wi = Vec3::new(-0.5, 0.1, 0.8).normalize();
        let refl = Vec3::new(0.3, -0.2, 0.9).normalize();
        let trans = Vec3::new(0.2, 0.1, -0.9).normalize();
        for wo in [refl, trans] {
            let (a, b) = (t_sep.f_cos(wi, wo), sep.f_cos(wi, wo));
            assert!(b > 0.0 && (a - b).abs() < 1e-14 * b, "{a} vs {b}");
        }
        let (a, b) = (t_sum.f_cos(wi, refl), cor.f_cos(wi, refl));
        assert!((a - b).abs() < 1e-12 * b, "{a} vs {b}");
    }

    /// V-Ray's GTR at gamma 2 is GGX with separable exact masking: the target BSDF equals
    /// stfit-core's separable GGX dielectric over pairs on every side (a grid of directions
    /// that avoids the horizon, where V-Ray's G1 is 0 for `cos theta <= 1e-3`).
    #[test]
    fn vray_gtr_at_gamma_two_is_separable_ggx() {
        let alpha = 0.3;
        let core = RoughDielectric::new(Ggx::new(alpha).unwrap(), 1.5, Masking::Separable).unwrap();
        let vray = TargetDielectric::new(VRayGtr::new(alpha, 2.0).unwrap(), 1.5).unwrap();
        let dirs: Vec<Vec3> = (1..12)
            .flat_map(|t| {
                (0..6).map(move |p| {
                    let (t, p) = (f64::from(t) * 14.0f64.to_radians(), f64::from(p));
                    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
                })
            })
            .collect();
        let mut worst: f64 = 0.0;
        for &wi in &dirs {
            for &wo in &dirs {
                let (a, b) = (vray.f_cos(wi, wo), core.f_cos(wi, wo));
                worst = worst.max((a - b).abs() / b.max(1e-3));
            }
        }
        assert!(worst < 1e-9, "largest relative difference {worst:.2e}");
    }

    /// Mitsuba's rational Beckmann G1 is within its documented 0.35% of the exact one, and
    /// Cycles' Lambda approximation likewise close to the exact Lambda.
    #[test]
    fn beckmann_approximations_are_close_to_exact_smith() {
        let b = Beckmann::new(0.4).unwrap();
        for deg in [10.0f64, 40.0, 60.0, 75.0, 85.0] {
            let t = deg.to_radians();
            let w = Vec3::new(t.sin(), 0.0, t.cos());
            let exact_l = b.lambda(w);
            let a = beckmann_a(0.4, w);
            let g = mitsuba_beckmann_g1(a);
            assert!((g * (1.0 + exact_l) - 1.0).abs() < 4e-3, "{deg}: {g}");
            let l = cycles_beckmann_lambda(a);
            assert!(
                ((1.0 + l) / (1.0 + exact_l) - 1.0).abs() < 4e-3,
                "{deg}: {l} vs {exact_l}"
            );
        }
    }

    /// A mixture whose haze does not transmit is lobe `a` in transmission and the mixture in
    /// reflection.
    #[test]
    fn haze_mixture_applies_to_reflection_or_to_both_lobes() {
        let a = target(Ggx::new(0.2).unwrap().into(), Smith::LambdaSum);
        let b = target(Ggx::new(0.6).unwrap().into(), Smith::LambdaSum);
        let wi = Vec3::new(-0.5, 0.0, 0.75f64.sqrt());
        let (refl, trans) = (
            Vec3::new(0.4, 0.1, 0.9).normalize(),
            Vec3::new(0.3, 0.0, -0.95).normalize(),
        );
        for haze_transmits in [false, true] {
            let m = Mixture {
                a,
                b,
                weight: 0.3,
                haze_transmits,
            };
            let mix = |wo| 0.7 * a.f_cos(wi, wo) + 0.3 * b.f_cos(wi, wo);
            assert!((m.f_cos(wi, refl) - mix(refl)).abs() < 1e-15);
            let expect = if haze_transmits {
                mix(trans)
            } else {
                a.f_cos(wi, trans)
            };
            assert!((m.f_cos(wi, trans) - expect).abs() < 1e-15);
        }
    }
}
