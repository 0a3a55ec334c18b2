//! The fitted model to export: a stored fit's [`Model`] (which carries everything needed to
//! evaluate it again) and a description of where it came from, for file comments.

use stfit_core::Vec3;
use stfit_core::bsdf::RoughDielectric;
use stfit_core::error::check_walk_gamma;
use stfit_core::ndf::AnyNdf;
use stfit_core::walk::{DielectricFacet, Microsurface, ScatteringOrders};
use stfit_fit::data::Quantity;
use stfit_fit::forward::Forward;
use stfit_fit::{FitResult, Gamma, Model};

use crate::ExportError;

/// A fitted rough-dielectric model ready to export.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportModel {
    /// The fitted model: NDF, alpha, gamma, the fit's calibration scale, eta, masking, orders,
    /// walks and seed. The scale is not part of the physical BSDF and no export applies it;
    /// translations are measured in the fit's units `sqrt(L)`, which include it.
    pub model: Model,
    ndf: AnyNdf,
    /// What was fitted to what: sample, model, fit quality, data file, stfit version.
    pub source: String,
}

impl ExportModel {
    /// The model of a stored fit, described by the fit's sample, model, rmse, data file and
    /// stfit version.
    ///
    /// The description goes into comments of every target's file, so the fit's free texts (its
    /// data file and stfit version, as well as its sample, which [`FitResult::label`] escapes)
    /// have their control characters escaped (`\n` as the two characters `\` `n`): a line
    /// break in a hand-edited fits file would otherwise end a `#` or `//` comment and put the
    /// rest of the text into the scene file or script as code.
    pub fn from_fit(fit: &FitResult) -> Result<Self, ExportError> {
        let data = escape_control(fit.data.as_deref().unwrap_or("data not from a file"));
        let source = format!(
            "{}, rmse sqrt(L) {} over {} points of {data}, fitted by stfit {}",
            fit.label(),
            crate::translate::four_digits(fit.rmse_sqrt_l),
            fit.n_points,
            escape_control(&fit.stfit_version)
        );
        Self::new(fit.model, source)
    }

    /// `model` to export, described by `source`; refuses a model that cannot be evaluated
    /// ([`Model::check`]).
    pub fn new(model: Model, source: impl Into<String>) -> Result<Self, ExportError> {
        model.check()?;
        Ok(Self {
            ndf: model.ndf()?,
            model,
            source: source.into(),
        })
    }

    /// The fitted NDF.
    pub fn ndf(&self) -> AnyNdf {
        self.ndf
    }

    /// Relative index of the glass, `n_inside / n_outside`.
    pub fn eta(&self) -> f64 {
        self.model.eta
    }

    /// The fit's calibration factor (measured `L` = scale times the model's).
    pub fn scale(&self) -> f64 {
        self.model.scale
    }

    /// The roughness alpha.
    pub fn alpha(&self) -> f64 {
        self.model.alpha
    }

    /// The Student-T shape, `None` for Beckmann and GGX.
    pub fn gamma(&self) -> Option<f64> {
        self.model.gamma.value()
    }

    /// The model in one line for comments: `student-t alpha 0.2 gamma 3 (free), eta 1.51,
    /// separable masking, orders single`.
    pub fn describe(&self) -> String {
        let m = &self.model;
        let gamma = match m.gamma {
            Gamma::NotApplicable => String::new(),
            Gamma::Fixed(g) => format!(" gamma {g} (held fixed)"),
            Gamma::Free(g) => format!(" gamma {g}"),
        };
        let walks = match (m.walks, m.seed) {
            (Some(w), Some(s)) => format!(" ({w} walks per incidence direction, seed {s})"),
            _ => String::new(),
        };
        format!(
            "{} alpha {}{gamma}, eta {}, {} masking, orders {}{walks}",
            m.kind.name(),
            m.alpha,
            m.eta,
            m.masking.name(),
            m.orders.name()
        )
    }

    /// The analytic single-scattering BSDF of the model with its masking (height-correlated for
    /// an all-orders model: the random walk's order 1).
    pub fn single(&self) -> RoughDielectric<AnyNdf> {
        RoughDielectric::new(self.ndf, self.model.eta, self.model.masking)
            .expect("the model was checked")
    }

