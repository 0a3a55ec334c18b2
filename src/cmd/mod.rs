//! The subcommands of `stfit`: one module each, with a clap `Args` struct and a `run` function
//! returning [`CmdResult`].

use std::fmt;
use std::io::{self, Write};
use std::path::Path;

use clap::ValueEnum;
use stfit_core::bsdf::Masking;
use stfit_fit::LoadError;

pub mod albedo;
pub mod eval;
pub mod export;
pub mod fit;
pub mod report;
pub mod surface;
pub mod synth;

/// Why a command failed. The binary prints `error: <message>` and exits with [`exit_code`].
///
/// [`exit_code`]: CmdError::exit_code
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CmdError {
    /// Invalid arguments (exit status 2, as for clap's own usage errors).
    Usage(String),
    /// Bad input data, a failed fit, or an I/O problem (exit status 1).
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

impl From<LoadError> for CmdError {
    fn from(e: LoadError) -> Self {
        Self::Failed(e.to_string())
    }
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
        Err(e) => Err(CmdError::Failed(format!("cannot write to stdout: {e}"))),
    }
}

/// Writes `text` to the file at `path`, replacing it.
pub fn write_file(path: &Path, text: &str) -> CmdResult {
    std::fs::write(path, text)
        .map_err(|e| CmdError::Failed(format!("{}: cannot write: {e}", path.display())))
}

/// `--masking`: the Smith masking-shadowing form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum MaskingArg {
    /// `G1(wi) G1(wo)`, as in Walter et al. 2007 and the published fits.
    #[default]
    Separable,
    /// Height-correlated Smith.
    Correlated,
}

impl MaskingArg {
    /// The name as given on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Separable => "separable",
            Self::Correlated => "correlated",
        }
    }
}

impl From<MaskingArg> for Masking {
    fn from(m: MaskingArg) -> Self {
        match m {
            MaskingArg::Separable => Masking::Separable,
            MaskingArg::Correlated => Masking::Correlated,
        }
    }
}

/// Checks a relative index of refraction given as `--eta`.
pub fn check_eta_arg(eta: f64) -> Result<f64, CmdError> {
    stfit_core::error::check_eta(eta).map_err(|e| CmdError::Usage(format!("--eta: {e}")))
}
