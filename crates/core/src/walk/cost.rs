//! What a run of random walks will cost, measured before it starts.
//!
//! Walks get long where the microsurface is rough and its slopes heavy-tailed: about
//! `0.2 alpha / (gamma - 3/2)` scattering events per walk for Student-T near `gamma = 3/2`, tens
//! of thousands at large alpha. A short pilot run from the same incident direction measures the
//! mean path length and the time per walk on this machine, so that a front end can say how long
//! a run will take before starting it (the command line prints a note above
//! [`LONG_RUN_SECONDS`] and draws a progress bar on a terminal).

use std::time::Instant;

use super::Estimator;
use crate::math::Vec3;

/// Walks of a pilot run: few enough to cost nothing next to the run, many enough for the mean
/// path length to within tens of percent.
pub const PILOT_WALKS: u64 = 64;

/// Estimated wall time, in seconds, above which a run is long enough to announce.
pub const LONG_RUN_SECONDS: f64 = 10.0;

/// The cost of one walk, from a pilot run ([`WalkCost::measure`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkCost {
    /// Mean number of scattering events per walk.
    pub mean_bounces: f64,
    /// Wall time of one walk on one thread, in seconds.
    pub seconds_per_walk: f64,
    /// Fraction of the pilot's flux dropped at the safety cap
    /// ([`MAX_BOUNCES`](super::MAX_BOUNCES)).
    pub truncated: f64,
    /// Threads the estimators will run on (rayon's current pool).
    pub threads: usize,
}

impl WalkCost {
    /// Runs [`PILOT_WALKS`] walks from `wi` (random numbers of their own, from `seed`; the
    /// estimates of the run itself are unchanged) and times them.
    pub fn measure(estimator: &dyn Estimator, wi: Vec3, seed: u64) -> Self {
        let start = Instant::now();
        // The pilot runs on one thread: its time is the time of one walk, not of a share.
        let pilot = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map(|pool| pool.install(|| estimator.albedo(wi, PILOT_WALKS, seed)))
            .unwrap_or_else(|_| estimator.albedo(wi, PILOT_WALKS, seed));
        Self {
            mean_bounces: pilot.mean_bounces,
            seconds_per_walk: start.elapsed().as_secs_f64() / PILOT_WALKS as f64,
            truncated: pilot.truncated,
            threads: rayon::current_num_threads(),
        }
    }

    /// Estimated wall time of `walks` walks spread over [`WalkCost::threads`] threads.
    pub fn seconds(&self, walks: u64) -> f64 {
        self.seconds_per_walk * walks as f64 / self.threads.max(1) as f64
    }
}

/// A duration in seconds as people say it: `40 s`, `12 min`, `3.5 h`, `2.1 days`.
pub fn describe_seconds(s: f64) -> String {
    if s < 90.0 {
        format!("{s:.0} s")
    } else if s < 90.0 * 60.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 48.0 * 3600.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1} days", s / 86400.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ndf::StudentT;
    use crate::walk::{DielectricFacet, Microsurface};

    /// The pilot's path length follows the model's growth near gamma = 3/2 (about
    /// `0.2 alpha / (gamma - 3/2)` events per walk), and the estimated time scales with walks
    /// and threads.
    #[test]
    fn the_pilot_measures_the_growth_of_path_length_near_gamma_three_halves() {
        let wi = Vec3::new(-0.5, 0.0, 0.75f64.sqrt());
        let cost = |alpha, gamma| {
            let glass = Microsurface::new(
                StudentT::new(alpha, gamma).unwrap(),
                DielectricFacet::new(1.5).unwrap(),
            );
            WalkCost::measure(&glass, wi, 3)
        };
        let short = cost(0.3, 3.0);
        let long = cost(2.0, 1.51);
        assert!(
            short.mean_bounces >= 1.0 && short.mean_bounces < 5.0,
            "{short:?}"
        );
        let expected = 0.2 * 2.0 / 0.01;
        assert!(
            long.mean_bounces > 0.3 * expected && long.mean_bounces < 3.0 * expected,
            "{long:?}"
        );
        assert!(long.seconds_per_walk > 0.0 && long.truncated == 0.0);
        let one = long.seconds(1000);
        assert!((long.seconds(2000) - 2.0 * one).abs() < 1e-12 * one);
        let serial = WalkCost { threads: 1, ..long };
        let expected = long.seconds_per_walk * 1000.0;
        assert!((serial.seconds(1000) - expected).abs() < 1e-12 * expected);
        assert!((one * long.threads as f64 - expected).abs() < 1e-12 * expected);
    }

    #[test]
    fn durations_are_said_in_their_unit() {
        assert_eq!(describe_seconds(40.0), "40 s");
        assert_eq!(describe_seconds(720.0), "12 min");
        assert_eq!(describe_seconds(3.5 * 3600.0), "3.5 h");
        assert_eq!(describe_seconds(3.0 * 86400.0), "3.0 days");
    }
}
