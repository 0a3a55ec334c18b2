//! `stfit report DATA`: Figure-1-style comparison plots (SVG and PNG) and a markdown table of
//! the model fits of every sample, fitted first or read from stored fits, each drawn with the
//! model it was fitted with.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stfit_fit::{Dataset, FitResult, FitsFile, all_models};
use stfit_report::{ReportOptions, YScale};

use super::fit::{FitOptionArgs, ModelArg, fit_with_progress, selected};
use super::{
    CmdError, CmdResult, Retired, failed, long_run, print_stdout, refuse_overwriting_input, usage,
};

/// Arguments of `stfit report`.
#[derive(Debug, Clone, Args)]
pub struct ReportArgs {
    /// Measurement files or folders (see data-format.md).
    #[arg(value_name = "DATA", required = true, num_args = 1..)]
    pub data: Vec<PathBuf>,
    /// Folder for the figures and fits.md (created if missing; files in it are replaced).
    #[arg(long, value_name = "DIR", default_value = "report")]
    pub out: PathBuf,
    /// Report only the sample called NAME (default: every sample, in file order).
    #[arg(long, value_name = "NAME")]
    pub sample: Option<String>,
    /// Plot stored fits (the JSON of `stfit DATA --out FILE`), each with its own model,
    /// instead of fitting the four models first.
    #[arg(long, value_name = "FILE.json")]
    pub fits: Option<PathBuf>,
    /// Vertical axis of the plots: sqrt(L) (the published view) or L.
    #[arg(long, value_enum, default_value_t = YAxisArg::Sqrt)]
    pub y_axis: YAxisArg,
    /// How to fit first (without --fits); stored fits carry their own.
    #[command(flatten)]
    pub fit: FitOptionArgs,
    #[command(flatten)]
    pub retired: Retired,
}

/// `--y-axis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum YAxisArg {
    /// sqrt(L), the published view.
    Sqrt,
    /// L.
    Linear,
}

/// Runs `stfit report`. `given` lists the fit options given on the command line (as flags such
/// as `--eta`): with `--fits` they are refused, since stored fits carry their own.
pub fn run(args: ReportArgs, given: &[String]) -> CmdResult {
    args.retired.check()?;
    let opts = ReportOptions {
        y_scale: match args.y_axis {
            YAxisArg::Sqrt => YScale::Sqrt,
            YAxisArg::Linear => YScale::Linear,
        },
    };
    // Without --fits the four models of --model all are fitted: `--model all` says so, any
    // other --model (the default, student-t, included when given) and --gamma would not hold.
    let model_given = given.iter().any(|g| g == "--model");
    if args.fits.is_none()
        && ((model_given && args.fit.model != ModelArg::All) || args.fit.gamma.is_some())
    {
        return Err(usage(
            "a report fits the four models of --model all: no other --model applies, nor --gamma",
        ));
    }
    if let (Some(_), Some(flag)) = (&args.fits, given.first()) {
        return Err(usage(format!(
            "{flag} does not apply with --fits: stored fits carry the model they were fitted with"
        )));
    }
    // Where the fits come from; options are checked before any file is read.
    enum Source<'a> {
        Stored(&'a std::path::Path),
        Fit(stfit_fit::FitOptions),
    }
    let source = match &args.fits {
        Some(path) => Source::Stored(path),
        None => Source::Fit(args.fit.fit_options(given)?),
    };
    let data = selected(
        stfit_fit::load_paths(&args.data).map_err(failed)?,
        args.sample.as_deref(),
    )?;
    let stored = matches!(source, Source::Stored(_));
    let (fits, whose) = match source {
        Source::Stored(path) => (
            stored_fits(path, &data, args.sample.is_some())?,
            // Stored fits may not match the data: name both files.
            format!(
                "{} with the fits of {}",
                data.source.display(),
                path.display()
            ),
        ),
        Source::Fit(o) => (
            fit_with_progress(&data, &all_models(), &o, true)?,
            data.source.display().to_string(),
        ),
    };
    // The walks of the all-orders fits run again to draw them: announced when long (a
    // hand-edited `walks` in stored fits can make hours of them).
    long_run::note_if_long(
        stfit_report::walk_seconds(&data, &fits, &opts),
        stfit_report::WALKS_DESCRIPTION,
        if stored {
            "fits with fewer --walks make it shorter"
        } else {
            "fewer --walks make it shorter"
        },
    );
    let report = stfit_report::render_report(&data, &fits, &opts)
        .map_err(|e| failed(format!("{whose}: {e}")))?;
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    // The files the report reads, those of a data folder included, against every file it
    // writes, before any is written.
    let mut inputs = stfit_fit::load::data_files(&args.data).unwrap_or_else(|_| args.data.clone());
    inputs.extend(args.fits.iter().cloned());
    for f in &report.files {
        refuse_overwriting_input(&args.out.join(&f.name), &inputs)?;
    }
    let paths = report.write_to(&args.out).map_err(failed)?;
    let mut text = String::new();
    for p in paths {
        text.push_str(&format!("{}\n", p.display()));
    }
    print_stdout(&text)
}

/// Reads stored fits; with `--sample` (`selected`), keeps those of the selected sample.
fn stored_fits(
    path: &std::path::Path,
    data: &Dataset,
    selected: bool,
) -> Result<Vec<FitResult>, CmdError> {
    // Fits whose model cannot be evaluated are named in the report's warnings, not refused.
    let mut fits = FitsFile::read_unchecked(path).map_err(failed)?.fits;
    if fits.is_empty() {
        return Err(failed(format!(
            "{}: the file holds no fits",
            path.display()
        )));
    }
    if selected {
        fits.retain(|f| data.samples.iter().any(|s| s.name == f.sample));
        if fits.is_empty() {
            return Err(failed(format!(
                "{}: no stored fit of the selected sample",
                path.display()
            )));
        }
    }
    Ok(fits)
}
