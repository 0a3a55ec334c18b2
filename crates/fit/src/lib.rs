//! stfit-fit: loading and validating rough-glass transmission measurements, and fitting
//! microfacet models (Beckmann, GGX, Student-T) to them.
//!
//! Measurement convention (theory section 8, `data-format.md`): light arrives from air at
//! `theta_i` and `theta_o` is the transmitted direction inside the glass, 180 degrees straight
//! through; the measured quantity is `L = scale * f_t(wi, wo) * cos(theta_i) / eta^2`.
//!
//! Fitting: [`fit::fit_sample`] fits one model, [`fit::fit_all`] the four models of
//! `--model all`; [`fit::predict`] and [`ModelParams::l_single_batch`] evaluate a model for
//! plots. [`objective`] holds the per-sample precomputation and the scale-projected loss.

pub mod data;
pub mod fit;
pub mod load;
pub mod model;
pub mod objective;
pub mod optimize;
pub mod synth;

pub use data::{Dataset, Measurement, Sample};
pub use fit::{FitError, fit_all, fit_sample};
pub use load::{LoadError, LoadErrorKind, load_path};
pub use model::{
    FitOptions, FitResult, Loss, ModelKind, ModelParams, ModelSpec, Optimizer, Scattering,
};
pub use synth::{SynthError, SynthSpec};
