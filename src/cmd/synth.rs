//! `stfit synth`: write synthetic measurements of known truth in the data format.

use std::fs::OpenOptions;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use stfit_fit::synth::{HEADER, SynthSpec, parse_angle_list, write_csv};
use stfit_fit::{ModelKind, ModelParams, Scattering};

use super::fit::{ScatteringArg, masking as fit_masking};
use super::{CmdError, CmdResult, MaskingArg, check_eta_arg, print_stdout};

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
    #[arg(
        long,
        value_name = "E",
        default_value_t = 1.51,
        allow_negative_numbers = true
    )]
    pub eta: f64,
    /// Smith masking-shadowing form [default: separable; correlated, the only one allowed, with
    /// --scattering multiple].
    #[arg(long, value_enum)]
    pub masking: Option<MaskingArg>,
    /// Scattering orders: `multiple` adds the random walk's orders >= 2 (--walks per incidence
    /// angle, seeded with --seed) to the height-correlated single-scattering BTDF.
    #[arg(long, value_enum, default_value_t = ScatteringArg::Single)]
    pub scattering: ScatteringArg,
    /// Random walks per incidence angle (--scattering multiple).
    #[arg(long, value_name = "N", default_value_t = 100_000)]
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

/// Runs `stfit synth`.
pub fn run(args: SynthArgs) -> CmdResult {
    let angles = |flag: &str, text: &str| {
        parse_angle_list(text).map_err(|e| CmdError::Usage(format!("{flag}: {e}")))
    };
    let kind = ModelKind::from(args.model);
    let masking = fit_masking(args.scattering, args.masking)?;
    if args.scattering == ScatteringArg::Multiple && args.walks == 0 {
        return Err(CmdError::Usage(
            "--walks must be a positive number of walks, got 0".into(),
        ));
    }
    let spec = SynthSpec {
        params: ModelParams {
            kind,
            alpha: args.alpha,
            gamma: args.gamma.unwrap_or(f64::NAN),
            scale: args.scale,
        },
        gamma_given: args.gamma.is_some(),
        eta: check_eta_arg(args.eta)?,
        masking: masking.into(),
        scattering: match args.scattering {
            ScatteringArg::Single => Scattering::Single,
            ScatteringArg::Multiple => Scattering::Multiple,
        },
        walks: args.walks,
        theta_i_deg: angles("--theta-i", &args.theta_i)?,
        theta_o_deg: angles("--theta-o", &args.theta_o)?,
        noise: args.noise,
        seed: args.seed,
        name: args.sample.clone(),
    };
    let sample = spec
        .sample()
        .map_err(|e| CmdError::Usage(format!("synth: {e}")))?;

    let gamma = args
        .gamma
        .map_or(String::new(), |g| format!(" --gamma {g}"));
    let (scattering_flags, model_line) = match args.scattering {
        ScatteringArg::Single => (
            String::new(),
            "single-scattering L = scale f_t cos(theta_i) / eta^2",
        ),
        ScatteringArg::Multiple => (
            format!(" --scattering multiple --walks {}", args.walks),
            "all-orders L = scale (f_single + f_multi) cos(theta_i) / eta^2, f_multi by the \
             random walk",
        ),
    };
    let comment = format!(
        "stfit {} synth --model {} --alpha {}{gamma} --scale {} --noise {} --seed {} \
         --theta-i {} --theta-o {} --eta {} --masking {}{scattering_flags} --sample {}\n\
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
    let write_error = |path: &Path, e: std::io::Error| {
        CmdError::Failed(format!("{}: cannot write: {e}", path.display()))
    };
    match (&args.out, args.append) {
        (Some(path), true) => {
            let header = !path.exists();
            if !header {
                check_header(path)?;
            }
            let mut file = OpenOptions::new()
                .create(true)
                .append(true)
                .open(path)
                .map_err(|e| write_error(path, e))?;
            let mut buf = Vec::new();
            write_csv(&mut buf, &[sample], header, Some(&comment))
                .and_then(|()| file.write_all(&buf))
                .map_err(|e| write_error(path, e))
        }
        (Some(path), false) => {
            let mut buf = Vec::new();
            write_csv(&mut buf, &[sample], true, Some(&comment))
                .and_then(|()| std::fs::write(path, &buf))
                .map_err(|e| write_error(path, e))
        }
        (None, _) => {
            let mut buf = Vec::new();
            write_csv(&mut buf, &[sample], true, Some(&comment))
                .map_err(|e| CmdError::Failed(format!("cannot format the rows: {e}")))?;
            print_stdout(&String::from_utf8_lossy(&buf))
        }
    }
}

/// Checks that an existing file to append to starts (after comments and blank lines) with the
/// header that `synth` writes, so that the appended rows belong to its columns.
fn check_header(path: &Path) -> CmdResult {
    let bytes = std::fs::read(path)
        .map_err(|e| CmdError::Failed(format!("{}: cannot read: {e}", path.display())))?;
    let text = String::from_utf8_lossy(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes));
    let expected = HEADER.join(",");
    let found = text
        .lines()
        .enumerate()
        .find(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    match found {
        Some((_, line)) if line.trim() == expected => {
            if text.ends_with('\n') {
                Ok(())
            } else {
                Err(CmdError::Failed(format!(
                    "{}: cannot append: the file does not end with a line break",
                    path.display()
                )))
            }
        }
        Some((i, line)) => Err(CmdError::Failed(format!(
            "{}:{}: cannot append: the header is '{}', synth writes '{expected}'",
            path.display(),
            i + 1,
            line.trim()
        ))),
        None => Err(CmdError::Failed(format!(
            "{}: cannot append: the file has no header line",
            path.display()
        ))),
    }
}
