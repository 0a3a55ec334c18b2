//! Fitting a microfacet model to one sample: variable projection of the scale, multi-start
//! local minimisation over the shape (with eta free, also from every piece between the jumps
//! of the cost in eta: `hop_eta`), and heteroscedasticity-robust standard errors (sandwich)
//! at the optimum.
//!
//! The model is [`Model`]'s ([`crate::forward`] evaluates it). With orders `single` it is
//! Walter et al.'s analytic single-scattering BTDF with the masking of `FitOptions::masking`.
//! With orders `all` it is `f = f_single + f_multi`: `f_single` the analytic single-scattering
//! BTDF with height-correlated masking (exactly the random walk's order 1 term) and `f_multi`
//! the orders >= 2 estimate of `FitOptions::walks` random walks per incident direction, with a
//! fixed seed per direction for every evaluation (common random numbers), so the objective is
//! a deterministic function of the parameters. That estimator is not smooth: as the
//! parameters change, rare heavy-tailed walk events switch on and off, so the objective has
//! small jumps that a local search can settle in. By default
//! ([`MultipleTerm::Surrogate`], [`crate::surrogate`]) the search does not call the walks at every
//! evaluation: it interpolates the walk term quadratically between a few parameter points around
//! the start (the optimum of the same model's single-scattering fit), rebuilt around the
//! optimum until the optimum lies inside them (typically one or two surrogates: 4 to 14 sets of
//! walks per fit, against a few hundred). The fit is reported with the walk term at the
//! optimum (scale, rmse), and its standard errors add the Monte Carlo error of that term,
//! propagated to first order from the independent chunks of walks, to the sandwich below.
//! [`MultipleTerm::Exact`] evaluates fresh walks at every evaluation (Nelder-Mead suits it;
//! L-BFGS's finite-difference gradients see the jumps) and its standard errors do not include
//! the Monte Carlo error.
//!
//! Search coordinates: `x0 = ln(alpha)` and, for Student-T with free gamma,
//! `x1 = ln(gamma - 3/2)`, so every point of the search space is a valid model. They are
//! clamped to `alpha in [ALPHA_MIN, ALPHA_MAX]` and `gamma - 3/2 in [GAMMA_EXCESS_MIN,
//! GAMMA_EXCESS_MAX]` (a fit that ends on such a bound says the data want a model outside the
//! family, e.g. Beckmann-like tails for Student-T).
//!
//! Standard errors (natural units of alpha, gamma, scale): with the residuals of the chosen loss
//! `r_j = sqrt(w_j) (y_j - T(scale * m_j(alpha, gamma)))` (`T = sqrt` or identity) and their
//! Jacobian `J` in `theta = (alpha, [gamma], [eta], scale)` (central finite differences in
//! alpha, gamma and eta, analytic in scale), with `J_j` its row of point `j`, the covariance is
//! the heteroscedasticity-robust sandwich (White 1980) in MacKinnon and White's 1985 HC3 form,
//! each squared residual divided by `(1 - h_j)^2`, `h_j = J_j (J^T J)^{-1} J_j^T` the leverage
//! of point `j`:
//!
//! ```text
//! Cov(theta) = (J^T J)^{-1} (sum_j r_j^2 / (1 - h_j)^2 J_j^T J_j) (J^T J)^{-1}.
//! ```
//!
//! Unlike the classical `sigma^2 (J^T J)^{-1}` (`sigma^2 = RSS / (n - p)`), which assumes every
//! residual has the same variance, it stays calibrated when the noise varies from point to point
//! (multiplicative noise on `L` seen through the sqrt loss) and when the model misses some of
//! the data systematically (a stray-light floor no model reproduces); for equal noise and small
//! leverages it agrees with the classical form up to sampling error. `r_j / (1 - h_j)` is, to
//! first order, point `j`'s residual from the fit without it: a point that pulls the fit toward
//! itself has a residual smaller than its noise (on average `(1 - h_j)` times its variance), and
//! a narrow lobe puts much of the information on alpha and the scale into its few peak points
//! (largest leverages 0.25 to 0.8 on the Walter grid for alpha 0.05 to 0.2). There the plain
//! sandwich, even with the HC1 factor `n/(n-p)`, is too small. Measured on synthetic data of
//! known truth (23 configurations of the three models, both grids, the three losses, eta held
//! and free, 5% multiplicative noise or equal noise on `sqrt(L)`, 200 seeds each): where the
//! largest leverage was 0.25 or more, the standard deviation of `(fitted - true) / stderr` of
//! alpha, gamma and the scale was 1.0 to 2.6 (median 1.27) with HC1, 0.96 to 1.84 (1.14) with
//! HC2's `1 - h_j`, and 0.85 to 1.27 (1.06) with HC3; below 0.25, 0.97 to 1.31 (1.06) with HC1
//! and 0.93 to 1.23 (1.01) with HC3. The seed-to-seed spread of the fits was within about 15%
//! of the linearised covariance with the true noise: what HC3 leaves above 1 is the sampling
//! error of the estimate itself, which one high-leverage residual dominates.

use std::path::PathBuf;

use rayon::prelude::*;
use stfit_core::ParamError;
use stfit_core::Vec3;
use stfit_core::bsdf::Masking;
use stfit_core::error::{check_gamma, show};
use stfit_core::walk::ScatteringOrders;
use thiserror::Error;

use crate::data::{Dataset, Measured, Sample, short};
use crate::forward::{Forward, WalkTerm};
use crate::loss::{Projected, Projection, signed_sqrt};
use crate::model::{Gamma, Model, ModelKind, ModelSpec, all_models};
use crate::optimize::minimize;
use crate::options::{ETA_MAX, ETA_MIN, FitOptions, Loss, MultipleTerm, Parameter};
use crate::result::{FitResult, FitWarning};
use crate::surrogate::Surrogate;

/// Smallest roughness the search reaches.
pub const ALPHA_MIN: f64 = 1e-3;
/// Largest roughness the search reaches.
pub const ALPHA_MAX: f64 = 20.0;
/// Smallest `gamma - 3/2` the search reaches.
pub const GAMMA_EXCESS_MIN: f64 = 1e-3;
/// Largest `gamma - 3/2` the search reaches (Student-T is then within a fraction of a percent
/// of Beckmann).
pub const GAMMA_EXCESS_MAX: f64 = 500.0;

/// Roughness values of the starting grid.
const ALPHA_GRID: [f64; 8] = [0.02, 0.04, 0.07, 0.12, 0.2, 0.35, 0.6, 1.0];
/// Shape values of the starting grid (free-gamma Student-T).
const GAMMA_GRID: [f64; 5] = [1.7, 2.2, 3.2, 6.0, 20.0];
/// Glass indices of the starting grid (free eta).
const ETA_GRID: [f64; 4] = [1.3, 1.45, 1.6, 1.8];
/// Local optimisations are started from at most this many grid local minima.
const MAX_STARTS: usize = 3;
/// Most rounds of [`hop_eta`]'s scan of the pieces of the eta axis.
const ETA_HOP_ROUNDS: usize = 4;
/// Most pieces [`hop_eta`] scans one by one: a sample whose transmitted points cut the eta
/// axis into more is scanned at this many even steps of `ln(eta - 1)` instead, so that a scan
/// costs about as much as one local search.
const ETA_PIECES_MAX: usize = 128;
/// Step of the orders >= 2 surrogate's design in `ln alpha` ([`crate::surrogate`]).
const SURROGATE_STEP_ALPHA: f64 = 0.12;
/// Step in `ln(gamma - 3/2)`.
const SURROGATE_STEP_GAMMA: f64 = 0.2;
/// Step in `ln(eta - 1)`.
const SURROGATE_STEP_ETA: f64 = 0.06;
/// Most surrogates built in one fit: after the last, its optimum is taken wherever it lies.
const SURROGATE_ROUNDS: usize = 5;

