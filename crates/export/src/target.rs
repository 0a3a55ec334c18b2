//! The renderers' own rough-dielectric BSDFs, implemented after their sources, so that a fit
//! can be translated into them and the translation's error measured.
//!
//! Every renderer here evaluates Walter et al. 2007's microfacet dielectric: the same half
//! vector, Fresnel term, Jacobian and `n_o^2` factor as stfit-core's
//! [`RoughDielectric`](stfit_core::bsdf::RoughDielectric) for light `wi` (each source is cited
//! at its [`Smith`] variant). They differ in the NDF and in the masking-shadowing term G, so a
//! target BSDF is stfit-core's single-scattering value with separable exact Smith masking,
//! multiplied by `G_target / G_separable`: the formula exists once.

use stfit_core::Vec3;
use stfit_core::bsdf::{Masking, RoughDielectric};
use stfit_core::ndf::{AnyNdf, Ndf};

use crate::ExportError;

/// The masking-shadowing term G of a renderer's rough dielectric, in terms of
/// `a = 1 + Lambda(w')` (`w'` the direction mirrored to the upper hemisphere).
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
    /// Lambda: pbrt-v4 `TrowbridgeReitzDistribution::G` (mmp/pbrt-v4, src/pbrt/util/scattering.h,
    /// used by `DielectricBxDF::f`, src/pbrt/bxdfs.h), appleseed `StdMDF::G` / `GGXMDF::G`
    /// (appleseedhq/appleseed, src/appleseed/foundation/math/microfacet.cpp, used by
    /// `GlassBSDF`, src/appleseed/renderer/modeling/bsdf/glassbsdf.cpp), and the OpenPBR
    /// viewer's `ggx_G2`.
    Uncorrelated,
    /// Cycles `bsdf_G` = `1 / (1 + lambdaI + lambdaO)` for reflection and transmission, where
    /// Beckmann's Lambda is the rational approximation
    /// `((0.396 a - 1.259) a + 1) / ((2.181 a + 3.535) a)` for `a < 1.6`, 0 above (GGX exact);
    /// from blender/blender, intern/cycles/kernel/closure/bsdf_microfacet.h.
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

/// A renderer's rough dielectric interface: index 1 above, `eta` below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetDielectric {
    ndf: AnyNdf,
    eta: f64,
    smith: Smith,
    base: RoughDielectric<AnyNdf>,
}

impl TargetDielectric {
    /// A target BSDF with the given NDF, relative index and masking term.
    pub fn new(ndf: AnyNdf, eta: f64, smith: Smith) -> Result<Self, ExportError> {
        Ok(Self {
            ndf,
            eta,
            smith,
            base: RoughDielectric::new(ndf, eta, Masking::Separable)?,
        })
    }

    /// The NDF.
    pub fn ndf(&self) -> AnyNdf {
        self.ndf
    }

    /// The relative index.
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// `1 + Lambda(w')` of the exact Smith function.
    fn a(&self, w: Vec3) -> f64 {
        let up = if w.z < 0.0 { -w } else { w };
        1.0 + self.ndf.lambda(up)
    }

    /// `G_target / G_separable` for the pair.
    fn g_ratio(&self, wi: Vec3, wo: Vec3) -> f64 {
        let (ai, ao) = (self.a(wi), self.a(wo));
        let beckmann_alpha = match self.ndf {
            AnyNdf::Beckmann(b) => Some(b.alpha()),
            _ => None,
        };
        match (self.smith, beckmann_alpha) {
            (Smith::Separable, _) => 1.0,
            (Smith::Uncorrelated, _) | (Smith::Cycles, None) => ai * ao / (ai + ao - 1.0),
            (Smith::MitsubaSeparable, None) => 1.0,
            (Smith::MitsubaSeparable, Some(alpha)) => {
                let g = mitsuba_beckmann_g1(beckmann_a(alpha, wi))
                    * mitsuba_beckmann_g1(beckmann_a(alpha, wo));
                g * ai * ao
            }
            (Smith::Cycles, Some(alpha)) => {
                let li = cycles_beckmann_lambda(beckmann_a(alpha, wi));
                let lo = cycles_beckmann_lambda(beckmann_a(alpha, wo));
                ai * ao / (1.0 + li + lo)
            }
        }
    }

    /// `f_cos(wi, wo)` of the renderer's BSDF for light `wi`.
    pub fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        let base = self.base.f_cos(wi, wo);
        if base == 0.0 {
            return 0.0;
        }
        let r = self.g_ratio(wi, wo);
        if r.is_finite() { base * r } else { 0.0 }
    }
}

/// A linear mixture of two target BSDFs, `(1 - w) a + w b` (OpenPBR's specular haze).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mixture {
    pub a: TargetDielectric,
    pub b: TargetDielectric,
    pub weight: f64,
}

impl Mixture {
    /// `f_cos(wi, wo)` of the mixture.
    pub fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        (1.0 - self.weight) * self.a.f_cos(wi, wo) + self.weight * self.b.f_cos(wi, wo)
    }
}

/// Anything that evaluates `f_cos(wi, wo)` for light `wi`.
pub trait Scatter: Sync {
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64;
}

impl Scatter for TargetDielectric {
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        TargetDielectric::f_cos(self, wi, wo)
    }
}

impl Scatter for Mixture {
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        Mixture::f_cos(self, wi, wo)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stfit_core::ndf::{Beckmann, Ggx};

    /// With separable exact masking the target BSDF is stfit-core's, and with the
    /// uncorrelated form it equals the height-correlated reflection lobe of stfit-core (whose
    /// reflection G is `1/(1 + Lambda_i + Lambda_o)`).
    #[test]
    fn target_masking_forms_reduce_to_core_where_they_coincide() {
        let ndf: AnyNdf = Ggx::new(0.3).unwrap().into();
        let sep = RoughDielectric::new(ndf, 1.5, Masking::Separable).unwrap();
        let cor = RoughDielectric::new(ndf, 1.5, Masking::Correlated).unwrap();
        let t_sep = TargetDielectric::new(ndf, 1.5, Smith::Separable).unwrap();
        let t_unc = TargetDielectric::new(ndf, 1.5, Smith::Uncorrelated).unwrap();
        let wi = Vec3::new(-0.5, 0.1, 0.8).normalize();
        let refl = Vec3::new(0.3, -0.2, 0.9).normalize();
        let trans = Vec3::new(0.2, 0.1, -0.9).normalize();
        for wo in [refl, trans] {
            assert!((t_sep.f_cos(wi, wo) - sep.f_cos(wi, wo)).abs() < 1e-14);
        }
        let (a, b) = (t_unc.f_cos(wi, refl), cor.f_cos(wi, refl));
        assert!((a - b).abs() < 1e-12 * b, "{a} vs {b}");
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
}
