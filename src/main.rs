//! The `stfit` command line: `stfit DATA [flags]` fits microfacet models to measured
//! transmission through rough glass; subcommands do the rest. Each subcommand is one variant of
//! [`Command`] and one module under `cmd/` with an `Args` struct and a `run` function. The
//! commands only parse arguments and print: the work is done by the library crates.

use std::process::ExitCode;

use clap::parser::ValueSource;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

mod cmd;

/// Fit microfacet models (Beckmann, GGX, Student-T) to measured transmission through rough
/// glass.
///
/// Without a subcommand, fits the models to every sample of DATA (see data-format.md) and
/// prints a table (or JSON with --json).
#[derive(Debug, Parser)]
#[command(
    name = "stfit",
    version,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
struct Cli {
    #[command(flatten)]
    fit: cmd::fit::FitArgs,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Write synthetic measurements of a known model in the data format.
    Synth(cmd::synth::SynthArgs),
    /// Evaluate the BSDF (f * |wo.z|) of a rough surface for direction pairs read as CSV on
    /// stdin: in closed form for single scattering, else by random walk with standard errors.
    Eval(cmd::eval::Args),
    /// Fractions of the incident flux a rough surface reflects and transmits, by random walk
    /// (height-field NDFs, or vmf/porous with --walk null).
    Albedo(cmd::albedo::Args),
    /// Directional-albedo (energy-compensation) tables: E_ss by quadrature, all orders by
    /// random walks, on a grid of alpha, gamma, eta and mu or Cycles' nodes (tables-format.md).
    Tables(Box<cmd::tables::Args>),
    /// Figure-1-style plots (SVG and PNG) of the four model fits of every sample, an overview,
    /// residuals, the fitted NDFs and a markdown table of the fits.
    Report(cmd::report::ReportArgs),
    /// Write stored fits as renderer materials (Mitsuba 3, pbrt-v4, Cycles, appleseed,
    /// OpenPBR, V-Ray) or as an LBNL WINDOW BSDF file for Radiance.
    Export(cmd::export::Args),
}

/// The fit options: with [`given_flags`], those given on the command line.
const FIT_OPTIONS: [&str; 12] = [
    "model",
    "gamma",
    "eta",
    "scale",
    "loss",
    "log_floor",
    "optimizer",
    "masking",
    "orders",
    "walks",
    "seed",
    "multiple_term",
];

/// The options among `ids` given on the command line (not defaulted) of `matches`, as flags
/// such as `--log-floor`, so that a command can refuse those that do not apply.
fn given_flags(matches: &clap::ArgMatches, ids: &[&str]) -> Vec<String> {
    ids.iter()
        .filter(|id| matches.value_source(id) == Some(ValueSource::CommandLine))
        .map(|id| format!("--{}", id.replace('_', "-")))
        .collect()
}

/// The options among `ids` given to the subcommand `name`.
fn given_to(matches: &clap::ArgMatches, name: &str, ids: &[&str]) -> Vec<String> {
    matches
        .subcommand_matches(name)
        .map(|m| given_flags(m, ids))
        .unwrap_or_default()
}

fn main() -> ExitCode {
    // A report always fits the four models of --model all: its help hides --model and --gamma.
    let matches = Cli::command()
        .mut_subcommand("report", |report| {
            report
                .mut_arg("model", |a| a.hide(true))
                .mut_arg("gamma", |a| a.hide(true))
        })
        .get_matches();
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        None => cmd::fit::run(cli.fit, &given_flags(&matches, &FIT_OPTIONS)),
        Some(Command::Synth(args)) => {
            cmd::synth::run(args, &given_to(&matches, "synth", &["walks"]))
        }
        Some(Command::Eval(args)) => {
            cmd::eval::run(&args, &given_to(&matches, "eval", &["walks", "seed"]))
        }
        Some(Command::Albedo(args)) => cmd::albedo::run(&args),
        Some(Command::Report(args)) => {
            cmd::report::run(args, &given_to(&matches, "report", &FIT_OPTIONS))
        }
        Some(Command::Tables(args)) => cmd::tables::run(*args),
        Some(Command::Export(args)) => {
            let radiance = ["layer", "absorption", "walks", "seed"];
            cmd::export::run(&args, &given_to(&matches, "export", &radiance))
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
