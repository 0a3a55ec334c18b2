//! Local minimisation of a smooth cost over unbounded `Vec<f64>` parameters with argmin:
//! Nelder-Mead, or L-BFGS with a More-Thuente line search and central finite-difference
//! gradients.

use std::cell::Cell;

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
        Ok((self.f)(x))
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

/// Minimises `f` from `x0` with the chosen optimiser.
pub fn minimize<F: Fn(&[f64]) -> f64>(
    f: F,
    x0: &[f64],
    optimizer: Optimizer,
) -> Result<Minimum, Error> {
    let problem = Problem {
        f,
        evals: Cell::new(0),
    };
    let (x, cost, iterations) = match optimizer {
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
    };
    let x = x.ok_or_else(|| Error::msg("optimizer returned no parameters"))?;
    Ok(Minimum {
        x,
        cost,
        iterations,
    })
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
}
