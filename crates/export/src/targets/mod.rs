//! Renderer targets: each module writes one renderer's material in its own parameterisation,
//! with a comment stating the source fit and the error of the translation.
//!
//! Policy: where the renderer has the fitted NDF family, its parameters are an exact mapping
//! of the fitted NDF (the round trip GGX -> GGX keeps alpha) and the translation error reported
//! is what the renderer's own masking term changes; where it has not (a Student-T fit for a
//! GGX or Beckmann renderer, GTR, a two-lobe mixture), the renderer's BSDF is fitted to the
//! fitted BSDF over the sphere of directions ([`crate::translate`]).

pub mod appleseed;
pub mod cycles;
pub mod mitsuba3;
pub mod openpbr;
pub mod pbrt_v4;
pub mod vray;

use stfit_core::ndf::{AnyNdf, Beckmann, Ggx};
use stfit_fit::{FitResult, Gamma};

use crate::target::{CoreMicrofacet, Smith, TargetDielectric};
use crate::translate::{self, Family, Reference, Translation, from_log_coord, log_coord};
use crate::{ExportError, ExportModel};

/// A renderer or tool to export to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Mitsuba3,
    PbrtV4,
    Cycles,
    Appleseed,
    OpenPbr,
    VRay,
    Radiance,
}

impl Target {
    /// Every target.
    pub const ALL: [Target; 7] = [
        Target::Mitsuba3,
        Target::PbrtV4,
        Target::Cycles,
        Target::Appleseed,
        Target::OpenPbr,
        Target::VRay,
        Target::Radiance,
    ];

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Mitsuba3 => "mitsuba3",
            Self::PbrtV4 => "pbrt-v4",
            Self::Cycles => "cycles",
            Self::Appleseed => "appleseed",
            Self::OpenPbr => "openpbr",
            Self::VRay => "vray",
            Self::Radiance => "radiance",
        }
    }
}

/// One output file of an export.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportFile {
    /// File extension without the dot.
    pub extension: &'static str,
    /// The file of this fit alone.
    pub text: String,
    /// For an XML file that a renderer reads as a document: this fit's part of a document of
    /// several fits ([`join`]). `None` where the fits' texts follow one another (scene
    /// descriptions, scripts, and appleseed's `<bsdf>` elements, which go into a project's
    /// assembly).
    pub xml: Option<XmlPart>,
}

/// The XML declaration that opens an XML document.
pub const XML_DECLARATION: &str = "<?xml version=\"1.0\"?>\n";

/// A fit's part of one XML document holding several fits: the content that goes inside the
/// document's root element, and the document's opening (XML declaration and root start tag)
/// and closing (root end tag), the same for every fit of a target.
#[derive(Debug, Clone, PartialEq)]
pub struct XmlPart {
    pub open: String,
    pub content: String,
    pub close: &'static str,
}

/// What an export produced.
#[derive(Debug, Clone, PartialEq)]
pub struct Export {
    pub files: Vec<ExportFile>,
    /// Clamps and other departures from the fit, for the user.
    pub warnings: Vec<String>,
    /// The translation (parameters, error, sensitivity), where the target has one.
    pub translation: Option<Translation>,
}

/// The name of an export file of the fit `id`: `ID-TARGET.EXT`, such as
/// `frosted_student_t-mitsuba3.xml`.
pub fn file_name(id: &str, target: Target, extension: &str) -> String {
    format!("{id}-{}.{extension}", target.name())
}

/// The files of several exports joined into one text per file type (extension), in order of
/// first appearance: one export's file as it is; several exports' XML documents
/// ([`ExportFile::xml`]) as one document, their contents inside one root element, separated by
/// a blank line; other texts one after another, separated by a blank line.
pub fn join(exports: &[Export]) -> Vec<ExportFile> {
    let mut groups: Vec<Vec<&ExportFile>> = Vec::new();
    for f in exports.iter().flat_map(|e| &e.files) {
        match groups.iter_mut().find(|g| g[0].extension == f.extension) {
            Some(g) => g.push(f),
            None => groups.push(vec![f]),
        }
    }
    groups
        .into_iter()
        .map(|group| match (group.as_slice(), &group[0].xml) {
            ([one], _) => (*one).clone(),
            (_, Some(part)) => {
                let parts: Vec<&str> = group
                    .iter()
                    .map(|f| f.xml.as_ref().map_or(f.text.as_str(), |p| &p.content))
                    .collect();
                ExportFile {
                    extension: group[0].extension,
                    text: format!("{}{}{}", part.open, parts.join("\n"), part.close),
                    xml: None,
                }
            }
            (_, None) => ExportFile {
                extension: group[0].extension,
                text: group
                    .iter()
                    .map(|f| f.text.as_str())
                    .collect::<Vec<_>>()
                    .join("\n"),
                xml: None,
            },
        })
        .collect()
}

