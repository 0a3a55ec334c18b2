//! `stfit export FITS.json --to TARGET`: write each stored fit as a renderer material or a
//! Radiance/WINDOW BSDF file (the work is done by the stfit-export crate).
//!
//! Today's fits JSON has no eta, masking or scattering orders: they are read from the record
//! where present (`eta`, `masking`, `orders`, `walks`, `seed`) and otherwise take the fit
//! command's defaults (eta 1.51, separable masking, single scattering).

use std::path::{Path, PathBuf};

use clap::{Args as ClapArgs, ValueEnum};
use serde_json::Value;
use stfit_core::bsdf::Masking;
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};
use stfit_core::walk::ScatteringOrders;
use stfit_export::radiance::{LayerKind, RadianceOptions};
use stfit_export::targets::{self, Export, ExportFile, Target};
use stfit_export::{ExportError, ExportModel};

use super::{CmdError, CmdResult, print_stdout, write_file};

/// Arguments of `stfit export`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// Stored fits: the JSON of `stfit DATA --json` or `--out`.
    #[arg(value_name = "FITS.json")]
    pub fits: PathBuf,
    /// What to write.
    #[arg(long, value_enum)]
    pub to: TargetArg,
    /// Export only the fits of the sample called NAME.
    #[arg(long, value_name = "NAME")]
    pub sample: Option<String>,
    /// Export only the fits of this model (student-t: free gamma; student-t-fixed: gamma held).
    #[arg(long, value_enum)]
    pub model: Option<ModelArg>,
    /// Output file (several fits go into one file, except for radiance), or an existing folder
    /// (one file per fit, named SAMPLE_MODEL-TARGET.EXT). Default: stdout.
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
    /// radiance: incident directions per Klems patch (Monte Carlo quadrature).
    #[arg(long, value_name = "N", default_value_t = 65_536)]
    pub samples: u64,
    /// radiance: seed of the quadrature.
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
}

/// `--to`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TargetArg {
    /// Mitsuba 3 roughdielectric (XML element and Python dict).
    Mitsuba3,
    /// pbrt-v4 Material "dielectric" line.
    #[value(name = "pbrt-v4")]
    PbrtV4,
    /// Blender Cycles Glass and Principled BSDF (Python for Blender).
    Cycles,
    /// appleseed glass_bsdf with its STD (Student-T) microfacets.
    Appleseed,
    /// OpenPBR open_pbr_surface (MaterialX), specular haze where meaningful.
    Openpbr,
    /// LBNL WINDOW BSDF XML, Klems full basis (Radiance, WINDOW).
    Radiance,
}

/// `--model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModelArg {
    Beckmann,
    Ggx,
    StudentT,
    StudentTFixed,
}

/// `--layer`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LayerArg {
    Pane,
    Interface,
}

/// One stored fit, ready to export.
struct Fit {
    id: String,
    model: ExportModel,
}

/// Runs `stfit export`.
pub fn run(args: &Args) -> CmdResult {
    if !(0.0..1.0).contains(&args.absorption) {
        return Err(CmdError::Usage(format!(
            "--absorption must be in [0, 1), got {}",
            args.absorption
        )));
    }
    if args.samples == 0 {
        return Err(CmdError::Usage("--samples must be at least 1".into()));
    }
    let target = match args.to {
        TargetArg::Mitsuba3 => Target::Mitsuba3,
        TargetArg::PbrtV4 => Target::PbrtV4,
        TargetArg::Cycles => Target::Cycles,
        TargetArg::Appleseed => Target::Appleseed,
        TargetArg::Openpbr => Target::OpenPbr,
        TargetArg::Radiance => Target::Radiance,
    };
    if target != Target::Radiance && (args.layer != LayerArg::Pane || args.absorption != 0.0) {
        return Err(CmdError::Usage(
            "--layer and --absorption apply to --to radiance only".into(),
        ));
    }
    let fits = read_fits(&args.fits)?;
    let fits: Vec<Fit> = fits
        .into_iter()
        .filter(|(sample, kind, _)| {
            args.sample.as_ref().is_none_or(|s| s == sample)
                && args.model.is_none_or(|m| m == *kind)
        })
        .map(|(_, _, f)| f)
        .collect();
    if fits.is_empty() {
        return Err(CmdError::Failed(format!(
            "{}: no fit matches the selection",
            args.fits.display()
        )));
    }
    let folder = args.out.as_deref().filter(|p| p.is_dir());
    if target == Target::Radiance && fits.len() > 1 && args.out.is_some() && folder.is_none() {
        return Err(CmdError::Usage(
            "radiance writes one BSDF file per fit: select one fit (--sample, --model) or give --out an existing folder".into(),
        ));
    }
    let opts = RadianceOptions {
        layer: match args.layer {
            LayerArg::Pane => LayerKind::Pane,
            LayerArg::Interface => LayerKind::Interface,
        },
        absorption: args.absorption,
        samples_per_patch: args.samples,
        seed: args.seed,
    };
    let mut joined: Vec<ExportFile> = Vec::new();
    for fit in &fits {
        let export = export_one(target, fit, &opts).map_err(|e| {
            CmdError::Failed(format!("{}: fit {}: {e}", args.fits.display(), fit.id))
        })?;
        for w in &export.warnings {
            eprintln!("warning: {}: {w}", fit.id);
        }
        if let Some(t) = &export.translation {
            eprintln!("{}: {}", fit.id, t.summary());
        }
        match folder {
            Some(dir) => {
                for f in &export.files {
                    let path = dir.join(format!("{}-{}.{}", fit.id, target.name(), f.extension));
                    write_file(&path, &f.text)?;
                    println!("{}", path.display());
                }
            }
            None => {
                for f in export.files {
                    match joined.iter_mut().find(|j| j.extension == f.extension) {
                        Some(j) => {
                            j.text.push('\n');
                            j.text.push_str(&f.text);
                        }
                        None => joined.push(f),
                    }
                }
            }
        }
    }
    if folder.is_some() {
        return Ok(());
    }
    match &args.out {
        Some(out) => {
            for (k, f) in joined.iter().enumerate() {
                let path = if k == 0 {
                    out.clone()
                } else {
                    out.with_extension(f.extension)
                };
                write_file(&path, &f.text)?;
            }
            Ok(())
        }
        None => print_stdout(
            &joined
                .iter()
                .map(|f| f.text.as_str())
                .collect::<Vec<_>>()
                .join("\n"),
        ),
    }
}

