//! The default command, `stfit DATA [flags]`: fit models to every sample of a measurement file
//! and print a table or JSON.

use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use stfit_fit::{
    Dataset, FitOptions, FitResult, Loss, ModelKind, ModelSpec, Optimizer, Sample, Scattering,
};

use super::{CmdError, CmdResult, MaskingArg, check_eta_arg, print_stdout, write_file};

/// Arguments of the default (fit) command.
#[derive(Debug, Clone, Args)]
pub struct FitArgs {
    /// Measurement file: CSV with columns theta_i_deg, theta_o_deg and L or sqrt_L, optionally
    /// sample and weight (see data-format.md). A file named like a subcommand needs a path
    /// such as ./synth.
    #[arg(value_name = "DATA", required = true)]
    pub data: Option<PathBuf>,
    /// Model to fit; `all` fits beckmann, ggx, student-t with gamma fixed at 3 and student-t
    /// with free gamma.
    #[arg(long, value_enum, default_value_t = ModelArg::StudentT)]
    pub model: ModelArg,
    /// Hold the Student-T shape gamma at G (> 3/2) instead of fitting it (student-t only).
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// Fit only the sample called NAME (default: every sample, in file order).
    #[arg(long, value_name = "NAME")]
    pub sample: Option<String>,
    /// Relative index of refraction of the glass.
    #[arg(
        long,
        value_name = "E",
        default_value_t = 1.51,
        allow_negative_numbers = true
    )]
    pub eta: f64,
    /// Least squares on sqrt(L) or on L.
    #[arg(long, value_enum, default_value_t = LossArg::Sqrt)]
    pub loss: LossArg,
    /// Local optimiser for the shape parameters.
    #[arg(long, value_enum, default_value_t = OptimizerArg::NelderMead)]
    pub optimizer: OptimizerArg,
    /// Smith masking-shadowing form of the single-scattering model [default: separable].
    /// Multiple scattering is height-correlated by construction: it takes no --masking but
    /// `correlated`.
    #[arg(long, value_enum)]
    pub masking: Option<MaskingArg>,
    /// Scattering orders of the model. `multiple` adds the random walk's order >= 2 estimate to
    /// the height-correlated single-scattering BTDF, with the same random numbers at every
    /// evaluation (deterministic for a --seed); it starts from the single-scattering optimum and
    /// is slower (use the default Nelder-Mead: L-BFGS is not recommended there).
    #[arg(long, value_enum, default_value_t = ScatteringArg::Single)]
    pub scattering: ScatteringArg,
    /// Random walks per incidence angle per model evaluation (--scattering multiple).
    #[arg(long, value_name = "N", default_value_t = 20_000)]
    pub walks: u64,
    /// Seed of the random walks (--scattering multiple).
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// Print the fits as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the fits as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// `--model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModelArg {
    Beckmann,
    Ggx,
    StudentT,
    All,
}

/// `--loss`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LossArg {
    /// Least squares on sqrt(L).
    Sqrt,
    /// Least squares on L.
    Linear,
}

/// `--optimizer`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OptimizerArg {
    NelderMead,
    Lbfgs,
}

/// `--scattering`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ScatteringArg {
    /// The analytic single-scattering BSDF of Walter et al. 2007.
    Single,
    /// All orders: the height-correlated single-scattering BTDF plus the random walk's orders
    /// >= 2.
    Multiple,
}

/// The `--json` document and the `--out` file.
#[derive(Debug, Serialize)]
struct FitReport<'a> {
    fits: &'a [FitResult],
}

/// Runs the fit command.
pub fn run(args: FitArgs) -> CmdResult {
    let path = args
        .data
        .as_deref()
        .ok_or_else(|| CmdError::Usage("a DATA file is required".into()))?;
    let specs = model_specs(args.model, args.gamma)?;
    let opts = FitOptions {
        eta: check_eta_arg(args.eta)?,
        loss: match args.loss {
            LossArg::Sqrt => Loss::Sqrt,
            LossArg::Linear => Loss::Linear,
        },
        optimizer: match args.optimizer {
            OptimizerArg::NelderMead => Optimizer::NelderMead,
            OptimizerArg::Lbfgs => Optimizer::Lbfgs,
        },
        masking: masking(args.scattering, args.masking)?.into(),
        scattering: match args.scattering {
            ScatteringArg::Single => Scattering::Single,
            ScatteringArg::Multiple => Scattering::Multiple,
        },
        seed: args.seed,
        walk_samples: check_walks(args.walks)?,
    };

    if let Some(out) = &args.out {
        let same = |a: &std::path::Path, b: &std::path::Path| matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b);
        if same(out, path) {
            return Err(CmdError::Usage(format!(
                "--out {} is the data file; refusing to overwrite it",
                out.display()
            )));
        }
    }
    let data = Dataset::load(path)?;
    let samples: Vec<&Sample> = match &args.sample {
        Some(name) => vec![data.sample(name)?],
        None => data.samples.iter().collect(),
    };
    let mut fits = Vec::with_capacity(samples.len() * specs.len());
    let bar = progress_bar(&args, (samples.len() * specs.len()) as u64);
    for sample in samples {
        for &spec in &specs {
            if let Some(bar) = &bar {
                bar.set_message(format!("{} {}", sample.name, spec_label(spec)));
            }
            fits.push(fit_one(sample, spec, &opts).map_err(|e| {
                CmdError::Failed(format!(
                    "{}: sample '{}', model {}: {e}",
                    path.display(),
                    sample.name,
                    spec_label(spec)
                ))
            })?);
            if let Some(bar) = &bar {
                bar.inc(1);
            }
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }

    let json = || {
        let mut text = serde_json::to_string_pretty(&FitReport { fits: &fits })
            .map_err(|e| CmdError::Failed(format!("cannot encode the fits as JSON: {e}")))?;
        text.push('\n');
        Ok::<_, CmdError>(text)
    };
    if let Some(out) = &args.out {
        write_file(out, &json()?)?;
    }
    if args.json {
        print_stdout(&json()?)
    } else {
        print_stdout(&table(&fits))
    }
}

