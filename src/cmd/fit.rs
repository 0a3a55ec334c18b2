//! The default command, `stfit DATA [flags]`: fit models to every sample of a measurement file
//! and print a table or JSON.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use stfit_core::ScatteringOrders;
use stfit_fit::{
    DEFAULT_ETA, DEFAULT_WALKS, Dataset, FitOptions, FitResult, FitsFile, Loss, ModelKind,
    ModelSpec, Optimizer, all_models, fit_dataset,
};
use stfit_report::fits_table;

use super::{
    CmdError, CmdResult, MaskingArg, OrdersArg, Retired, check_eta_arg, failed, masking_of,
    print_stdout, usage, write_file,
};

/// Arguments of the default (fit) command.
#[derive(Debug, Clone, Args)]
pub struct FitArgs {
    /// Measurement file: CSV with columns theta_i_deg, theta_o_deg and L or sqrt_L, optionally
    /// sample and weight (see data-format.md). A file named like a subcommand needs a path
    /// such as ./synth.
    #[arg(value_name = "DATA", required = true)]
    pub data: Option<PathBuf>,
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
    /// Relative index of refraction of the glass.
    #[arg(long, value_name = "E", default_value_t = DEFAULT_ETA, allow_negative_numbers = true)]
    pub eta: f64,
    /// Least squares on sqrt(L) or on L.
    #[arg(long, value_enum, default_value_t = LossArg::Sqrt)]
    pub loss: LossArg,
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
    #[arg(long, value_enum, default_value_t = OrdersArg::Single)]
    pub orders: OrdersArg,
    /// Random walks per incidence direction per model evaluation (--orders all).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_WALKS)]
    pub walks: u64,
    /// Seed of the random walks (--orders all).
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub seed: u64,
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

impl FitOptionArgs {
    /// The models to fit, or a usage error.
    pub fn specs(&self) -> Result<Vec<ModelSpec>, CmdError> {
        if let Some(g) = self.gamma {
            if self.model != ModelArg::StudentT {
                return Err(usage(
                    "--gamma fixes the Student-T shape; it needs --model student-t",
                ));
            }
            stfit_core::error::check_gamma(g).map_err(|e| usage(format!("--gamma: {e}")))?;
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

    /// The fit options, or a usage error.
    pub fn fit_options(&self) -> Result<FitOptions, CmdError> {
        let orders = ScatteringOrders::from(self.orders);
        if orders == ScatteringOrders::Multiple {
            return Err(usage(
                "--orders multiple (orders >= 2 only) models no measurement: fit with --orders \
                 single or all",
            ));
        }
        if orders == ScatteringOrders::All && self.walks == 0 {
            return Err(usage("--walks must be a positive number of walks, got 0"));
        }
        let opts = FitOptions {
            eta: check_eta_arg(self.eta)?,
            loss: match self.loss {
                LossArg::Sqrt => Loss::Sqrt,
                LossArg::Linear => Loss::Linear,
            },
            optimizer: match self.optimizer {
                OptimizerArg::NelderMead => Optimizer::NelderMead,
                OptimizerArg::Lbfgs => Optimizer::Lbfgs,
            },
            masking: masking_of(orders, self.masking)?,
            orders,
            walks: self.walks,
            seed: self.seed,
        };
        opts.check().map_err(usage)?;
        Ok(opts)
    }
}

/// Runs the fit command.
pub fn run(args: FitArgs) -> CmdResult {
    args.retired.check()?;
    let path = args
        .data
        .as_deref()
        .ok_or_else(|| usage("a DATA file is required"))?;
    let specs = args.options.specs()?;
    let opts = args.options.fit_options()?;
    if let Some(out) = &args.out {
        if same_file(out, path) {
            return Err(usage(format!(
                "--out {} is the data file; refusing to overwrite it",
                out.display()
            )));
        }
    }
    let data = selected(Dataset::load(path).map_err(failed)?, args.sample.as_deref())?;
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

/// Whether two paths name the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
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
    fits
}
