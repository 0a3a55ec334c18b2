//! The subcommands of `stfit`: one module each, with a clap `Args` struct and a `run` function
//! returning [`CmdResult`]. They parse arguments, call the library crates and print; nothing
//! else happens here.

use std::fmt;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use clap::ValueEnum;
use stfit_core::ScatteringOrders;
use stfit_core::bsdf::Masking;
use stfit_fit::files::same_file;

pub mod albedo;
pub mod eval;
pub mod export;
pub mod fit;
pub mod long_run;
pub mod report;
pub mod surface;
pub mod synth;
pub mod tables;

/// Why a command failed. The binary prints `error: <message>` and exits with [`exit_code`].
///
/// [`exit_code`]: CmdError::exit_code
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CmdError {
    /// Invalid command-line values, parameters included (exit status 2, as for clap's own
    /// usage errors).
    Usage(String),
    /// Bad input data, a failed computation, or an I/O problem (exit status 1).
    Failed(String),
}

impl CmdError {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::Usage(_) => 2,
            Self::Failed(_) => 1,
        }
    }
}

impl fmt::Display for CmdError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Usage(m) | Self::Failed(m) => f.write_str(m),
        }
    }
}

/// A usage error (exit status 2) from anything displayable.
pub fn usage(e: impl fmt::Display) -> CmdError {
    CmdError::Usage(e.to_string())
}

/// The usage error of a walk flag (`--walks`, `--seed`, ...) given where nothing walks.
pub fn walks_only(flag: &str) -> CmdError {
    usage(format!(
        "{flag} applies to --orders all only (single scattering is analytic)"
    ))
}

/// A failure (exit status 1) from anything displayable.
pub fn failed(e: impl fmt::Display) -> CmdError {
    CmdError::Failed(e.to_string())
}

/// What every subcommand returns.
pub type CmdResult = Result<(), CmdError>;

/// Writes `text` to stdout. A closed pipe (`stfit ... | head`) ends output quietly instead of
/// failing.
pub fn print_stdout(text: &str) -> CmdResult {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(failed(format!("cannot write to stdout: {e}"))),
    }
}

/// Writes `text` to the file at `path`, replacing it. A path ending in `/` names a folder,
/// which this output is not: said so, rather than the system's 'Is a directory'.
pub fn write_file(path: &Path, text: &str) -> CmdResult {
    if path.as_os_str().to_string_lossy().ends_with('/') {
        return Err(failed(format!(
            "{}: a file is written here, not a folder: give a file name",
            path.display()
        )));
    }
    std::fs::write(path, text).map_err(|e| failed(format!("{}: cannot write: {e}", path.display())))
}

/// Refuses to write the output `out` (the file `--out` names, or one written inside the folder
/// it names) when it is one of `inputs`, the files the command reads: a usage error (exit 2)
/// naming both. Files are compared by identity ([`same_file`]: device and inode on Unix), so a
/// hard link, a symbolic link or another spelling of an input's path is that input.
pub fn refuse_overwriting_input(out: &Path, inputs: &[PathBuf]) -> CmdResult {
    match inputs.iter().find(|p| same_file(out, p)) {
        Some(path) => Err(usage(format!(
            "--out {} is the input file {}; refusing to overwrite it",
            out.display(),
            path.display()
        ))),
        None => Ok(()),
    }
}

/// `--masking`: the Smith masking-shadowing form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MaskingArg {
    /// `G1(wi) G1(wo)`, as in Walter et al. 2007 and the published fits.
    Separable,
    /// Height-correlated Smith (the Beta function for transmission); the only masking of the
    /// random walk, so of orders multiple and all.
    Correlated,
}

impl From<MaskingArg> for Masking {
    fn from(m: MaskingArg) -> Self {
        match m {
            MaskingArg::Separable => Masking::Separable,
            MaskingArg::Correlated => Masking::Correlated,
        }
    }
}

/// `--orders`: which scattering orders, the one vocabulary of every command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OrdersArg {
    /// Order 1: paths that scatter exactly once.
    Single,
    /// Orders >= 2 only.
    Multiple,
    /// Every order: the full BSDF.
    All,
}

impl From<OrdersArg> for ScatteringOrders {
    fn from(o: OrdersArg) -> Self {
        match o {
            OrdersArg::Single => Self::Single,
            OrdersArg::Multiple => Self::Multiple,
            OrdersArg::All => Self::All,
        }
    }
}

/// `--orders` of the commands that model a measurement (fit, report, synth): the same words as
/// [`OrdersArg`], but `multiple` is not listed, since orders >= 2 alone model no measurement;
/// it is still parsed, so that the command refuses it with that reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MeasuredOrdersArg {
    /// Order 1: paths that scatter exactly once.
    Single,
    /// Orders >= 2 only (refused: no measurement holds them alone).
    #[value(hide = true)]
    Multiple,
    /// Every order: the full BSDF.
    All,
}

impl From<MeasuredOrdersArg> for ScatteringOrders {
    fn from(o: MeasuredOrdersArg) -> Self {
        match o {
            MeasuredOrdersArg::Single => Self::Single,
            MeasuredOrdersArg::Multiple => Self::Multiple,
            MeasuredOrdersArg::All => Self::All,
        }
    }
}

/// The masking of `orders`: as given, or the default of the orders; the library's one rule
/// (orders >= 2 need correlated masking) applied, a violation being a usage error.
pub fn masking_of(
    orders: ScatteringOrders,
    given: Option<MaskingArg>,
) -> Result<Masking, CmdError> {
    orders
        .masking(given.map(Masking::from))
        .map_err(|e| usage(format!("--masking: {e}")))
}

/// Checks a relative index of refraction given as `--eta`.
pub fn check_eta_arg(eta: f64) -> Result<f64, CmdError> {
    stfit_core::error::check_eta(eta).map_err(|e| usage(format!("--eta: {e}")))
}

/// Flags of earlier versions, refused with a message that names their replacement (exit 2).
#[derive(Debug, Clone, clap::Args)]
pub struct Retired {
    #[arg(long, hide = true, allow_hyphen_values = true)]
    scattering: Option<String>,
    #[arg(long, hide = true, allow_hyphen_values = true)]
    samples: Option<String>,
}

impl Retired {
    /// A usage error if a retired flag was given.
    pub fn check(&self) -> CmdResult {
        if self.scattering.is_some() {
            return Err(usage(
                "--scattering is gone: use --orders single|multiple|all (order 1, orders >= 2, \
                 every order)",
            ));
        }
        if self.samples.is_some() {
            return Err(usage(
                "--samples is gone: use --walks N (the number of random walks)",
            ));
        }
        Ok(())
    }
}
