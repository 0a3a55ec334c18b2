//! The `stfit` command line.

mod cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Microfacet models of rough glass: evaluate, simulate and fit them to measurements.
#[derive(Debug, Parser)]
#[command(name = "stfit", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Evaluate the single-scattering rough dielectric BSDF (f * |wo.z|) for directions read
    /// as CSV on stdin.
    Eval(cmd::eval::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Eval(args) => cmd::eval::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
