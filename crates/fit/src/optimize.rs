//! Local minimisation of a smooth cost over unbounded `Vec<f64>` parameters with argmin:
//! Nelder-Mead, or L-BFGS with a More-Thuente line search and central finite-difference
//! gradients.
//!
//! argmin's own errors never leave this module: every evaluation is recorded, and a solver
//! that stops with an error (a degenerate line search, a simplex of equal costs, its internal
//! "potential bug" checks) yields the best point it evaluated. The one failure is a cost that
//! is not finite anywhere the solver looked ([`NoFiniteCost`]).

use std::cell::{Cell, RefCell};

use argmin::core::{CostFunction, Error, Executor, Gradient, State};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::neldermead::NelderMead;
use argmin::solver::quasinewton::LBFGS;

use crate::options::Optimizer;

/// Iteration cap of one local minimisation.
pub const MAX_ITERS: u64 = 400;
/// Cost-evaluation cap of one local minimisation (a guard, far above normal use).
pub const MAX_EVALS: u64 = 20_000;
/// Nelder-Mead stops when the standard deviation of the simplex costs falls below this. The
/// fitting costs are normalised to `[0, 1]`, so this is relative to the data's energy.
const NM_SD_TOLERANCE: f64 = 1e-15;
/// Initial Nelder-Mead simplex edge, in the (logarithmic) search coordinates.
const NM_STEP: f64 = 0.15;
/// L-BFGS stops when the gradient norm falls below this.
const LBFGS_TOL_GRAD: f64 = 1e-11;
/// L-BFGS stops when an iteration changes the (normalised) cost by less than this.
const LBFGS_TOL_COST: f64 = 1e-16;
/// L-BFGS memory.
const LBFGS_MEMORY: usize = 7;

/// The outcome of one local minimisation.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    pub x: Vec<f64>,
    pub cost: f64,
    pub iterations: u64,
}

/// Why a minimisation found no point: the cost was NaN or infinite at every point evaluated,
/// `evaluations` of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the cost is not finite at any of the {evaluations} points evaluated")]
pub struct NoFiniteCost {
    pub evaluations: u64,
}

/// A cost function for argmin, guarded against runaway solvers.
///
/// argmin 0.11's More-Thuente line search has no iteration cap and loops forever once L-BFGS
/// proposes a non-finite step (which happens at convergence, when finite-difference gradient
/// noise makes the curvature pair degenerate). Evaluations at non-finite parameters, or beyond
/// [`MAX_EVALS`], therefore fail; L-BFGS turns a failed line search into a normal stop and keeps
/// its best point.
struct Problem<F> {
    f: F,
    evals: Cell<u64>,
    /// The best finite cost evaluated and its parameters.
    best: RefCell<Option<(Vec<f64>, f64)>>,
}

impl<F: Fn(&[f64]) -> f64> CostFunction for Problem<F> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> Result<f64, Error> {
        if !x.iter().all(|v| v.is_finite()) {
            return Err(Error::msg("non-finite parameters"));
        }
        let n = self.evals.get() + 1;
        self.evals.set(n);
        if n > MAX_EVALS {
            return Err(Error::msg("evaluation budget exhausted"));
        }
        // NaN (which argmin's comparisons mishandle) counts as +inf: never a minimum.
        let c = (self.f)(x);
        let c = if c.is_nan() { f64::INFINITY } else { c };
        if c.is_finite() {
            let mut best = self.best.borrow_mut();
            if best.as_ref().is_none_or(|(_, b)| c < *b) {
                *best = Some((x.clone(), c));
            }
        }
        Ok(c)
    }
}

impl<F: Fn(&[f64]) -> f64> Gradient for Problem<F> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;

    fn gradient(&self, x: &Vec<f64>) -> Result<Vec<f64>, Error> {
        let f = |x: &Vec<f64>| self.cost(x);
        finitediff::vec::central_diff(&f)(x)
    }
}

