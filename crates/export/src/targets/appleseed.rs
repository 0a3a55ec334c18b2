//! appleseed: a `glass_bsdf` with its Student-T ("STD") microfacet distribution.
//!
//! Conventions from appleseedhq/appleseed:
//! - src/appleseed/renderer/modeling/bsdf/microfacethelper.h: `alpha = max(0.001,
//!   roughness^2)` (isotropic), and `highlight_falloff_to_gama(t) = mix(1.51, 40, t^5)`.
//! - src/appleseed/foundation/math/microfacet.cpp, `StdMDF`: `D = 1 / (pi alpha^2 cos^4 (1 +
//!   tan^2 / ((gamma - 1) alpha^2))^gamma)` (Ribardiere et al. 2017, eq. 18), which is stfit's
//!   Student-T with the same alpha and gamma, and `G = 1 / (1 + Lambda(wo) + Lambda(wi))` with
//!   the exact Student-T Lambda (their eq. 14) ([`Smith::LambdaSum`]).
//! - src/appleseed/renderer/modeling/bsdf/glassbsdf.cpp: inputs `mdf` (`beckmann`, `ggx`,
//!   `std`), `surface_transmittance` (default 0.85: written as 1), `reflection_tint`,
//!   `refraction_tint`, `ior` in [1, 2.5], `roughness` in [0, 1], `highlight_falloff` in
//!   [0, 1], `anisotropy`.
//!
//! So (alpha, gamma) maps exactly to `roughness = sqrt(alpha)` and `highlight_falloff =
//! ((gamma - 1.51) / 38.49)^(1/5)` for gamma in [1.51, 40] and alpha in [0.001, 1]; outside,
//! the parameter is clamped with a warning and the error of the clamped model is reported.

use super::{AlphaMap, Export, ExportFile, Family1, Microfacet, provenance, translate_microfacet};
use crate::target::{CoreMicrofacet, Smith, TargetDielectric};
use crate::translate::{self, Family, Reference};
use crate::{ExportError, ExportModel};
use stfit_core::ndf::{AnyNdf, StudentT};

/// The glass_bsdf inputs stfit writes, all defined by appleseed.
pub const PARAMETERS: [&str; 8] = [
    "mdf",
    "surface_transmittance",
    "reflection_tint",
    "refraction_tint",
    "ior",
    "roughness",
    "highlight_falloff",
    "anisotropy",
];

/// Smallest and largest gamma of appleseed's highlight falloff.
pub const GAMMA_MIN: f64 = 1.51;
pub const GAMMA_MAX: f64 = 40.0;

/// `highlight_falloff_to_gama`.
pub fn gamma_of_falloff(t: f64) -> f64 {
    GAMMA_MIN + (GAMMA_MAX - GAMMA_MIN) * t.powi(5)
}

/// Inverse of [`gamma_of_falloff`] on [1.51, 40].
pub fn falloff_of_gamma(g: f64) -> f64 {
    ((g - GAMMA_MIN) / (GAMMA_MAX - GAMMA_MIN))
        .max(0.0)
        .powf(0.2)
}

/// appleseed's STD glass: parameters (roughness, highlight_falloff).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Std {
    pub eta: f64,
}

impl Family for Std {
    type Bsdf = TargetDielectric<CoreMicrofacet>;

    fn names(&self) -> Vec<&'static str> {
        vec!["roughness", "highlight_falloff"]
    }

    fn build(&self, p: &[f64]) -> Result<Self::Bsdf, ExportError> {
        let alpha = (p[0] * p[0]).max(0.001);
        let ndf: AnyNdf = StudentT::new(alpha, gamma_of_falloff(p[1]))?.into();
        TargetDielectric::new(
            CoreMicrofacet {
                ndf,
                smith: Smith::LambdaSum,
            },
            self.eta,
        )
    }

    fn params_of(&self, x: &[f64]) -> Vec<f64> {
        vec![x[0].clamp(0.001f64.sqrt(), 1.0), x[1].clamp(0.0, 1.0)]
    }

    fn search_of(&self, p: &[f64]) -> Vec<f64> {
        p.to_vec()
    }

    fn starts(&self) -> Vec<Vec<f64>> {
        vec![vec![0.5, 0.4]]
    }
}

