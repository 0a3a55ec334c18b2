//! V-Ray: a `BRDFVRayMtl` with its "Microfacet GTR (GGX)" BRDF, in a `.vrscene` fragment.
//!
//! Conventions:
//! - Parameters, from ChaosGroup/vray_for_blender_addon,
//!   python_exporter/plugins_desc/BRDF/BRDFVRayMtl.json (V-Ray's own plugin description):
//!   `brdf_type` 4 is GGX ("Microfacet GTR"); `gtr_gamma` ("GGX tail falloff", default 2.0,
//!   range 0.001 to 1000, interface range 2 to 10); `reflect_glossiness` and
//!   `refract_glossiness` in [0, 1] (default 1); `option_use_roughness` (default false) reads
//!   them as roughness; `fresnel` (default false: written true), `fresnel_ior_lock` (default
//!   true), `refract_ior`, `reflect`/`refract` colours (default black: written white),
//!   `hilight_glossiness_lock` (default true), `gtr_energy_compensation` (default 0, none).
//! - The BSDF, from ChaosGroup/vraymtl_glsl, vraymtl.glsl (Chaos's GLSL port of the V-Ray 6
//!   VRayMtl): `alpha = max(1 - glossiness, 1e-4)^2`, GTR `D` and V-Ray's separable `G1 G1`
//!   with its closed forms at `gamma = 0..4` and a spline between them ([`crate::gtr`]).
//! - Assumed, not public: V-Ray's glossy refraction with `brdf_type` GGX. The GLSL port
//!   approximates refraction by a Phong-like lobe around the refracted direction
//!   (`sampleRefractBRDF`); V-Ray's own BTDF source is not published. stfit assumes Walter et
//!   al. 2007's microfacet BTDF with the same GTR `D` at `refract_glossiness` and V-Ray's `G1`
//!   of each direction (the direction inside the glass mirrored to the upper side), with
//!   `refract_glossiness = reflect_glossiness`. The translation error is that of this model.
//!
//! Student-T and Beckmann fits are translated by fitting (glossiness, gtr_gamma) over the
//! sphere of directions (gtr_gamma searched in [0.1, 10], 10 being V-Ray's interface maximum);
//! a GGX fit maps exactly to `gtr_gamma` 2.

use super::{Export, ExportFile, provenance, warning_notes};
use crate::gtr::VRayGtr;
use crate::target::TargetDielectric;
use crate::translate::{self, Family, Reference, Translation, from_log_coord, log_coord};
use crate::{ExportError, ExportModel};
use stfit_core::ndf::AnyNdf;

/// The BRDFVRayMtl parameters stfit writes, all defined by V-Ray.
pub const PARAMETERS: [&str; 14] = [
    "brdf_type",
    "diffuse",
    "reflect",
    "reflect_glossiness",
    "hilight_glossiness_lock",
    "fresnel",
    "fresnel_ior_lock",
    "gtr_gamma",
    "gtr_energy_compensation",
    "refract",
    "refract_glossiness",
    "refract_ior",
    "option_use_roughness",
    "option_double_sided",
];

/// Roughness `1 - glossiness` searched in this range (alpha from 1e-4 to 0.98).
pub const ROUGHNESS_RANGE: (f64, f64) = (0.01, 0.99);
/// `gtr_gamma` searched in this range.
pub const GAMMA_RANGE: (f64, f64) = (0.1, 10.0);

/// V-Ray's GTR alpha of a glossiness: `max(1 - glossiness, 1e-4)^2`.
pub fn alpha_of_glossiness(g: f64) -> f64 {
    let r = (1.0 - g).max(1e-4);
    r * r
}

/// V-Ray's GTR glass: parameters (glossiness, gtr_gamma).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VRayGlass {
    pub eta: f64,
    /// Starting points (glossiness, gtr_gamma).
    pub starts: [(f64, f64); 2],
}

impl Family for VRayGlass {
    type Bsdf = TargetDielectric<VRayGtr>;

    fn names(&self) -> Vec<&'static str> {
        vec!["glossiness", "gtr_gamma"]
    }

    fn build(&self, p: &[f64]) -> Result<Self::Bsdf, ExportError> {
        TargetDielectric::new(VRayGtr::new(alpha_of_glossiness(p[0]), p[1])?, self.eta)
    }

    fn params_of(&self, x: &[f64]) -> Vec<f64> {
        let (r0, r1) = ROUGHNESS_RANGE;
        vec![
            1.0 - from_log_coord(x[0], r0, r1),
            from_log_coord(x[1], GAMMA_RANGE.0, GAMMA_RANGE.1),
        ]
    }

    fn search_of(&self, p: &[f64]) -> Vec<f64> {
        let (r0, r1) = ROUGHNESS_RANGE;
        vec![
            log_coord(1.0 - p[0], r0, r1),
            log_coord(p[1], GAMMA_RANGE.0, GAMMA_RANGE.1),
        ]
    }

    fn starts(&self) -> Vec<Vec<f64>> {
        self.starts.iter().map(|&(g, t)| vec![g, t]).collect()
    }
}