fn export_one(target: Target, fit: &Fit, opts: &RadianceOptions) -> Result<Export, ExportError> {
    if target == Target::Radiance {
        let (text, _) = stfit_export::radiance::export(&fit.model, opts, &fit.id)?;
        return Ok(Export {
            files: vec![ExportFile {
                extension: "xml",
                text,
            }],
            warnings: Vec::new(),
            translation: None,
        });
    }
    targets::export(target, &fit.model, &fit.id)
}

/// Reads every fit record of a fits file: `(sample, model selector, fit)`.
fn read_fits(path: &Path) -> Result<Vec<(String, ModelArg, Fit)>, CmdError> {
    let fail = |m: String| CmdError::Failed(format!("{}: {m}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let doc: Value =
        serde_json::from_str(&text).map_err(|e| fail(format!("not valid JSON: {e}")))?;
    let records = doc
        .get("fits")
        .and_then(Value::as_array)
        .ok_or_else(|| fail("no `fits` array".into()))?;
    let file_name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    records
        .iter()
        .enumerate()
        .map(|(k, r)| read_fit(r, &file_name).map_err(|m| fail(format!("fits[{k}]: {m}"))))
        .collect()
}

/// One fit record.
fn read_fit(r: &Value, file_name: &str) -> Result<(String, ModelArg, Fit), String> {
    let num = |key: &str| -> Result<f64, String> {
        r.get(key)
            .and_then(Value::as_f64)
            .ok_or_else(|| format!("field `{key}` is missing or not a number"))
    };
    let opt_num = |key: &str| -> Result<Option<f64>, String> {
        match r.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => v
                .as_f64()
                .map(Some)
                .ok_or_else(|| format!("field `{key}` is not a number")),
        }
    };
    let string = |key: &str| -> Result<Option<&str>, String> {
        match r.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => v
                .as_str()
                .map(Some)
                .ok_or_else(|| format!("field `{key}` is not a string")),
        }
    };
    let sample = string("sample")?
        .ok_or("field `sample` is missing")?
        .to_string();
    let model = string("model")?.ok_or("field `model` is missing")?;
    let alpha = num("alpha")?;
    let gamma = opt_num("gamma")?;
    let fixed = r
        .get("gamma_fixed")
        .and_then(Value::as_bool)
        .unwrap_or(false);
    let scale = num("scale")?;
    let bad = |e: stfit_core::ParamError| format!("{e}");
    let (ndf, kind): (AnyNdf, ModelArg) = match (model, gamma) {
        ("beckmann", _) => (
            Beckmann::new(alpha).map_err(bad)?.into(),
            ModelArg::Beckmann,
        ),
        ("ggx", _) => (Ggx::new(alpha).map_err(bad)?.into(), ModelArg::Ggx),
        ("student-t", Some(g)) => (
            StudentT::new(alpha, g).map_err(bad)?.into(),
            if fixed {
                ModelArg::StudentTFixed
            } else {
                ModelArg::StudentT
            },
        ),
        ("student-t", None) => return Err("field `gamma` is missing for a student-t fit".into()),
        (other, _) => {
            return Err(format!(
                "field `model`: unknown model `{other}` (expected beckmann, ggx or student-t)"
            ));
        }
    };
    let eta = opt_num("eta")?.unwrap_or(1.51);
    let masking = match string("masking")? {
        None | Some("separable") => Masking::Separable,
        Some("correlated") => Masking::Correlated,
        Some(o) => return Err(format!("field `masking`: unknown value `{o}`")),
    };
    let orders = match string("orders")? {
        None | Some("single") => ScatteringOrders::Single,
        Some("all") => ScatteringOrders::All,
        Some(o) => return Err(format!("field `orders`: `{o}` (expected single or all)")),
    };
    let rmse = opt_num("rmse_sqrt_l")?;
    let n = opt_num("n_points")?;
    let gamma_text = match (gamma, fixed) {
        (Some(g), true) => format!(" (gamma fixed at {g})"),
        _ => String::new(),
    };
    let source = format!(
        "sample {sample}, {model} fit{gamma_text}{} from {file_name}",
        match (rmse, n) {
            (Some(r), Some(n)) => format!(", rmse sqrt(L) {r:.4} over {n} points,"),
            _ => String::new(),
        }
    );
    let mut m =
        ExportModel::new(ndf, eta, masking, orders, scale, source).map_err(|e| e.to_string())?;
    if let Some(w) = opt_num("walks")? {
        m.walks = w as u64;
    }
    if let Some(s) = opt_num("seed")? {
        m.seed = s as u64;
    }
    let suffix = if kind == ModelArg::StudentTFixed {
        "-gamma-fixed"
    } else {
        ""
    };
    let id = targets::identifier(&format!("{sample}-{model}{suffix}"));
    Ok((sample, kind, Fit { id, model: m }))
}
