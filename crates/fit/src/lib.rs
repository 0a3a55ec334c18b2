//! stfit-fit: loading and validating rough-glass measurements, the forward model, the
//! objective and the optimisers that fit microfacet models (Beckmann, GGX, Student-T) to them,
//! the stored-fits file, and synthetic measurements of known truth.
//!
//! Measurement convention ([`conventions`], theory section 8, `data-format.md`): light arrives
//! from air at `theta_i` and `theta_o` is the transmitted direction inside the glass, 180
//! degrees straight through; the measured quantity is
//! `L = scale * f_t(wi, wo) * cos(theta_i) / eta^2`.
//!
//! - [`load_path`] reads a measurement file into a [`Dataset`];
//! - [`fit_dataset`] (or [`fit_sample`]) fits [`ModelSpec`]s with [`FitOptions`] and returns
//!   [`FitResult`]s, each of which carries its [`Model`];
//! - [`Model::predict`] evaluates a model, for plots and checks;
//! - [`FitsFile`] stores fits (`fits-format.md`); [`synth`] simulates measurements.
//!
//! ```no_run
//! use stfit_fit::{FitOptions, all_models, fit_dataset, load_path};
//!
//! let data = load_path("fits/example.csv".as_ref())?;
//! let fits = fit_dataset(&data, &all_models(), &FitOptions::default(), &|_, _| {})?;
//! for fit in &fits {
//!     println!("{}: alpha {:.4}, rmse {:.4}", fit.label(), fit.model.alpha, fit.rmse_sqrt_l);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod conventions;
pub mod data;
pub mod files;
pub mod fit;
pub mod forward;
pub mod load;
mod loss;
pub mod model;
pub mod optimize;
pub mod options;
pub mod pabopto;
pub mod pairs;
pub mod result;
pub mod surrogate;
pub mod synth;

pub use conventions::{DEFAULT_ETA, reduced_azimuth_deg};
pub use data::{Angles, Dataset, Measured, Measurement, Quantity, Sample, short};
pub use fit::{
    DatasetFitError, FitError, FitWalkCost, fit_all, fit_dataset, fit_sample, fit_walk_cost,
};
pub use load::{Column, LoadError, LoadErrorKind, load_columns, load_path, load_paths};
pub use model::{Gamma, Model, ModelKind, ModelSpec, all_models};
pub use options::{
    DEFAULT_LOG_FLOOR, DEFAULT_WALKS, FitOptions, Loss, MultipleTerm, Optimizer, Parameter,
};
pub use result::{FITS_VERSION, FitResult, FitWarning, FitsFile, FitsFileError};
pub use stfit_core::ScatteringOrders;
pub use stfit_core::bsdf::Masking;
pub use synth::{Grid, SynthError, SynthSpec};
