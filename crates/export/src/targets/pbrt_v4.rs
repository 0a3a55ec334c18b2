//! pbrt-v4: a `MakeNamedMaterial` line of type `dielectric`, named by the fit's identifier.
//!
//! A named material, not an anonymous `Material`: pbrt-v4's `Material` directive replaces the
//! current material (`BasicSceneBuilder::Material`, src/pbrt/scene.cpp), so of several fits'
//! `Material` lines in one file only the last would reach a shape, whereas each
//! `MakeNamedMaterial` (`BasicSceneBuilder::MakeNamedMaterial`, same file) defines a material
//! that `NamedMaterial "ID"` selects; pbrt refuses a name defined twice, and the fits of one
//! file have distinct identifiers ([`crate::batch`]).
//!
//! Conventions from mmp/pbrt-v4: `DielectricMaterial::Create` (src/pbrt/materials.cpp) reads
//! `eta` (default 1.5), `roughness` (default 0; `uroughness`/`vroughness` override it),
//! `remaproughness` (default true) and `displacement`; with `remaproughness` true the
//! Trowbridge-Reitz alpha is `TrowbridgeReitzDistribution::RoughnessToAlpha(roughness) =
//! sqrt(roughness)` (src/pbrt/util/scattering.h), so stfit writes `roughness = alpha^2` and
//! states `remaproughness true` explicitly. The BSDF is `DielectricBxDF` (src/pbrt/bxdfs.h,
//! `DielectricBxDF::f` in src/pbrt/bxdfs.cpp): Walter et al. 2007 with GGX only and
//! `G = 1 / (1 + Lambda(wo) + Lambda(wi))` for reflection and transmission
//! ([`Smith::LambdaSum`]); `eta` is the index below the surface (against the shading normal)
//! over the index above, stfit's `n_inside / n_outside`, and in radiance mode
//! (`TransportMode::Radiance`, with pbrt's `wi` toward the light) its transmission carries the
//! `1 / etap^2` that makes it stfit's radiance-convention BSDF.
//!
//! Checked in pbrt-v4 itself (commit 5f7a606, built from source): the example fits' files parse
//! and render without a warning, and its `DielectricBxDF::f` agrees with stfit's model of the
//! written parameters to single precision (README, export section);
//! crates/export/tests/pbrt_v4_bsdf.rs keeps a transcription of that evaluation.

use super::{
    AlphaMap, Export, ExportFile, Family1, Microfacet, provenance, translate_microfacet,
    warning_notes,
};
use crate::target::Smith;
use crate::translate::Reference;
use crate::{ExportError, ExportModel};

/// pbrt-v4's smallest rough alpha: `TrowbridgeReitzDistribution::EffectivelySmooth` (src/pbrt/util/scattering.h)
/// is `max(alpha_x, alpha_y) < 1e-3f`, and `DielectricBxDF` then scatters as a perfectly smooth
/// dielectric (a delta lobe), whatever the roughness.
pub const SMOOTH_BELOW_ALPHA: f32 = 1e-3;

/// Whether pbrt-v4 renders `roughness` (with `remaproughness` true) as a smooth dielectric: its
/// alpha `sqrt(roughness)`, computed in single precision as pbrt does, is below
/// [`SMOOTH_BELOW_ALPHA`].
pub fn renders_smooth(roughness: f64) -> bool {
    (roughness as f32).sqrt() < SMOOTH_BELOW_ALPHA
}

/// The dielectric parameters stfit writes, all defined by pbrt-v4.
pub const PARAMETERS: [&str; 3] = ["eta", "roughness", "remaproughness"];

/// The translation to pbrt-v4's Trowbridge-Reitz dielectric.
pub fn family(eta: f64) -> Microfacet {
    Microfacet {
        ndf: Family1::Ggx,
        eta,
        smith: Smith::LambdaSum,
        map: AlphaMap::SqrtRoughness,
        name: "roughness",
        max_param: 100.0,
        min_alpha: 0.0,
    }
}

/// Writes the named material `id` with its comment.
pub fn export(model: &ExportModel, id: &str, reference: &Reference) -> Result<Export, ExportError> {
    // The reference's own warnings first: incidences it does not resolve.
    let mut warnings = reference.warnings().to_vec();
    let t = translate_microfacet(&family(model.eta()), model, reference, &mut warnings)?;
    let roughness = t.params[0].value;
    if renders_smooth(roughness) {
        warnings.push(format!(
            "roughness {roughness:.3e} (alpha {:.3e}) is below pbrt-v4's smallest rough alpha 1e-3: pbrt renders it as a perfectly smooth dielectric (TrowbridgeReitzDistribution::EffectivelySmooth)",
            roughness.sqrt()
        ));
    }
    let mut notes = provenance(
        model,
        Some(&t),
        &[
            &format!(
                "pbrt-v4 dielectric: remaproughness true (its default), alpha = sqrt(roughness) = {}",
                roughness.sqrt()
            ),
            &format!("select it for the shapes that follow with: NamedMaterial \"{id}\""),
        ],
    );
    notes.extend(warning_notes(&warnings));
    let mut text = String::new();
    for n in notes {
        text.push_str(&format!("# {n}\n"));
    }
    text.push_str(&format!(
        "MakeNamedMaterial \"{id}\" \"string type\" [ \"dielectric\" ] \"float eta\" [ {} ] \"float roughness\" [ {roughness} ] \"bool remaproughness\" [ true ]\n",
        model.eta()
    ));
    Ok(Export {
        files: vec![ExportFile {
            extension: "pbrt",
            text,
            xml: None,
        }],
        warnings,
        translation: Some(t),
    })
}
