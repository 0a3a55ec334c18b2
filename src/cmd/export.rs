//! `stfit export FITS.json --to TARGET`: write each stored fit as a renderer material or a
//! Radiance/WINDOW BSDF file. The fits carry their models (fits-format.md); the work is done by
//! the stfit-export crate.

use std::path::PathBuf;

use clap::{Args as ClapArgs, ValueEnum};
use stfit_export::radiance::{DEFAULT_WALKS_PER_PATCH, LayerKind, QuadratureRule, RadianceOptions};
use stfit_export::{
    BatchError, Destination, FitExport, Selection, Target, export_fits, export_walks,
    radiance_walks_apply, select_fits,
};
use stfit_fit::{FitsFile, ModelKind};

use super::{
    CmdResult, Retired, failed, long_run, print_stdout, refuse_overwriting_input, usage, write_file,
};

/// Arguments of `stfit export`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// Stored fits: the JSON of `stfit DATA --out FILE` (fits-format.md).
    #[arg(value_name = "FITS.json")]
    pub fits: PathBuf,
    /// What to write.
    #[arg(long, value_enum)]
    pub to: TargetArg,
    /// Export only the fits of the sample called NAME.
    #[arg(long, value_name = "NAME")]
    pub sample: Option<String>,
    /// Export only the fits of this model (student-t: gamma fitted; student-t-fixed: gamma
    /// held fixed).
    #[arg(long, value_enum)]
    pub model: Option<ModelArg>,
    /// Output file (several fits go into one file, except for radiance), or a folder (one file
    /// per fit, named SAMPLE_MODEL-TARGET.EXT): an existing one, or a path ending in `/`,
    /// created if missing. Default: stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// radiance: a pane (the rough face over a smooth back face, with all inter-reflections)
    /// or the single rough interface.
    #[arg(long, value_enum, default_value_t = LayerArg::Pane)]
    pub layer: LayerArg,
    /// radiance, pane: fraction of the light absorbed in one crossing of the glass at normal
    /// incidence (0: lossless).
    #[arg(
        long,
        value_name = "A",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub absorption: f64,
    /// radiance: random walks per Klems patch where the matrices need walks (the pane; the
    /// orders >= 2 of an all-orders interface). A single-scattering interface is integrated
    /// by deterministic quadrature.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_WALKS_PER_PATCH)]
    pub walks: u64,
    /// radiance: seed of the walks.
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub retired: Retired,
}

/// `--to`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TargetArg {
    /// Mitsuba 3 roughdielectric (XML element and Python dict).
    Mitsuba3,
    /// pbrt-v4 named dielectric material (MakeNamedMaterial).
    #[value(name = "pbrt-v4")]
    PbrtV4,
    /// Blender Cycles Glass and Principled BSDF (Python for Blender).
    Cycles,
    /// appleseed glass_bsdf (GGX; Beckmann and Student-T fits translated).
    Appleseed,
    /// OpenPBR open_pbr_surface (MaterialX), specular haze where meaningful.
    Openpbr,
    /// V-Ray BRDFVRayMtl with its GTR microfacets (.vrscene).
    Vray,
    /// LBNL WINDOW BSDF XML, Klems full basis (Radiance, WINDOW).
    Radiance,
}

impl From<TargetArg> for Target {
    fn from(t: TargetArg) -> Self {
        match t {
            TargetArg::Mitsuba3 => Self::Mitsuba3,
            TargetArg::PbrtV4 => Self::PbrtV4,
            TargetArg::Cycles => Self::Cycles,
            TargetArg::Appleseed => Self::Appleseed,
            TargetArg::Openpbr => Self::OpenPbr,
            TargetArg::Vray => Self::VRay,
            TargetArg::Radiance => Self::Radiance,
        }
    }
}

/// `--model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModelArg {
    Beckmann,
    Ggx,
    /// Student-T with gamma fitted.
    StudentT,
    /// Student-T with gamma held fixed.
    StudentTFixed,
}

/// `--layer`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LayerArg {
    Pane,
    Interface,
}

