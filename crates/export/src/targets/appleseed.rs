//! appleseed: a `glass_bsdf`, whose microfacet distribution is GGX.
//!
//! Conventions from appleseedhq/appleseed (master, as released in appleseed 2.1.0-beta):
//! - src/appleseed/renderer/modeling/bsdf/glassbsdf.cpp, `GlassBSDFImpl`: inputs
//!   `surface_transmittance` (no default: written as 1), `surface_transmittance_multiplier`,
//!   `reflection_tint`, `refraction_tint`, `roughness` (default 0.15), `anisotropy`, `ior`
//!   (default 1.5, relative to the medium outside), the volume inputs and
//!   `energy_compensation` (default 0, none). The BSDF is Walter et al. 2007 with `GGXMDF` only:
//!   the `mdf` choice (`beckmann`, `ggx`, `std`) and the STD `highlight_falloff` were removed
//!   ("Use GGX for all microfacet shading models", appleseed issue 2550, pull request 2560,
//!   2019), so a `glass_bsdf` given `mdf std` renders GGX and ignores `highlight_falloff`.
//! - src/appleseed/renderer/modeling/bsdf/microfacethelper.h,
//!   `microfacet_alpha_from_roughness`: `alpha = max(0.001, roughness^2)` (isotropic).
//! - src/appleseed/foundation/math/microfacet.cpp, `GGXMDF::G`: `1 / (1 + Lambda(wo) +
//!   Lambda(wi))` for reflection and transmission ([`Smith::LambdaSum`]).
//!
//! So a GGX fit maps exactly to `roughness = sqrt(alpha)` (clamped to [sqrt(0.001), 1] with a
//! warning); Beckmann and Student-T fits are translated by fitting the roughness of appleseed's
//! GGX glass over the sphere of directions.

use super::{
    AlphaMap, Export, ExportFile, Family1, Microfacet, provenance, translate_microfacet,
    warning_notes, xml_comment,
};
use crate::target::Smith;
use crate::translate::Reference;
use crate::{ExportError, ExportModel};

/// The glass_bsdf inputs stfit writes, all defined by appleseed.
pub const PARAMETERS: [&str; 6] = [
    "surface_transmittance",
    "reflection_tint",
    "refraction_tint",
    "ior",
    "roughness",
    "anisotropy",
];

/// appleseed's smallest alpha (`microfacet_alpha_from_roughness`).
pub const ALPHA_MIN: f64 = 0.001;

/// appleseed's GGX glass with its roughness parameter.
pub fn family(eta: f64) -> Microfacet {
    Microfacet {
        ndf: Family1::Ggx,
        eta,
        smith: Smith::LambdaSum,
        map: AlphaMap::RoughnessSquared,
        name: "roughness",
        max_param: 1.0,
        min_alpha: ALPHA_MIN,
    }
}

/// Writes the appleseed project fragment.
pub fn export(model: &ExportModel, id: &str, reference: &Reference) -> Result<Export, ExportError> {
    // The reference's own warnings first: incidences it does not resolve.
    let mut warnings = reference.warnings().to_vec();
    if !(1.0..=2.5).contains(&model.eta()) {
        return Err(ExportError::Unsupported(format!(
            "appleseed's glass_bsdf takes ior in [1, 2.5], the fit has eta {}",
            model.eta()
        )));
    }
    let t = translate_microfacet(&family(model.eta()), model, reference, &mut warnings)?;
    let roughness = t.params[0].value;
    if roughness * roughness < ALPHA_MIN {
        warnings.push(format!(
            "roughness {roughness:.6} (alpha {:.6}) is below appleseed's floor: it renders alpha {ALPHA_MIN}",
            roughness * roughness
        ));
    }
    let mut notes = provenance(
        model,
        Some(&t),
        &[
            "appleseed glass_bsdf: GGX only (no mdf choice since appleseed 2.1), alpha = max(0.001, roughness^2), G = 1/(1 + Lambda_i + Lambda_o) (glassbsdf.cpp, microfacethelper.h, microfacet.cpp)",
        ],
    );
    notes.extend(warning_notes(&warnings));
    let mut text = xml_comment(&notes);
    text.push_str(&format!("<bsdf name=\"{id}\" model=\"glass_bsdf\">\n"));
    let mut param = |n: &str, v: String| {
        text.push_str(&format!("    <parameter name=\"{n}\" value=\"{v}\" />\n"))
    };
    param("surface_transmittance", "1.0".into());
    param("reflection_tint", "1.0".into());
    param("refraction_tint", "1.0".into());
    param("ior", model.eta().to_string());
    param("roughness", roughness.to_string());
    param("anisotropy", "0.0".into());
    text.push_str("</bsdf>\n");
    Ok(Export {
        files: vec![ExportFile {
            extension: "xml",
            text,
            xml: None,
        }],
        warnings,
        translation: Some(t),
    })
}
