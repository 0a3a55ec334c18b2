//! Long random-walk runs announced to Python users before they start, as the command line
//! announces them on stderr: a `stfit.LongRunWarning` (a `UserWarning`) for a run estimated at
//! over ten seconds, with the command line's words ([`long_run_note`]). Python's warning
//! filters show it once per call site, silence it (`"ignore"`) or turn it into an error
//! (`"error"`, which stops the call before its walks start).

use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use stfit_core::walk::{WalkCost, long_run_note};

pyo3::create_exception!(
    stfit,
    LongRunWarning,
    PyUserWarning,
    "A run of random walks estimated to take over ten seconds is about to start (the note the \
     command line prints on stderr): it says what will run, about how long it will take and what \
     makes it shorter. With `warnings.simplefilter('error', stfit.LongRunWarning)` the call \
     raises it instead, before its walks start."
);

/// What makes the runs of a Python call shorter.
pub const FEWER_WALKS: &str = "fewer walks make it shorter";

/// Warns with `note`, if any, as a `stfit.LongRunWarning`.
fn warn(py: Python<'_>, note: Option<String>) -> PyResult<()> {
    if let Some(note) = note {
        let category = py.get_type::<LongRunWarning>();
        py.import("warnings")?
            .call_method1("warn", (note, category))?;
    }
    Ok(())
}

/// Warns before a run of random walks estimated at `seconds` if it exceeds ten seconds:
/// `WHAT will take about TIME (SHORTER)`.
pub fn warn_if_long(py: Python<'_>, seconds: f64, what: &str, shorter: &str) -> PyResult<()> {
    warn(py, long_run_note(seconds, what, shorter))
}

/// Warns before a run of `walks` walks of the measured `cost` (`all_walks` in all) if it will
/// take over ten seconds.
pub fn warn_if_costly(py: Python<'_>, cost: WalkCost, walks: u64, all_walks: u64) -> PyResult<()> {
    warn(py, cost.long_run_note(walks, all_walks, FEWER_WALKS))
}
