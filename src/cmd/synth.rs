//! `stfit synth`: write synthetic measurements of known truth in the data format.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stfit_core::ScatteringOrders;
use stfit_fit::pabopto::{PabValue, write_pabopto};
use stfit_fit::synth::{SynthSpec, parse_angle_list, shell_option, write_csv, write_file};
use stfit_fit::{DEFAULT_ETA, DEFAULT_WALKS, Gamma, Grid, Model, ModelKind, SynthError};

use super::{
    CmdError, CmdResult, MaskingArg, MeasuredOrdersArg, Retired, check_eta_arg, failed, long_run,
    masking_of, print_stdout, usage, walks_only,
};

/// Arguments of `stfit synth`.
#[derive(Debug, Clone, Args)]
pub struct SynthArgs {
    /// True model.
    #[arg(long, value_enum)]
    pub model: SynthModelArg,
    /// True roughness, in [1e-8, 100].
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
    /// The grid: in-plane (the Walter form, L) or general (any direction pairs on both sides,
    /// reflection and transmission, the BSDF).
    #[arg(long, value_enum, default_value_t = GridArg::InPlane)]
    pub grid: GridArg,
    /// Incidence angles in degrees: a comma list of numbers and inclusive start:stop:step
    /// ranges. In-plane: in [0, 90) [default: 0,30,60,80]; general: polar angles of the
    /// direction toward the light in [0, 180] without 90, above 90 from inside the glass
    /// [default: 0,30,60,120,150].
    #[arg(long, value_name = "LIST")]
    pub theta_i: Option<String>,
    /// Azimuths of the incidence directions in degrees (general grid), any finite values,
    /// negative ones too (`--phi-i -90,90`) [default: 0].
    #[arg(long, value_name = "LIST", allow_hyphen_values = true)]
    pub phi_i: Option<String>,
    /// Outgoing directions in degrees. In-plane: inside the glass in (90, 270), 180 straight
    /// through [default: 106:254:2]; general: polar angles toward the detector in [0, 180]
    /// without 90 [default: 5:175:10].
    #[arg(long, value_name = "LIST")]
    pub theta_o: Option<String>,
    /// Azimuths of the outgoing directions in degrees (general grid), any finite values,
    /// negative ones too (`--phi-o -170:170:20`) [default: 0:340:20].
    #[arg(long, value_name = "LIST", allow_hyphen_values = true)]
    pub phi_o: Option<String>,
    /// Write the general grid as pab-opto goniophotometer files (one per incidence direction
    /// and side, into the folder --out), with DSF (BSDF times |cos theta_o|) or BSDF values.
    #[arg(long, value_enum, requires = "out")]
    pub pabopto: Option<PabArg>,
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
    #[arg(long, value_enum, default_value_t = MeasuredOrdersArg::Single)]
    pub orders: MeasuredOrdersArg,
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

/// `stfit synth --grid`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum GridArg {
    /// In-plane transmission from the air (the Walter form): columns theta_i_deg,
    /// theta_o_deg, L.
    InPlane,
    /// Any direction pairs: columns theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg, bsdf.
    General,
}

