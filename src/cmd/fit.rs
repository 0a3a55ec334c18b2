//! The default command, `stfit DATA [flags]`: fit models to every sample of a measurement file
//! and print a table or JSON.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use stfit_core::ScatteringOrders;
use stfit_fit::{
    DEFAULT_ETA, DEFAULT_LOG_FLOOR, DEFAULT_WALKS, Dataset, FitOptions, FitResult, FitsFile, Loss,
    ModelKind, ModelSpec, MultipleTerm, Optimizer, Parameter, all_models, fit_dataset,
    fit_walk_cost, load_paths,
};
use stfit_report::fits_table;

use super::{
    CmdError, CmdResult, MaskingArg, MeasuredOrdersArg, Retired, failed, long_run, masking_of,
    print_stdout, refuse_overwriting_input, usage, walks_only, write_file,
};

/// Arguments of the default (fit) command.
#[derive(Debug, Clone, Args)]
pub struct FitArgs {
    /// Measurement files or folders: CSV (in-plane: theta_i_deg, theta_o_deg, L or sqrt_L;
    /// general: theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg, bsdf; optionally sample and
    /// weight) or pab-opto goniophotometer files; see data-format.md. A file named like a
    /// subcommand needs a path such as ./synth.
    #[arg(value_name = "DATA", required = true, num_args = 1..)]
    pub data: Vec<PathBuf>,
    #[command(flatten)]
    pub options: FitOptionArgs,
    /// Fit only the sample called NAME (default: every sample, in file order).
    #[arg(long, value_name = "NAME")]
    pub sample: Option<String>,
    /// Print the fits as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the fits as JSON (fits-format.md) to FILE.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub retired: Retired,
}

/// What to fit and how: shared by the fit command and `stfit report`, which fits first.
#[derive(Debug, Clone, Args)]
pub struct FitOptionArgs {
    /// Model to fit; `all` fits beckmann, ggx, student-t with gamma fixed at 3 and student-t
    /// with free gamma.
    #[arg(long, value_enum, default_value_t = ModelArg::StudentT)]
    pub model: ModelArg,
    /// Hold the Student-T shape gamma at G (> 3/2) instead of fitting it (student-t only).
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// Relative index of refraction n_inside / n_outside of the glass: a value, or `free` to
    /// fit it (multi-start search in [1.05, 3]).
    #[arg(long, value_name = "E|free", default_value_t = DEFAULT_ETA.to_string(), allow_negative_numbers = true)]
    pub eta: String,
    /// The per-sample calibration scale: `free` (fitted) or a value to hold it at (`1` for
    /// absolutely calibrated data; a normal double, at least 2.2e-308).
    #[arg(
        long,
        value_name = "S|free",
        default_value = "free",
        allow_negative_numbers = true
    )]
    pub scale: String,
    /// Least squares on sqrt(value), on the value, or on ln(value + floor) (a relative loss
    /// for data spanning decades; floor = --log-floor times the sample's largest value).
    #[arg(long, value_enum, default_value_t = LossArg::Sqrt)]
    pub loss: LossArg,
    /// The floor of --loss log, relative to each sample's largest measured value, in
    /// [1e-12, 1].
    #[arg(long, value_name = "F", default_value_t = DEFAULT_LOG_FLOOR, allow_negative_numbers = true)]
    pub log_floor: f64,
    /// Local optimiser for the shape parameters.
    #[arg(long, value_enum, default_value_t = OptimizerArg::NelderMead)]
    pub optimizer: OptimizerArg,
    /// Smith masking-shadowing form [default: separable for --orders single; --orders all is
    /// height-correlated by construction and takes only correlated].
    #[arg(long, value_enum)]
    pub masking: Option<MaskingArg>,
    /// Scattering orders of the model: single (the analytic single-scattering BSDF) or all
    /// (the height-correlated single-scattering BSDF plus the random walk's orders >= 2, with
    /// the same random numbers at every evaluation, deterministic for a --seed; it starts from
    /// the single-scattering optimum and is slower; use the default Nelder-Mead).
    #[arg(long, value_enum, default_value_t = MeasuredOrdersArg::Single)]
    pub orders: MeasuredOrdersArg,
    /// Random walks per incidence direction per model evaluation (--orders all).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_WALKS)]
    pub walks: u64,
    /// Seed of the random walks (--orders all).
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
    /// How --orders all computes the orders >= 2 term while it searches: a quadratic
    /// surrogate interpolating walk estimates at a few parameter points (fast), or fresh walks
    /// at every evaluation (exact, slow); both report the fit with the walks at the optimum,
    /// and the JSON records which (`multiple_term`).
    #[arg(long, value_enum, default_value_t = MultipleTermArg::Surrogate)]
    pub multiple_term: MultipleTermArg,
}

