//! The subcommands of the `stfit` binary, one module each.

pub mod eval;
