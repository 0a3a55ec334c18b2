//! `stfit synth`: write synthetic measurements of known truth in the data format.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stfit_core::ScatteringOrders;
use stfit_fit::synth::{SynthSpec, parse_angle_list, write_csv, write_file};
use stfit_fit::{DEFAULT_ETA, DEFAULT_WALKS, Gamma, Model, ModelKind, SynthError};

use super::{
    CmdResult, MaskingArg, OrdersArg, Retired, check_eta_arg, failed, masking_of, print_stdout,
    usage,
};

/// Arguments of `stfit synth`.
#[derive(Debug, Clone, Args)]
pub struct SynthArgs {
    /// True model.
    #[arg(long, value_enum)]
    pub model: SynthModelArg,
    /// True roughness (> 0).
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub alpha: f64,
    /// True Student-T shape (> 3/2); required for student-t, refused otherwise.
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// Calibration factor multiplying the model (> 0).
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    pub scale: f64,
    /// Relative noise: each value is max(0, L (1 + SIGMA z)) with z standard normal.
    #[arg(
        long,
        value_name = "SIGMA",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub noise: f64,
    /// Seed of the noise; the same seed and arguments give the same file.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Incidence angles in degrees, [0, 90): a comma list of numbers and start:stop:step ranges.
    #[arg(long, value_name = "LIST", default_value = "0,30,60,80")]
    pub theta_i: String,
    /// Directions inside the glass in degrees, (90, 270), 180 straight through: a comma list of
    /// numbers and inclusive start:stop:step ranges.
    #[arg(long, value_name = "LIST", default_value = "106:254:2")]
    pub theta_o: String,
    /// Relative index of refraction of the glass.
    #[arg(long, value_name = "E", default_value_t = DEFAULT_ETA, allow_negative_numbers = true)]
    pub eta: f64,
    /// Smith masking-shadowing form [default: separable for --orders single; correlated, the
    /// only one allowed, for --orders all].
    #[arg(long, value_enum)]
    pub masking: Option<MaskingArg>,
    /// Scattering orders: single, or all (the random walk's orders >= 2, --walks per incidence
    /// direction seeded with --seed, added to the height-correlated single-scattering BTDF, as
    /// the fit of --orders all models it).
    #[arg(long, value_enum, default_value_t = OrdersArg::Single)]
    pub orders: OrdersArg,
    /// Random walks per incidence direction (--orders all).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_WALKS)]
    pub walks: u64,
    /// Sample name written in the sample column.
    #[arg(long, value_name = "NAME", default_value = "synthetic")]
    pub sample: String,
    /// Write to FILE instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Append the rows to --out FILE (which must have the same header, or not exist yet)
    /// instead of replacing it, to put several samples in one file.
    #[arg(long, requires = "out")]
    pub append: bool,
    #[command(flatten)]
    pub retired: Retired,
}

/// `stfit synth --model`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SynthModelArg {
    Beckmann,
    Ggx,
    StudentT,
}

impl From<SynthModelArg> for ModelKind {
    fn from(m: SynthModelArg) -> Self {
        match m {
            SynthModelArg::Beckmann => Self::Beckmann,
            SynthModelArg::Ggx => Self::Ggx,
            SynthModelArg::StudentT => Self::StudentT,
        }
    }
}

/// Runs `stfit synth`. Invalid values of the model and the grid are usage errors (exit 2);
/// a file that cannot be written or appended to is a failure (1).
pub fn run(args: SynthArgs) -> CmdResult {
    args.retired.check()?;
    let angles =
        |flag: &str, text: &str| parse_angle_list(text).map_err(|e| usage(format!("{flag}: {e}")));
    let kind = ModelKind::from(args.model);
    let orders = ScatteringOrders::from(args.orders);
    if orders == ScatteringOrders::Multiple {
        return Err(usage(
            "--orders multiple (orders >= 2 only) models no measurement: synthesise --orders \
             single or all",
        ));
    }
    let masking = masking_of(orders, args.masking)?;
    let walks = orders == ScatteringOrders::All;
    let spec = SynthSpec {
        model: Model {
            kind,
            alpha: args.alpha,
            gamma: args.gamma.map_or(Gamma::NotApplicable, Gamma::Fixed),
            scale: args.scale,
            eta: check_eta_arg(args.eta)?,
            masking,
            orders,
            walks: walks.then_some(args.walks),
            seed: walks.then_some(args.seed),
        },
        theta_i_deg: angles("--theta-i", &args.theta_i)?,
        theta_o_deg: angles("--theta-o", &args.theta_o)?,
        noise: args.noise,
        seed: args.seed,
        name: args.sample.clone(),
    };
    let sample = spec.sample().map_err(|e| usage(format!("synth: {e}")))?;

    let gamma = args
        .gamma
        .map_or(String::new(), |g| format!(" --gamma {g}"));
    let (orders_flags, model_line) = if walks {
        (
            format!(" --orders all --walks {}", args.walks),
            "all-orders L = scale (f_single + f_multi) cos(theta_i) / eta^2, f_multi by the \
             random walk",
        )
    } else {
        (
            String::new(),
            "single-scattering L = scale f_t cos(theta_i) / eta^2",
        )
    };
    let comment = format!(
        "stfit {} synth --model {} --alpha {}{gamma} --scale {} --noise {} --seed {} \
         --theta-i {} --theta-o {} --eta {} --masking {}{orders_flags} --sample {}\n\
         {model_line} with noise max(0, L (1 + noise z))",
        env!("CARGO_PKG_VERSION"),
        kind.name(),
        args.alpha,
        args.scale,
        args.noise,
        args.seed,
        args.theta_i,
        args.theta_o,
        args.eta,
        masking.name(),
        args.sample,
    );
    match &args.out {
        Some(path) => {
            write_file(path, &[sample], Some(&comment), args.append).map_err(|e| match e {
                SynthError::Append { .. } | SynthError::Io { .. } | SynthError::Load(_) => {
                    failed(e)
                }
                other => usage(other),
            })
        }
        None => {
            let mut buf = Vec::new();
            write_csv(&mut buf, &[sample], true, Some(&comment))
                .map_err(|e| failed(format!("cannot format the rows: {e}")))?;
            print_stdout(&String::from_utf8_lossy(&buf))
        }
    }
}