/// `n` and `noun`, in the plural unless `n` is 1: "1 parameter", "2 parameters".
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// Why a fit could not be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FitError {
    /// Fewer usable points (finite, positive weight) than the fit needs.
    #[error(
        "sample `{}`: {}, a fit with {} needs at least {needed}",
        short(sample),
        counted(*n, "usable point"),
        counted(*params, "parameter")
    )]
    TooFewPoints {
        sample: String,
        n: usize,
        params: usize,
        needed: usize,
    },
    /// Every usable measured value is zero: nothing to fit.
    #[error("sample `{}`: every measured value is zero", short(sample))]
    AllZero { sample: String },
    /// A measurement outside the model's domain.
    #[error("sample `{}`, point {} (counting from 1): {reason}", short(sample), index + 1)]
    InvalidData {
        sample: String,
        /// The point's index in the sample, from 0.
        index: usize,
        reason: String,
    },
    /// An invalid model parameter or option (gamma <= 3/2, eta <= 0, non-finite values).
    #[error("invalid parameter: {0}")]
    InvalidParameter(#[from] ParamError),
    /// A model specification that makes no sense (e.g. a fixed gamma for GGX).
    #[error("invalid model: {0}")]
    InvalidSpec(String),
    /// A fit option outside its documented range or at odds with another (a held scale that is
    /// not a normal double, a log floor outside [1e-12, 1], one walk, orders multiple); front
    /// ends put the option's name before the message.
    #[error("{0}")]
    InvalidOption(String),
    /// The model is zero at every point whatever its parameters.
    #[error(
        "sample `{}`: no microfacet connects any measured pair of directions",
        short(sample)
    )]
    NoSignal { sample: String },
    /// The cost was not finite at any point the optimiser evaluated, from every start.
    #[error(
        "sample `{}`, model {model}: the model is not finite at any of the {evaluations} \
         points the optimizer tried; {}",
        short(sample),
        match held_scale {
            Some(s) => format!(
                "the held scale {} may make the model overflow, or the measured directions \
                 lie where the model overflows (near-specular pairs with a tiny roughness)",
                show(*s)
            ),
            None => "the measured directions may lie where the model overflows \
                     (near-specular pairs with a tiny roughness)"
                .to_owned(),
        }
    )]
    NoFiniteCost {
        sample: String,
        model: &'static str,
        evaluations: u64,
        /// The scale, when it was held rather than fitted.
        held_scale: Option<f64>,
    },
    /// A model value that overflows or underflows f64.
    #[error("{0}")]
    NotRepresentable(String),
    /// The calibration scale cannot be fitted or held as asked.
    #[error("sample `{}`: {reason}", short(sample))]
    Scale { sample: String, reason: String },
}

/// A fit of one sample of a dataset that failed, with where.
/// Its message names the file, the sample and the model once each.
#[derive(Debug, Clone, PartialEq, Error)]
pub struct DatasetFitError {
    /// The data file.
    pub file: PathBuf,
    pub sample: String,
    /// The model, as [`ModelSpec::label`] names it.
    pub model: String,
    pub error: Box<FitError>,
}

impl FitError {
    /// Whether the message already names the sample (and which parts of the context a wrapper
    /// should add): `(sample, model)`.
    fn names(&self) -> (bool, bool) {
        match self {
            Self::NoFiniteCost { .. } => (true, true),
            Self::TooFewPoints { .. }
            | Self::AllZero { .. }
            | Self::InvalidData { .. }
            | Self::NoSignal { .. }
            | Self::Scale { .. } => (true, false),
            Self::InvalidParameter(_)
            | Self::InvalidSpec(_)
            | Self::InvalidOption(_)
            | Self::NotRepresentable(_) => (false, false),
        }
    }
}

impl std::fmt::Display for DatasetFitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let file = short(&self.file.display().to_string());
        match self.error.names() {
            (true, true) => write!(f, "{file}: {}", self.error),
            (true, false) => write!(f, "{file}: model {}, {}", self.model, self.error),
            _ => write!(
                f,
                "{file}: sample '{}', model {}: {}",
                short(&self.sample),
                self.model,
                self.error
            ),
        }
    }
}

/// A sample checked and precomputed once, fitted by several models.
#[derive(Clone)]
struct Prepared<'a> {
    sample: &'a Sample,
    forward: Forward,
    /// Measured values of the usable points, divided by [`Prepared::unit`]: the fit works in
    /// these units, so that data of any magnitude (1e-200 or 1e300) give the same fit, up to
    /// the unit, and the same relative standard errors.
    v: Vec<f64>,
    w: Vec<f64>,
    /// The largest magnitude of the usable values (1 when they are all zero).
    unit: f64,
    /// Distinct direction pairs among the usable points whose value is not zero: the points
    /// that carry information on the shape (copies of one measurement add none).
    informative: usize,
    /// What the usable points measure.
    measured: Measured,
}

impl<'a> Prepared<'a> {
    fn new(sample: &'a Sample, opts: &FitOptions) -> Result<Self, FitError> {
        opts.check()?;
        let invalid = |index: usize, reason: String| FitError::InvalidData {
            sample: sample.name.clone(),
            index,
            reason,
        };
        let mut pairs = Vec::with_capacity(sample.points.len());
        let mut quantity = Vec::with_capacity(sample.points.len());
        let (mut v, mut w) = (Vec::new(), Vec::new());
        for (index, p) in sample.points.iter().enumerate() {
            if !(p.weight.is_finite() && p.weight >= 0.0) {
                return Err(invalid(
                    index,
                    format!("weight must be finite and >= 0, got {}", show(p.weight)),
                ));
            }
            if p.weight == 0.0 {
                continue;
            }
            if !p.value.is_finite() {
                return Err(invalid(
                    index,
                    format!(
                        "{} must be finite, got {}",
                        p.quantity().name(),
                        show(p.value)
                    ),
                ));
            }
            p.check_angles().map_err(|reason| invalid(index, reason))?;
            pairs.push(p.directions());
            quantity.push(p.quantity());
            v.push(p.value);
            w.push(p.weight);
        }
        let measured = Measured::of(quantity.iter().copied());
        let unit = v.iter().fold(0.0f64, |m, &v: &f64| m.max(v.abs()));
        if unit > 0.0 && unit < f64::MIN_POSITIVE {
            // Subnormal values carry fewer than 16 digits, and a scale fitted to them could
            // not be applied to a model without underflow.
            return Err(FitError::Scale {
                sample: sample.name.clone(),
                reason: format!(
                    "the largest value is {}, below the normal range of doubles (2.2e-308): \
                     too few digits to fit; multiply the values by a power of 10",
                    show(unit)
                ),
            });
        }
        let unit = if unit > 0.0 { unit } else { 1.0 };
        v.iter_mut().for_each(|v| *v /= unit);
        let informative = distinct_pairs(
            pairs
                .iter()
                .zip(&v)
                .filter(|&(_, &v)| v != 0.0)
                .map(|(pair, _)| *pair),
        );
        let forward = Forward::new(
            &pairs,
            quantity,
            opts.masking,
            opts.orders,
            opts.walks,
            opts.seed,
        )?;
        Ok(Self {
            sample,
            forward,
            v,
            w,
            unit,
            informative,
            measured,
        })
    }
}

/// A point of the shape search: roughness, shape and glass index.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Point {
    alpha: f64,
    gamma: Gamma,
    eta: f64,
}

/// The parameters searched for one model specification.
#[derive(Debug, Clone, Copy)]
struct Shape {
    kind: ModelKind,
    gamma: Gamma<()>,
    eta: Parameter,
}

impl Shape {
    fn new(spec: ModelSpec, opts: &FitOptions) -> Result<Self, FitError> {
        if let Gamma::Fixed(g) = spec.gamma() {
            if opts.orders == ScatteringOrders::All {
                stfit_core::error::check_walk_gamma(g)?;
            } else {
                check_gamma(g)?;
            }
        }
        Ok(Self {
            kind: spec.kind(),
            gamma: spec.gamma(),
            eta: opts.eta,
        })
    }

    /// Number of searched coordinates.
    fn dims(&self) -> usize {
        1 + usize::from(self.gamma.is_free()) + usize::from(self.eta.is_free())
    }

    /// The point of search coordinates `x`, clamped to the search box.
    fn point(&self, x: &[f64]) -> Point {
        let mut k = 0;
        let mut next = |lo: f64, hi: f64| {
            let v = x[k].clamp(lo.ln(), hi.ln()).exp();
            k += 1;
            v
        };
        let alpha = next(ALPHA_MIN, ALPHA_MAX);
        let gamma = match self.gamma {
            Gamma::NotApplicable => Gamma::NotApplicable,
            Gamma::Fixed(g) => Gamma::Fixed(g),
            Gamma::Free(()) => Gamma::Free(1.5 + next(GAMMA_EXCESS_MIN, GAMMA_EXCESS_MAX)),
        };
        let eta = match self.eta {
            Parameter::Fixed(e) => e,
            Parameter::Free => 1.0 + next(ETA_MIN - 1.0, ETA_MAX - 1.0),
        };
        Point { alpha, gamma, eta }
    }

