//! stfit-export: from a fitted microfacet model to what renderers and daylighting tools read.
//!
//! - [`ExportModel`] is a stored fit's model to export ([`ExportModel::from_fit`]): the fit
//!   carries everything needed to evaluate it again (NDF, eta, masking, orders, walks).
//! - [`targets`]: one module per renderer (Mitsuba 3, pbrt-v4, Cycles, appleseed, OpenPBR,
//!   V-Ray), each writing that renderer's own material parameterisation with a comment stating
//!   the source fit and the error of the translation. Where the renderer's BSDF cannot
//!   represent the fit exactly, the renderer's BSDF (implemented here after its source,
//!   [`target`], [`gtr`]) is fitted to the fitted BSDF over the sphere of directions with
//!   stfit's own optimiser ([`translate`]).
//! - [`export_fits`]: the exports of a set of stored fits, selected, named and laid out in files
//!   as `stfit export` writes them ([`batch`]).
//! - [`radiance`]: an LBNL WINDOW BSDF XML file (Klems full basis) of a pane or of the single
//!   rough interface, the format Radiance and WINDOW read for glazing.
//!
//! Conventions are those of stfit-core: z is the macro-normal, the outside (index 1) is z > 0,
//! directions point away from the surface, `wi` toward the light; `f_cos(wi, wo) = f |wo.z|`
//! with no radiance `1/eta^2` scaling. For light `wi` this is the physical BSDF of the radiance
//! equation (the same function as pbrt-v4's radiance-mode `f(wo = view, wi = light)` and
//! Mitsuba 3's importance-mode `eval(wi = light, wo)`), so it compares with renderers directly.

pub mod batch;
pub mod directions;
pub mod error;
pub mod gtr;
pub mod model;
pub mod radiance;
pub mod target;
pub mod targets;
pub mod translate;

pub use batch::{
    Batch, BatchError, Destination, ExportWalks, FitExport, Item, Output, Refused, export_fits,
    export_walks, radiance_walk_seconds, radiance_walks_apply, reference_walk_seconds, select_fits,
};
pub use error::ExportError;
pub use model::ExportModel;
pub use targets::{
    Export, ExportFile, Selection, Target, XmlPart, file_name, fit_identifier, join,
};

use stfit_fit::FitResult;

use radiance::RadianceOptions;

/// Exports a stored fit to `target`, the material named by [`fit_identifier`]; `radiance`
/// holds the options of [`Target::Radiance`] (ignored by the other targets).
pub fn export_fit(
    fit: &FitResult,
    target: Target,
    radiance: &RadianceOptions,
) -> Result<Export, ExportError> {
    let model = ExportModel::from_fit(fit)?;
    let id = fit_identifier(fit);
    if target != Target::Radiance {
        return targets::export(target, &model, &id);
    }
    let (text, _) = radiance::export(&model, radiance, &id)?;
    Ok(Export {
        files: vec![ExportFile {
            extension: "xml",
            text,
            xml: None,
        }],
        warnings: Vec::new(),
        translation: None,
    })
}
