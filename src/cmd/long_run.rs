//! Long random-walk runs made visible: a pilot run estimates the cost before the walks start
//! (`stfit_core::walk::WalkCost`), a note on stderr announces a run longer than
//! `LONG_RUN_SECONDS` ([`announce`], or [`note_if_long`] for a command that states its walks
//! in its own words), and a progress bar is drawn when stderr is a terminal.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use stfit_core::walk::{WalkCost, long_run_note};

/// Estimated time, in seconds, above which a progress bar is drawn on a terminal.
const BAR_SECONDS: f64 = 2.0;

/// Announces on stderr a run of `walks` walks of the measured `cost` if it will be long
/// ([`WalkCost::long_run_note`]), and returns a progress bar counting `bar_walks` walks (every
/// walk of the run) when one is worth drawing.
pub fn announce(cost: WalkCost, walks: u64, bar_walks: u64) -> Option<ProgressBar> {
    if let Some(note) = cost.long_run_note(walks, bar_walks, "fewer --walks make it shorter") {
        eprintln!("note: {note}");
    }
    let seconds = cost.seconds(walks);
    (seconds > BAR_SECONDS && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(bar_walks);
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} walks, eta {eta}") {
            bar.set_style(style);
        }
        bar
    })
}

/// Announces on stderr, when the `seconds` estimated for it exceed
/// [`LONG_RUN_SECONDS`](stfit_core::walk::LONG_RUN_SECONDS), a run
/// of random walks that a command is about to start: `note: WHAT will take about TIME
/// (SHORTER)` ([`long_run_note`]), `what` naming the walks and `shorter` what makes them
/// shorter.
pub fn note_if_long(seconds: f64, what: &str, shorter: &str) {
    if let Some(note) = long_run_note(seconds, what, shorter) {
        eprintln!("note: {note}");
    }
}