/// The glossiness of a GTR alpha, inside the searched range.
fn glossiness_of_alpha(alpha: f64) -> f64 {
    1.0 - alpha.sqrt().clamp(ROUGHNESS_RANGE.0, ROUGHNESS_RANGE.1)
}

/// The translation: exact for GGX (`gtr_gamma` 2), else fitted over the sphere, from the GTR
/// nearest the fitted NDF (Student-T `(alpha, gamma)` is GTR `(alpha sqrt(gamma - 1), gamma)`
/// up to a factor `cos^(2 gamma - 4)`; Beckmann is Student-T's limit, started at gamma 10) and
/// from GGX's `(alpha, 2)`.
pub fn translation(
    model: &ExportModel,
    reference: &Reference,
    warnings: &mut Vec<String>,
) -> Result<Translation, ExportError> {
    let alpha = model.alpha();
    let family = |starts| VRayGlass {
        eta: model.eta(),
        starts,
    };
    let plain = (glossiness_of_alpha(alpha), 2.0);
    match model.ndf() {
        AnyNdf::Ggx(_) => {
            let g = glossiness_of_alpha(alpha);
            if (alpha_of_glossiness(g) - alpha).abs() > 1e-12 * alpha {
                warnings.push(format!(
                    "GGX alpha {alpha} is outside V-Ray's glossiness range used here (alpha 1e-4 to 0.98): clamped to {}",
                    alpha_of_glossiness(g)
                ));
            }
            translate::evaluate(&family([plain, plain]), model, reference, &[g, 2.0])
        }
        AnyNdf::StudentT(st) => {
            let gamma = st.gamma().min(GAMMA_RANGE.1);
            let near = (
                glossiness_of_alpha(alpha * (gamma - 1.0).sqrt()),
                gamma.max(GAMMA_RANGE.0),
            );
            translate::fit(&family([near, plain]), model, reference, warnings)
        }
        AnyNdf::Beckmann(_) => {
            let near = (glossiness_of_alpha(3.0 * alpha), GAMMA_RANGE.1);
            translate::fit(&family([near, plain]), model, reference, warnings)
        }
    }
}

/// The largest difference between V-Ray's G1 and the exact Smith G1 of its GTR over polar
/// angles 1 to 89 degrees.
fn g1_deviation(gtr: &VRayGtr) -> f64 {
    (1..90)
        .map(|deg| {
            let c = f64::from(deg).to_radians().cos();
            (gtr.g1(c) - gtr.g1_exact(c)).abs()
        })
        .fold(0.0, f64::max)
}

/// Writes the `.vrscene` fragment: the BRDF and a `MtlSingleBRDF` using it.
pub fn export(model: &ExportModel, id: &str, reference: &Reference) -> Result<Export, ExportError> {
    // The reference's own warnings first: incidences it does not resolve.
    let mut warnings = reference.warnings().to_vec();
    let t = translation(model, reference, &mut warnings)?;
    let (g, gamma) = (t.params[0].value, t.params[1].value);
    let gtr = VRayGtr::new(alpha_of_glossiness(g), gamma)?;
    let mut notes = provenance(
        model,
        Some(&t),
        &[
            "V-Ray BRDFVRayMtl, brdf_type 4 (Microfacet GTR): alpha = (1 - glossiness)^2, GTR D with gtr_gamma, separable G1 G1 (ChaosGroup/vraymtl_glsl, vraymtl.glsl)",
            "assumed: V-Ray's glossy refraction is Walter et al.'s BTDF with the same GTR D and G1 at refract_glossiness (its source is not public); refract_glossiness = reflect_glossiness",
        ],
    );
    notes.push(
        "V-Ray's G1 is 0 for cos theta <= 1e-3 (beyond 89.94 degrees): the outermost polar node of the sphere of directions (89.95 degrees) lies there, so even a GGX fit (mapped exactly) shows a nonzero rmse over the sphere".to_string(),
    );
    notes.push(format!(
        "V-Ray's G1 at gtr_gamma {gamma:.4} (a spline through its closed forms at 0..4) differs from the exact Smith G1 of this GTR by at most {:.1e}",
        g1_deviation(&gtr)
    ));
    let mut text = String::new();
    for n in &notes {
        text.push_str(&format!("// {n}\n"));
    }
    for w in warning_notes(&warnings) {
        text.push_str(&format!("// {w}\n"));
    }
    let eta = model.eta();
    text.push_str(&format!(
        "BRDFVRayMtl {id} {{\n  brdf_type=4;\n  diffuse=AColor(0, 0, 0, 1);\n  reflect=AColor(1, 1, 1, 1);\n  reflect_glossiness={g};\n  hilight_glossiness_lock=1;\n  fresnel=1;\n  fresnel_ior_lock=1;\n  gtr_gamma={gamma};\n  gtr_energy_compensation=0;\n  refract=AColor(1, 1, 1, 1);\n  refract_glossiness={g};\n  refract_ior={eta};\n  option_use_roughness=0;\n  option_double_sided=1;\n}}\n\nMtlSingleBRDF {id}_mtl {{\n  brdf={id};\n}}\n"
    ));
    Ok(Export {
        files: vec![ExportFile {
            extension: "vrscene",
            text,
            xml: None,
        }],
        warnings,
        translation: Some(t),
    })
}