/// The masking of the model: separable unless given; multiple scattering takes correlated only.
pub fn masking(
    scattering: ScatteringArg,
    given: Option<MaskingArg>,
) -> Result<MaskingArg, CmdError> {
    match (scattering, given) {
        (ScatteringArg::Single, m) => Ok(m.unwrap_or(MaskingArg::Separable)),
        (ScatteringArg::Multiple, None | Some(MaskingArg::Correlated)) => {
            Ok(MaskingArg::Correlated)
        }
        (ScatteringArg::Multiple, Some(m)) => Err(CmdError::Usage(format!(
            "--masking {}: multiple scattering is height-correlated by construction (the random \
             walk); omit --masking or give `correlated`",
            m.name()
        ))),
    }
}

/// Checks `--walks`.
fn check_walks(walks: u64) -> Result<usize, CmdError> {
    match usize::try_from(walks) {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(CmdError::Usage(format!(
            "--walks must be a positive number of walks, got {walks}"
        ))),
    }
}

/// A bar counting fits on stderr, for multiple-scattering runs when stderr is a terminal and
/// the output is not JSON.
fn progress_bar(args: &FitArgs, fits: u64) -> Option<ProgressBar> {
    let show =
        args.scattering == ScatteringArg::Multiple && !args.json && std::io::stderr().is_terminal();
    show.then(|| {
        let bar = ProgressBar::new(fits);
        if let Ok(style) =
            ProgressStyle::with_template("{spinner} {bar:30} {pos}/{len} fits, {msg}")
        {
            bar.set_style(style);
        }
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        bar
    })
}

/// Fits one model to one sample with the fitting engine.
fn fit_one(sample: &Sample, spec: ModelSpec, opts: &FitOptions) -> Result<FitResult, String> {
    stfit_fit::fit_sample(sample, spec, opts).map_err(|e| e.to_string())
}

/// The models to fit for `--model` and `--gamma`.
fn model_specs(model: ModelArg, gamma: Option<f64>) -> Result<Vec<ModelSpec>, CmdError> {
    let spec = |kind, gamma_fixed| ModelSpec { kind, gamma_fixed };
    if let Some(g) = gamma {
        if model != ModelArg::StudentT {
            return Err(CmdError::Usage(
                "--gamma fixes the Student-T shape; it needs --model student-t".into(),
            ));
        }
        stfit_core::error::check_gamma(g).map_err(|e| CmdError::Usage(format!("--gamma: {e}")))?;
    }
    Ok(match model {
        ModelArg::Beckmann => vec![spec(ModelKind::Beckmann, None)],
        ModelArg::Ggx => vec![spec(ModelKind::Ggx, None)],
        ModelArg::StudentT => vec![spec(ModelKind::StudentT, gamma)],
        // Beckmann, GGX, Student-T with gamma fixed at 3, Student-T with free gamma.
        ModelArg::All => stfit_fit::fit::all_models().to_vec(),
    })
}

/// A model as named in messages: `student-t (gamma = 3)` for a fixed shape.
fn spec_label(spec: ModelSpec) -> String {
    match spec.gamma_fixed {
        Some(g) => format!("{} (gamma = {g})", spec.kind.name()),
        None => spec.kind.name().to_owned(),
    }
}

/// `x` to `digits` significant digits, in scientific notation when very small or large.
fn sig(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let exponent = x.abs().log10().floor() as i32;
    if !(-5..6).contains(&exponent) {
        return format!("{:.*e}", digits.saturating_sub(1), x);
    }
    let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
    format!("{x:.decimals$}")
}