    /// The search box, per searched coordinate.
    fn bounds(&self) -> Vec<(f64, f64)> {
        let mut b = vec![(ALPHA_MIN.ln(), ALPHA_MAX.ln())];
        if self.gamma.is_free() {
            b.push((GAMMA_EXCESS_MIN.ln(), GAMMA_EXCESS_MAX.ln()));
        }
        if self.eta.is_free() {
            b.push(((ETA_MIN - 1.0).ln(), (ETA_MAX - 1.0).ln()));
        }
        b
    }

    /// The steps of the orders >= 2 surrogate's design, per searched coordinate
    /// ([`SURROGATE_STEP_ALPHA`] and the others).
    fn surrogate_steps(&self) -> Vec<f64> {
        let mut h = vec![SURROGATE_STEP_ALPHA];
        if self.gamma.is_free() {
            h.push(SURROGATE_STEP_GAMMA);
        }
        if self.eta.is_free() {
            h.push(SURROGATE_STEP_ETA);
        }
        h
    }

    /// The search bounds that the point of search coordinates `x` lies on (or beyond, where
    /// [`Shape::point`] clamps it), as `(parameter, bound)`.
    fn bounds_reached(&self, x: &[f64]) -> Vec<(&'static str, f64)> {
        let mut axes = vec![("alpha", ALPHA_MIN, ALPHA_MAX, 0.0)];
        if self.gamma.is_free() {
            axes.push(("gamma", GAMMA_EXCESS_MIN, GAMMA_EXCESS_MAX, 1.5));
        }
        if self.eta.is_free() {
            axes.push(("eta", ETA_MIN - 1.0, ETA_MAX - 1.0, 1.0));
        }
        let mut out = Vec::new();
        for ((name, lo, hi, offset), &xk) in axes.into_iter().zip(x) {
            // Relative 1e-6 of the parameter (offset excluded): closer is on the bound.
            const TOL: f64 = 1e-6;
            if xk <= lo.ln() + TOL {
                out.push((name, offset + lo));
            } else if xk >= hi.ln() - TOL {
                out.push((name, offset + hi));
            }
        }
        out
    }

    /// The search coordinates of a point.
    fn coords(&self, p: Point) -> Vec<f64> {
        let mut x = vec![p.alpha.ln()];
        if let Gamma::Free(g) = p.gamma {
            x.push((g - 1.5).ln());
        }
        if self.eta.is_free() {
            x.push((p.eta - 1.0).ln());
        }
        x
    }

    /// The starting grid: every combination of the grids of the searched parameters, as a
    /// list of points and the grid's extent per searched axis.
    fn grid(&self) -> (Vec<Point>, Vec<usize>) {
        let gammas: Vec<Gamma> = match self.gamma {
            Gamma::NotApplicable => vec![Gamma::NotApplicable],
            Gamma::Fixed(g) => vec![Gamma::Fixed(g)],
            Gamma::Free(()) => GAMMA_GRID.iter().map(|&g| Gamma::Free(g)).collect(),
        };
        let etas: Vec<f64> = match self.eta {
            Parameter::Fixed(e) => vec![e],
            Parameter::Free => ETA_GRID.to_vec(),
        };
        let mut points = Vec::new();
        for &eta in &etas {
            for &gamma in &gammas {
                for &alpha in &ALPHA_GRID {
                    points.push(Point { alpha, gamma, eta });
                }
            }
        }
        let mut extent = vec![ALPHA_GRID.len()];
        if self.gamma.is_free() {
            extent.push(gammas.len());
        }
        if self.eta.is_free() {
            extent.push(etas.len());
        }
        (points, extent)
    }

    /// The model at `p` and `scale` with the physics of `opts`.
    fn model(&self, p: Point, scale: f64, opts: &FitOptions) -> Model {
        let walks = opts.orders == ScatteringOrders::All;
        Model {
            kind: self.kind,
            alpha: p.alpha,
            gamma: p.gamma,
            scale,
            eta: p.eta,
            masking: opts.masking,
            orders: opts.orders,
            walks: walks.then_some(opts.walks),
            seed: walks.then_some(opts.seed),
        }
    }
}

/// Evaluates the reduced (scale-projected) cost of a sample.
struct Evaluator<'p, 'a> {
    prep: &'p Prepared<'a>,
    proj: Projected,
    shape: Shape,
    opts: FitOptions,
    /// The surrogate orders >= 2 term added to `prep`'s (single-scattering) model.
    multi: Option<&'p Surrogate>,
}

impl Evaluator<'_, '_> {
    /// Unit-scale model values at `p`.
    fn unit_model(&self, p: Point, m: &mut Vec<f64>) -> Result<(), FitError> {
        let ndf = self.shape.model(p, 1.0, &self.opts).ndf()?;
        self.prep.forward.unit_model(&ndf, p.eta, m)?;
        if let Some(s) = self.multi {
            s.add_to(&self.shape.coords(p), m);
        }
        Ok(())
    }

    /// Reduced cost and best scale at `p`.
    fn project(&self, p: Point) -> Result<Projection, FitError> {
        let mut m = Vec::with_capacity(self.prep.forward.len());
        self.unit_model(p, &mut m)?;
        Ok(self.proj.project(&m))
    }

    /// Reduced cost at search coordinates `x` (`+inf` if the model is invalid there; the
    /// clamped box makes that unreachable).
    fn cost(&self, x: &[f64]) -> f64 {
        self.project(self.shape.point(x))
            .map_or(f64::INFINITY, |p| p.cost)
    }

    /// Starting points: the grid points whose cost is below that of all their grid
    /// neighbours, best first, at most [`MAX_STARTS`].
    fn starts(&self) -> Vec<Vec<f64>> {
        let (points, extent) = self.shape.grid();
        // Each cost is independent: evaluated in parallel, the grid lets a fit of many grid
        // points (free gamma) share the cores with the other fits.
        let costs: Vec<f64> = points
            .par_iter()
            .map(|&p| self.cost(&self.shape.coords(p)))
            .collect();
        // Index of the grid point at multi-index `ix` (axis 0 fastest).
        let flat = |ix: &[usize]| {
            ix.iter()
                .zip(&extent)
                .rev()
                .fold(0, |acc, (&i, &n)| acc * n + i)
        };
        let mut minima: Vec<(f64, usize)> = Vec::new();
        for (k, &c) in costs.iter().enumerate() {
            let mut ix = Vec::with_capacity(extent.len());
            let mut rest = k;
            for &n in &extent {
                ix.push(rest % n);
                rest /= n;
            }
            let lower_neighbour = (0..extent.len()).any(|axis| {
                [-1isize, 1].iter().any(|&d| {
                    let i = ix[axis] as isize + d;
                    if i < 0 || i >= extent[axis] as isize {
                        return false;
                    }
                    let mut nb = ix.clone();
                    nb[axis] = i as usize;
                    costs[flat(&nb)] < c
                })
            });
            if !lower_neighbour {
                minima.push((c, k));
            }
        }
        minima.sort_by(|a, b| a.0.total_cmp(&b.0));
        minima
            .iter()
            .take(MAX_STARTS)
            .map(|&(_, k)| self.shape.coords(points[k]))
            .collect()
    }
}

/// Fits one model to one sample.
pub fn fit_sample(
    sample: &Sample,
    spec: ModelSpec,
    opts: &FitOptions,
) -> Result<FitResult, FitError> {
    let shape = Shape::new(spec, opts)?;
    let prep = Prepared::new(sample, opts)?;
    fit_prepared(&prep, shape, opts)
}

/// Fits the four models of [`all_models`] to one sample.
pub fn fit_all(sample: &Sample, opts: &FitOptions) -> Result<Vec<FitResult>, FitError> {
    let prep = Prepared::new(sample, opts)?;
    all_models()
        .into_iter()
        .map(|spec| fit_prepared(&prep, Shape::new(spec, opts)?, opts))
        .collect()
}

