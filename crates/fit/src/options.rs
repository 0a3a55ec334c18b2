//! How a fit is made: the loss, the optimiser, and the physics of the model (glass index,
//! masking, scattering orders, walks), with their defaults and the rules for which go together.

use serde::{Deserialize, Serialize};
use stfit_core::bsdf::Masking;
use stfit_core::error::{check_eta, show};
use stfit_core::walk::ScatteringOrders;

use crate::conventions::DEFAULT_ETA;
use crate::fit::FitError;

/// Default number of random walks per incident direction of the all-orders model's orders >= 2
/// term, at every model evaluation (fits, `synth`, report curves).
pub const DEFAULT_WALKS: u64 = 20_000;

/// Default floor of the log loss, relative to the largest measured value of a sample.
pub const DEFAULT_LOG_FLOOR: f64 = 1e-3;

/// The loss minimised by a fit, on the measured value `y` (`L` or the BSDF) and the model `m`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Loss {
    /// Least squares on `sqrt(y)` (the published comparison's view).
    #[default]
    Sqrt,
    /// Least squares on `y`.
    Linear,
    /// Least squares on `ln(y + floor)`, `floor` = [`FitOptions::log_floor`] times the
    /// sample's largest measured value: a relative loss for data spanning decades, where the
    /// floor keeps values near zero (noise) from dominating.
    Log,
}

impl Loss {
    /// `sqrt`, `linear` or `log`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Sqrt => "sqrt",
            Self::Linear => "linear",
            Self::Log => "log",
        }
    }
}

/// A model parameter that a fit either holds at a value or fits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Parameter {
    /// Held at this value.
    Fixed(f64),
    /// Fitted.
    Free,
}

impl Parameter {
    /// Whether the parameter is fitted.
    pub fn is_free(self) -> bool {
        self == Self::Free
    }
}

/// The local optimiser of the shape parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Optimizer {
    #[default]
    NelderMead,
    Lbfgs,
}

impl Optimizer {
    /// `nelder-mead` or `lbfgs`.
    pub fn name(self) -> &'static str {
        match self {
            Self::NelderMead => "nelder-mead",
            Self::Lbfgs => "lbfgs",
        }
    }
}

/// How an all-orders fit computes the walk's orders >= 2 term while it searches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MultipleTerm {
    /// A quadratic surrogate in the search coordinates, interpolating the walk estimates at a
    /// few parameter points around the search (recentred until the optimum lies inside them):
    /// a handful of walk sets per fit instead of one per cost evaluation ([`crate::surrogate`]).
    #[default]
    Surrogate,
    /// Fresh walks (the same random numbers) at every cost evaluation: the slow reference.
    Exact,
}

impl MultipleTerm {
    /// `surrogate` or `exact`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Surrogate => "surrogate",
            Self::Exact => "exact",
        }
    }
}

/// Smallest glass index of a fit, held or free (inside the core's supported range,
/// [`stfit_core::error::ETA_MIN`]).
pub const ETA_MIN: f64 = 1.05;
/// Largest glass index of a fit, held or free.
pub const ETA_MAX: f64 = 3.0;

/// Validates the glass index of a fit: in [[`ETA_MIN`], [`ETA_MAX`]].
pub fn check_fit_eta(eta: f64) -> Result<f64, stfit_core::ParamError> {
    if (ETA_MIN..=ETA_MAX).contains(&eta) {
        check_eta(eta)
    } else {
        Err(stfit_core::ParamError::OutOfRange {
            name: "eta",
            value: eta,
            expected: "the glass of a fit has eta in [1.05, 3]",
        })
    }
}

/// Settings shared by every fit in a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Relative index of the glass `n_inside / n_outside`: held (default
    /// [`DEFAULT_ETA`]) or fitted in `[ETA_MIN, ETA_MAX]`.
    pub eta: Parameter,
    /// The per-sample calibration scale: fitted (the default; calibration is rarely absolute)
    /// or held at a value (`1` for absolutely calibrated data).
    pub scale: Parameter,
    pub loss: Loss,
    /// The floor of [`Loss::Log`], relative to the sample's largest measured value (default
    /// [`DEFAULT_LOG_FLOOR`]).
    pub log_floor: f64,
    pub optimizer: Optimizer,
    /// Smith masking: any for single scattering, correlated for all orders
    /// ([`ScatteringOrders::check_masking`]).
    pub masking: Masking,
    /// `single` or `all` (a fit of orders >= 2 alone would fit no measurement).
    pub orders: ScatteringOrders,
    /// Walks per incident direction of the orders >= 2 term (orders all).
    pub walks: u64,
    /// Seed of those walks (orders all).
    pub seed: u64,
    /// How the orders >= 2 term is computed during the search (orders all).
    pub multiple_term: MultipleTerm,
}