/// `--multiple-term`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MultipleTermArg {
    /// A quadratic surrogate in the parameters, from a few sets of walks per fit.
    Surrogate,
    /// Fresh walks (the same random numbers) at every cost evaluation.
    Exact,
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
    /// Least squares on sqrt(value).
    Sqrt,
    /// Least squares on the value.
    Linear,
    /// Least squares on ln(value + floor).
    Log,
}

/// A parameter given as a value or `free`, checked by `check` when a value.
fn parameter(
    flag: &str,
    text: &str,
    check: impl Fn(f64) -> Result<f64, String>,
) -> Result<Parameter, CmdError> {
    if text == "free" {
        return Ok(Parameter::Free);
    }
    let v: f64 = text.trim().parse().map_err(|_| {
        let hint = if flag == "--scale" && matches!(text, "sqrt" | "linear" | "log") {
            " (the vertical axis of report plots is --y-axis)"
        } else {
            ""
        };
        usage(format!(
            "{flag}: invalid value '{text}': neither a number nor `free`{hint}"
        ))
    })?;
    check(v)
        .map(Parameter::Fixed)
        .map_err(|e| usage(format!("{flag}: {e}")))
}

/// `--optimizer`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OptimizerArg {
    NelderMead,
    Lbfgs,
}

impl FitOptionArgs {
    /// The models to fit, or a usage error.
    pub fn specs(&self) -> Result<Vec<ModelSpec>, CmdError> {
        if let Some(g) = self.gamma {
            if self.model != ModelArg::StudentT {
                return Err(usage(
                    "--gamma fixes the Student-T shape; it needs --model student-t",
                ));
            }
            let check = if self.orders == MeasuredOrdersArg::All {
                stfit_core::error::check_walk_gamma
            } else {
                stfit_core::error::check_gamma
            };
            check(g).map_err(|e| usage(format!("--gamma: {e}")))?;
        }
        Ok(match self.model {
            ModelArg::Beckmann => vec![ModelSpec::beckmann()],
            ModelArg::Ggx => vec![ModelSpec::ggx()],
            ModelArg::StudentT => {
                vec![ModelSpec::new(ModelKind::StudentT, self.gamma).map_err(usage)?]
            }
            ModelArg::All => all_models().to_vec(),
        })
    }