/// Fits every model of `specs` to every sample of `data` (results in file order, then in the
/// order of `specs`), recording the data file in each result, and calls `progress(done,
/// total)` after each fit. The fits run in parallel (rayon); each is deterministic, so the
/// results do not depend on the number of threads. Fails with the first failed fit in that
/// order, saying which.
pub fn fit_dataset(
    data: &Dataset,
    specs: &[ModelSpec],
    opts: &FitOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<FitResult>, DatasetFitError> {
    let total = data.samples.len() * specs.len();
    let fail = |sample: &Sample, spec: &ModelSpec, error| DatasetFitError {
        file: data.source.clone(),
        sample: sample.name.clone(),
        model: spec.label(),
        error: Box::new(error),
    };
    let Some(first) = specs.first() else {
        return Ok(Vec::new());
    };
    // A sample that cannot be prepared fails its first fit.
    let preps: Vec<(&Sample, Result<Prepared, FitError>)> = data
        .samples
        .iter()
        .map(|sample| (sample, Prepared::new(sample, opts)))
        .collect();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut tasks: Vec<_> = preps
        .iter()
        .flat_map(|prep| specs.iter().map(move |spec| (prep, spec)))
        .enumerate()
        .collect();
    // The fits with free gamma (the largest starting grids and simplices) are handed out
    // first, each to the next free thread, so that a long fit does not start
    // last and leave the other cores idle at the end.
    tasks.sort_by_key(|(k, (_, spec))| (!spec.gamma().is_free(), *k));
    let mut fits: Vec<(usize, Result<FitResult, DatasetFitError>)> = tasks
        .into_iter()
        .par_bridge()
        .map(|(k, ((sample, prep), spec))| {
            let fit = (|| {
                let prep = prep.as_ref().map_err(|e| fail(sample, first, e.clone()))?;
                let mut fit = Shape::new(*spec, opts)
                    .and_then(|shape| fit_prepared(prep, shape, opts))
                    .map_err(|e| fail(sample, spec, e))?;
                fit.data = Some(data.source.display().to_string());
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress(n, total);
                Ok(fit)
            })();
            (k, fit)
        })
        .collect();
    fits.sort_by_key(|(k, _)| *k);
    fits.into_iter().map(|(_, fit)| fit).collect()
}

fn fit_prepared(prep: &Prepared, shape: Shape, opts: &FitOptions) -> Result<FitResult, FitError> {
    let sample = &prep.sample.name;
    let n = prep.v.len();
    let p = shape.dims() + usize::from(opts.scale.is_free());
    if n < p + 1 {
        return Err(FitError::TooFewPoints {
            sample: sample.clone(),
            n,
            params: p,
            needed: p + 1,
        });
    }
    if prep.informative == 0 {
        return Err(FitError::AllZero {
            sample: sample.clone(),
        });
    }
    // The fit works in units of the largest measured magnitude (`Prepared::unit`).
    let unit = prep.unit;
    let scale_in_units = match opts.scale {
        Parameter::Free => Parameter::Free,
        Parameter::Fixed(s) => {
            let su = s / unit;
            if !(su.is_finite() && su >= f64::MIN_POSITIVE) {
                return Err(FitError::Scale {
                    sample: sample.clone(),
                    reason: format!(
                        "the fixed scale {} is out of proportion to the data, whose largest \
                         magnitude is {}",
                        show(s),
                        show(unit)
                    ),
                });
            }
            Parameter::Fixed(su)
        }
    };
    let proj = Projected::new(opts.loss, &prep.v, &prep.w, opts.log_floor, scale_in_units);
    // The model itself: single scattering, or all orders with fresh walks at every evaluation.
    let eval = Evaluator {
        prep,
        proj,
        shape,
        opts: *opts,
        multi: None,
    };
    if !prep.forward.has_walks() {
        let (best, iterations) = search(&eval, eval.starts())?;
        let (best, iterations) = hop_eta(&eval, best, iterations)?;
        return finish(&eval, &best.x, iterations, None);
    }
    let (prep_single, start) = single_scattering_start(prep, shape, opts)?;
    match opts.multiple_term {
        MultipleTerm::Exact => {
            let (best, iterations) = search(&eval, vec![start])?;
            finish(&eval, &best.x, iterations, None)
        }
        MultipleTerm::Surrogate => {
            fit_with_surrogate(prep, &prep_single, shape, opts, eval.proj, start)
        }
    }
}

/// The start of an all-orders fit of `prep`, in search coordinates, and `prep` with its
/// single-scattering part alone. Multiple scattering is a correction to single scattering: the
/// fit starts from the optimum of the same model's single-scattering fit (height-correlated
/// masking, the walk's order 1).
fn single_scattering_start<'a>(
    prep: &Prepared<'a>,
    shape: Shape,
    opts: &FitOptions,
) -> Result<(Prepared<'a>, Vec<f64>), FitError> {
    let single = FitOptions {
        orders: ScatteringOrders::Single,
        masking: Masking::Correlated,
        ..*opts
    };
    let prep_single = Prepared {
        forward: prep.forward.single_part(),
        ..prep.clone()
    };
    let r = fit_prepared(&prep_single, shape, &single)?;
    let start = shape.coords(Point {
        alpha: r.model.alpha,
        gamma: r.model.gamma,
        eta: r.model.eta,
    });
    Ok((prep_single, start))
}

/// The fewest estimates of the orders >= 2 term (sets of walks) that an all-orders fit makes:
/// with the surrogate, the nodes of one surrogate ([`crate::surrogate`]) and the estimate at
/// its optimum; with the exact term, the first simplex of the search (`p + 1` points for `p`
/// searched coordinates), one step, and at the optimum its estimate and the `2p` of its
/// standard errors. A fit usually makes a few times more (more surrogates, more steps).
fn fewest_term_estimates(shape: Shape, term: MultipleTerm) -> usize {
    let p = shape.dims();
    match term {
        MultipleTerm::Surrogate => crate::surrogate::nodes(p).len() + 1,
        MultipleTerm::Exact => (p + 1) + 1 + 1 + 2 * p,
    }
}

/// What the random walks of all-orders fits cost at the least ([`fit_walk_cost`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitWalkCost {
    /// The fewest estimates of the orders >= 2 term the fits make, summed over the fits.
    pub estimates: usize,
    /// Their estimated wall time, in seconds, on rayon's current pool.
    pub seconds: f64,
    /// Walks per incident direction of each estimate.
    pub walks: u64,
}

impl FitWalkCost {
    /// What the walks are, for a note before a long run.
    pub fn what(&self) -> String {
        format!(
            "the random walks of the all-orders fits (at least {} estimates of the orders >= 2 \
             term, {} walks per incident direction each)",
            self.estimates, self.walks
        )
    }
}

/// The least the random walks of the fits of `specs` to every sample of `data` will cost, for
/// a note before a long run: for each fit, the orders >= 2 term at its start (the
/// single-scattering optimum) timed by a pilot run ([`Forward::walk_seconds`]: random numbers
/// of its own, at most a sixteenth of one estimate's work), times the fewest estimates the fit
/// makes: with the surrogate term the nodes of one surrogate ([`crate::surrogate`]) and the
/// estimate at its optimum; with the exact term the first simplex, a step, and at the optimum
/// its estimate and those of its standard errors. A fit usually makes a few times more, so the
/// time is a lower bound. Zero for single scattering; a sample or model that cannot be fitted counts
/// zero (its fit reports why).
pub fn fit_walk_cost(data: &Dataset, specs: &[ModelSpec], opts: &FitOptions) -> FitWalkCost {
    let mut cost = FitWalkCost {
        estimates: 0,
        seconds: 0.0,
        walks: opts.walks,
    };
    if opts.orders == ScatteringOrders::Single {
        return cost;
    }
    for sample in &data.samples {
        let Ok(prep) = Prepared::new(sample, opts) else {
            continue;
        };
        for &spec in specs {
            let one = || -> Result<(usize, f64), FitError> {
                let shape = Shape::new(spec, opts)?;
                let (_, start) = single_scattering_start(&prep, shape, opts)?;
                let pt = shape.point(&start);
                let ndf = shape.model(pt, 1.0, opts).ndf()?;
                let n = fewest_term_estimates(shape, opts.multiple_term);
                Ok((n, n as f64 * prep.forward.walk_seconds(&ndf, pt.eta)?))
            };
            if let Ok((n, seconds)) = one() {
                cost.estimates += n;
                cost.seconds += seconds;
            }
        }
    }
    cost
}

/// The all-orders fit with the surrogate orders >= 2 term ([`crate::surrogate`]): a surrogate
/// around the single-scattering optimum `start`, minimised, and rebuilt around the optimum
/// until the optimum lies in the span of its nodes (at most [`SURROGATE_ROUNDS`] surrogates).
/// The fit is then reported with the exact walk term at the optimum (its rmse, scale and Monte
/// Carlo error), the surrogate's derivatives giving the Jacobian.
fn fit_with_surrogate(
    prep: &Prepared,
    prep_single: &Prepared,
    shape: Shape,
    opts: &FitOptions,
    proj: Projected,
    start: Vec<f64>,
) -> Result<FitResult, FitError> {
    let term_at = |x: &[f64]| {
        let pt = shape.point(x);
        let ndf = shape.model(pt, 1.0, opts).ndf()?;
        Ok(prep.forward.walk_term(&ndf, pt.eta)?)
    };
    let (bounds, step) = (shape.bounds(), shape.surrogate_steps());
    let mut center = start;
    let mut iterations = 0;
    for round in 1..=SURROGATE_ROUNDS {
        // Keep every node inside the search box.
        for ((c, &(lo, hi)), &h) in center.iter_mut().zip(&bounds).zip(&step) {
            *c = c.clamp(lo + h, hi - h);
        }
        let surrogate = Surrogate::build(&center, &step, term_at)?;
        let eval = Evaluator {
            prep: prep_single,
            proj: proj.clone(),
            shape,
            opts: *opts,
            multi: Some(&surrogate),
        };
        let (best, it) = search(&eval, vec![center.clone()])?;
        iterations += it;
        let x = shape.coords(shape.point(&best.x));
        if surrogate.spans(&x) || round == SURROGATE_ROUNDS {
            return finish(&eval, &x, iterations, Some(&term_at(&x)?));
        }
        center = x;
    }
    unreachable!("the last round returns")
}