/// `stfit synth --pabopto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PabArg {
    /// `#format: theta phi DSF`.
    Dsf,
    /// `#format: theta phi BSDF`.
    Bsdf,
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
/// `given` lists the walk flags given on the command line: refused without `--orders all`.
pub fn run(args: SynthArgs, given: &[String]) -> CmdResult {
    args.retired.check()?;
    let list = |flag: &str,
                given: &Option<String>,
                default: &str|
     -> Result<(String, Vec<f64>), CmdError> {
        let text = given.clone().unwrap_or_else(|| default.to_string());
        let angles = parse_angle_list(&text).map_err(|e| usage(format!("{flag}: {e}")))?;
        Ok((text, angles))
    };
    let (grid, grid_flags) = match args.grid {
        GridArg::InPlane => {
            for (given, flag) in [(&args.phi_i, "--phi-i"), (&args.phi_o, "--phi-o")] {
                if given.is_some() {
                    return Err(usage(format!("{flag} applies only to --grid general")));
                }
            }
            if args.pabopto.is_some() {
                return Err(usage(
                    "--pabopto writes a general grid: it needs --grid general",
                ));
            }
            let (ti_text, theta_i_deg) = list("--theta-i", &args.theta_i, "0,30,60,80")?;
            let (to_text, theta_o_deg) = list("--theta-o", &args.theta_o, "106:254:2")?;
            (
                Grid::InPlane {
                    theta_i_deg,
                    theta_o_deg,
                },
                format!(
                    "{} {}",
                    shell_option("--theta-i", &ti_text),
                    shell_option("--theta-o", &to_text)
                ),
            )
        }
        GridArg::General => {
            let (ti_text, theta_i_deg) = list("--theta-i", &args.theta_i, "0,30,60,120,150")?;
            let (pi_text, phi_i_deg) = list("--phi-i", &args.phi_i, "0")?;
            let (to_text, theta_o_deg) = list("--theta-o", &args.theta_o, "5:175:10")?;
            let (po_text, phi_o_deg) = list("--phi-o", &args.phi_o, "0:340:20")?;
            (
                Grid::Spherical {
                    theta_i_deg,
                    phi_i_deg,
                    theta_o_deg,
                    phi_o_deg,
                },
                format!(
                    "--grid general {} {} {} {}",
                    shell_option("--theta-i", &ti_text),
                    shell_option("--phi-i", &pi_text),
                    shell_option("--theta-o", &to_text),
                    shell_option("--phi-o", &po_text)
                ),
            )
        }
    };
    let kind = ModelKind::from(args.model);
    let orders = ScatteringOrders::from(args.orders);
    if orders == ScatteringOrders::Multiple {
        return Err(usage(
            "--orders multiple (orders >= 2 only) models no measurement: synthesise --orders \
             single or all",
        ));
    }
    if args.append && args.pabopto.is_some() {
        return Err(usage(
            "--append adds rows to a CSV file; pab-opto files are one per incidence",
        ));
    }
    let masking = masking_of(orders, args.masking)?;
    let walks = orders == ScatteringOrders::All;
    if let (false, Some(flag)) = (walks, given.first()) {
        return Err(walks_only(flag));
    }
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
        grid,
        noise: args.noise,
        seed: args.seed,
        name: args.sample.clone(),
    };
    let synth_error = |e| match e {
        // An angle comes from its flag: name the flag, not the file's column.
        SynthError::Angle { column, .. } => {
            let flag = column.trim_end_matches("_deg").replace('_', "-");
            usage(format!("--{flag}: {e}"))
        }
        e => usage(format!("synth: {e}")),
    };
    // The output options of the command line recorded in the file (below), checked before
    // any walk runs.
    let out_flags = match (&args.out, args.pabopto) {
        (None, _) => String::new(),
        (Some(path), pabopto) => {
            let Some(text) = path.to_str().filter(|t| !t.chars().any(char::is_control)) else {
                return Err(usage(format!(
                    "--out: '{}' cannot be recorded in the file's command line: a path must be \
                     UTF-8 without control characters",
                    path.display().to_string().escape_debug()
                )));
            };
            let form = match pabopto {
                Some(PabArg::Dsf) => " --pabopto dsf",
                Some(PabArg::Bsdf) => " --pabopto bsdf",
                None => "",
            };
            let append = if args.append { " --append" } else { "" };
            format!("{form} {}{append}", shell_option("--out", text))
        }
    };
    if walks {
        long_run::note_if_long(
            spec.walk_seconds().map_err(synth_error)?,
            &spec.walks_description(),
            "fewer --walks make it shorter",
        );
    }
    let sample = spec.sample().map_err(synth_error)?;

    let show = stfit_core::error::show;
    let gamma = args.gamma.map_or(String::new(), |g| {
        format!(" {}", shell_option("--gamma", &show(g)))
    });
    let value = match args.grid {
        GridArg::InPlane => "L = scale f_t cos(theta_i) / eta^2",
        GridArg::General => "BSDF = scale f",
    };
    let (orders_flags, model_line) = if walks {
        (
            format!(" --orders all --walks {}", args.walks),
            format!("all orders: {value} with f = f_single + f_multi, f_multi by the random walk"),
        )
    } else {
        (String::new(), format!("single scattering: {value}"))
    };
    // The command that writes this file again, pasted into a POSIX shell (every option
    // spelled out, defaults too, and words quoted where a shell would change them), then the
    // version and the model.
    let comment = format!(
        "stfit synth --model {} {}{gamma} {} {} --seed {} {grid_flags} {} --masking {}\
         {orders_flags} {}{out_flags}\n\
         written by stfit {}: {model_line}, with noise max(0, v (1 + noise z))",
        kind.name(),
        shell_option("--alpha", &show(args.alpha)),
        shell_option("--scale", &show(args.scale)),
        shell_option("--noise", &show(args.noise)),
        args.seed,
        shell_option("--eta", &show(args.eta)),
        masking.name(),
        shell_option("--sample", &args.sample),
        env!("CARGO_PKG_VERSION"),
    );
    match (&args.out, args.pabopto) {
        (Some(dir), Some(form)) => {
            let form = match form {
                PabArg::Dsf => PabValue::Dsf,
                PabArg::Bsdf => PabValue::Bsdf,
            };
            if args.sample.contains('"') {
                return Err(usage(
                    "--sample: a pab-opto sample name cannot hold a double quote",
                ));
            }
            // The error names the folder or the file that cannot be written.
            let paths = write_pabopto(dir, &sample, form, Some(&comment)).map_err(failed)?;
            let mut listing = String::new();
            for p in paths {
                listing.push_str(&format!("{}\n", p.display()));
            }
            print_stdout(&listing)
        }
        (Some(path), None) => {
            write_file(path, &[sample], Some(&comment), args.append).map_err(|e| match e {
                SynthError::Append { .. } | SynthError::Io { .. } | SynthError::Load(_) => {
                    failed(e)
                }
                other => usage(other),
            })
        }
        (None, _) => {
            let mut buf = Vec::new();
            write_csv(&mut buf, &[sample], true, Some(&comment)).map_err(failed)?;
            print_stdout(&String::from_utf8_lossy(&buf))
        }
    }
}
