//! Long random-walk runs made visible: a pilot run estimates the cost before the walks start
//! (`stfit_core::walk::WalkCost`), a note on stderr announces a run longer than
//! `LONG_RUN_SECONDS`, and a progress bar is drawn when stderr is a terminal.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use stfit_core::Vec3;
use stfit_core::walk::{Estimator, LONG_RUN_SECONDS, WalkCost, describe_seconds};

/// Estimated time, in seconds, above which a progress bar is drawn on a terminal.
const BAR_SECONDS: f64 = 2.0;

/// Measures the cost of `walks` walks from `wi` by a pilot run, announces the run on stderr if
/// it will be long, and returns a progress bar counting walks when one is worth drawing.
pub fn announce(estimator: &dyn Estimator, wi: Vec3, walks: u64, seed: u64) -> Option<ProgressBar> {
    let cost = WalkCost::measure(estimator, wi, seed ^ 0x005e_ed0f_9170);
    let seconds = cost.seconds(walks);
    if seconds > LONG_RUN_SECONDS {
        let mut note = format!(
            "note: about {:.0} scattering events per walk: {walks} walks will take about {} on \
             {} threads (fewer --walks make it shorter; so do a smaller alpha and, for Student-T, a \
             larger gamma)",
            cost.mean_bounces,
            describe_seconds(seconds),
            cost.threads,
        );
        if cost.truncated > 0.0 {
            note += &format!(
                "; walks of a pilot run reached the safety cap on scattering events and dropped \
                 {:.1e} of its flux",
                cost.truncated
            );
        }
        eprintln!("{note}");
    }
    (seconds > BAR_SECONDS && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(walks);
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} walks, eta {eta}") {
            bar.set_style(style);
        }
        bar
    })
}
