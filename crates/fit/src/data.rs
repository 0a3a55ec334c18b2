//! In-memory measurements: one or more named samples of (theta_i, theta_o, L) points.

use std::path::PathBuf;

/// One measured point of transmitted light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    /// Incidence angle from the outside, degrees in [0, 90).
    pub theta_i_deg: f64,
    /// Direction inside the glass in the plane of incidence, degrees in (90, 270); 180 is
    /// straight through.
    pub theta_o_deg: f64,
    /// The measured `L` (a `sqrt_L` column is squared on load).
    pub l: f64,
    /// Least-squares weight (1 when the file has no `weight` column).
    pub weight: f64,
}

/// The measurements of one physical sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// The sample's name (empty when the file has no `sample` column).
    pub name: String,
    pub points: Vec<Measurement>,
}

/// Every sample read from one file, in order of first appearance.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    /// Where the data came from, for messages.
    pub source: PathBuf,
    pub samples: Vec<Sample>,
}