impl Default for FitOptions {
    /// Single scattering with separable masking, least squares on `sqrt(L)`, Nelder-Mead, eta
    /// held at 1.51 ([`DEFAULT_ETA`]), the scale fitted; [`DEFAULT_WALKS`] walks from seed 1
    /// for orders all, with the surrogate orders >= 2 term.
    fn default() -> Self {
        Self {
            eta: Parameter::Fixed(DEFAULT_ETA),
            scale: Parameter::Free,
            loss: Loss::Sqrt,
            log_floor: DEFAULT_LOG_FLOOR,
            optimizer: Optimizer::NelderMead,
            masking: Masking::Separable,
            orders: ScatteringOrders::Single,
            walks: DEFAULT_WALKS,
            seed: 1,
            multiple_term: MultipleTerm::Surrogate,
        }
    }
}

impl FitOptions {
    /// The defaults with `orders` and their default masking
    /// ([`ScatteringOrders::default_masking`]).
    pub fn with_orders(orders: ScatteringOrders) -> Self {
        Self {
            orders,
            masking: orders.default_masking(),
            ..Self::default()
        }
    }

    /// Checks the options: a valid eta (fixed) or its search range, a finite scale > 0 if
    /// fixed, a log floor > 0, orders single or all with a masking they allow, and at least one
    /// walk for orders all.
    pub fn check(&self) -> Result<(), FitError> {
        if let Parameter::Fixed(eta) = self.eta {
            check_fit_eta(eta)?;
        }
        if let Parameter::Fixed(scale) = self.scale {
            check_fit_scale(scale)?;
        }
        check_log_floor(self.log_floor)?;
        check_orders(self.orders, self.masking)?;
        if self.orders == ScatteringOrders::All {
            check_fit_walks(self.walks)?;
        }
        Ok(())
    }
}

/// Validates a held calibration scale: a finite, normal double > 0 (at least
/// `f64::MIN_POSITIVE`, 2.2e-308). Below that a double has fewer than 16 significant digits,
/// so the scale would not come back as given.
pub fn check_fit_scale(scale: f64) -> Result<f64, FitError> {
    if scale.is_finite() && scale >= f64::MIN_POSITIVE {
        Ok(scale)
    } else {
        Err(FitError::InvalidOption(format!(
            "a held scale must be a finite number of at least 2.2e-308 (a normal double > 0), \
             got {}",
            show(scale)
        )))
    }
}

/// The supported range of the log loss's floor, relative to the sample's largest value.
pub const LOG_FLOOR_RANGE: (f64, f64) = (1e-12, 1.0);

/// Validates the log loss's floor relative to the sample's largest value: in
/// [`LOG_FLOOR_RANGE`], so that the absolute floor is a positive number for any data stfit
/// reads, and the loss still compares logarithms (a floor above the largest value would make
/// it nearly linear).
pub fn check_log_floor(floor: f64) -> Result<f64, FitError> {
    let (lo, hi) = LOG_FLOOR_RANGE;
    if (lo..=hi).contains(&floor) {
        Ok(floor)
    } else {
        Err(FitError::InvalidOption(format!(
            "the log floor must be in [1e-12, 1] (a fraction of the sample's largest value), \
             got {}",
            show(floor)
        )))
    }
}

/// Validates the walks per incident direction of an all-orders fit: in `[2, MAX_WALKS]`
/// ([`stfit_core::walk::MAX_WALKS`]). The fit's standard errors include the walk term's Monte
/// Carlo error, which the walks' own scatter estimates: one walk has none to show.
pub fn check_fit_walks(walks: u64) -> Result<u64, FitError> {
    if walks > stfit_core::walk::MAX_WALKS {
        return Err(FitError::InvalidOption(format!(
            "walks must be in [2, 1e9] for an all-orders fit, got {walks}"
        )));
    }
    if walks < 2 {
        return Err(FitError::InvalidOption(
            "an all-orders fit needs at least 2 walks per incident direction: its standard \
             errors include the walk term's, which one walk cannot estimate"
                .into(),
        ));
    }
    Ok(walks)
}

/// The orders a model of measurements can have, single or all, with a masking they allow.
pub fn check_orders(orders: ScatteringOrders, masking: Masking) -> Result<(), FitError> {
    if orders == ScatteringOrders::Multiple {
        return Err(FitError::InvalidOption(
            "orders multiple (>= 2 only) model no measurement: fit and simulate with single or \
             all"
            .into(),
        ));
    }
    orders
        .check_masking(masking)
        .map_err(|e| FitError::InvalidOption(e.to_string()))?;
    Ok(())
}
