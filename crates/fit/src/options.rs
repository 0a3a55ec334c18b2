//! How a fit is made: the loss, the optimiser, and the physics of the model (glass index,
//! masking, scattering orders, walks), with their defaults and the rules for which go together.

use serde::{Deserialize, Serialize};
use stfit_core::bsdf::Masking;
use stfit_core::error::check_eta;
use stfit_core::walk::ScatteringOrders;

use crate::conventions::DEFAULT_ETA;
use crate::fit::FitError;

/// Default number of random walks per incident direction of the all-orders model's orders >= 2
/// term, at every model evaluation (fits, `synth`, report curves).
pub const DEFAULT_WALKS: u64 = 20_000;

/// The loss minimised by a fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Loss {
    /// Least squares on `sqrt(L)` (the published comparison's view).
    #[default]
    Sqrt,
    /// Least squares on `L`.
    Linear,
}

impl Loss {
    /// `sqrt` or `linear`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Sqrt => "sqrt",
            Self::Linear => "linear",
        }
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

/// Settings shared by every fit in a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Relative index of the glass (default [`DEFAULT_ETA`]).
    pub eta: f64,
    pub loss: Loss,
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
}

impl Default for FitOptions {
    /// Single scattering with separable masking, least squares on `sqrt(L)`, Nelder-Mead, eta
    /// 1.51 ([`DEFAULT_ETA`]); [`DEFAULT_WALKS`] walks from seed 1 for orders all.
    fn default() -> Self {
        Self {
            eta: DEFAULT_ETA,
            loss: Loss::Sqrt,
            optimizer: Optimizer::NelderMead,
            masking: Masking::Separable,
            orders: ScatteringOrders::Single,
            walks: DEFAULT_WALKS,
            seed: 1,
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

    /// Checks the options: a valid eta, orders single or all with a masking they allow, and at
    /// least one walk for orders all.
    pub fn check(&self) -> Result<(), FitError> {
        check_eta(self.eta)?;
        check_orders(self.orders, self.masking)?;
        if self.orders == ScatteringOrders::All && self.walks == 0 {
            return Err(FitError::InvalidSpec(
                "orders all need at least one random walk per incident direction".into(),
            ));
        }
        Ok(())
    }
}

/// The orders a model of measurements can have, single or all, with a masking they allow.
pub fn check_orders(orders: ScatteringOrders, masking: Masking) -> Result<(), FitError> {
    if orders == ScatteringOrders::Multiple {
        return Err(FitError::InvalidSpec(
            "orders multiple (>= 2 only) model no measurement: fit and simulate with single or \
             all"
            .into(),
        ));
    }
    orders
        .check_masking(masking)
        .map_err(|e| FitError::InvalidSpec(e.to_string()))?;
    Ok(())
}