/// Minimises `f` from `x0` with the chosen optimiser: the solver's best point, or, if the
/// solver stopped with an error, the best point it evaluated.
pub fn minimize<F: Fn(&[f64]) -> f64>(
    f: F,
    x0: &[f64],
    optimizer: Optimizer,
) -> Result<Minimum, NoFiniteCost> {
    let problem = Problem {
        f,
        evals: Cell::new(0),
        best: RefCell::new(None),
    };
    let solved = run(&problem, x0, optimizer);
    let best = problem.best.borrow().clone();
    match (solved, best) {
        (Ok((Some(x), cost, iterations)), _) if cost.is_finite() => Ok(Minimum {
            x,
            cost,
            iterations,
        }),
        (solved, Some((x, cost))) => Ok(Minimum {
            x,
            cost,
            iterations: solved.map_or(0, |s| s.2),
        }),
        (_, None) => Err(NoFiniteCost {
            evaluations: problem.evals.get(),
        }),
    }
}

/// Runs the solver on `problem` from `x0`: its best parameters, cost and iterations.
fn run<F: Fn(&[f64]) -> f64>(
    problem: &Problem<F>,
    x0: &[f64],
    optimizer: Optimizer,
) -> Result<(Option<Vec<f64>>, f64, u64), Error> {
    let problem = Borrowed(problem);
    Ok(match optimizer {
        Optimizer::NelderMead => {
            let mut simplex = vec![x0.to_vec()];
            for i in 0..x0.len() {
                let mut v = x0.to_vec();
                v[i] += NM_STEP;
                simplex.push(v);
            }
            let solver = NelderMead::new(simplex).with_sd_tolerance(NM_SD_TOLERANCE)?;
            let res = Executor::new(problem, solver)
                .configure(|s| s.max_iters(MAX_ITERS))
                .run()?;
            let s = res.state();
            (s.get_best_param().cloned(), s.get_best_cost(), s.get_iter())
        }
        Optimizer::Lbfgs => {
            let solver = LBFGS::new(MoreThuenteLineSearch::new(), LBFGS_MEMORY)
                .with_tolerance_grad(LBFGS_TOL_GRAD)?
                .with_tolerance_cost(LBFGS_TOL_COST)?;
            let res = Executor::new(problem, solver)
                .configure(|s| s.param(x0.to_vec()).max_iters(MAX_ITERS))
                .run()?;
            let s = res.state();
            (s.get_best_param().cloned(), s.get_best_cost(), s.get_iter())
        }
    })
}

/// A borrowed [`Problem`], so that its record of evaluations outlives the solver.
struct Borrowed<'p, F>(&'p Problem<F>);

impl<F: Fn(&[f64]) -> f64> CostFunction for Borrowed<'_, F> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> Result<f64, Error> {
        self.0.cost(x)
    }
}

impl<F: Fn(&[f64]) -> f64> Gradient for Borrowed<'_, F> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;

    fn gradient(&self, x: &Vec<f64>) -> Result<Vec<f64>, Error> {
        self.0.gradient(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_optimizers_find_a_rosenbrock_minimum() {
        let f = |x: &[f64]| (1.0 - x[0]).powi(2) + 10.0 * (x[1] - x[0] * x[0]).powi(2);
        for opt in [Optimizer::NelderMead, Optimizer::Lbfgs] {
            let m = minimize(f, &[-0.5, 0.8], opt).unwrap();
            assert!((m.x[0] - 1.0).abs() < 1e-4, "{opt:?}: {:?}", m);
            assert!((m.x[1] - 1.0).abs() < 1e-4, "{opt:?}: {:?}", m);
        }
    }

    /// A flat cost (nothing to minimise), a NaN cost and a cost finite only near the start
    /// give a point or a typed error, never an argmin message.
    #[test]
    fn degenerate_costs_give_a_point_or_a_typed_error() {
        for opt in [Optimizer::NelderMead, Optimizer::Lbfgs] {
            let flat = minimize(|_: &[f64]| 1.0, &[0.3, 0.1], opt).unwrap();
            assert_eq!(flat.cost, 1.0, "{opt:?}");
            let nan = minimize(|_: &[f64]| f64::NAN, &[0.3], opt).unwrap_err();
            assert!(nan.evaluations > 0, "{opt:?}");
            let spike = |x: &[f64]| {
                if x[0].abs() < 1e-3 {
                    x[0] * x[0]
                } else {
                    f64::NAN
                }
            };
            let m = minimize(spike, &[0.0], opt).unwrap();
            assert!(m.cost.is_finite() && m.x[0].abs() < 1e-3, "{opt:?}: {m:?}");
        }
    }
}