/// The best local minimum of `eval`'s cost from `starts` (the first of equal ones), and the
/// iterations of all of them.
fn search(
    eval: &Evaluator,
    starts: Vec<Vec<f64>>,
) -> Result<(crate::optimize::Minimum, u64), FitError> {
    // The searches are independent: run in parallel, taken in the order of `starts`, so the
    // result does not depend on the number of threads.
    let found: Vec<_> = starts
        .par_iter()
        .map(|x0| minimize(|x| eval.cost(x), x0, eval.opts.optimizer))
        .collect();
    let mut best: Option<crate::optimize::Minimum> = None;
    let mut iterations = 0;
    let mut evaluations = 0;
    for result in found {
        match result {
            Ok(m) => {
                iterations += m.iterations;
                if best.as_ref().is_none_or(|b| m.cost < b.cost) {
                    best = Some(m);
                }
            }
            Err(e) => evaluations += e.evaluations,
        }
    }
    let best = best.ok_or_else(|| FitError::NoFiniteCost {
        sample: eval.prep.sample.name.clone(),
        model: eval.shape.kind.name(),
        evaluations,
        held_scale: match eval.opts.scale {
            Parameter::Fixed(s) => Some(s),
            Parameter::Free => None,
        },
    })?;
    Ok((best, iterations))
}

/// With eta free, the best local minimum of `eval`'s cost from `best` across the jumps of the
/// cost in eta. The single-scattering model of a transmission pair jumps where its refraction
/// half vector turns horizontal ([`Forward::horizontal_etas`]; by `D` of horizontal facets,
/// which is not zero for GGX and for Student-T with gamma <= 2), so a local search stays in the
/// piece between two such indices where it started, and the starting grid's few indices can
/// miss the piece of the optimum. The cost is evaluated at the middle of every piece (in
/// `ln(eta - 1)`; at even steps when there are more than [`ETA_PIECES_MAX`]) at `best`'s
/// alpha and gamma, and local searches start from the points that beat `best`, best first (at
/// most [`MAX_STARTS`]), and from the middles of the two pieces beside `best`'s whether they
/// beat it or not (once each: across a jump near the optimum, alpha and gamma held at `best`'s
/// can fit far worse than after a search), until none finds a lower cost (at most
/// [`ETA_HOP_ROUNDS`] times). With eta held, `best` as it is.
fn hop_eta(
    eval: &Evaluator,
    mut best: crate::optimize::Minimum,
    mut iterations: u64,
) -> Result<(crate::optimize::Minimum, u64), FitError> {
    if !eval.shape.eta.is_free() {
        return Ok((best, iterations));
    }
    let jumps = eval.prep.forward.horizontal_etas(ETA_MIN, ETA_MAX);
    let middles = eta_scan(&jumps);
    let mut searched = vec![false; middles.len()];
    for _ in 0..ETA_HOP_ROUNDS {
        let at = eval.shape.point(&best.x);
        let coords = |m: f64| {
            eval.shape.coords(Point {
                eta: 1.0 + m.exp(),
                ..at
            })
        };
        let piece = eta_piece(&jumps, (at.eta - 1.0).ln());
        let mut starts = Vec::new();
        for k in [piece.checked_sub(1), Some(piece + 1)]
            .into_iter()
            .flatten()
        {
            if k < middles.len() && !searched[k] {
                searched[k] = true;
                starts.push(coords(middles[k]));
            }
        }
        let mut below: Vec<(f64, Vec<f64>)> = middles
            .par_iter()
            .map(|&m| {
                let x = coords(m);
                (eval.cost(&x), x)
            })
            .filter(|(c, _)| *c < best.cost)
            .collect();
        below.sort_by(|a, b| a.0.total_cmp(&b.0));
        starts.extend(below.into_iter().take(MAX_STARTS).map(|(_, x)| x));
        if starts.is_empty() {
            break;
        }
        let (found, it) = search(eval, starts)?;
        iterations += it;
        if found.cost >= best.cost {
            break;
        }
        best = found;
    }
    Ok((best, iterations))
}

/// The free eta's search range `[ETA_MIN, ETA_MAX]` in `ln(eta - 1)`, where [`eta_scan`]
/// spreads its points.
fn ln_eta_range() -> (f64, f64) {
    ((ETA_MIN - 1.0).ln(), (ETA_MAX - 1.0).ln())
}

/// The index in [`eta_scan`]'s points of the piece holding `x = ln(eta - 1)`: the piece
/// between the jumps around it, or, for more than [`ETA_PIECES_MAX`] pieces, the even step.
fn eta_piece(jumps: &[f64], x: f64) -> usize {
    if jumps.len() < ETA_PIECES_MAX {
        jumps.partition_point(|&j| (j - 1.0).ln() < x)
    } else {
        let (lo, hi) = ln_eta_range();
        let n = ETA_PIECES_MAX as f64;
        ((x - lo) / (hi - lo) * n).floor().clamp(0.0, n - 1.0) as usize
    }
}

/// The points of `ln(eta - 1)` that [`hop_eta`] scans, given the ascending indices in
/// `(ETA_MIN, ETA_MAX)` where the cost jumps: the middle of every piece of the search range
/// they cut, or, for more than [`ETA_PIECES_MAX`] pieces, that many even steps.
fn eta_scan(jumps: &[f64]) -> Vec<f64> {
    let (lo, hi) = ln_eta_range();
    if jumps.len() < ETA_PIECES_MAX {
        let mut ends = vec![lo];
        ends.extend(jumps.iter().map(|e| (e - 1.0).ln()));
        ends.push(hi);
        ends.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
    } else {
        // Many points, each of whose jump is small: an even scan of the whole range.
        let n = ETA_PIECES_MAX as f64;
        (0..ETA_PIECES_MAX)
            .map(|k| lo + (hi - lo) * (k as f64 + 0.5) / n)
            .collect()
    }
}

