//! OpenPBR: a transmissive `open_pbr_surface` (MaterialX) whose specular lobe is the
//! specular-haze mixture of two GGX lobes.
//!
//! Conventions read from the OpenPBR viewer's specular BRDF carrying pull request 254 of
//! AcademySoftwareFoundation/OpenPBR ("specular haze (dual-lobe NDF)"): core lobe alpha =
//! `specular_roughness^2`, haze lobe alpha = `mix(specular_roughness, 1,
//! specular_haze_spread)^2` (isotropic; both floored at 1e-4), and the BSDF mixes `D G2` of
//! the two lobes with weight `specular_haze` (`G2` height-correlated,
//! [`Smith::Uncorrelated`]); `specular_haze` and `specular_haze_spread` (default 0.3) are
//! OpenPBR 1.2 parameters. stfit assumes the same mixture for the transmitted lobe
//! (`transmission_weight` 1). The mixture is fitted to the fitted BSDF over the sphere of
//! directions; the haze is written only where it is meaningful, that is where it lowers the
//! rmse by at least [`MEANINGFUL_GAIN`] relative to the best single GGX lobe (haze 0).

use super::{AlphaMap, Export, ExportFile, Family1, Microfacet, provenance, translate_microfacet};
use crate::target::{Mixture, Smith, TargetDielectric};
use crate::translate::{self, Family, Reference, Translation, from_unit_coord, unit_coord};
use crate::{ExportError, ExportModel};
use stfit_core::ndf::Ggx;

/// Relative rmse reduction below which the haze lobe is not written.
pub const MEANINGFUL_GAIN: f64 = 0.05;

/// The open_pbr_surface inputs stfit writes.
pub const PARAMETERS: [&str; 7] = [
    "base_weight",
    "specular_weight",
    "specular_roughness",
    "specular_ior",
    "specular_haze",
    "specular_haze_spread",
    "transmission_weight",
];

/// The haze mixture: (specular_roughness, specular_haze, specular_haze_spread).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Haze {
    pub eta: f64,
    pub start_roughness: f64,
}

fn lobe(alpha: f64, eta: f64) -> Result<TargetDielectric, ExportError> {
    TargetDielectric::new(Ggx::new(alpha.max(1e-4))?.into(), eta, Smith::Uncorrelated)
}

impl Family for Haze {
    type Bsdf = Mixture;

    fn names(&self) -> Vec<&'static str> {
        vec![
            "specular_roughness",
            "specular_haze",
            "specular_haze_spread",
        ]
    }

    fn build(&self, p: &[f64]) -> Result<Mixture, ExportError> {
        let r = p[0];
        let rh = r + (1.0 - r) * p[2];
        Ok(Mixture {
            a: lobe(r * r, self.eta)?,
            b: lobe(rh * rh, self.eta)?,
            weight: p[1],
        })
    }

    fn params_of(&self, x: &[f64]) -> Vec<f64> {
        x.iter().map(|&v| from_unit_coord(v)).collect()
    }

    fn search_of(&self, p: &[f64]) -> Vec<f64> {
        p.iter().map(|&v| unit_coord(v)).collect()
    }

    fn starts(&self) -> Vec<Vec<f64>> {
        let r = self.start_roughness.clamp(0.01, 0.99);
        vec![vec![r * 0.9, 0.2, 0.3], vec![r * 0.8, 0.4, 0.6]]
    }
}

/// Writes the MaterialX document.
pub fn export(model: &ExportModel, id: &str, reference: &Reference) -> Result<Export, ExportError> {
    let mut warnings = Vec::new();
    let single = Microfacet {
        ndf: Family1::Ggx,
        eta: model.eta,
        smith: Smith::Uncorrelated,
        map: AlphaMap::RoughnessSquared,
        name: "specular_roughness",
        max_param: 1.0,
    };
    let one = translate_microfacet(&single, model, reference, &mut warnings)?;
    let haze = translate::fit(
        &Haze {
            eta: model.eta,
            start_roughness: one.params[0].value,
        },
        model,
        reference,
    )?;
    let meaningful = haze.rmse < (1.0 - MEANINGFUL_GAIN) * one.rmse;
    let t: Translation = if meaningful {
        haze.clone()
    } else {
        one.clone()
    };
    let mut notes = provenance(
        model,
        Some(&t),
        &[
            "OpenPBR: alpha = specular_roughness^2; haze lobe alpha = mix(specular_roughness, 1, specular_haze_spread)^2 (OpenPBR 1.2, PR 254)",
        ],
    );
    notes.push(format!(
        "single GGX lobe: rmse {:.4}; two-lobe haze mixture: rmse {:.4} ({}).",
        one.rmse,
        haze.rmse,
        if meaningful {
            "haze written"
        } else {
            "gain below 5%: haze not meaningful, not written"
        }
    ));
    let mut text = String::from("<?xml version=\"1.0\"?>\n<!--\n");
    for n in &notes {
        text.push_str(&format!("  {}\n", n.replace("--", "- -")));
    }
    text.push_str("-->\n<materialx version=\"1.39\">\n");
    text.push_str(&format!(
        "  <open_pbr_surface name=\"{id}\" type=\"surfaceshader\">\n"
    ));
    let mut input = |n: &str, v: f64| {
        text.push_str(&format!(
            "    <input name=\"{n}\" type=\"float\" value=\"{v}\" />\n"
        ))
    };
    input("base_weight", 0.0);
    input("specular_weight", 1.0);
    input("specular_roughness", t.params[0].value);
    input("specular_ior", model.eta);
    if meaningful {
        input("specular_haze", haze.params[1].value);
        input("specular_haze_spread", haze.params[2].value);
    }
    input("transmission_weight", 1.0);
    text.push_str(&format!(
        "  </open_pbr_surface>\n  <surfacematerial name=\"{id}_material\" type=\"material\">\n    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"{id}\" />\n  </surfacematerial>\n</materialx>\n"
    ));
    Ok(Export {
        files: vec![ExportFile {
            extension: "mtlx",
            text,
        }],
        warnings,
        translation: Some(t),
    })
}
