//! Typed errors of report generation.

use std::path::PathBuf;

use plotters::drawing::DrawingAreaErrorKind;
use thiserror::Error;

/// Why a report could not be made.
#[derive(Debug, Error)]
pub enum ReportError {
    /// The dataset has no samples (or `--sample` matched none).
    #[error("no samples to report")]
    NoSamples,
    /// A sample has no measurements.
    #[error("sample `{}` has no measurements", stfit_fit::short(.0))]
    EmptySample(String),
    /// A fit names a sample that is not in the data.
    #[error(
        "fit of model {model} names sample `{}`, which is not in the data",
        stfit_fit::short(sample)
    )]
    UnknownSample { sample: String, model: String },
    /// Two fits fill the same panel of one sample.
    #[error("sample `{}` has more than one {model} fit", stfit_fit::short(sample))]
    DuplicateFit { sample: String, model: String },
    /// A fit was made on a different number of points than the data has: stale or foreign fits.
    #[error(
        "{model} fit of sample `{}` was made on {fit_points} points, the data has {data_points}",
        stfit_fit::short(sample)
    )]
    PointCount {
        sample: String,
        model: String,
        fit_points: usize,
        data_points: usize,
    },
    /// A fit's parameters do not describe a valid model.
    #[error(
        "{model} fit of sample `{}` is invalid: {reason}",
        stfit_fit::short(sample)
    )]
    InvalidFit {
        sample: String,
        model: String,
        reason: String,
    },
    /// The embedded font could not be registered with plotters.
    #[error("the embedded DejaVu Sans font could not be registered")]
    Font,
    /// Drawing failed in plotters.
    #[error("drawing failed: {0}")]
    Draw(String),
    /// PNG encoding failed.
    #[error("PNG encoding failed: {0}")]
    Png(#[from] png::EncodingError),
    /// A file or directory could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl ReportError {
    /// [`ReportError::InvalidFit`] of `fit`, whose model could not be evaluated, or whose record
    /// is outside the documented ranges ([`stfit_fit::FitResult::check`]), for `e`.
    pub(crate) fn invalid_fit(fit: &stfit_fit::FitResult, e: impl std::fmt::Display) -> Self {
        Self::InvalidFit {
            sample: fit.sample.clone(),
            model: crate::view::ModelSlot::of(fit).title().to_string(),
            reason: e.to_string(),
        }
    }
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for ReportError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        Self::Draw(e.to_string())
    }
}
