//! stfit-fit: loading and validating rough-glass transmission measurements, and fitting
//! microfacet models (Beckmann, GGX, Student-T) to them.
//!
//! Measurement convention (theory section 8, `data-format.md`): light arrives from air at
//! `theta_i` and `theta_o` is the transmitted direction inside the glass, 180 degrees straight
//! through; the measured quantity is `L = scale * f_t(wi, wo) * cos(theta_i) / eta^2`.

pub mod data;
pub mod load;
pub mod model;
pub mod synth;

pub use data::{Dataset, Measurement, Sample};
pub use load::{LoadError, LoadErrorKind, load_path};
pub use model::{
    FitOptions, FitResult, Loss, ModelKind, ModelParams, ModelSpec, Optimizer, Scattering,
};
pub use synth::{SynthError, SynthSpec};
