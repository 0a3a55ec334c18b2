//! The rough dielectric of Walter et al. 2007, generic over the NDF.

use super::microfacet::{HalfVector, Masking, SmithTerm, projected_area, reflect, refract, upper};
use super::{AnalyticBsdf, Bsdf, BsdfSample, fresnel_dielectric};
use crate::error::{ParamError, check_eta};
use crate::math::Vec3;
use crate::ndf::{AnyNdf, Ndf, TabulatedStudentT};
use rand::{Rng, RngExt};

/// A rough dielectric interface: index 1 above (z > 0), `eta` below; single scattering
/// (Walter et al. 2007) with exact unpolarised Fresnel and the chosen Smith masking.
///
/// Light may arrive from either side. A direction below the surface sees the same microfacet
/// normals (all with `h.z > 0`) from underneath, and is masked by the mirrored surface.
///
/// ```
/// use stfit_core::bsdf::{AnalyticBsdf, Bsdf, Masking, RoughDielectric};
/// use stfit_core::ndf::StudentT;
/// use stfit_core::rand::SeedableRng;
/// use stfit_core::Vec3;
///
/// let glass = RoughDielectric::new(StudentT::new(0.4, 3.0)?, 1.51, Masking::Separable)?;
/// let wi = Vec3::new(0.0, 0.0, 1.0); // light from the air, at normal incidence
/// let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
/// let s = glass.sample(wi, &mut rng).expect("a direction");
/// // The sample's weight and density are those of the closed form at its direction.
/// assert!((s.weight * s.pdf - glass.f_cos(wi, s.wo)).abs() < 1e-9 * glass.f_cos(wi, s.wo));
/// assert!((s.pdf - glass.density(wi, s.wo)).abs() < 1e-9 * s.pdf);
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughDielectric<N> {
    ndf: N,
    eta: f64,
    masking: Masking,
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

    /// The same interface (index and masking) with the NDF `ndf`: for instance the concrete
    /// NDF of a `RoughDielectric<AnyNdf>` ([`AnyNdf::with`](crate::ndf::AnyNdf::with)).
    pub fn with_ndf<M: Ndf>(&self, ndf: M) -> RoughDielectric<M> {
        RoughDielectric {
            ndf,
            eta: self.eta,
            masking: self.masking,
        }
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

    /// The Smith term of the direction `w` (either side) for this interface's masking, `a = 1 +
    /// Lambda(w')` ([`Masking::term`]). Callers that evaluate many pairs sharing directions
    /// compute it once per direction and call [`RoughDielectric::f_cos_with_terms`].
    pub fn smith_term(&self, w: Vec3) -> SmithTerm {
        self.masking.term(projected_area(&self.ndf, w) / w.z.abs())
    }

    /// [`AnalyticBsdf::f_cos`] from the Smith terms of `wi` and `wo`
    /// ([`RoughDielectric::smith_term`]).
    #[inline]
    pub fn f_cos_with_terms(&self, wi: Vec3, wo: Vec3, t_i: SmithTerm, t_o: SmithTerm) -> f64 {
        self.f_cos_by(wi, wo, || (t_i, t_o))
    }

    /// `f_cos` with the Smith terms computed by `terms` only where a facet connects the pair.
    #[inline]
    fn f_cos_by(&self, wi: Vec3, wo: Vec3, terms: impl FnOnce() -> (SmithTerm, SmithTerm)) -> f64 {
        let Some(hv) = HalfVector::new(wi, wo, self.eta) else {
            return 0.0;
        };
        let d = self.ndf.d(hv.h);
        if d == 0.0 {
            return 0.0;
        }
        let (t_i, t_o) = terms();
        let f = hv.dielectric_fresnel_of(wi, wo, self.eta);
        hv.walter_factor(wi.z, f) * self.masking.g(hv.reflect, t_i, t_o) * d
    }

    #[inline]
    fn density_of(&self, hv: &HalfVector, sigma_i: f64) -> f64 {
        let d = self.ndf.d(hv.h);
        if d == 0.0 || sigma_i <= 0.0 || sigma_i.is_nan() {
            return 0.0;
        }
        hv.cos_ih.abs() * d / sigma_i * hv.dielectric_weight(self.eta, 1.0 / self.eta)
    }
}

impl RoughDielectric<AnyNdf> {
    /// `f(wi, wo) |wo.z|` ([`AnalyticBsdf::f_cos`]) at every pair of a batch, as every front end
    /// evaluates a batch: a Student-T NDF through its [`TabulatedStudentT`] (Lambda's continued
    /// fractions interpolated, to a few ulps of the exact ones; the table, tens of
    /// microseconds, is paid once per batch), so that `stfit eval` and the Python package print
    /// the same digits. Like [`AnalyticBsdf::f_cos`] it takes the directions as given: front ends
    /// scale those they accept within a tolerance to unit length where they accept them
    /// ([`to_unit`](crate::math::to_unit)).
    pub fn f_cos_batch(&self, pairs: &[(Vec3, Vec3)]) -> Vec<f64> {
        match self.ndf {
            AnyNdf::StudentT(st) => {
                let fast = self.with_ndf(TabulatedStudentT::new(st));
                pairs.iter().map(|&(wi, wo)| fast.f_cos(wi, wo)).collect()
            }
            _ => pairs.iter().map(|&(wi, wo)| self.f_cos(wi, wo)).collect(),
        }
    }
}

impl<N: Ndf> AnalyticBsdf for RoughDielectric<N> {
    /// `f(wi, wo) |wo.z|` by the single-scattering model of Walter et al. 2007 (theory section 5):
    /// reflection when `wi` and `wo` are on the same side, transmission otherwise, with `wi`
    /// toward the light (see the [module documentation](super) for the convention). Zero for
    /// grazing directions and for configurations no facet connects.
    ///
    /// `f_r = F G D / (4 |wi.z| |wo.z|)`,
    /// `f_t = |wi.h| |wo.h| n_o^2 (1 - F) G D / (|wi.z| |wo.z| (n_i wi.h + n_o wo.h)^2)`.
    fn f_cos(&self, wi: Vec3, wo: Vec3) -> f64 {
        self.f_cos_by(wi, wo, || (self.smith_term(wi), self.smith_term(wo)))
    }

    /// Solid-angle density of `wo` under [`Bsdf::sample`]:
    /// `D_wi(h) |d omega_h / d omega_o| (F or 1 - F)` with `D_wi(h) = |wi.h| D(h) / sigma_i`,
    /// `sigma_i` the projected area seen from the side of `wi`.
    fn density(&self, wi: Vec3, wo: Vec3) -> f64 {
        match HalfVector::new(wi, wo, self.eta) {
            Some(hv) => self.density_of(&hv, projected_area(&self.ndf, wi)),
            None => 0.0,
        }
    }
}

impl<N: Ndf> Bsdf for RoughDielectric<N> {
    /// [`AnalyticBsdf::f_cos`]; the generator is not used.
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
        let f = fresnel_dielectric(wi.dot(&h), self.eta);
        let reflect_lobe = rng.random::<f64>() < f;
        let wo = if reflect_lobe {
            reflect(wi, h)
        } else {
            refract(wi, h, self.eta)?
        };
        if (wo.z * wi.z > 0.0) != reflect_lobe || wo.z == 0.0 {
            return None;
        }
        // Recompute the half vector from (wi, wo), so that the returned pdf and weight are
        // exactly those of pdf(wi, wo) and eval(wi, wo): rounding can move a facet sampled at
        // h.z ~ 0, where D may diverge (Student-T, gamma < 2), to h.z <= 0.
        let hv = HalfVector::new(wi, wo, self.eta)?;
        let sigma_i = projected_area(&self.ndf, wi);
        let pdf = self.density_of(&hv, sigma_i);
        let m = self.masking;
        let a_i = sigma_i / wi.z.abs();
        let a_o = projected_area(&self.ndf, wo) / wo.z.abs();
        let weight = m.g(reflect_lobe, m.term(a_i), m.term(a_o)) * a_i;
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