    /// The fit options, or a usage error. `given` lists the fit flags given on the command
    /// line (such as `--walks`): those that do not apply to the chosen orders or loss are
    /// refused rather than silently ignored.
    pub fn fit_options(&self, given: &[String]) -> Result<FitOptions, CmdError> {
        let orders = ScatteringOrders::from(self.orders);
        let given = |flag: &str| given.iter().any(|g| g == flag);
        if orders == ScatteringOrders::Single {
            for flag in ["--walks", "--seed", "--multiple-term"] {
                if given(flag) {
                    return Err(walks_only(flag));
                }
            }
        }
        if self.loss != LossArg::Log && given("--log-floor") {
            return Err(usage("--log-floor applies to --loss log only"));
        }
        if orders == ScatteringOrders::Multiple {
            return Err(usage(
                "--orders multiple (orders >= 2 only) models no measurement: fit with --orders \
                 single or all",
            ));
        }
        if orders == ScatteringOrders::All {
            stfit_fit::options::check_fit_walks(self.walks)
                .map_err(|e| usage(format!("--walks: {e}")))?;
        }
        let opts = FitOptions {
            eta: parameter("--eta", &self.eta, |e| {
                stfit_fit::options::check_fit_eta(e).map_err(|e| e.to_string())
            })?,
            scale: parameter("--scale", &self.scale, |s| {
                stfit_fit::options::check_fit_scale(s).map_err(|e| e.to_string())
            })?,
            loss: match self.loss {
                LossArg::Sqrt => Loss::Sqrt,
                LossArg::Linear => Loss::Linear,
                LossArg::Log => Loss::Log,
            },
            log_floor: stfit_fit::options::check_log_floor(self.log_floor)
                .map_err(|e| usage(format!("--log-floor: {e}")))?,
            optimizer: match self.optimizer {
                OptimizerArg::NelderMead => Optimizer::NelderMead,
                OptimizerArg::Lbfgs => Optimizer::Lbfgs,
            },
            masking: masking_of(orders, self.masking)?,
            orders,
            walks: self.walks,
            seed: self.seed,
            multiple_term: match self.multiple_term {
                MultipleTermArg::Surrogate => MultipleTerm::Surrogate,
                MultipleTermArg::Exact => MultipleTerm::Exact,
            },
        };
        opts.check().map_err(usage)?;
        Ok(opts)
    }
}

/// Runs the fit command.
pub fn run(args: FitArgs, given: &[String]) -> CmdResult {
    args.retired.check()?;
    if args.data.is_empty() {
        return Err(usage("a DATA file is required"));
    }
    let specs = args.options.specs()?;
    let opts = args.options.fit_options(given)?;
    if let Some(out) = &args.out {
        // Every file the fit reads, those of a folder included (a listing that fails is
        // reported by the read).
        let files = stfit_fit::load::data_files(&args.data).unwrap_or_else(|_| args.data.clone());
        refuse_overwriting_input(out, &files)?;
    }
    let data = selected(
        load_paths(&args.data).map_err(failed)?,
        args.sample.as_deref(),
    )?;
    let fits = fit_with_progress(&data, &specs, &opts, !args.json)?;
    let json = || FitsFile::new(fits.clone()).to_json();
    if let Some(out) = &args.out {
        write_file(out, &json())?;
    }
    if args.json {
        print_stdout(&json())
    } else {
        print_stdout(&fits_table(&fits))
    }
}

/// The dataset restricted to the sample `name`, when one is given.
pub fn selected(mut data: Dataset, name: Option<&str>) -> Result<Dataset, CmdError> {
    if let Some(name) = name {
        let sample = data.sample(name).map_err(failed)?.clone();
        data.samples = vec![sample];
    }
    Ok(data)
}

/// Fits `specs` to every sample of `data`, with a bar counting fits on stderr for all-orders
/// fits when stderr is a terminal and `show` is set.
pub fn fit_with_progress(
    data: &Dataset,
    specs: &[ModelSpec],
    opts: &FitOptions,
    show: bool,
) -> Result<Vec<FitResult>, CmdError> {
    if opts.orders != ScatteringOrders::Single {
        let cost = fit_walk_cost(data, specs, opts);
        long_run::note_if_long(cost.seconds, &cost.what(), "fewer --walks make it shorter");
    }
    let show = show && opts.orders != ScatteringOrders::Single && std::io::stderr().is_terminal();
    let bar = show.then(|| {
        let bar = ProgressBar::new((data.samples.len() * specs.len()) as u64);
        if let Ok(style) = ProgressStyle::with_template("{spinner} {bar:30} {pos}/{len} fits") {
            bar.set_style(style);
        }
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        bar
    });
    let progress = |done: usize, _total: usize| {
        if let Some(bar) = &bar {
            bar.set_position(done as u64);
        }
    };
    let fits = fit_dataset(data, specs, opts, &progress).map_err(failed);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    for fit in fits.iter().flatten() {
        for w in &fit.warnings {
            eprintln!("warning: {}: {w}", fit.label());
        }
    }
    fits
}
