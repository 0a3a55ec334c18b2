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

/// Walks of a pilot run's first batch: few enough to cost nothing next to the run, many enough
/// for the mean path length to within tens of percent.
pub const PILOT_WALKS: u64 = 64;

/// Wall time a pilot run spends at least, in seconds, unless its walks reach
/// [`PILOT_MAX_WALKS`]: batches of 64, 256, ... walks run until one lasts this long, so that
/// the time per walk is read off a batch long enough for the clock and free of the start-up
/// costs (caches, the first allocations) that a lone batch of 64 short walks is dominated by.
pub const PILOT_SECONDS: f64 = 2e-3;

/// Walks of a pilot run's largest batch.
pub const PILOT_MAX_WALKS: u64 = 1 << 16;

/// Incident directions whose pairs a pilot of [`WalkCost::measure_pairs`] runs.
pub const PILOT_INCIDENCES: usize = 8;

/// A pilot runs at most this fraction of its run's work (and at least one walk), so that a
/// short run is not paid twice.
pub const PILOT_SHARE: f64 = 1.0 / 16.0;

/// The most walks a pilot batch may have: [`PILOT_SHARE`] of a run of `walks` walks over
/// `groups` incident directions when the pilot walks from `picked` of them, at least 1 and at
/// most [`PILOT_MAX_WALKS`].
fn pilot_cap(walks: u64, groups: usize, picked: usize) -> u64 {
    let share = PILOT_SHARE * walks as f64 * groups as f64 / picked.max(1) as f64;
    (share as u64).clamp(1, PILOT_MAX_WALKS)
}

/// The seed of a pilot run for a run from `seed`: random numbers of its own, so that a pilot
/// never shares walks with the run (the estimates of the run are unchanged by it).
pub fn pilot_seed(seed: u64) -> u64 {
    seed ^ 0x005e_ed0f_9170
}

/// Estimated wall time, in seconds, above which a run is long enough to announce.
pub const LONG_RUN_SECONDS: f64 = 10.0;

/// The cost of one walk, from a pilot run ([`WalkCost::measure`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkCost {
    /// Mean number of scattering events per walk that left within the orders (0 when none
    /// of the pilot's did).
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
    /// The cost of [`Estimator::albedo`] from `wi` for a run of `walks` walks: runs batches of
    /// [`PILOT_WALKS`], 4 times as many, ... walks from `wi` on one thread (random numbers of
    /// their own, from `seed`; the estimates of the run itself are unchanged) until a batch
    /// lasts [`PILOT_SECONDS`] or reaches [`PILOT_SHARE`] of the run's walks (at least one)
    /// or [`PILOT_MAX_WALKS`], and reads the cost off the last batch.
    pub fn measure(estimator: &dyn Estimator, wi: Vec3, walks: u64, seed: u64) -> Self {
        let (pilot, seconds_per_walk) = single_threaded(|| {
            time_batches(pilot_cap(walks, 1, 1), |n, batch| {
                estimator.albedo(wi, n, seed.wrapping_add(batch))
            })
        });
        Self {
            mean_bounces: pilot.mean_bounces.unwrap_or(0.0),
            seconds_per_walk,
            truncated: pilot.truncated,
            threads: rayon::current_num_threads(),
        }
    }

    /// The cost of [`eval_pairs`](super::eval_pairs) of `pairs` with `walks` walks per
    /// incident direction, per walk from each incident direction: the next-event estimates
    /// toward every `wo` and the walks from each `wo` (bidirectional estimators) included.
    /// The pilot runs `eval_pairs` itself, in batches as [`WalkCost::measure`] does (at most
    /// [`PILOT_SHARE`] of the run's work), on the pairs of at most [`PILOT_INCIDENCES`]
    /// incident directions spread evenly through their order, and scales its time by the
    /// number of incident directions; the path length and the flux at the safety cap are
    /// those of [`PILOT_WALKS`] albedo walks (at most that share of `walks`) from the first
    /// incident direction.
    pub fn measure_pairs(
        estimator: &dyn Estimator,
        pairs: &[(Vec3, Vec3)],
        walks: u64,
        seed: u64,
    ) -> Self {
        let groups = super::estimate::incidence_groups(pairs);
        let Some(&(first, _)) = groups.first() else {
            return Self {
                mean_bounces: 0.0,
                seconds_per_walk: 0.0,
                truncated: 0.0,
                threads: rayon::current_num_threads(),
            };
        };
        let step = groups.len().div_ceil(PILOT_INCIDENCES);
        let picked: Vec<_> = groups.iter().step_by(step).collect();
        let subset: Vec<(Vec3, Vec3)> = picked
            .iter()
            .flat_map(|(_, members)| members.iter().map(|&k| pairs[k]))
            .collect();
        let cap = pilot_cap(walks, groups.len(), picked.len());
        let path_walks = PILOT_WALKS.min(pilot_cap(walks, 1, 1));
        let ((_, seconds_per_walk), path) = single_threaded(|| {
            let timed = time_batches(cap, |n, batch| {
                super::eval_pairs(estimator, &subset, n, seed.wrapping_add(batch))
            });
            (timed, estimator.albedo(first, path_walks, seed))
        });
        Self {
            mean_bounces: path.mean_bounces.unwrap_or(0.0),
            seconds_per_walk: seconds_per_walk * groups.len() as f64 / picked.len() as f64,
            truncated: path.truncated,
            threads: rayon::current_num_threads(),
        }
    }

    /// Estimated wall time of `walks` walks spread over [`WalkCost::threads`] threads.
    pub fn seconds(&self, walks: u64) -> f64 {
        self.seconds_per_walk * walks as f64 / self.threads.max(1) as f64
    }
}