/// The fit at search coordinates `x`: scale, rmse and standard errors. With `exact`, the walk
/// term at `x` replaces the surrogate's in the model whose scale and rmse are reported, and its
/// Monte Carlo error enters the standard errors.
fn finish(
    eval: &Evaluator,
    x: &[f64],
    iterations: u64,
    exact: Option<&WalkTerm>,
) -> Result<FitResult, FitError> {
    let (prep, shape, opts) = (eval.prep, eval.shape, &eval.opts);
    let sample = &prep.sample.name;
    let (n, unit) = (prep.v.len(), prep.unit);
    let p = shape.dims() + usize::from(opts.scale.is_free());
    let point = shape.point(x);
    let mut m = Vec::new();
    eval.unit_model(point, &mut m)?;
    if let Some(term) = exact {
        m.clear();
        prep.forward
            .unit_model(&shape.model(point, 1.0, opts).ndf()?, point.eta, &mut m)?;
        for (m, t) in m.iter_mut().zip(&term.values) {
            *m += t;
        }
    }
    if m.iter().all(|&m| m == 0.0) {
        return Err(FitError::NoSignal {
            sample: sample.clone(),
        });
    }
    let scale_u = eval.proj.project(&m).scale;
    if scale_u.is_nan() || scale_u <= 0.0 {
        return Err(FitError::Scale {
            sample: sample.clone(),
            reason: "the best scale is 0: the measured values do not rise with the model \
                     anywhere (are they mostly negative or zero where the model is large?)"
                .into(),
        });
    }
    // A held scale is reported as given, not as its round trip through the fit's units.
    let scale = match opts.scale {
        Parameter::Fixed(s) => s,
        Parameter::Free => scale_u * unit,
    };
    if !scale.is_finite() || scale == 0.0 {
        return Err(FitError::Scale {
            sample: sample.clone(),
            reason: format!(
                "the fitted scale {scale_u:e} times the data's magnitude {unit:e} is not a \
                 representable number"
            ),
        });
    }
    let rmse_sqrt_l = (prep
        .v
        .iter()
        .zip(&m)
        .map(|(&v, &m)| (signed_sqrt(v) - (scale_u * m).sqrt()).powi(2))
        .sum::<f64>()
        / n as f64)
        .sqrt()
        * unit.sqrt();

    let mut warnings = Vec::new();
    if prep.informative < p {
        warnings.push(FitWarning::FewInformativePoints {
            informative: prep.informative,
            parameters: p,
        });
    }
    for (parameter, bound) in shape.bounds_reached(x) {
        warnings.push(FitWarning::AtBound {
            parameter: parameter.to_owned(),
            bound,
        });
    }
    let se = match standard_errors(eval, point, scale_u, &m, exact)? {
        Curvature::Errors(se) => se,
        Curvature::Singular => {
            warnings.push(FitWarning::SingularCurvature);
            StandardErrors::default()
        }
        Curvature::NotDifferentiable(parameter) => {
            warnings.push(FitWarning::NotDifferentiable {
                parameter: parameter.to_owned(),
            });
            StandardErrors::default()
        }
        Curvature::TotalReflectionOnset { onset, share } => {
            warnings.push(FitWarning::TotalReflectionOnset { onset, share });
            StandardErrors::default()
        }
    };
    // A flagged fit has no standard errors: its curvature does not describe an interior
    // optimum of well-determined parameters.
    let se = if warnings.is_empty() {
        se
    } else {
        StandardErrors::default()
    };
    Ok(FitResult {
        sample: sample.clone(),
        model: shape.model(point, scale, opts),
        eta_fixed: !opts.eta.is_free(),
        scale_fixed: !opts.scale.is_free(),
        loss: opts.loss,
        log_floor: (opts.loss == Loss::Log).then_some(opts.log_floor),
        optimizer: opts.optimizer,
        multiple_term: (opts.orders == ScatteringOrders::All).then_some(opts.multiple_term),
        measured: prep.measured,
        rmse_sqrt_l,
        n_points: n,
        alpha_stderr: se.alpha,
        gamma_stderr: se.gamma,
        eta_stderr: se.eta,
        // Undefined where the product is not representable (data near the limits of f64).
        scale_stderr: se
            .scale
            .map(|s| s * unit)
            .filter(|s| s.is_finite() && *s > 0.0),
        warnings,
        iterations,
        data: None,
        stfit_version: env!("CARGO_PKG_VERSION").to_owned(),
    })
}

/// Standard errors of the fitted parameters; `None` for a parameter held fixed or absent, and
/// wherever the curvature does not determine it.
#[derive(Debug, Clone, Copy, Default)]
struct StandardErrors {
    alpha: Option<f64>,
    gamma: Option<f64>,
    eta: Option<f64>,
    scale: Option<f64>,
}

/// What the curvature of the loss at the optimum gives.
enum Curvature {
    /// The standard errors.
    Errors(StandardErrors),
    /// Singular, a point of leverage 1, or a standard error that is not a finite positive
    /// number or exceeds the width of its parameter's search range.
    Singular,
    /// The single-scattering model jumps or kinks in this parameter within the step of its
    /// finite difference: the one-sided differences of its column disagree by more than
    /// [`KINK_RATIO`].
    NotDifferentiable(&'static str),
    /// A free eta's information comes mostly from pairs near the index where they turn totally
    /// reflected ([`total_reflection_onset`]): the onset of the pair that carries the most,
    /// and the share of the information of those pairs.
    TotalReflectionOnset { onset: f64, share: f64 },
}

/// The largest squared norm of the difference between a column's forward and backward
/// differences, relative to the squared norm of the central column, of a model differentiable
/// at the optimum. For a smooth model the ratio is of the order of the relative step squared
/// (1e-8). Where a data point's refraction support ends inside the step (its refraction half
/// vector turns horizontal: GGX and Student-T jump to 0 there) and that point dominates the
/// column, one one-sided difference is the jump and the other about 0: a ratio near 4. The
/// bound leaves out the kinks where total internal reflection sets in (the Fresnel factor's
/// slope is infinite there) unless they are as one-sided: measured on eta-free fits of
/// general grids at eta 1.7 with 5% noise, their ratios of 0.01 to 0.8 came with standard
/// errors that were still calibrated, (fitted - true) / stderr within 3.
const KINK_RATIO: f64 = 2.0;

/// The share of a free eta's information above which the pairs of one total-reflection onset
/// make its standard error unreliable ([`total_reflection_onset`]).
const ONSET_SHARE: f64 = 0.5;

/// Whether a free eta's information rests on the pairs of one total-reflection onset: of the
/// eta information `sum_j col_j^2` (`col` the eta column of the weighted Jacobian), the points
/// whose onsets (`onsets`, per point, [`Forward::total_reflection_etas`]) agree to a relative
/// 1e-9 (a pair, its mirror image and its reverse) carry more than [`ONSET_SHARE`]. Returns
/// that onset and the share of its points.
///
/// Just below its onset a pair's model differs from its value there by about the square root
/// of the distance, so its slope in eta is unbounded: a pair near its onset can outweigh every
/// other point, and then eta and its standard error rest on that one pair's noise, where the
/// linearisation behind the standard error fails and the fit can be drawn onto the onset. A
/// pair away from its onset carries a share like any other point's. Measured on synthetic
/// general data with light from inside, 5% noise, fitted with free eta: Beckmann alpha 0.5,
/// true eta 1.45, log loss, correlated masking, seeds 2001 to 2600: the 24 fits whose largest
/// onset share was above one half (92% to 99%) ended 4.3 to 106 standard errors from the truth;
/// of the others (at most 6%), none ended beyond 3. GGX alpha 0.5, true eta 1.5 (an onset at
/// 1.500), sqrt loss, seeds 2001 to 2200: 193 fits had 66% to 97% and held all 9 fits beyond 3
/// standard errors. A rule counting the points whose onset lies within 3 standard errors of
/// eta missed 2 of the 24 Beckmann fits (65 standard errors from the truth): the dominant pair
/// itself makes the standard error small.
fn total_reflection_onset(col: &[f64], onsets: &[Option<f64>]) -> Option<(f64, f64)> {
    let total: f64 = col.iter().map(|c| c * c).sum();
    let mut info: Vec<(f64, f64)> = col
        .iter()
        .zip(onsets)
        .filter_map(|(c, onset)| onset.map(|o| (o, c * c)))
        .collect();
    info.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut groups: Vec<(f64, f64)> = Vec::new();
    for (onset, i) in info {
        match groups.last_mut() {
            Some(g) if onset - g.0 <= 1e-9 * onset => g.1 += i,
            _ => groups.push((onset, i)),
        }
    }
    let (onset, most) = groups.into_iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
    let share = most / total;
    (share > ONSET_SHARE).then_some((onset, share))
}

/// Standard errors of `(alpha, [gamma], [eta], [scale])` as in the module docs, in the fit's
/// units, or why there are none: a singular curvature (also a standard error that is not a
/// finite positive number, or a shape parameter's exceeding the width of its search range), or
/// a single-scattering model that is not differentiable in a parameter at the optimum (an
/// optimum pinned where the model jumps, to which a linearisation does not apply: the central
/// difference across the jump gave standard errors 10 to 1000 times too small).
fn standard_errors(
    eval: &Evaluator,
    p: Point,
    scale: f64,
    m: &[f64],
    term: Option<&WalkTerm>,
) -> Result<Curvature, FitError> {
    let proj = &eval.proj;
    let n = m.len();
    let sw: Vec<f64> = proj.w.iter().map(|w| w.sqrt()).collect();

    // Columns of J (up to sign): d T(scale m_j) / d theta_k, times sqrt(w_j).
    let mut cols: Vec<Vec<f64>> = Vec::new();
    // With the walk's orders >= 2 the model is piecewise smooth in the parameters (a walk's
    // discrete choices switch as they change): a wider step averages over those jumps, and
    // one-sided differences are not compared.
    let walks = eval.prep.forward.has_walks();
    // The check is for the analytic single-scattering model; the orders >= 2 term (walks or
    // their surrogate, and at the optimum the walks while the columns use the surrogate) is
    // left to the wider step and the Monte Carlo error.
    let check_kinks = !walks && eval.multi.is_none() && term.is_none();
    let mut kinked: Option<&'static str> = None;
    let mut fd_column = |name: &'static str, plus: Point, minus: Point, h2: f64| {
        let (mut mp, mut mm) = (Vec::new(), Vec::new());
        eval.unit_model(plus, &mut mp)?;
        eval.unit_model(minus, &mut mm)?;
        if check_kinks && kinked.is_none() {
            let (mut asymmetry, mut slope) = (0.0, 0.0);
            for j in 0..n {
                let t = |v: f64| proj.transform(scale * v);
                let (forward, backward) = (t(mp[j]) - t(m[j]), t(m[j]) - t(mm[j]));
                asymmetry += proj.w[j] * (forward - backward).powi(2);
                slope += proj.w[j] * (0.5 * (forward + backward)).powi(2);
            }
            if asymmetry > KINK_RATIO * slope {
                kinked = Some(name);
            }
        }
        cols.push(
            (0..n)
                .map(|j| {
                    sw[j] * (proj.transform(scale * mp[j]) - proj.transform(scale * mm[j])) / h2
                })
                .collect(),
        );
        Ok::<(), FitError>(())
    };
    let rel_step = if walks { 1e-2 } else { 1e-4 };
    let ha = rel_step * p.alpha;
    let at_alpha = |alpha| Point { alpha, ..p };
    fd_column(
        "alpha",
        at_alpha(p.alpha + ha),
        at_alpha(p.alpha - ha),
        2.0 * ha,
    )?;
    if let Gamma::Free(g) = p.gamma {
        let hg = rel_step * (g - 1.5);
        let at_gamma = |g| Point {
            gamma: Gamma::Free(g),
            ..p
        };
        fd_column("gamma", at_gamma(g + hg), at_gamma(g - hg), 2.0 * hg)?;
    }
    if eval.shape.eta.is_free() {
        let he = rel_step * (p.eta - 1.0);
        let at_eta = |eta| Point { eta, ..p };
        fd_column("eta", at_eta(p.eta + he), at_eta(p.eta - he), 2.0 * he)?;
    }
    let scale_free = proj.fixed_scale.is_none();
    if scale_free {
        cols.push(
            (0..n)
                .map(|j| sw[j] * proj.d_transform_d_scale(scale, m[j]))
                .collect(),
        );
    }
    if let Some(parameter) = kinked {
        return Ok(Curvature::NotDifferentiable(parameter));
    }
    let residuals: Vec<f64> = (0..n)
        .map(|j| sw[j] * (proj.y[j] - proj.transform(scale * m[j])))
        .collect();
    let Some(mut cov) = sandwich_covariance(&cols, &residuals) else {
        return Ok(Curvature::Singular);
    };
    if let Some(term) = term {
        // The slope over one standard error of the term: where the model is far above its
        // Monte Carlo error this is the derivative of the first-order propagation; where the
        // model is near 0 (a Beckmann tail underflowing at grazing pairs) the square root's
        // derivative is unbounded and would make every standard error infinite.
        for (k, v) in walk_variance(&cols, term, |j| {
            sw[j] * proj.model_slope(scale, m[j], term.stderr_at(j))
        })
        .into_iter()
        .enumerate()
        {
            cov[k][k] += v;
        }
    }
    let se: Vec<f64> = (0..cols.len()).map(|k| cov[k][k].sqrt()).collect();
    if se.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Ok(Curvature::Singular);
    }
    // A shape parameter whose standard error exceeds the width of its whole search range is
    // not determined by the data (a scale held far from the data's flattens the loss), even
    // where rounding leaves the curvature invertible.
    let mut widths = vec![ALPHA_MAX - ALPHA_MIN];
    if p.gamma.is_free() {
        widths.push(GAMMA_EXCESS_MAX - GAMMA_EXCESS_MIN);
    }
    if eval.shape.eta.is_free() {
        widths.push(ETA_MAX - ETA_MIN);
    }
    if se.iter().zip(&widths).any(|(s, w)| s > w) {
        return Ok(Curvature::Singular);
    }
    if eval.shape.eta.is_free() {
        let k = 1 + usize::from(p.gamma.is_free());
        let onsets = eval.prep.forward.total_reflection_etas();
        if let Some((onset, share)) = total_reflection_onset(&cols[k], &onsets) {
            return Ok(Curvature::TotalReflectionOnset { onset, share });
        }
    }
    let mut se = se.into_iter();
    Ok(Curvature::Errors(StandardErrors {
        alpha: se.next(),
        gamma: if p.gamma.is_free() { se.next() } else { None },
        eta: if eval.shape.eta.is_free() {
            se.next()
        } else {
            None
        },
        scale: if scale_free { se.next() } else { None },
    }))
}

