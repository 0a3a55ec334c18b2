//! The fitted model to export.

use stfit_core::Vec3;
use stfit_core::bsdf::{Masking, RoughDielectric};
use stfit_core::error::{check_eta, finite};
use stfit_core::ndf::{AnyNdf, Ndf};
use stfit_core::walk::{DielectricFacet, Microsurface, ScatteringOrders};

use crate::ExportError;

/// Random walks per incidence direction used to evaluate an all-orders model's orders >= 2
/// when nothing else is given (the fit command's default).
pub const DEFAULT_WALKS: u64 = 20_000;

/// A fitted rough-dielectric model, everything needed to evaluate it again.
///
/// The lead's `FitResult` will carry all of this; `From<&FitResult>` belongs beside it.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportModel {
    /// The fitted NDF (Beckmann, GGX or Student-T with its alpha and gamma).
    pub ndf: AnyNdf,
    /// Relative index of the glass, `n_inside / n_outside`.
    pub eta: f64,
    /// Smith masking of the single-scattering model. An all-orders model is height-correlated
    /// by construction (the random walk's order 1) and ignores it.
    pub masking: Masking,
    /// `Single` (Walter et al. 2007) or `All` (the height-correlated single-scattering BSDF
    /// plus the random walk's orders >= 2).
    pub orders: ScatteringOrders,
    /// The fit's calibration factor: the measured `L` is `scale` times the model's. It is not
    /// part of the physical BSDF and no export applies it; translations are measured in the
    /// fit's units `sqrt(L)`, which include it.
    pub scale: f64,
    /// Random walks per incidence direction and their seed, for the orders >= 2 of an
    /// all-orders model.
    pub walks: u64,
    pub seed: u64,
    /// What was fitted to what: sample, model, fit quality, data file, stfit version.
    pub source: String,
}

impl ExportModel {
    /// A model to export; refuses `ScatteringOrders::Multiple` (orders >= 2 alone are no
    /// fitted model), an invalid eta and a non-finite or non-positive scale.
    pub fn new(
        ndf: AnyNdf,
        eta: f64,
        masking: Masking,
        orders: ScatteringOrders,
        scale: f64,
        source: impl Into<String>,
    ) -> Result<Self, ExportError> {
        check_eta(eta)?;
        let scale = finite("scale", scale)?;
        if scale <= 0.0 {
            return Err(ExportError::Unsupported(format!(
                "the fit's scale must be > 0, got {scale}"
            )));
        }
        if orders == ScatteringOrders::Multiple {
            return Err(ExportError::Unsupported(
                "a fitted model has orders `single` or `all`, not `multiple`".into(),
            ));
        }
        Ok(Self {
            ndf,
            eta,
            masking,
            orders,
            scale,
            walks: DEFAULT_WALKS,
            seed: 1,
            source: source.into(),
        })
    }

    /// The NDF family's name as stfit writes it.
    pub fn ndf_name(&self) -> &'static str {
        match self.ndf {
            AnyNdf::Beckmann(_) => "beckmann",
            AnyNdf::Ggx(_) => "ggx",
            AnyNdf::StudentT(_) => "student-t",
        }
    }

    /// The masking of the single-scattering term actually used: the model's for single
    /// scattering, height-correlated for all orders.
    pub fn single_masking(&self) -> Masking {
        match self.orders {
            ScatteringOrders::Single => self.masking,
            _ => Masking::Correlated,
        }
    }

    /// The analytic single-scattering BSDF of the model.
    pub fn single(&self) -> RoughDielectric<AnyNdf> {
        RoughDielectric::new(self.ndf, self.eta, self.single_masking())
            .expect("eta was checked in ExportModel::new")
    }

    /// The microsurface of the model's NDF with dielectric facets (random walk), restricted to
    /// `orders`.
    pub fn microsurface(&self, orders: ScatteringOrders) -> Microsurface<AnyNdf, DielectricFacet> {
        let facet = DielectricFacet::new(self.eta).expect("eta was checked in ExportModel::new");
        Microsurface::new(self.ndf, facet).with_orders(orders)
    }

    /// `f_cos(wi, wo)` of the fitted model for every `wo` of `wos`: the analytic single
    /// scattering BSDF, plus for an all-orders model the orders >= 2 estimated from
    /// [`ExportModel::walks`] walks from `wi` (seed [`ExportModel::seed`]).
    pub fn f_cos_many(&self, wi: Vec3, wos: &[Vec3]) -> Vec<f64> {
        let single = self.single();
        let mut out: Vec<f64> = wos.iter().map(|&wo| single.f_cos(wi, wo)).collect();
        if self.orders == ScatteringOrders::All {
            let multi = self.microsurface(ScatteringOrders::Multiple);
            let est = multi.eval_many(wi, wos, self.walks, self.seed);
            for (o, e) in out.iter_mut().zip(est) {
                *o += e.mean;
            }
        }
        out
    }

    /// The roughness alpha of the fitted NDF.
    pub fn alpha(&self) -> f64 {
        self.ndf.alpha()
    }

    /// The Student-T shape gamma, `None` for Beckmann and GGX.
    pub fn gamma(&self) -> Option<f64> {
        self.ndf.gamma()
    }

    /// Smith `Lambda` of the fitted NDF toward `w` (either side), `Lambda(upper(w))`.
    pub fn lambda(&self, w: Vec3) -> f64 {
        let up = if w.z < 0.0 { -w } else { w };
        self.ndf.lambda(up)
    }
}