/// `value ± stderr`, or `value ± ?` when the standard error is unknown (not finite).
fn with_stderr(value: f64, stderr: Option<f64>) -> String {
    match stderr {
        Some(se) if se.is_finite() => format!("{} ± {}", sig(value, 5), sig(se, 2)),
        _ => format!("{} ± ?", sig(value, 5)),
    }
}

/// The readable table of fits: one row per sample and model.
fn table(fits: &[FitResult]) -> String {
    let header = [
        "sample",
        "model",
        "alpha",
        "gamma",
        "scale",
        "rmse sqrt(L)",
        "n",
    ]
    .map(String::from);
    let rows: Vec<[String; 7]> = fits
        .iter()
        .map(|f| {
            let gamma = match (f.model, f.gamma) {
                (ModelKind::StudentT, Some(g)) if f.gamma_fixed => format!("{} (fixed)", sig(g, 5)),
                (ModelKind::StudentT, Some(g)) => with_stderr(g, f.gamma_stderr),
                _ => "-".into(),
            };
            [
                if f.sample.is_empty() {
                    "-".into()
                } else {
                    f.sample.clone()
                },
                f.model.name().into(),
                with_stderr(f.alpha, Some(f.alpha_stderr)),
                gamma,
                with_stderr(f.scale, Some(f.scale_stderr)),
                sig(f.rmse_sqrt_l, 4),
                f.n_points.to_string(),
            ]
        })
        .collect();
    let mut widths = header.clone().map(|h| h.chars().count());
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut text = String::new();
    for row in std::iter::once(&header).chain(&rows) {
        let mut line = String::new();
        for (i, (cell, &w)) in row.iter().zip(&widths).enumerate() {
            if i > 0 {
                line.push_str("  ");
            }
            // The count column is right-aligned, the others left-aligned.
            if i == row.len() - 1 {
                let _ = write!(line, "{cell:>w$}");
            } else {
                let _ = write!(line, "{cell:<w$}");
            }
        }
        text.push_str(line.trim_end());
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn result(model: ModelKind, gamma: Option<f64>, gamma_fixed: bool) -> FitResult {
        FitResult {
            sample: "frosted".into(),
            model,
            alpha: 0.201_234_5,
            gamma,
            gamma_fixed,
            scale: 1.234_567,
            rmse_sqrt_l: 0.004_123_4,
            n_points: 300,
            alpha_stderr: 0.001_234,
            gamma_stderr: gamma.filter(|_| !gamma_fixed).map(|_| 0.081),
            scale_stderr: f64::NAN,
            iterations: 42,
        }
    }

    #[test]
    fn significant_digits() {
        assert_eq!(sig(0.2012345, 5), "0.20123");
        assert_eq!(sig(3.0, 5), "3.0000");
        assert_eq!(sig(0.001234, 2), "0.0012");
        assert_eq!(sig(1234.6, 2), "1235");
        assert_eq!(sig(1.5e-9, 2), "1.5e-9");
        assert_eq!(sig(2.14e-4, 2), "0.00021");
        assert_eq!(sig(0.0, 3), "0");
        assert_eq!(sig(f64::NAN, 3), "NaN");
    }

    #[test]
    fn table_has_a_header_and_aligned_rows() {
        let fits = [
            result(ModelKind::Ggx, None, false),
            result(ModelKind::StudentT, Some(3.0), true),
            result(ModelKind::StudentT, Some(2.95), false),
        ];
        let text = table(&fits);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[0].starts_with("sample   model      alpha"));
        assert!(lines[0].ends_with("rmse sqrt(L)    n"));
        assert!(lines[1].contains("0.20123 ± 0.0012"));
        assert!(lines[1].contains("1.2346 ± ?"));
        assert!(lines[1].contains("  -  "));
        assert!(lines[2].contains("3.0000 (fixed)"));
        assert!(lines[3].contains("2.9500 ± 0.081"));
        assert!(
            lines
                .iter()
                .skip(1)
                .all(|l| l.ends_with("0.004123      300"))
        );
        let col = |l: &str| l.find("alpha").or_else(|| l.find("0.20123"));
        assert!(lines.iter().all(|l| col(l) == col(lines[0])));
    }

    #[test]
    fn model_specs_follow_the_flags() {
        assert_eq!(model_specs(ModelArg::All, None).unwrap().len(), 4);
        assert_eq!(
            model_specs(ModelArg::StudentT, Some(2.5)).unwrap(),
            [ModelSpec {
                kind: ModelKind::StudentT,
                gamma_fixed: Some(2.5)
            }]
        );
        for (model, gamma) in [
            (ModelArg::Ggx, Some(3.0)),
            (ModelArg::All, Some(3.0)),
            (ModelArg::StudentT, Some(1.5)),
            (ModelArg::StudentT, Some(f64::NAN)),
        ] {
            assert!(matches!(model_specs(model, gamma), Err(CmdError::Usage(_))));
        }
    }
}
