//! OpenPBR: a transmissive `open_pbr_surface` (MaterialX) whose specular lobe is the
//! specular-haze mixture of two GGX lobes.
//!
//! Conventions, from AcademySoftwareFoundation/OpenPBR, branch dev_1.2 (OpenPBR 1.2, unreleased
//! at the time of writing; `specular_haze` came with pull requests 254 and 298):
//! - index.html, "Microfacet model": GGX with `alpha = specular_roughness^2`, `G` from the
//!   Smith model; "Specular haze": the base BSDF is `(1 - specular_haze) f_core + specular_haze
//!   f_haze`, and "for the dielectric base, both core and haze BSDF lobes are given by
//!   f_dielectric except with a different roughness value for the haze", `r_haze =
//!   lerp(specular_roughness, 1, specular_haze_spread)` (default spread 0.3): by the
//!   specification the haze applies to the transmitted light too.
//! - reference/open_pbr_surface.mtlx (the reference MaterialX graph): the haze mixes only the
//!   `dielectric_bsdf` reflection lobes (`scatter_mode` R); the transmission
//!   (`dielectric_transmission`, `scatter_mode` T) keeps the core roughness alone. A renderer
//!   that compiles this graph transmits without the haze.
//! - `G`: height-correlated `1 / (1 + Lambda_i + Lambda_o)` ([`Smith::LambdaSum`]), as the
//!   OpenPBR viewer's `ggx_G2` and MaterialX's `mx_ggx_smith_G2`.
//!
//! The mixture is fitted, per the specification (haze in both lobes), to the fitted BSDF over
//! the sphere of directions; the haze is written only where it is meaningful, that is where it
//! lowers the rmse by at least [`MEANINGFUL_GAIN`] relative to the best single GGX lobe
//! (haze 0) both as the specification reads it and as the reference graph renders it (haze in
//! reflection only): a haze that only the specification's reading rewards would render worse
//! than the single lobe wherever the graph is compiled, and released MaterialX (1.39) declares
//! OpenPBR 1.1, which has no `specular_haze` and ignores it. The comment gives both rmse.

use super::{
    AlphaMap, Export, ExportFile, Family1, Microfacet, XML_DECLARATION, XmlPart, provenance,
    translate_microfacet, warning_notes, xml_comment,
};
use crate::target::{CoreMicrofacet, Mixture, Smith, TargetDielectric};
use crate::translate::{
    self, Family, Reference, Translation, from_unit_coord, rmse_text, unit_coord,
};
use crate::{ExportError, ExportModel};
use stfit_core::ndf::Ggx;

/// The root start tag of the MaterialX documents written (MaterialX 1.39).
const MATERIALX_ROOT: &str = "<materialx version=\"1.39\">\n";

/// The root end tag of the MaterialX documents written.
const MATERIALX_CLOSE: &str = "</materialx>\n";

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
    /// Whether the haze lobe transmits too (the specification) or only reflects (the reference
    /// MaterialX graph).
    pub haze_transmits: bool,
}

fn lobe(alpha: f64, eta: f64) -> Result<TargetDielectric<CoreMicrofacet>, ExportError> {
    let micro = CoreMicrofacet {
        ndf: Ggx::new(alpha.max(1e-4))?.into(),
        smith: Smith::LambdaSum,
    };
    TargetDielectric::new(micro, eta)
}

impl Family for Haze {
    type Bsdf = Mixture<CoreMicrofacet>;

    fn names(&self) -> Vec<&'static str> {
        vec![
            "specular_roughness",
            "specular_haze",
            "specular_haze_spread",
        ]
    }

    fn build(&self, p: &[f64]) -> Result<Self::Bsdf, ExportError> {
        let r = p[0];
        let rh = r + (1.0 - r) * p[2];
        Ok(Mixture {
            a: lobe(r * r, self.eta)?,
            b: lobe(rh * rh, self.eta)?,
            weight: p[1],
            haze_transmits: self.haze_transmits,
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
    // The reference's own warnings first: incidences it does not resolve.
    let mut warnings = reference.warnings().to_vec();
    let single = Microfacet {
        ndf: Family1::Ggx,
        eta: model.eta(),
        smith: Smith::LambdaSum,
        map: AlphaMap::RoughnessSquared,
        name: "specular_roughness",
        max_param: 1.0,
        min_alpha: 0.0,
    };
    let one = translate_microfacet(&single, model, reference, &mut warnings)?;
    let spec = Haze {
        eta: model.eta(),
        start_roughness: one.params[0].value,
        haze_transmits: true,
    };
    let mut haze_warnings = Vec::new();
    let haze = translate::fit(&spec, model, reference, &mut haze_warnings)?;
    // The mixture's rmse as the reference graph renders the fitted values.
    let graph = Haze {
        haze_transmits: false,
        ..spec
    };
    let haze_values: Vec<f64> = haze.params.iter().map(|p| p.value).collect();
    let graph_rmse = reference.rmse(&graph.build(&haze_values)?);
    let gains = |rmse: f64| rmse < (1.0 - MEANINGFUL_GAIN) * one.rmse;
    let meaningful = gains(haze.rmse) && gains(graph_rmse);
    let t: Translation = if meaningful {
        warnings.extend(haze_warnings);
        haze.clone()
    } else {
        one.clone()
    };
    let mut notes = provenance(
        model,
        Some(&t),
        &[
            "OpenPBR (1.2, dev_1.2 index.html): alpha = specular_roughness^2; haze lobe alpha = lerp(specular_roughness, 1, specular_haze_spread)^2, mixed with weight specular_haze into the whole dielectric BSDF",
        ],
    );
    notes.push(format!(
        "single GGX lobe: rmse {}; two-lobe haze mixture: rmse {} as the specification reads it, {} as the reference MaterialX graph (reference/open_pbr_surface.mtlx) renders it, with the haze in reflection only ({}).",
        rmse_text(one.rmse, reference.rms()),
        rmse_text(haze.rmse, reference.rms()),
        rmse_text(graph_rmse, reference.rms()),
        if meaningful {
            "haze written"
        } else {
            "gain below 5% in either: haze not written"
        }
    ));
    notes.extend(warning_notes(&warnings));
    let comment = xml_comment(&notes);
    let mut text = String::new();
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
    input("specular_ior", model.eta());
    if meaningful {
        input("specular_haze", haze.params[1].value);
        input("specular_haze_spread", haze.params[2].value);
    }
    input("transmission_weight", 1.0);
    text.push_str(&format!(
        "  </open_pbr_surface>\n  <surfacematerial name=\"{id}_material\" type=\"material\">\n    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"{id}\" />\n  </surfacematerial>\n"
    ));
    // One fit: the comment before the document's root; several: each fit's comment before
    // its nodes inside one root.
    Ok(Export {
        files: vec![ExportFile {
            extension: "mtlx",
            text: format!("{XML_DECLARATION}{comment}{MATERIALX_ROOT}{text}{MATERIALX_CLOSE}"),
            xml: Some(XmlPart {
                open: format!("{XML_DECLARATION}{MATERIALX_ROOT}"),
                content: format!("{comment}{text}"),
                close: MATERIALX_CLOSE,
            }),
        }],
        warnings,
        translation: Some(t),
    })
}