/// The identifier of a fit in scene files and file names: its sample and model with every
/// character outside `[A-Za-z0-9]` replaced by `_`, such as `frosted_student_t` and
/// `frosted_student_t_gamma_fixed`; the sample's name is cut to its first
/// [`MAX_SAMPLE_CHARS`](stfit_fit::files::MAX_SAMPLE_CHARS) characters, so that file names stay within every file system's limit.
/// An identifier that would start with a digit (a sample named `2024 frosted`) starts with `_`
/// instead (`_2024_frosted_ggx`): it names a Python variable and function in the Mitsuba 3 and
/// Cycles scripts, where a leading digit is a syntax error.
pub fn fit_identifier(fit: &FitResult) -> String {
    let suffix = if fit.model.gamma.is_fixed() {
        "-gamma-fixed"
    } else {
        ""
    };
    let sample: String = fit
        .sample
        .chars()
        .take(stfit_fit::files::MAX_SAMPLE_CHARS)
        .collect();
    let id: String = format!("{sample}-{}{suffix}", fit.model.kind.name())
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if id.starts_with(|c: char| c.is_ascii_digit()) {
        format!("_{id}")
    } else {
        id
    }
}

/// Which stored fits to export: all, or those of one sample and/or one model (gamma free or held
/// fixed for Student-T).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Selection {
    pub sample: Option<String>,
    pub kind: Option<stfit_fit::ModelKind>,
    /// For Student-T: `Some(true)` only fits with gamma held fixed, `Some(false)` only free.
    pub gamma_fixed: Option<bool>,
}

impl Selection {
    /// Whether `fit` is selected.
    pub fn matches(&self, fit: &FitResult) -> bool {
        let m = &fit.model;
        self.sample.as_ref().is_none_or(|s| *s == fit.sample)
            && self.kind.is_none_or(|k| k == m.kind)
            && self.gamma_fixed.is_none_or(|fixed| match m.gamma {
                Gamma::NotApplicable => true,
                g => g.is_fixed() == fixed,
            })
    }
}

/// How a renderer's roughness parameter maps to the NDF's alpha.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AlphaMap {
    /// The parameter is alpha.
    Alpha,
    /// `alpha = sqrt(roughness)` (pbrt-v4's default `remaproughness`).
    SqrtRoughness,
    /// `alpha = roughness^2` (Cycles, appleseed, OpenPBR).
    RoughnessSquared,
}

impl AlphaMap {
    /// alpha of a parameter value.
    pub fn alpha(self, p: f64) -> f64 {
        match self {
            Self::Alpha => p,
            Self::SqrtRoughness => p.sqrt(),
            Self::RoughnessSquared => p * p,
        }
    }

    /// The parameter value of an alpha.
    pub fn param(self, alpha: f64) -> f64 {
        match self {
            Self::Alpha => alpha,
            Self::SqrtRoughness => alpha * alpha,
            Self::RoughnessSquared => alpha.sqrt(),
        }
    }
}

/// The NDF families renderers offer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family1 {
    Ggx,
    Beckmann,
}

/// A renderer's one-parameter microfacet dielectric (GGX or Beckmann).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Microfacet {
    pub ndf: Family1,
    pub eta: f64,
    pub smith: Smith,
    pub map: AlphaMap,
    pub name: &'static str,
    /// Largest parameter value the renderer accepts.
    pub max_param: f64,
    /// Smallest alpha the renderer renders (it raises smaller ones to this): the family's BSDF
    /// is built at `max(min_alpha, alpha)`, so a translation's error is that of what renders.
    /// 0 where the renderer takes every alpha as given.
    pub min_alpha: f64,
}

/// Smallest alpha a translation into a [`Microfacet`] family searches: 10 times below the
/// fits' own floor ([`stfit_fit::fit::ALPHA_MIN`]).
pub const TRANSLATE_ALPHA_MIN: f64 = 1e-4;

impl Microfacet {
    /// The renderer parameter of [`TRANSLATE_ALPHA_MIN`]: the search's lower bound, in alpha
    /// whatever the renderer's mapping (pbrt-v4's `roughness = alpha^2` reaches 1e-8).
    fn min_param(&self) -> f64 {
        self.map.param(TRANSLATE_ALPHA_MIN).min(self.max_param)
    }
}

impl Family for Microfacet {
    type Bsdf = TargetDielectric<CoreMicrofacet>;