/// Runs `run(walks, batch)` for `walks` = [`PILOT_WALKS`], 4 times as many, ... until a batch
/// lasts [`PILOT_SECONDS`] or reaches `max_walks` walks, returning the last batch's result and
/// its wall time per walk. Every batch is at most `max_walks`, and the batches before the last
/// take less than [`PILOT_SECONDS`] each. Callers run it on one thread ([`single_threaded`]).
fn time_batches<T>(max_walks: u64, run: impl Fn(u64, u64) -> T) -> (T, f64) {
    let mut walks = PILOT_WALKS.min(max_walks).max(1);
    let mut batch = 0;
    loop {
        let start = Instant::now();
        let result = run(walks, batch);
        let seconds = start.elapsed().as_secs_f64();
        if seconds >= PILOT_SECONDS || walks >= max_walks {
            return (result, seconds / walks as f64);
        }
        walks = (walks * 4).min(max_walks);
        batch += 1;
    }
}

/// Runs `f` on a pool of one thread: a pilot's time is the time of its walks, not of a share.
fn single_threaded<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(pool) => pool.install(f),
        Err(_) => f(),
    }
}

/// The note that announces a run of random walks estimated at `seconds`, when that exceeds
/// [`LONG_RUN_SECONDS`]: `WHAT will take about TIME (SHORTER)`, `what` naming the walks and
/// `shorter` what makes them shorter; `None` for a shorter run. Front ends give it to their
/// users before the run starts: the command line on stderr after `note: `, the Python package
/// as a warning.
pub fn long_run_note(seconds: f64, what: &str, shorter: &str) -> Option<String> {
    (seconds > LONG_RUN_SECONDS).then(|| {
        format!(
            "{what} will take about {} ({shorter})",
            describe_seconds(seconds)
        )
    })
}

impl WalkCost {
    /// The note that announces a run of `walks` walks of this cost when it will take over
    /// [`LONG_RUN_SECONDS`] ([`WalkCost::seconds`]): the mean path length, the `all_walks` walks
    /// of the whole run and how long they will take, `shorter` (what makes the run shorter: a
    /// smaller alpha and, for Student-T, a larger gamma are added to it), and the flux a pilot
    /// walk dropped at the safety cap, if any; `None` for a shorter run.
    pub fn long_run_note(&self, walks: u64, all_walks: u64, shorter: &str) -> Option<String> {
        let seconds = self.seconds(walks);
        if seconds <= LONG_RUN_SECONDS {
            return None;
        }
        let bounces = if self.mean_bounces < 10.0 {
            format!("{:.1}", self.mean_bounces)
        } else {
            format!("{:.0}", self.mean_bounces)
        };
        let mut note = format!(
            "about {bounces} scattering events per walk: {all_walks} walks will take about {} on \
             {} threads ({shorter}; so do a smaller alpha and, for Student-T, a larger gamma)",
            describe_seconds(seconds),
            self.threads,
        );
        if self.truncated > 0.0 {
            note += &format!(
                "; walks of a pilot run reached the safety cap on scattering events and dropped \
                 {:.1e} of its flux",
                self.truncated
            );
        }
        Some(note)
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
            WalkCost::measure(&glass, wi, 100_000, 3)
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

    /// The pilot of a batch of pairs takes its path length from albedo walks of the first
    /// incident direction, times the estimator itself on a subset of incident directions,
    /// and measures nothing for no pairs.
    #[test]
    fn the_pilot_of_pairs_walks_from_the_first_incidence_and_times_every_incidence() {
        let glass = Microsurface::new(
            StudentT::new(0.5, 2.0).unwrap(),
            DielectricFacet::new(1.5).unwrap(),
        );
        let pairs: Vec<(Vec3, Vec3)> = (0..20)
            .flat_map(|i| {
                let t = 0.05 * f64::from(i);
                let wi = Vec3::new(-t.sin(), 0.0, t.cos());
                [
                    (wi, Vec3::new(0.3, 0.1, 0.9f64.sqrt())),
                    (wi, Vec3::new(0.2, -0.4, -0.8f64.sqrt())),
                ]
            })
            .collect();
        let cost = WalkCost::measure_pairs(&glass, &pairs, 1000, 5);
        let first = glass.albedo(pairs[0].0, PILOT_WALKS.min(1000 / 16), 5);
        assert_eq!(Some(cost.mean_bounces), first.mean_bounces);
        assert_eq!(cost.truncated, first.truncated);
        assert!(cost.seconds_per_walk > 0.0, "{cost:?}");
        let none = WalkCost::measure_pairs(&glass, &[], 1000, 5);
        assert_eq!(none.seconds(1000), 0.0);
    }

    /// A pilot walks at most a sixteenth of its run (at least one walk), whatever the share of
    /// the incident directions it walks from.
    #[test]
    fn a_pilot_never_repeats_its_run() {
        assert_eq!(pilot_cap(64, 8, 8), 4);
        assert_eq!(pilot_cap(64, 200, 8), 100);
        assert_eq!(pilot_cap(10, 1, 1), 1);
        assert_eq!(pilot_cap(u64::MAX, 1, 1), PILOT_MAX_WALKS);
    }

    #[test]
    fn durations_are_said_in_their_unit() {
        assert_eq!(describe_seconds(40.0), "40 s");
        assert_eq!(describe_seconds(720.0), "12 min");
        assert_eq!(describe_seconds(3.5 * 3600.0), "3.5 h");
        assert_eq!(describe_seconds(3.0 * 86400.0), "3.0 days");
    }
}
