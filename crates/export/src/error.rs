//! Why an export could not be made.

use thiserror::Error;

/// An export that cannot be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ExportError {
    /// A parameter outside its valid range (from stfit-core).
    #[error("invalid parameter: {0}")]
    Param(#[from] stfit_core::ParamError),
    /// A model that cannot be evaluated (from stfit-fit).
    #[error("{0}")]
    Model(#[from] stfit_fit::FitError),
    /// A model or option that the export does not support.
    #[error("{0}")]
    Unsupported(String),
    /// The translation optimiser failed.
    #[error("translation failed: {0}")]
    Optimizer(String),
}
