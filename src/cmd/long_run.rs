//! Long random-walk runs made visible: a pilot run estimates the cost before the walks start
//! (`stfit_core::walk::WalkCost`), a note on stderr announces a run longer than
//! `LONG_RUN_SECONDS` ([`announce`], or [`note_if_long`] for a command that states its walks
//! in its own words), and a progress bar is drawn when stderr is a terminal.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use stfit_core::walk::{LONG_RUN_SECONDS, WalkCost, describe_seconds};

/// Estimated time, in seconds, above which a progress bar is drawn on a terminal.
const BAR_SECONDS: f64 = 2.0;

/// Announces on stderr a run of `walks` walks of the measured `cost` if it will be long, and
/// returns a progress bar counting `bar_walks` walks (every walk of the run) when one is worth
/// drawing.
pub fn announce(cost: WalkCost, walks: u64, bar_walks: u64) -> Option<ProgressBar> {
    let seconds = cost.seconds(walks);
    if seconds > LONG_RUN_SECONDS {
        let mut note = format!(
            "note: about {} scattering events per walk: {bar_walks} walks will take about {} on \
             {} threads (fewer --walks make it shorter; so do a smaller alpha and, for Student-T, a \
             larger gamma)",
            show_bounces(cost.mean_bounces),
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
        let bar = ProgressBar::new(bar_walks);
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} walks, eta {eta}") {
            bar.set_style(style);
        }
        bar
    })
}

/// Announces on stderr, when the `seconds` estimated for it exceed [`LONG_RUN_SECONDS`], a run
/// of random walks that a command is about to start: `note: WHAT will take about TIME
/// (SHORTER)`, `what` naming the walks and `shorter` what makes them shorter.
pub fn note_if_long(seconds: f64, what: &str, shorter: &str) {
    if seconds > LONG_RUN_SECONDS {
        eprintln!(
            "note: {what} will take about {} ({shorter})",
            describe_seconds(seconds)
        );
    }
}

/// A mean path length as said in the note: one decimal below 10 (`1.4`), whole numbers above.
fn show_bounces(mean: f64) -> String {
    if mean < 10.0 {
        format!("{mean:.1}")
    } else {
        format!("{mean:.0}")
    }
}