/// Runs `stfit export`. A fit whose export is refused is reported on its own line (`error:
/// FILE: sample 'x', ggx to appleseed: reason`) while the others are written; the command then
/// fails (exit 1) with `N of M exports refused`. `given` lists the Radiance flags given on the command line: refused
/// with another target, even at their default values.
pub fn run(args: &Args, given: &[String]) -> CmdResult {
    args.retired.check()?;
    let target = Target::from(args.to);
    let radiance = RadianceOptions {
        layer: match args.layer {
            LayerArg::Pane => LayerKind::Pane,
            LayerArg::Interface => LayerKind::Interface,
        },
        absorption: args.absorption,
        walks_per_patch: args.walks,
        seed: args.seed,
        rule: QuadratureRule::DEFAULT,
    };
    radiance.check().map_err(usage)?;
    if target != Target::Radiance && !given.is_empty() {
        return Err(usage(
            "--layer, --absorption, --walks and --seed apply to --to radiance only",
        ));
    }
    let selection = Selection {
        sample: args.sample.clone(),
        kind: args.model.map(|m| match m {
            ModelArg::Beckmann => ModelKind::Beckmann,
            ModelArg::Ggx => ModelKind::Ggx,
            ModelArg::StudentT | ModelArg::StudentTFixed => ModelKind::StudentT,
        }),
        gamma_fixed: args.model.and_then(|m| match m {
            ModelArg::StudentT => Some(false),
            ModelArg::StudentTFixed => Some(true),
            _ => None,
        }),
    };
    let inputs = std::slice::from_ref(&args.fits);
    if let Some(out) = &args.out {
        // The file named, before the export's work; the files of a folder once named below.
        refuse_overwriting_input(out, inputs)?;
    }
    let file = FitsFile::read(&args.fits).map_err(failed)?;
    let walk_flags: Vec<&str> = given
        .iter()
        .map(String::as_str)
        .filter(|f| matches!(*f, "--walks" | "--seed"))
        .collect();
    if !walk_flags.is_empty() && !radiance_walks_apply(&file.fits, &selection, radiance.layer) {
        return Err(usage(format!(
            "{} {} to the pane and to the orders >= 2 of all-orders fits; the interface of the \
             selected single-scattering fits is integrated by quadrature, without walks",
            walk_flags.join(" and "),
            if walk_flags.len() == 1 {
                "applies"
            } else {
                "apply"
            }
        )));
    }
    let dest = match args.out.as_deref() {
        None => Destination::Stdout,
        Some(p) if p.is_dir() => Destination::Folder(p),
        Some(p)
            if p.as_os_str()
                .to_string_lossy()
                .ends_with(std::path::MAIN_SEPARATOR) =>
        {
            stfit_fit::files::create_folder(p)
                .map_err(|e| failed(format!("{}: cannot create the folder: {e}", p.display())))?;
            Destination::Folder(p)
        }
        Some(p) => Destination::File(p),
    };
    let batch_error = |e| match e {
        BatchError::OneFilePerFit => usage(
            "radiance writes one BSDF file per fit: select one fit (--sample, --model) or give --out an existing folder",
        ),
        e @ BatchError::SamePath { .. } => usage(format!("--out: {e}")),
        e => failed(format!("{}: {e}", args.fits.display())),
    };
    let selected = select_fits(&file.fits, &selection, target, dest).map_err(batch_error)?;
    let walks = export_walks(&selected, target, &radiance);
    long_run::note_if_long(
        walks.seconds,
        &walks.what,
        if walks.fits_own {
            "fits with fewer --walks make it shorter"
        } else {
            "fewer --walks make it shorter"
        },
    );
    let batch =
        export_fits(&file.fits, &selection, target, &radiance, dest).map_err(batch_error)?;
    for item in &batch.items {
        match item {
            Ok(FitExport { id, export }) => {
                for w in &export.warnings {
                    eprintln!("warning: {id}: {w}");
                }
                if let Some(t) = &export.translation {
                    eprintln!("{id}: {}", t.summary());
                }
            }
            // Each refusal on its own line; the others are written below, then the count.
            Err(refused) => eprintln!("error: {}: {refused}", args.fits.display()),
        }
    }
    // Every file written, those beside a file or inside a folder included, before any is.
    for path in batch.outputs.iter().filter_map(|o| o.path.as_deref()) {
        refuse_overwriting_input(path, inputs)?;
    }
    for out in &batch.outputs {
        match &out.path {
            Some(path) => {
                write_file(path, &out.text)?;
                if matches!(dest, Destination::Folder(_)) {
                    println!("{}", path.display());
                }
            }
            None => print_stdout(&out.text)?,
        }
    }
    match batch.refusal_summary() {
        Some(summary) => Err(failed(summary)),
        None => Ok(()),
    }
}
