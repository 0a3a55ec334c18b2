//! Mitsuba 3: a `roughdielectric` BSDF element and the equivalent Python dict.
//!
//! Conventions from mitsuba-renderer/mitsuba3, src/bsdfs/roughdielectric.cpp: parameters
//! `distribution` (`beckmann`, the default, or `ggx`), `alpha` (used as is, no remapping),
//! `int_ior` (default bk7), `ext_ior` (default air, 1.000277: written as 1 so that the
//! relative index is the fitted eta), `sample_visible`, `alpha_u`/`alpha_v`,
//! `specular_reflectance`/`specular_transmittance`. Walter et al. 2007 with separable
//! `G = smith_g1(wi) smith_g1(wo)` (include/mitsuba/render/microfacet.h; Beckmann's G1 there is
//! a rational approximation, [`Smith::MitsubaSeparable`]).
//!
//! The XML file is a document Mitsuba loads (`mi.load_file`, `<include filename="..."/>` in a
//! scene): for one fit its `<bsdf>` is the root, with the scene format's `version`; for several,
//! a `<scene version="3.0.0">` holds their `<bsdf>` elements, each referable by its `id`.

use super::{
    Export, ExportFile, Family1, Microfacet, XML_DECLARATION, XmlPart, provenance,
    translate_microfacet, warning_notes, xml_comment,
};
use crate::target::Smith;
use crate::translate::{Reference, Translation};
use crate::{ExportError, ExportModel};
use stfit_core::ndf::AnyNdf;

/// The roughdielectric parameters stfit writes, all defined by Mitsuba 3.
pub const PARAMETERS: [&str; 4] = ["distribution", "alpha", "int_ior", "ext_ior"];

/// The Mitsuba 3 scene format version of the files written (src/core/xml.cpp reads files
/// whose root element carries one).
pub const SCENE_VERSION: &str = "3.0.0";

/// Mitsuba's smallest alpha: `MicrofacetDistribution::configure` (include/mitsuba/render/microfacet.h)
/// raises alpha to `max(alpha, 1e-4)`.
pub const ALPHA_MIN: f64 = 1e-4;

fn family(ndf: Family1, eta: f64) -> Microfacet {
    Microfacet {
        ndf,
        eta,
        smith: Smith::MitsubaSeparable,
        map: super::AlphaMap::Alpha,
        name: "alpha",
        max_param: 10.0,
        min_alpha: ALPHA_MIN,
    }
}

/// The translation to Mitsuba's GGX or Beckmann (the better of the two for a Student-T fit).
pub fn translation(
    model: &ExportModel,
    reference: &Reference,
    warnings: &mut Vec<String>,
) -> Result<(Family1, Translation), ExportError> {
    let candidates: &[Family1] = match model.ndf() {
        AnyNdf::Ggx(_) => &[Family1::Ggx],
        AnyNdf::Beckmann(_) => &[Family1::Beckmann],
        AnyNdf::StudentT(_) => &[Family1::Ggx, Family1::Beckmann],
    };
    let mut best: Option<(Family1, Translation)> = None;
    for &c in candidates {
        let t = translate_microfacet(&family(c, model.eta()), model, reference, warnings)?;
        if best.as_ref().is_none_or(|(_, b)| t.rmse < b.rmse) {
            best = Some((c, t));
        }
    }
    Ok(best.expect("at least one candidate"))
}

/// Writes the XML element and the Python dict.
pub fn export(model: &ExportModel, id: &str, reference: &Reference) -> Result<Export, ExportError> {
    // The reference's own warnings first: incidences it does not resolve.
    let mut warnings = reference.warnings().to_vec();
    let (ndf, t) = translation(model, reference, &mut warnings)?;
    let alpha = t.params[0].value;
    if alpha < ALPHA_MIN {
        warnings.push(format!(
            "alpha {alpha:.3e} is below Mitsuba 3's floor: it renders alpha {ALPHA_MIN} (MicrofacetDistribution::configure)"
        ));
    }
    let dist = match ndf {
        Family1::Ggx => "ggx",
        Family1::Beckmann => "beckmann",
    };
    let mut notes = provenance(
        model,
        Some(&t),
        &[
            "Mitsuba 3 roughdielectric: alpha used as is (no remapping), separable Smith G (src/bsdfs/roughdielectric.cpp)",
        ],
    );
    notes.extend(warning_notes(&warnings));
    let comment = xml_comment(&notes);
    // Mitsuba reads a file (mi.load_file, <include>) whose root element has a version; the
    // bsdf inside a scene of several fits takes the scene's.
    let bsdf = |version: &str| {
        format!(
            "{comment}<bsdf type=\"roughdielectric\" id=\"{id}\"{version}>\n    <string name=\"distribution\" value=\"{dist}\"/>\n    <float name=\"alpha\" value=\"{alpha}\"/>\n    <float name=\"int_ior\" value=\"{}\"/>\n    <float name=\"ext_ior\" value=\"1\"/>\n</bsdf>\n",
            model.eta()
        )
    };
    let mut py = String::new();
    for n in &notes {
        py.push_str(&format!("# {n}\n"));
    }
    py.push_str(&format!(
        "{id} = {{\n    'type': 'roughdielectric',\n    'distribution': '{dist}',\n    'alpha': {alpha},\n    'int_ior': {},\n    'ext_ior': 1.0,\n}}\n",
        model.eta()
    ));
    Ok(Export {
        files: vec![
            ExportFile {
                extension: "xml",
                text: bsdf(&format!(" version=\"{SCENE_VERSION}\"")),
                xml: Some(XmlPart {
                    open: format!("{XML_DECLARATION}<scene version=\"{SCENE_VERSION}\">\n"),
                    content: bsdf(""),
                    close: "</scene>\n",
                }),
            },
            ExportFile {
                extension: "py",
                text: py,
                xml: None,
            },
        ],
        warnings,
        translation: Some(t),
    })
}