/// Writes the appleseed project fragment.
pub fn export(model: &ExportModel, id: &str, reference: &Reference) -> Result<Export, ExportError> {
    let mut warnings = Vec::new();
    if !(1.0..=2.5).contains(&model.eta()) {
        return Err(ExportError::Unsupported(format!(
            "appleseed's glass_bsdf takes ior in [1, 2.5], the fit has eta {}",
            model.eta()
        )));
    }
    let (mdf, t) = match model.ndf() {
        AnyNdf::StudentT(st) => {
            let (alpha, gamma) = (st.alpha(), st.gamma());
            let mut r = alpha.sqrt();
            if r > 1.0 {
                warnings.push(format!(
                    "roughness {r:.6} (alpha {alpha}) exceeds appleseed's maximum 1: clamped"
                ));
                r = 1.0;
            }
            if alpha < 0.001 {
                warnings.push(format!(
                    "alpha {alpha} is below appleseed's floor 0.001: it renders alpha 0.001"
                ));
            }
            let g = gamma.clamp(GAMMA_MIN, GAMMA_MAX);
            if g != gamma {
                warnings.push(format!(
                    "gamma {gamma:.6} is outside appleseed's highlight-falloff range [{GAMMA_MIN}, {GAMMA_MAX}]: clamped to {g}"
                ));
            }
            let fam = Std { eta: model.eta() };
            (
                "std",
                translate::evaluate(&fam, model, reference, &[r, falloff_of_gamma(g)])?,
            )
        }
        AnyNdf::Ggx(_) | AnyNdf::Beckmann(_) => {
            let ndf = if matches!(model.ndf(), AnyNdf::Ggx(_)) {
                Family1::Ggx
            } else {
                Family1::Beckmann
            };
            let fam = Microfacet {
                ndf,
                eta: model.eta(),
                smith: Smith::LambdaSum,
                map: AlphaMap::RoughnessSquared,
                name: "roughness",
                max_param: 1.0,
            };
            let t = translate_microfacet(&fam, model, reference, &mut warnings)?;
            (
                if ndf == Family1::Ggx {
                    "ggx"
                } else {
                    "beckmann"
                },
                t,
            )
        }
    };
    let roughness = t.params[0].value;
    let falloff = t.value("highlight_falloff");
    let mut text = String::from("<!--\n");
    for n in provenance(
        model,
        Some(&t),
        &[
            "appleseed glass_bsdf: alpha = roughness^2, gamma = mix(1.51, 40, highlight_falloff^5) (microfacethelper.h)",
        ],
    ) {
        text.push_str(&format!("  {}\n", n.replace("--", "- -")));
    }
    for w in &warnings {
        text.push_str(&format!("  warning: {}\n", w.replace("--", "- -")));
    }
    text.push_str("-->\n");
    text.push_str(&format!("<bsdf name=\"{id}\" model=\"glass_bsdf\">\n"));
    let mut param = |n: &str, v: String| {
        text.push_str(&format!("    <parameter name=\"{n}\" value=\"{v}\" />\n"))
    };
    param("mdf", mdf.into());
    param("surface_transmittance", "1.0".into());
    param("reflection_tint", "1.0".into());
    param("refraction_tint", "1.0".into());
    param("ior", model.eta().to_string());
    param("roughness", roughness.to_string());
    if let Some(f) = falloff {
        param("highlight_falloff", f.to_string());
    }
    param("anisotropy", "0.0".into());
    text.push_str("</bsdf>\n");
    Ok(Export {
        files: vec![ExportFile {
            extension: "xml",
            text,
        }],
        warnings,
        translation: Some(t),
    })
}