/// The number of distinct direction pairs (compared bit for bit) among `pairs`.
fn distinct_pairs(pairs: impl Iterator<Item = (Vec3, Vec3)>) -> usize {
    let mut keys: Vec<[u64; 6]> = pairs
        .map(|(a, b)| [a.x, a.y, a.z, b.x, b.y, b.z].map(f64::to_bits))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.len()
}

/// The variances of the fitted parameters due to the Monte Carlo error of the orders >= 2
/// `term`, to first order: a change `delta` of the unit-scale model moves the least-squares
/// optimum by `-(J^T J)^{-1} J^T diag(g) delta`, `g_j = sqrt(w_j) d T(scale m_j) / d m_j`
/// (taken as the caller's secant over the term's standard error; `cols` the columns of `J`),
/// whose variance [`WalkTerm::variance_of`] estimates from the
/// independent batches of walks. Zeros if `J^T J` is numerically singular.
fn walk_variance(cols: &[Vec<f64>], term: &WalkTerm, g: impl Fn(usize) -> f64) -> Vec<f64> {
    let (p, n) = (cols.len(), term.values.len());
    let jtj: Vec<Vec<f64>> = (0..p)
        .map(|a| {
            (0..p)
                .map(|b| (0..n).map(|j| cols[a][j] * cols[b][j]).sum())
                .collect()
        })
        .collect();
    let Some(bread) = invert_spd(&jtj) else {
        return vec![0.0; p];
    };
    (0..p)
        .map(|k| {
            let a: Vec<f64> = (0..n)
                .map(|j| g(j) * (0..p).map(|l| bread[k][l] * cols[l][j]).sum::<f64>())
                .collect();
            term.variance_of(&a)
        })
        .collect()
}

/// The largest leverage of a point whose residual still estimates its noise: `1 - h_j` below
/// this is rounding of a point that alone fixes a combination of the parameters (every point
/// when there are as many points as parameters), and its residual is 0 whatever its noise.
const LEVERAGE_MAX: f64 = 1.0 - 1e-8;

/// The HC3 heteroscedasticity-robust covariance of least-squares estimates,
/// `(J^T J)^{-1} (sum_j (r_j / (1 - h_j))^2 J_j^T J_j) (J^T J)^{-1}` with the leverages
/// `h_j = J_j (J^T J)^{-1} J_j^T`, from the Jacobian columns `cols[k][j] = d r_j / d theta_k`
/// (up to a common sign) and the residuals `r_j` at the optimum; `None` if `J^T J` is
/// numerically singular or a leverage exceeds [`LEVERAGE_MAX`].
fn sandwich_covariance(cols: &[Vec<f64>], r: &[f64]) -> Option<Vec<Vec<f64>>> {
    let (p, n) = (cols.len(), r.len());
    let outer = |weight: &dyn Fn(usize) -> f64| -> Vec<Vec<f64>> {
        (0..p)
            .map(|a| {
                (0..p)
                    .map(|b| (0..n).map(|j| weight(j) * cols[a][j] * cols[b][j]).sum())
                    .collect()
            })
            .collect()
    };
    let bread = invert_spd(&outer(&|_| 1.0))?;
    // The residuals of the fits without each point, to first order.
    let mut left_out = Vec::with_capacity(n);
    for (j, r) in r.iter().enumerate() {
        let h: f64 = (0..p)
            .map(|a| cols[a][j] * (0..p).map(|b| bread[a][b] * cols[b][j]).sum::<f64>())
            .sum();
        if h.is_nan() || h > LEVERAGE_MAX {
            return None;
        }
        left_out.push(r / (1.0 - h));
    }
    let meat = outer(&|j| left_out[j] * left_out[j]);
    Some(
        (0..p)
            .map(|a| {
                (0..p)
                    .map(|b| {
                        let mut s = 0.0;
                        for k in 0..p {
                            for l in 0..p {
                                s += bread[a][k] * meat[k][l] * bread[l][b];
                            }
                        }
                        s
                    })
                    .collect()
            })
            .collect(),
    )
}

