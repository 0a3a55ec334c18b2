//! Blender Cycles: Glass BSDF and Principled BSDF values, as a script for Blender's Python API.
//!
//! Conventions from blender/blender (Blender 4):
//! - intern/cycles/kernel/svm/closure.h: the Glass node's closure sets `alpha = sqr(roughness)`,
//!   clamped to `alpha <= 1` (`bsdf_microfacet_*_glass_setup`,
//!   intern/cycles/kernel/closure/bsdf_microfacet.h), with GGX or Beckmann and `G = 1 / (1 +
//!   lambdaI + lambdaO)` (Beckmann's Lambda a rational approximation there;
//!   [`Smith::Cycles`]).
//! - The Principled BSDF (`CLOSURE_BSDF_PRINCIPLED_ID`, same file), read from its source: the
//!   transmission component is `bsdf_microfacet_ggx_glass_setup` with `alpha_x = alpha_y =
//!   sqr(roughness)` (GGX, or Multiscatter GGX with that distribution) and
//!   `FresnelGeneralizedSchlick` with `f0 = F0_from_ior(ior) * specular_tint`, `f90 = 1` and a
//!   negative exponent, which `bsdf_microfacet.h` evaluates as `mix(f0, f90, s)` with `s =
//!   (F_real - F0_real) / (1 - F0_real)`: with a white Specular Tint exactly the real dielectric
//!   Fresnel. Its transmission tint is `sqrt(base_color)` (1 for white), and with Transmission
//!   Weight 1 every other component is weighted by `1 - 1 = 0`. So a white Principled BSDF with
//!   Transmission Weight 1 is the same GGX glass as the Glass node with GGX.
//! - Multiscatter GGX (`MULTI_GGX`) in Blender 4 is no random walk: `bsdf_microfacet.h` and
//!   `bsdf_microfacet_util.h` (`microfacet_ggx_glass_albedo_scaling`) scale the
//!   single-scattering GGX glass lobe by the inverse of its tabulated albedo
//!   `E(cos, sqrt(alpha), ior)` (`energy_scale`), adding the higher orders' energy in the
//!   single-scattering lobe's shape. An all-orders fit is translated against the fit's full
//!   BSDF, higher orders included, so the translated lobe (or the stated error) already holds
//!   them: its scripts use single-scattering GGX (`GGX`) for both nodes, and what renders is
//!   what the translation's error describes. Multiscatter GGX would count them twice.

use super::{
    AlphaMap, Export, ExportFile, Family1, Microfacet, provenance, translate_microfacet,
    warning_notes,
};
use crate::target::Smith;
use crate::translate::{Reference, Translation};
use crate::{ExportError, ExportModel};
use stfit_core::ndf::AnyNdf;
use stfit_core::walk::ScatteringOrders;

/// The node inputs stfit sets.
pub const GLASS_INPUTS: [&str; 3] = ["Color", "Roughness", "IOR"];
pub const PRINCIPLED_INPUTS: [&str; 6] = [
    "Base Color",
    "Metallic",
    "Roughness",
    "IOR",
    "Transmission Weight",
    "Specular Tint",
];

fn family(ndf: Family1, eta: f64) -> Microfacet {
    Microfacet {
        ndf,
        eta,
        smith: Smith::Cycles,
        map: AlphaMap::RoughnessSquared,
        name: "Roughness",
        max_param: 1.0,
        min_alpha: 0.0,
    }
}

/// Writes the script.
pub fn export(model: &ExportModel, id: &str, reference: &Reference) -> Result<Export, ExportError> {
    // The reference's own warnings first: incidences it does not resolve.
    let mut warnings = reference.warnings().to_vec();
    let ggx = translate_microfacet(
        &family(Family1::Ggx, model.eta()),
        model,
        reference,
        &mut warnings,
    )?;
    let (glass_dist, glass): (Family1, Translation) = match model.ndf() {
        AnyNdf::Beckmann(_) | AnyNdf::StudentT(_) => {
            let b = translate_microfacet(
                &family(Family1::Beckmann, model.eta()),
                model,
                reference,
                &mut warnings,
            )?;
            if matches!(model.ndf(), AnyNdf::Beckmann(_)) || b.rmse < ggx.rmse {
                (Family1::Beckmann, b)
            } else {
                (Family1::Ggx, ggx.clone())
            }
        }
        AnyNdf::Ggx(_) => (Family1::Ggx, ggx.clone()),
    };
    let all_orders = model.model.orders == ScatteringOrders::All;
    let dist_name = match glass_dist {
        Family1::Ggx => "GGX",
        Family1::Beckmann => "BECKMANN",
    };
    let mut notes = provenance(
        model,
        Some(&glass),
        &[
            "Cycles Glass BSDF: alpha = Roughness^2 (intern/cycles/kernel/svm/closure.h)",
            "Cycles Principled BSDF, white with Transmission Weight 1 and white Specular Tint: the same GGX glass closure, real dielectric Fresnel (closure.h, bsdf_microfacet.h)",
        ],
    );
    notes.extend(warning_notes(&warnings));
    let mut text = String::new();
    for n in notes {
        text.push_str(&format!("# {n}\n"));
    }
    text.push_str(&format!(
        "# Principled BSDF (GGX): Roughness {}, {}\n",
        ggx.params[0].value,
        ggx.summary()
    ));
    if all_orders {
        text.push_str("# All-orders fit: single-scattering GGX, not Multiscatter GGX, whose albedo scaling (Blender 4) would add the higher orders a second time; the fit's higher orders are in the translated lobe or in the translation error above.\n");
    }
    let r = glass.params[0].value;
    let rp = ggx.params[0].value;
    text.push_str(&format!(
        "import bpy\n\n\
def {id}_glass():\n    \
    mat = bpy.data.materials.new(\"{id}_glass\")\n    \
    mat.use_nodes = True\n    \
    nodes = mat.node_tree.nodes\n    \
    glass = nodes.new(\"ShaderNodeBsdfGlass\")\n    \
    glass.distribution = '{dist_name}'\n    \
    glass.inputs[\"Color\"].default_value = (1.0, 1.0, 1.0, 1.0)\n    \
    glass.inputs[\"Roughness\"].default_value = {r}\n    \
    glass.inputs[\"IOR\"].default_value = {eta}\n    \
    out = nodes.get(\"Material Output\")\n    \
    mat.node_tree.links.new(glass.outputs[\"BSDF\"], out.inputs[\"Surface\"])\n    \
    return mat\n\n\
def {id}_principled():\n    \
    mat = bpy.data.materials.new(\"{id}_principled\")\n    \
    mat.use_nodes = True\n    \
    bsdf = mat.node_tree.nodes.get(\"Principled BSDF\")\n    \
    bsdf.distribution = '{pdist}'\n    \
    bsdf.inputs[\"Base Color\"].default_value = (1.0, 1.0, 1.0, 1.0)\n    \
    bsdf.inputs[\"Metallic\"].default_value = 0.0\n    \
    bsdf.inputs[\"Roughness\"].default_value = {rp}\n    \
    bsdf.inputs[\"IOR\"].default_value = {eta}\n    \
    bsdf.inputs[\"Transmission Weight\"].default_value = 1.0\n    \
    bsdf.inputs[\"Specular Tint\"].default_value = (1.0, 1.0, 1.0, 1.0)\n    \
    return mat\n",
        eta = model.eta(),
        pdist = "GGX",
    ));
    Ok(Export {
        files: vec![ExportFile {
            extension: "py",
            text,
            xml: None,
        }],
        warnings,
        translation: Some(glass),
    })
}