    /// The microsurface of the model's NDF with dielectric facets (random walk), restricted to
    /// `orders`. Refuses a Student-T shape the walk does not support
    /// ([`check_walk_gamma`]: below 1.501 walks grow without bound), which a single-scattering
    /// fit may have.
    pub fn microsurface(
        &self,
        orders: ScatteringOrders,
    ) -> Result<Microsurface<AnyNdf, DielectricFacet>, ExportError> {
        if let Some(g) = self.gamma() {
            check_walk_gamma(g)?;
        }
        let facet = DielectricFacet::new(self.model.eta).expect("the model was checked");
        Ok(Microsurface::new(self.ndf, facet).with_orders(orders))
    }

    /// Estimated wall time, in seconds, of the walks of [`Self::forward_values`] at `pairs` on
    /// rayon's current pool, for a note before a long export ([`Forward::walk_seconds`]): 0 for
    /// a single-scattering model.
    pub fn forward_walk_seconds(&self, pairs: &[(Vec3, Vec3)]) -> Result<f64, ExportError> {
        Ok(self
            .forward(pairs)?
            .walk_seconds(&self.ndf, self.model.eta)?)
    }

    /// The fitted model's value `q_j f(wi_j, wo_j)` at every pair, by the library's forward
    /// model (the one the fit used: for all orders, its walks and seed); `f` is the BSDF and
    /// `q_j` the quantity per unit BSDF value.
    pub fn forward_values(
        &self,
        pairs: &[(Vec3, Vec3)],
        q: Vec<f64>,
    ) -> Result<Vec<f64>, ExportError> {
        let forward = self.forward(pairs)?;
        let mut out = Vec::with_capacity(pairs.len());
        forward.unit_model(&self.ndf, self.model.eta, &mut out)?;
        out.iter_mut().zip(&q).for_each(|(v, q)| *v *= q);
        Ok(out)
    }

    /// The library's forward model of the fit (its masking, orders, walks and seed) at `pairs`,
    /// each valued as a BSDF.
    fn forward(&self, pairs: &[(Vec3, Vec3)]) -> Result<Forward, ExportError> {
        let m = &self.model;
        Ok(Forward::new(
            pairs,
            vec![Quantity::Bsdf; pairs.len()],
            m.masking,
            m.orders,
            m.walks.unwrap_or(0),
            m.seed.unwrap_or(0),
        )?)
    }
}

/// `text` with every control character (Unicode category Cc: line breaks, tabs, NUL, DEL, the
/// C1 controls) written as its Rust escape (`\n`, `\u{1}`), as [`stfit_fit::short`] does for
/// sample names.
fn escape_control(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use stfit_fit::ModelKind;

    /// A model that cannot be evaluated is refused with the library's reason.
    #[test]
    fn invalid_models_are_refused() {
        let bad = Model::single(ModelKind::Ggx, -0.1, Gamma::NotApplicable, 1.0);
        assert!(ExportModel::new(bad, "x").is_err());
        let bad = Model {
            orders: ScatteringOrders::All,
            ..Model::single(ModelKind::Ggx, 0.3, Gamma::NotApplicable, 1.0)
        };
        let e = ExportModel::new(bad, "x").unwrap_err().to_string();
        assert!(e.contains("correlated"), "{e}");
    }

    /// A single-scattering Student-T fit with gamma in (3/2, 1.501) is exported where no walk is
    /// needed, but its walks (the pane, Radiance) are refused by the walk's own rule rather than
    /// run without end.
    #[test]
    fn walks_of_a_gamma_below_the_walk_range_are_refused() {
        let fit = Model::single(ModelKind::StudentT, 0.3, Gamma::Free(1.5000001), 1.0);
        let model = ExportModel::new(fit, "x").unwrap();
        let e = model
            .microsurface(ScatteringOrders::All)
            .unwrap_err()
            .to_string();
        assert!(e.contains("gamma >= 1.501"), "{e}");
        let opts = crate::radiance::RadianceOptions {
            walks_per_patch: 2,
            ..Default::default()
        };
        let e = crate::radiance::klems(&model, &opts)
            .unwrap_err()
            .to_string();
        assert!(e.contains("gamma >= 1.501"), "{e}");
    }
}