/// Inverse of a small symmetric positive definite matrix by Gauss-Jordan elimination with
/// partial pivoting, after scaling to unit diagonal; `None` if it is numerically singular.
fn invert_spd(a: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let p = a.len();
    let d: Vec<f64> = (0..p).map(|i| a[i][i].sqrt()).collect();
    if d.iter().any(|&d| !(d > 0.0 && d.is_finite())) {
        return None;
    }
    // Work on the correlation-like matrix C = D^-1 A D^-1; A^-1 = D^-1 C^-1 D^-1.
    let mut c: Vec<Vec<f64>> = (0..p)
        .map(|i| (0..p).map(|j| a[i][j] / (d[i] * d[j])).collect())
        .collect();
    let mut inv: Vec<Vec<f64>> = (0..p)
        .map(|i| (0..p).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
        .collect();
    for col in 0..p {
        let piv = (col..p).max_by(|&x, &y| c[x][col].abs().total_cmp(&c[y][col].abs()))?;
        let pivot = c[piv][col].abs();
        if pivot.is_nan() || pivot <= 1e-12 {
            return None;
        }
        c.swap(col, piv);
        inv.swap(col, piv);
        let f = c[col][col];
        for k in 0..p {
            c[col][k] /= f;
            inv[col][k] /= f;
        }
        for r in 0..p {
            if r != col {
                let g = c[r][col];
                for k in 0..p {
                    c[r][k] -= g * c[col][k];
                    inv[r][k] -= g * inv[col][k];
                }
            }
        }
    }
    Some(
        (0..p)
            .map(|i| (0..p).map(|j| inv[i][j] / (d[i] * d[j])).collect())
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eta scan puts one point strictly inside every piece between the jumps, and at most
    /// `ETA_PIECES_MAX` points, evenly spread over the whole range, when the jumps are more;
    /// `eta_piece` finds the scan point of the piece (or step) holding an index.
    #[test]
    fn eta_scan_has_a_point_in_every_piece_or_an_even_cover() {
        let x = |e: f64| (e - 1.0).ln();
        let jumps = [1.2, 1.4, 1.407, 2.5];
        let scan = eta_scan(&jumps);
        let mut ends = vec![ETA_MIN];
        ends.extend(jumps);
        ends.push(ETA_MAX);
        assert_eq!(scan.len(), ends.len() - 1);
        for (k, (m, w)) in scan.iter().zip(ends.windows(2)).enumerate() {
            assert!(x(w[0]) < *m && *m < x(w[1]), "{m} not in {w:?}");
            assert_eq!(eta_piece(&jumps, *m), k);
        }
        assert_eq!(eta_piece(&jumps, x(1.403)), 2);
        assert_eq!(eta_scan(&[]).len(), 1);
        let many: Vec<f64> = (1..1000).map(|k| 1.05 + 1.95 * k as f64 / 1000.0).collect();
        let scan = eta_scan(&many);
        assert_eq!(scan.len(), ETA_PIECES_MAX);
        let step = (x(ETA_MAX) - x(ETA_MIN)) / ETA_PIECES_MAX as f64;
        assert!((scan[0] - x(ETA_MIN) - step / 2.0).abs() < 1e-12);
        assert!(scan.windows(2).all(|w| (w[1] - w[0] - step).abs() < 1e-12));
        for (k, m) in scan.iter().enumerate() {
            assert_eq!(eta_piece(&many, *m), k);
        }
        assert_eq!(eta_piece(&many, x(ETA_MAX)), ETA_PIECES_MAX - 1);
    }

    /// HC3's meat is that of the residuals of the least-squares fits without each point: a
    /// point of high leverage, which pulls the fit toward itself, counts with the error the fit
    /// of the other points makes there. With as many points as parameters every residual is 0
    /// whatever the noise, and there is no covariance.
    #[test]
    fn sandwich_uses_the_residuals_of_the_fits_without_each_point() {
        // A line through 6 points, the last far out (leverage about 0.8).
        let x = [0.0, 0.3, 0.5, 0.9, 1.2, 2.5];
        let y = [0.1, 0.5, 0.4, 1.2, 1.1, 2.1];
        let fit = |points: &[usize]| {
            let jtj = vec![
                vec![
                    points.iter().map(|&j| x[j] * x[j]).sum(),
                    points.iter().map(|&j| x[j]).sum(),
                ],
                vec![points.iter().map(|&j| x[j]).sum(), points.len() as f64],
            ];
            let jty = [
                points.iter().map(|&j| x[j] * y[j]).sum::<f64>(),
                points.iter().map(|&j| y[j]).sum::<f64>(),
            ];
            let inv = invert_spd(&jtj).unwrap();
            [0, 1].map(|a| inv[a][0] * jty[0] + inv[a][1] * jty[1])
        };
        let all: Vec<usize> = (0..6).collect();
        let [slope, intercept] = fit(&all);
        let r: Vec<f64> = (0..6).map(|j| y[j] - slope * x[j] - intercept).collect();
        let cols = vec![x.to_vec(), vec![1.0; 6]];
        let cov = sandwich_covariance(&cols, &r).unwrap();

        let bread = invert_spd(&[
            vec![x.iter().map(|x| x * x).sum(), x.iter().sum()],
            vec![x.iter().sum(), 6.0],
        ])
        .unwrap();
        let mut meat = [[0.0; 2]; 2];
        let mut largest = (0.0, 0.0);
        for j in 0..6 {
            let others: Vec<usize> = all.iter().copied().filter(|&k| k != j).collect();
            let [s, i] = fit(&others);
            let e = y[j] - s * x[j] - i;
            largest = if (e / r[j]).abs() > largest.0 {
                ((e / r[j]).abs(), x[j])
            } else {
                largest
            };
            let row = [x[j], 1.0];
            for a in 0..2 {
                for b in 0..2 {
                    meat[a][b] += e * e * row[a] * row[b];
                }
            }
        }
        // The far point's residual is the most shrunk by the fit through it.
        assert_eq!(largest.1, 2.5);
        assert!(largest.0 > 4.0, "{largest:?}");
        for a in 0..2 {
            for b in 0..2 {
                let mut want = 0.0;
                for k in 0..2 {
                    for l in 0..2 {
                        want += bread[a][k] * meat[k][l] * bread[l][b];
                    }
                }
                assert!(
                    (cov[a][b] - want).abs() < 1e-12 * want.abs().max(1e-3),
                    "{a}{b}"
                );
            }
        }
        assert!(sandwich_covariance(&[vec![1.0, 2.0], vec![1.0, 1.0]], &[0.0, 0.0]).is_none());
    }

    /// A count is in the singular for 1 only, so a fit of one parameter reads "1 parameter".
    #[test]
    fn too_few_points_counts_in_words() {
        let e = FitError::TooFewPoints {
            sample: "s".into(),
            n: 1,
            params: 1,
            needed: 2,
        };
        assert_eq!(
            e.to_string(),
            "sample `s`: 1 usable point, a fit with 1 parameter needs at least 2"
        );
        assert_eq!(counted(0, "usable point"), "0 usable points");
        assert_eq!(counted(3, "parameter"), "3 parameters");
    }

    /// The points of one onset (equal to a relative 1e-9: a pair and its mirror image) pool
    /// their information; the fit is flagged when one onset's points carry more than
    /// [`ONSET_SHARE`] of it, whatever their distance from eta, and that onset is named.
    #[test]
    fn onset_is_flagged_by_the_share_of_its_pairs() {
        let mirror = 1.452 * (1.0 + 1e-12);
        let onsets = [None, Some(1.452), Some(1.40), Some(mirror)];
        // 1.452 holds 0.36 + 0.25 of 1.0 + 0.36 + 0.09 + 0.25.
        let col = [1.0, 0.6, 0.3, 0.5];
        assert_eq!(total_reflection_onset(&col, &onsets), None);
        let col = [0.5, 0.6, 0.3, 0.5];
        let (onset, share) = total_reflection_onset(&col, &onsets).unwrap();
        assert_eq!(onset, 1.452);
        assert!((share - 0.61 / 0.95).abs() < 1e-12, "{share}");
        // Each alone would not be flagged: they are pooled only as one onset.
        let apart = [None, Some(1.452), Some(1.40), Some(1.4521)];
        assert_eq!(total_reflection_onset(&col, &apart), None);
        assert_eq!(total_reflection_onset(&col, &[None; 4]), None);
    }

    #[test]
    fn invert_spd_inverts() {
        let a = vec![
            vec![4.0, 1.0, 0.5],
            vec![1.0, 3.0, 0.2],
            vec![0.5, 0.2, 2.0],
        ];
        let inv = invert_spd(&a).unwrap();
        for (i, row) in a.iter().enumerate() {
            for j in 0..3 {
                let e: f64 = row.iter().zip(&inv).map(|(x, r)| x * r[j]).sum();
                assert!((e - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        assert!(invert_spd(&[vec![1.0, 1.0], vec![1.0, 1.0]]).is_none());
    }
}
