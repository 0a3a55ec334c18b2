//! Subcommands of the `stfit` binary.

pub mod albedo;
