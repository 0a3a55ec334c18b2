//! Typed errors for invalid model parameters, raised at the API boundary.

use thiserror::Error;

/// An invalid model parameter: constructors reject these instead of producing wrong numbers.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ParamError {
    /// A parameter is NaN or infinite.
    #[error("{name} must be finite, got {value}")]
    NonFinite { name: &'static str, value: f64 },
    /// Roughness must be strictly positive.
    #[error("alpha must be > 0, got {0}")]
    Alpha(f64),
    /// The Student-T shape must exceed 3/2 (a finite mean slope).
    #[error("gamma must be > 3/2, got {0}")]
    Gamma(f64),
    /// A relative index of refraction must be positive and not 1.
    #[error("eta must be > 0 and != 1, got {0}")]
    Eta(f64),
    /// Any other parameter outside its documented range.
    #[error("{name} is out of range: {value} ({expected})")]
    OutOfRange {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
}

/// Returns `value` if it is finite, else a [`ParamError::NonFinite`] naming it.
pub fn finite(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::NonFinite { name, value })
    }
}

/// Validates a roughness: finite and > 0.
pub fn check_alpha(alpha: f64) -> Result<f64, ParamError> {
    let alpha = finite("alpha", alpha)?;
    if alpha > 0.0 {
        Ok(alpha)
    } else {
        Err(ParamError::Alpha(alpha))
    }
}

/// Validates a Student-T shape: finite and > 3/2.
pub fn check_gamma(gamma: f64) -> Result<f64, ParamError> {
    let gamma = finite("gamma", gamma)?;
    if gamma > 1.5 {
        Ok(gamma)
    } else {
        Err(ParamError::Gamma(gamma))
    }
}

/// Validates a relative index of refraction: finite, > 0 and != 1.
pub fn check_eta(eta: f64) -> Result<f64, ParamError> {
    let eta = finite("eta", eta)?;
    if eta > 0.0 && eta != 1.0 {
        Ok(eta)
    } else {
        Err(ParamError::Eta(eta))
    }
}
