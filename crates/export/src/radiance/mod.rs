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
pub mod quadrature;

pub use layer::{Layer, Pane, RoughFace};
pub use matrices::{KlemsBsdf, Method, klems_monte_carlo};
pub use quadrature::{QuadratureError, QuadratureRule, klems_quadrature};

use std::fmt::Write as _;

use stfit_core::bsdf::RoughDielectric;
use stfit_core::ndf::{AnyNdf, Ndf};
use stfit_core::walk::ScatteringOrders;

use crate::{ExportError, ExportModel};
use matrices::{blocks_from_sums, monte_carlo_sums};

/// Random walks per Klems patch where the matrices need them (the pane; the orders >= 2 of an
/// all-orders interface) unless told otherwise: standard errors of about 2e-3 on a
/// hemispherical total of the pane (measured, README).
pub const DEFAULT_WALKS_PER_PATCH: u64 = 65_536;

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
    /// Random walks per Klems patch, where walks are needed.
    pub walks_per_patch: u64,
    /// Seed of the walks.
    pub seed: u64,
    /// Quadrature rule of the analytic single-scattering part.
    pub rule: QuadratureRule,
}

impl Default for RadianceOptions {
    fn default() -> Self {
        Self {
            layer: LayerKind::Pane,
            absorption: 0.0,
            walks_per_patch: DEFAULT_WALKS_PER_PATCH,
            seed: 1,
            rule: QuadratureRule::DEFAULT,
        }
    }
}

impl RadianceOptions {
    /// Checks the options: absorption in [0, 1) and for a pane only, at least two walks per
    /// patch (the file states standard errors, which one walk cannot estimate), at least one
    /// quadrature node.
    pub fn check(&self) -> Result<(), ExportError> {
        layer::check_absorption(self.absorption)?;
        if self.layer == LayerKind::Interface && self.absorption != 0.0 {
            return Err(ExportError::Unsupported(
                "absorption applies to a pane, not to a single interface".into(),
            ));
        }
        if self.walks_per_patch < 2 || stfit_core::walk::check_walks(self.walks_per_patch).is_err()
        {
            return Err(ExportError::Unsupported(format!(
                "walks per patch must be in [2, {}] (the file states their standard errors, \
                 which one walk cannot estimate), got {}",
                stfit_core::walk::MAX_WALKS,
                self.walks_per_patch
            )));
        }
        if !self.rule.is_valid() {
            return Err(ExportError::Unsupported(
                "the quadrature rule needs at least one node per dimension".into(),
            ));
        }
        Ok(())
    }
}

/// The Klems matrices of the model's layer:
/// - pane: Monte Carlo over random walks through the pane (the rough face with all orders of its
///   microsurface, every inter-reflection);
/// - interface of a single-scattering fit: the deterministic quadrature of the fitted BSDF;
/// - interface of an all-orders fit: the quadrature of its order 1 (the single-scattering BSDF
///   with height-correlated masking) plus the Monte Carlo of its orders >= 2.
///
/// Returns the matrices and the layer's description.
pub fn klems(
    model: &ExportModel,
    opts: &RadianceOptions,
) -> Result<(KlemsBsdf, String), ExportError> {
    opts.check()?;
    match opts.layer {
        LayerKind::Pane => {
            let pane = Pane::new(RoughFace::all_orders(model)?, model.eta(), opts.absorption)?;
            let bsdf = klems_monte_carlo(&pane, opts.walks_per_patch, opts.seed);
            Ok((bsdf, pane.describe()))
        }
        LayerKind::Interface => {
            let (mut sums, error) = interface_quadrature(model, opts.rule);
            let single = format!(
                "single rough interface as fitted ({}), glass (eta {}) on the back",
                model.describe(),
                model.eta()
            );
            if model.model.orders == ScatteringOrders::Single {
                let blocks = blocks_from_sums(&sums);
                let method = Method::Quadrature {
                    rule: opts.rule,
                    error,
                };
                return Ok((KlemsBsdf::new(blocks, method), single));
            }
            let multi = RoughFace::multiple_orders(model)?;
            let (mc, n) = monte_carlo_sums(&multi, opts.walks_per_patch, opts.seed);
            for (s, m) in sums.iter_mut().zip(&mc) {
                s.add(m);
            }
            let method = Method::Hybrid {
                rule: opts.rule,
                error,
                walks_per_patch: n,
            };
            Ok((KlemsBsdf::new(blocks_from_sums(&sums), method), single))
        }
    }
}

/// Walks per patch of the pilot run of [`walk_seconds`].
const PILOT_WALKS_PER_PATCH: u64 = 256;

