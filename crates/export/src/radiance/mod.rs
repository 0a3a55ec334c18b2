//! An LBNL WINDOW BSDF XML file (Klems full basis, 145 x 145; transmission and reflection,
//! front and back), the format Radiance and WINDOW read for glazing.
//!
//! Format facts, from LBNL-ETA/Radiance:
//! - src/common/bsdf_m.c (`SDloadMtx`, `load_bsdf_data`): `IncidentDataStructure` `Columns`
//!   means the values are stored with the incident index varying fastest, that is one text row
//!   per exiting patch (`bsdf[o * ninc + i]`); the blocks are `WavelengthDataBlock`s named by
//!   `WavelengthDataDirection` (`Transmission Front`, `Transmission Back`, `Reflection Front`,
//!   `Reflection Back`), each with `ColumnAngleBasis`/`RowAngleBasis` `LBNL/Klems Full`.
//!   WINDOW's front is the exterior; Radiance maps it to the side opposite the surface normal
//!   ("front and back are reversed from WINDOW 6 orientations"; doc/notes/BSDFdirections.txt).
//!   Negative values are read as 0.
//! - src/util/wrapBSDF.c: the `Visible` wavelength block (`<Wavelength unit="Integral">`, D65
//!   source, CIE Y detector) and the `DataDefinition` layout.
//! - Values are BSDF in 1/sr; the hemispherical total of an incident patch is
//!   `sum_o Lambda_o B_oi` (`get_extrema`), which checkBSDF (src/cv/checkBSDF.c) prints per
//!   component as "Max. Tot. Dir", the maximum over incident patches, in percent with one
//!   decimal.
//!
//! Here the front is the rough face: light from the air on the rough side, as the data were
//! measured. The physical BSDF is written: the fit's scale is a calibration factor of the
//! measurement and is not applied.

pub mod klems;
pub mod layer;
pub mod matrices;

pub use layer::{Layer, Pane, RoughFace};
pub use matrices::{KlemsBsdf, klems_bsdf};

use std::fmt::Write as _;

use crate::ExportModel;

/// The pane or the interface alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LayerKind {
    /// The rough face over a smooth back face at the same index, with every inter-reflection.
    #[default]
    Pane,
    /// The single rough interface (glass on the back side).
    Interface,
}

/// Options of a Radiance export.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadianceOptions {
    pub layer: LayerKind,
    /// Fraction absorbed in one crossing of the pane at normal incidence (pane only).
    pub absorption: f64,
    /// Incident directions per Klems patch.
    pub samples_per_patch: u64,
    pub seed: u64,
}

impl Default for RadianceOptions {
    fn default() -> Self {
        Self {
            layer: LayerKind::Pane,
            absorption: 0.0,
            samples_per_patch: 65_536,
            seed: 1,
        }
    }
}

/// The layer an export describes: the pane's rough face scatters with all orders of its
/// microsurface; the interface is the fitted model as fitted.
pub fn layer_of(model: &ExportModel, opts: &RadianceOptions) -> Result<Either, crate::ExportError> {
    Ok(match opts.layer {
        LayerKind::Pane => Either::Pane(Pane::new(
            RoughFace::all_orders(model),
            model.eta,
            opts.absorption,
        )?),
        LayerKind::Interface => {
            if opts.absorption != 0.0 {
                return Err(crate::ExportError::Unsupported(
                    "--absorption applies to a pane, not to a single interface".into(),
                ));
            }
            Either::Face(RoughFace::as_fitted(model))
        }
    })
}

/// A pane or a single face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Either {
    Pane(Pane),
    Face(RoughFace),
}

impl Layer for Either {
    fn scatter<R: rand::Rng + ?Sized>(
        &self,
        wi: stfit_core::Vec3,
        rng: &mut R,
    ) -> Option<(stfit_core::Vec3, f64)> {
        match self {
            Self::Pane(p) => p.scatter(wi, rng),
            Self::Face(f) => f.scatter(wi, rng),
        }
    }

    fn describe(&self) -> String {
        match self {
            Self::Pane(p) => p.describe(),
            Self::Face(f) => f.describe(),
        }
    }
}

/// Computes the Klems matrices of the model's layer and writes the WINDOW XML file.
pub fn export(
    model: &ExportModel,
    opts: &RadianceOptions,
    name: &str,
) -> Result<(String, KlemsBsdf), crate::ExportError> {
    let layer = layer_of(model, opts)?;
    let bsdf = klems_bsdf(&layer, opts.samples_per_patch, opts.seed);
    Ok((write_xml(model, &layer.describe(), &bsdf, name), bsdf))
}

/// A value with 5 significant digits, `0` for zero.
fn num(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.4e}")
    }
}

/// Text safe inside an XML comment or element.
fn xml_text(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace("--", "- -")
}

