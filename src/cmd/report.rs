//! `stfit report DATA`: Figure-1-style comparison plots (SVG and PNG) and a markdown table of
//! the four model fits of every sample, fitted first or read from stored fits.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stfit_fit::{Dataset, FitOptions, FitResult};
use stfit_report::{ReportOptions, YScale, read_fits_json};

use super::{CmdError, CmdResult, MaskingArg, check_eta_arg, print_stdout};

/// Arguments of `stfit report`.
#[derive(Debug, Clone, Args)]
pub struct ReportArgs {
    /// Measurement file (see data-format.md).
    #[arg(value_name = "DATA")]
    pub data: PathBuf,
    /// Folder for the figures and fits.md (created if missing; files in it are replaced).
    #[arg(long, value_name = "DIR", default_value = "report")]
    pub out: PathBuf,
    /// Report only the sample called NAME (default: every sample, in file order).
    #[arg(long, value_name = "NAME")]
    pub sample: Option<String>,
    /// Plot stored fits (the JSON of `stfit DATA --model all --json` or `--out`) instead of
    /// fitting first.
    #[arg(long, value_name = "FILE.json")]
    pub fits: Option<PathBuf>,
    /// Vertical axis: sqrt(L) (the published view) or L.
    #[arg(long, value_enum, default_value_t = ScaleArg::Sqrt)]
    pub scale: ScaleArg,
    /// Relative index of refraction of the glass (must match the fits).
    #[arg(
        long,
        value_name = "E",
        default_value_t = 1.51,
        allow_negative_numbers = true
    )]
    pub eta: f64,
    /// Smith masking-shadowing form of the model curves (must match the fits).
    #[arg(long, value_enum, default_value_t = MaskingArg::Separable)]
    pub masking: MaskingArg,
}

/// `--scale`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ScaleArg {
    /// sqrt(L), the published view.
    Sqrt,
    /// L.
    Linear,
}

/// Runs `stfit report`.
pub fn run(args: ReportArgs) -> CmdResult {
    let opts = ReportOptions {
        y_scale: match args.scale {
            ScaleArg::Sqrt => YScale::Sqrt,
            ScaleArg::Linear => YScale::Linear,
        },
        eta: check_eta_arg(args.eta)?,
        masking: args.masking.into(),
    };
    let mut data = Dataset::load(&args.data)?;
    if let Some(name) = &args.sample {
        let sample = data.sample(name)?.clone();
        data.samples = vec![sample];
    }
    let fits = match &args.fits {
        Some(path) => stored_fits(path, &data, args.sample.is_some())?,
        None => fit_every_sample(&data, &opts)?,
    };
    let report = stfit_report::render_report(&data, &fits, &opts)
        .map_err(|e| CmdError::Failed(format!("{}: {e}", args.data.display())))?;
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    let paths = report
        .write_to(&args.out)
        .map_err(|e| CmdError::Failed(e.to_string()))?;
    let mut text = String::new();
    for p in paths {
        text.push_str(&format!("{}\n", p.display()));
    }
    print_stdout(&text)
}

/// Reads stored fits; with `--sample`, keeps those of the selected sample.
fn stored_fits(
    path: &std::path::Path,
    data: &Dataset,
    selected: bool,
) -> Result<Vec<FitResult>, CmdError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CmdError::Failed(format!("{}: cannot read: {e}", path.display())))?;
    let mut fits =
        read_fits_json(&text).map_err(|e| CmdError::Failed(format!("{}: {e}", path.display())))?;
    if selected {
        fits.retain(|f| data.samples.iter().any(|s| s.name == f.sample));
    }
    Ok(fits)
}

/// Fits the four models of the seed paper's comparison to every sample.
fn fit_every_sample(data: &Dataset, opts: &ReportOptions) -> Result<Vec<FitResult>, CmdError> {
    let fit_opts = FitOptions {
        eta: opts.eta,
        masking: opts.masking,
        ..FitOptions::default()
    };
    let mut fits = Vec::new();
    for sample in &data.samples {
        let mut sample_fits = stfit_fit::fit_all(sample, &fit_opts)
            .map_err(|e| CmdError::Failed(format!("sample '{}': {e}", sample.name)))?;
        fits.append(&mut sample_fits);
    }
    Ok(fits)
}