/// Estimated wall time, in seconds, of the random walks of [`fn@klems`] for `model` under
/// `opts` on rayon's current pool, for a note before a long export: 0 where the layer has no
/// walks (the interface of a single-scattering fit) and where the run has at most 16 times the
/// 256 walks per patch of a pilot run; otherwise the wall time of that pilot (random numbers of
/// its own; the export is unchanged) scaled by the ratio of walks.
pub fn walk_seconds(model: &ExportModel, opts: &RadianceOptions) -> Result<f64, ExportError> {
    opts.check()?;
    let run = matrices::strata_per_side(opts.walks_per_patch).pow(2);
    let walks_in_interface = model.model.orders == ScatteringOrders::All;
    if run <= 16 * PILOT_WALKS_PER_PATCH
        || (opts.layer == LayerKind::Interface && !walks_in_interface)
    {
        return Ok(0.0);
    }
    fn timed<L: Layer>(layer: &L, seed: u64) -> f64 {
        let start = std::time::Instant::now();
        monte_carlo_sums(layer, PILOT_WALKS_PER_PATCH, seed);
        start.elapsed().as_secs_f64()
    }
    let seed = stfit_core::walk::pilot_seed(opts.seed);
    let pilot = match opts.layer {
        LayerKind::Pane => timed(
            &Pane::new(RoughFace::all_orders(model)?, model.eta(), opts.absorption)?,
            seed,
        ),
        LayerKind::Interface => timed(&RoughFace::multiple_orders(model)?, seed),
    };
    Ok(pilot * run as f64 / PILOT_WALKS_PER_PATCH as f64)
}

/// The quadrature of the model's single-scattering BSDF, its NDF dispatched once.
fn interface_quadrature(
    model: &ExportModel,
    rule: QuadratureRule,
) -> (Vec<matrices::BlockSums>, QuadratureError) {
    fn run<N: Ndf>(
        ndf: N,
        model: &ExportModel,
        rule: QuadratureRule,
    ) -> (Vec<matrices::BlockSums>, QuadratureError) {
        let bsdf = RoughDielectric::new(ndf, model.eta(), model.model.masking)
            .expect("the model was checked");
        quadrature::quadrature_sums(&bsdf, rule)
    }
    match model.ndf() {
        AnyNdf::Beckmann(n) => run(n, model, rule),
        AnyNdf::Ggx(n) => run(n, model, rule),
        AnyNdf::StudentT(n) => run(n, model, rule),
    }
}

/// Computes the Klems matrices of the model's layer ([`fn@klems`]) and writes the WINDOW XML
/// file, naming the material `name`.
pub fn export(
    model: &ExportModel,
    opts: &RadianceOptions,
    name: &str,
) -> Result<(String, KlemsBsdf), ExportError> {
    let (bsdf, layer) = klems(model, opts)?;
    Ok((write_xml(model, &layer, &bsdf, name), bsdf))
}

/// A value with 5 significant digits, `0` for zero.
fn num(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.4e}")
    }
}

/// Text safe inside an XML comment or element: `&`, `<` and `>` as entities, hyphens kept
/// apart and the characters XML 1.0 does not allow as U+FFFD
/// ([`crate::targets::xml_comment_text`]).
fn xml_text(s: &str) -> String {
    crate::targets::xml_comment_text(
        &s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;"),
    )
}

/// How the matrices were computed and how exact they are, for the file comment.
fn method_line(bsdf: &KlemsBsdf) -> String {
    let mc = |n: u64| {
        format!(
            "Monte Carlo: {n} cosine-weighted incident directions per patch (jittered grid), each followed by one random walk and binned into exiting patches; unbiased, largest standard error of a hemispherical total {:.2e}, of an entry holding >= 1% of its patch's flux {:.1}% (relative)",
            bsdf.max_total_stderr(),
            100.0 * bsdf.max_rel_stderr_significant()
        )
    };
    let quad = |rule: &QuadratureRule, error: &QuadratureError| {
        let coarser = rule.coarser();
        format!(
            "deterministic quadrature: the two azimuthal integrals reduced exactly to one over the azimuth difference (the BSDF is isotropic) against the patches' overlap kernel, Gauss-Legendre in cos^2 theta over the incident ring ({} nodes) and the exit ring ({} nodes) and in the azimuth difference on each linear piece of the kernel ({} nodes); estimated error (difference from the embedded coarser rule of {}/{}/{} nodes) {:.1e} on a hemispherical total, {:.1e} relative on an entry holding >= 1% of its patch's flux",
            rule.theta_incident,
            rule.theta_exit,
            rule.azimuth,
            coarser.theta_incident,
            coarser.theta_exit,
            coarser.azimuth,
            error.max_total,
            error.max_rel_significant
        )
    };
    match &bsdf.method {
        Method::MonteCarlo { walks_per_patch } => {
            format!("Patch averages by {}.", mc(*walks_per_patch))
        }
        Method::Quadrature { rule, error } => format!("Patch averages by {}.", quad(rule, error)),
        Method::Hybrid {
            rule,
            error,
            walks_per_patch,
        } => format!(
            "Patch averages: order 1 (height-correlated single scattering) by {}; orders >= 2 by {}.",
            quad(rule, error),
            mc(*walks_per_patch)
        ),
    }
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
            model.scale()
        ),
        "Values: BSDF in 1/sr, averaged over each pair of Klems patches weighted by projected solid angle on both sides.".to_string(),
        method_line(bsdf),
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