/// The WINDOW BSDF XML document.
pub fn write_xml(model: &ExportModel, layer: &str, bsdf: &KlemsBsdf, name: &str) -> String {
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let max_total = |n: &str| {
        bsdf.block(n)
            .map_or(0.0, |b| b.totals.iter().copied().fold(0.0, f64::max))
    };
    let lines = [
        format!("Written by stfit export {} (stfit-export).", env!("CARGO_PKG_VERSION")),
        format!("Source fit: {}", model.source),
        format!("Model: {}", layer),
        "Front = the rough face (light from the air on the rough side, as measured); front = WINDOW exterior.".to_string(),
        format!(
            "Physical BSDF: the fit's scale ({}) is a calibration factor of the measurement and is not applied.",
            model.scale
        ),
        "Values: BSDF in 1/sr, averaged over each pair of Klems patches weighted by projected solid angle on both sides.".to_string(),
        format!(
            "Quadrature: {} cosine-weighted incident directions per patch (jittered grid), each scattered once and binned into exiting patches; unbiased, largest standard error of a hemispherical total {:.2e}, of an entry holding >= 1% of its patch's flux {:.1}% (relative).",
            bsdf.samples_per_patch,
            bsdf.max_total_stderr(),
            100.0 * bsdf.blocks.iter().map(|b| b.max_rel_stderr_significant).fold(0.0, f64::max)
        ),
        format!(
            "Hemispherical totals, maximum over incident patches (checkBSDF's Max. Tot. Dir): Tf {:.4}, Rf {:.4}, Tb {:.4}, Rb {:.4}; largest loss of a patch {:.2e}.",
            max_total("Transmission Front"),
            max_total("Reflection Front"),
            max_total("Transmission Back"),
            max_total("Reflection Back"),
            bsdf.max_loss
        ),
    ];
    for l in lines {
        let _ = writeln!(s, "<!-- {} -->", xml_text(&l));
    }
    s.push_str("<WindowElement xmlns=\"http://windows.lbl.gov\" xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" xsi:schemaLocation=\"http://windows.lbl.gov/BSDF-v1.4.xsd\">\n");
    s.push_str("<WindowElementType>System</WindowElementType>\n<FileType>BSDF</FileType>\n<Optical>\n<Layer>\n");
    let _ = writeln!(
        s,
        "\t<Material>\n\t\t<Name>{}</Name>\n\t\t<Manufacturer>stfit</Manufacturer>\n\t\t<DeviceType>Other</DeviceType>\n\t</Material>",
        xml_text(name)
    );
    s.push_str("\t<DataDefinition>\n\t\t<IncidentDataStructure>Columns</IncidentDataStructure>\n\t\t<AngleBasis>\n");
    let _ = writeln!(
        s,
        "\t\t\t<AngleBasisName>{}</AngleBasisName>",
        klems::BASIS_NAME
    );
    for r in 0..klems::N_PHI.len() {
        let (lo, hi) = (klems::THETA_LO_DEG[r], klems::theta_hi_deg(r));
        let center = if r == 0 { 0.0 } else { 0.5 * (lo + hi) };
        let _ = writeln!(
            s,
            "\t\t\t<AngleBasisBlock>\n\t\t\t\t<Theta>{center}</Theta>\n\t\t\t\t<nPhis>{}</nPhis>\n\t\t\t\t<ThetaBounds>\n\t\t\t\t\t<LowerTheta>{lo}</LowerTheta>\n\t\t\t\t\t<UpperTheta>{hi}</UpperTheta>\n\t\t\t\t</ThetaBounds>\n\t\t\t</AngleBasisBlock>",
            klems::N_PHI[r]
        );
    }
    s.push_str("\t\t</AngleBasis>\n\t</DataDefinition>\n");
    for b in &bsdf.blocks {
        s.push_str("\t<WavelengthData>\n\t\t<LayerNumber>System</LayerNumber>\n");
        s.push_str("\t\t<Wavelength unit=\"Integral\">Visible</Wavelength>\n");
        s.push_str("\t\t<SourceSpectrum>CIE Illuminant D65 1nm.ssp</SourceSpectrum>\n");
        s.push_str("\t\t<DetectorSpectrum>ASTM E308 1931 Y.dsp</DetectorSpectrum>\n");
        let _ = writeln!(
            s,
            "\t\t<WavelengthDataBlock>\n\t\t\t<WavelengthDataDirection>{}</WavelengthDataDirection>\n\t\t\t<ColumnAngleBasis>{1}</ColumnAngleBasis>\n\t\t\t<RowAngleBasis>{1}</RowAngleBasis>\n\t\t\t<ScatteringDataType>BTDF</ScatteringDataType>\n\t\t\t<ScatteringData>",
            b.name,
            klems::BASIS_NAME
        );
        for o in 0..klems::N_PATCHES {
            let row: Vec<String> = (0..klems::N_PATCHES)
                .map(|i| num(b.values[o * klems::N_PATCHES + i]))
                .collect();
            s.push_str(&row.join(", "));
            s.push('\n');
        }
        s.push_str("\t\t\t</ScatteringData>\n\t\t</WavelengthDataBlock>\n\t</WavelengthData>\n");
    }
    s.push_str("</Layer>\n</Optical>\n</WindowElement>\n");
    s
}
