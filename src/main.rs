//! The `stfit` command line.

mod cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Fit microfacet models (Beckmann, GGX, Student-T) to measured transmission through rough glass.
#[derive(Debug, Parser)]
#[command(name = "stfit", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Fractions of incident flux reflected and transmitted by a rough dielectric, by random walk.
    Albedo(cmd::albedo::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Albedo(args) => cmd::albedo::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
