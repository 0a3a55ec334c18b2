//! Typed errors: an invalid table specification (the caller's arguments) and unreadable or
//! inconsistent shard files (bad data).

use thiserror::Error;

/// A table specification that cannot be computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpecError {
    /// An axis has a value outside its supported range, or no value.
    #[error("{axis} axis {message}")]
    Axis { axis: &'static str, message: String },
    /// An option does not apply, is missing, or contradicts another.
    #[error("{0}")]
    Invalid(String),
    /// A computed value is not finite: reported instead of written (a failure of the
    /// computation, not of the caller's arguments).
    #[error("{0}")]
    NotFinite(String),
}

/// A shard file that cannot be merged.
#[derive(Debug, Error)]
pub enum ShardError {
    /// The file is not a shard file of this format (with the parser's line and column).
    #[error("{file}: {message}")]
    Parse { file: String, message: String },
    /// The shards do not make up one table.
    #[error("{file}: {message}")]
    Mismatch { file: String, message: String },
    /// No shard was given, or shards are missing.
    #[error("{0}")]
    Incomplete(String),
}