    fn names(&self) -> Vec<&'static str> {
        vec![self.name]
    }

    fn build(&self, p: &[f64]) -> Result<Self::Bsdf, ExportError> {
        let alpha = self.map.alpha(p[0]).max(self.min_alpha);
        let ndf: AnyNdf = match self.ndf {
            Family1::Ggx => Ggx::new(alpha)?.into(),
            Family1::Beckmann => Beckmann::new(alpha)?.into(),
        };
        TargetDielectric::new(
            CoreMicrofacet {
                ndf,
                smith: self.smith,
            },
            self.eta,
        )
    }

    fn params_of(&self, x: &[f64]) -> Vec<f64> {
        vec![from_log_coord(x[0], self.min_param(), self.max_param)]
    }

    fn search_of(&self, p: &[f64]) -> Vec<f64> {
        vec![log_coord(p[0], self.min_param(), self.max_param)]
    }

    fn starts(&self) -> Vec<Vec<f64>> {
        [0.05, 0.2, 0.5]
            .iter()
            .map(|&a| vec![self.map.param(a).min(self.max_param)])
            .collect()
    }
}

/// Translates the model into a one-parameter microfacet family: the exact alpha when the fit
/// has that NDF (clamped to the renderer's range with a warning), a fit over the sphere
/// otherwise.
pub fn translate_microfacet(
    family: &Microfacet,
    model: &ExportModel,
    reference: &Reference,
    warnings: &mut Vec<String>,
) -> Result<Translation, ExportError> {
    let same = matches!(
        (family.ndf, model.ndf()),
        (Family1::Ggx, AnyNdf::Ggx(_)) | (Family1::Beckmann, AnyNdf::Beckmann(_))
    );
    if same {
        let p = family.map.param(model.alpha());
        let q = p.min(family.max_param);
        if q < p {
            warnings.push(format!(
                "{} {p:.6} (alpha {:.6}) exceeds the renderer's maximum {}: clamped",
                family.name,
                model.alpha(),
                family.max_param
            ));
        }
        translate::evaluate(family, model, reference, &[q])
    } else {
        translate::fit(family, model, reference, warnings)
    }
}

/// An XML comment holding `notes`, one per line ([`xml_comment_text`]), with its line break.
pub fn xml_comment(notes: &[String]) -> String {
    let mut comment = String::from("<!--\n");
    for n in notes {
        comment.push_str(&format!("  {}\n", xml_comment_text(n)));
    }
    comment.push_str("-->\n");
    comment
}

/// `text` made safe inside an XML comment (`<!-- ... -->`): XML 1.0 forbids `--` there, so a
/// space goes between any two hyphens in a row (a run of three or more included, which one
/// replacement of `--` by `- -` would leave as `- --`) and after a final hyphen (which would
/// run into the closing `-->`); characters XML 1.0 does not allow (control characters other
/// than tab and line breaks, U+FFFE, U+FFFF) become U+FFFD.
pub fn xml_comment_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c == '-' && out.ends_with('-') {
            out.push(' ');
        }
        let allowed = !c.is_control() || matches!(c, '\t' | '\n' | '\r');
        out.push(if allowed && c != '\u{FFFE}' && c != '\u{FFFF}' {
            c
        } else {
            '\u{FFFD}'
        });
    }
    if out.ends_with('-') {
        out.push(' ');
    }
    out
}

/// Comment lines of an export's warnings, `warning: ...`, for the file: what the user is told
/// on stderr stays with the file.
pub fn warning_notes(warnings: &[String]) -> Vec<String> {
    warnings.iter().map(|w| format!("warning: {w}")).collect()
}

/// Comment lines shared by every target: the source fit and the translation.
pub fn provenance(
    model: &ExportModel,
    t: Option<&Translation>,
    conventions: &[&str],
) -> Vec<String> {
    let mut v = vec![
        format!(
            "stfit export {}: {}",
            env!("CARGO_PKG_VERSION"),
            model.source
        ),
        format!(
            "fitted model: {}; the fit's scale {} is a calibration factor, not applied",
            model.describe(),
            model.scale()
        ),
    ];
    v.extend(conventions.iter().map(|s| s.to_string()));
    if let Some(t) = t {
        v.push(format!("translation: {}", t.summary()));
        v.extend(
            t.sensitivity_lines()
                .into_iter()
                .map(|l| format!("sensitivity: {l}")),
        );
    }
    v
}

/// Exports `model` to a renderer target (not [`Target::Radiance`], which
/// [`crate::radiance::export`] writes), with `id` naming the material.
pub fn export(target: Target, model: &ExportModel, id: &str) -> Result<Export, ExportError> {
    let reference = || Reference::standard(model);
    match target {
        Target::Mitsuba3 => mitsuba3::export(model, id, &reference()?),
        Target::PbrtV4 => pbrt_v4::export(model, id, &reference()?),
        Target::Cycles => cycles::export(model, id, &reference()?),
        Target::Appleseed => appleseed::export(model, id, &reference()?),
        Target::OpenPbr => openpbr::export(model, id, &reference()?),
        Target::VRay => vray::export(model, id, &reference()?),
        Target::Radiance => Err(ExportError::Unsupported(
            "radiance is written by stfit_export::radiance::export".into(),
        )),
    }
}
