//! The models fitted to measurements, and what a fit reports.

use serde::{Deserialize, Serialize};
use stfit_core::Vec3;
use stfit_core::math::radians;

/// The NDF family of a fitted model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    Beckmann,
    Ggx,
    StudentT,
}

impl ModelKind {
    /// The model's name as used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Beckmann => "beckmann",
            Self::Ggx => "ggx",
            Self::StudentT => "student-t",
        }
    }
}

/// A model to fit: a family, and for Student-T optionally a fixed gamma.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ModelSpec {
    pub kind: ModelKind,
    /// Student-T only: hold gamma at this value instead of fitting it.
    pub gamma_fixed: Option<f64>,
}

/// The result of fitting one model to one sample (the `--json` record).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitResult {
    pub sample: String,
    pub model: ModelKind,
    pub alpha: f64,
    /// `None` for Beckmann and GGX.
    pub gamma: Option<f64>,
    /// True when gamma was held fixed rather than fitted.
    pub gamma_fixed: bool,
    pub scale: f64,
    /// Root-mean-square residual of `sqrt(L)` over the sample's points.
    pub rmse_sqrt_l: f64,
    pub n_points: usize,
    /// Standard errors from the curvature of the loss at the optimum.
    pub alpha_stderr: f64,
    pub gamma_stderr: Option<f64>,
    pub scale_stderr: f64,
    pub iterations: u64,
}

/// Direction toward the light for incidence `theta_i` (degrees) from the outside:
/// `wi = (-sin theta_i, 0, cos theta_i)`.
pub fn wi_from_deg(theta_i_deg: f64) -> Vec3 {
    let t = radians(theta_i_deg);
    Vec3::new(-t.sin(), 0.0, t.cos())
}

/// Transmitted direction inside the glass for `theta_o` (degrees, 180 straight through):
/// `wo = (sin(theta_o - 180), 0, -cos(theta_o - 180))`.
pub fn wo_from_deg(theta_o_deg: f64) -> Vec3 {
    let t = radians(theta_o_deg - 180.0);
    Vec3::new(t.sin(), 0.0, -t.cos())
}

/// The loss minimised by a fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Loss {
    /// Least squares on `sqrt(L)` (the published comparison's view).
    #[default]
    Sqrt,
    /// Least squares on `L`.
    Linear,
}

/// The optimiser used for the shape parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Optimizer {
    #[default]
    NelderMead,
    Lbfgs,
}

/// Which scattering orders the model BSDF includes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scattering {
    /// The analytic single-scattering BSDF of Walter et al. 2007.
    #[default]
    Single,
    /// All orders, by the height-field random walk.
    Multiple,
}

/// Settings shared by every fit in a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Relative index of the glass (default 1.51).
    pub eta: f64,
    pub loss: Loss,
    pub optimizer: Optimizer,
    /// Smith masking of the single-scattering model. Ignored by `Scattering::Multiple`, whose
    /// model is height-correlated by construction (the random walk's order 1 term).
    pub masking: stfit_core::bsdf::Masking,
    pub scattering: Scattering,
    /// Seed of the random walks (common random numbers) for `Scattering::Multiple`.
    pub seed: u64,
    /// Random walks per incidence angle for `Scattering::Multiple`.
    pub walk_samples: usize,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            eta: 1.51,
            loss: Loss::Sqrt,
            optimizer: Optimizer::NelderMead,
            masking: stfit_core::bsdf::Masking::Separable,
            scattering: Scattering::Single,
            seed: 1,
            walk_samples: 100_000,
        }
    }
}

/// A fully specified model: family, shape and calibration scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelParams {
    pub kind: ModelKind,
    pub alpha: f64,
    /// Student-T shape; ignored for Beckmann and GGX.
    pub gamma: f64,
    pub scale: f64,
}

impl ModelParams {
    /// The model's NDF, or the parameter error for alpha <= 0, gamma <= 3/2 or non-finite values.
    pub fn ndf(&self) -> Result<stfit_core::ndf::AnyNdf, stfit_core::ParamError> {
        use stfit_core::ndf::{Beckmann, Ggx, StudentT};
        Ok(match self.kind {
            ModelKind::Beckmann => Beckmann::new(self.alpha)?.into(),
            ModelKind::Ggx => Ggx::new(self.alpha)?.into(),
            ModelKind::StudentT => StudentT::new(self.alpha, self.gamma)?.into(),
        })
    }

    /// Single-scattering model value `L = scale f_t(wi, wo) cos(theta_i) / eta^2` for angles in
    /// degrees in the data convention.
    pub fn l_single(
        &self,
        theta_i_deg: f64,
        theta_o_deg: f64,
        eta: f64,
        masking: stfit_core::bsdf::Masking,
    ) -> Result<f64, stfit_core::ParamError> {
        let bsdf = stfit_core::bsdf::RoughDielectric::new(self.ndf()?, eta, masking)?;
        let wi = wi_from_deg(theta_i_deg);
        let wo = wo_from_deg(theta_o_deg);
        // f_cos = f_t |wo.z|; L wants f_t cos(theta_i).
        let f_t = bsdf.f_cos(wi, wo) / wo.z.abs();
        Ok(self.scale * f_t * wi.z / (eta * eta))
    }

    /// [`ModelParams::l_single`] at many `(theta_i_deg, theta_o_deg)` pairs at once: the
    /// NDF-independent geometry is computed once per pair and Smith `Lambda` once per distinct
    /// direction.
    pub fn l_single_batch(
        &self,
        angles: &[(f64, f64)],
        eta: f64,
        masking: stfit_core::bsdf::Masking,
    ) -> Result<Vec<f64>, stfit_core::ParamError> {
        let ndf = self.ndf()?;
        stfit_core::error::finite("scale", self.scale)?;
        let geom = crate::objective::Geometry::new(angles.iter().copied(), eta)?;
        let mut out = Vec::with_capacity(angles.len());
        geom.unit_model(&ndf, masking, &mut out);
        out.iter_mut().for_each(|l| *l *= self.scale);
        Ok(out)
    }

    /// The all-orders model `L = scale (f_single + f_multi) cos(theta_i) / eta^2` at many
    /// `(theta_i_deg, theta_o_deg)` pairs: `f_single` the analytic single-scattering BTDF with
    /// height-correlated masking (exactly the walk's order 1), `f_multi` the order >= 2 estimate
    /// of `walks` random walks per incidence angle from `seed` (see
    /// [`MultipleGeometry`](crate::objective::MultipleGeometry)).
    pub fn l_multiple_batch(
        &self,
        angles: &[(f64, f64)],
        eta: f64,
        walks: u64,
        seed: u64,
    ) -> Result<Vec<f64>, stfit_core::ParamError> {
        let mut out = self.l_single_batch(angles, eta, stfit_core::bsdf::Masking::Correlated)?;
        let multi =
            crate::objective::MultipleGeometry::new(angles.iter().copied(), eta, walks, seed)?;
        let mut m = vec![0.0; angles.len()];
        multi.add_unit_model(&self.ndf()?, &mut m)?;
        out.iter_mut()
            .zip(&m)
            .for_each(|(l, m)| *l += self.scale * m);
        Ok(out)
    }
}
