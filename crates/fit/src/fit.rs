//! Fitting a microfacet model to one sample: variable projection of the scale, multi-start
//! local minimisation over the shape, and heteroscedasticity-robust standard errors (sandwich)
//! at the optimum.
//!
//! The model is [`Model`]'s ([`crate::forward`] evaluates it). With orders `single` it is
//! Walter et al.'s analytic single-scattering BTDF with the masking of `FitOptions::masking`.
//! With orders `all` it is `f = f_single + f_multi`: `f_single` the analytic single-scattering
//! BTDF with height-correlated masking (exactly the random walk's order 1 term) and `f_multi`
//! the orders >= 2 estimate of `FitOptions::walks` random walks per incident direction, with a
//! fixed seed per direction for every evaluation (common random numbers), so the objective is
//! a deterministic, piecewise smooth function of the parameters. Nelder-Mead suits it; L-BFGS
//! works but is not recommended (its finite-difference gradients see the jumps). The search
//! starts from the optimum of the same model's single-scattering fit (multiple scattering is a
//! correction to it) instead of the starting grid. The standard errors do not include the Monte
//! Carlo error of `f_multi`.
//!
//! Search coordinates: `x0 = ln(alpha)` and, for Student-T with free gamma,
//! `x1 = ln(gamma - 3/2)`, so every point of the search space is a valid model. They are
//! clamped to `alpha in [ALPHA_MIN, ALPHA_MAX]` and `gamma - 3/2 in [GAMMA_EXCESS_MIN,
//! GAMMA_EXCESS_MAX]` (a fit that ends on such a bound says the data want a model outside the
//! family, e.g. Beckmann-like tails for Student-T).
//!
//! Standard errors (natural units of alpha, gamma, scale): with the residuals of the chosen loss
//! `r_j = sqrt(w_j) (y_j - T(scale * m_j(alpha, gamma)))` (`T = sqrt` or identity) and their
//! Jacobian `J` in `theta = (alpha, [gamma], scale)` (central finite differences in alpha and
//! gamma, analytic in scale), with `J_j` its row of point `j`, the covariance is the
//! heteroscedasticity-robust sandwich (White 1980, with MacKinnon and White's 1985 HC1
//! small-sample factor):
//!
//! ```text
//! Cov(theta) = n/(n-p) (J^T J)^{-1} (sum_j r_j^2 J_j^T J_j) (J^T J)^{-1},
//! ```
//!
//! `n` the number of fitted points and `p` the number of fitted parameters. Unlike the classical
//! `sigma^2 (J^T J)^{-1}` (`sigma^2 = RSS / (n - p)`), which assumes every residual has the same
//! variance, it stays calibrated when the noise varies from point to point (multiplicative
//! noise on `L` seen through the sqrt loss) and when the model misses some of the data
//! systematically (a stray-light floor no model reproduces); for equal noise it agrees with the
//! classical form up to sampling error.

use std::path::PathBuf;

use stfit_core::ParamError;
use stfit_core::bsdf::Masking;
use stfit_core::error::check_gamma;
use stfit_core::walk::ScatteringOrders;
use thiserror::Error;

use crate::conventions::{
    THETA_I_RANGE, THETA_O_RANGE, pair_from_deg, theta_i_in_range, theta_o_in_range,
};
use crate::data::{Dataset, Sample};
use crate::forward::Forward;
use crate::loss::{Projected, Projection, signed_sqrt};
use crate::model::{Gamma, Model, ModelKind, ModelSpec, all_models};
use crate::optimize::minimize;
use crate::options::{FitOptions, Loss};
use crate::result::FitResult;

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
/// Local optimisations are started from at most this many grid local minima.
const MAX_STARTS: usize = 3;

/// Why a fit could not be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FitError {
    /// Fewer usable points (finite, positive weight) than the fit needs.
    #[error(
        "sample `{sample}`: {n} usable points, a fit with {params} parameters needs at least {needed}"
    )]
    TooFewPoints {
        sample: String,
        n: usize,
        params: usize,
        needed: usize,
    },
    /// Every usable measured value is zero: nothing to fit.
    #[error("sample `{sample}`: every measured value is zero")]
    AllZero { sample: String },
    /// A measurement outside the model's domain.
    #[error("sample `{sample}`, point {index}: {reason}")]
    InvalidData {
        sample: String,
        index: usize,
        reason: String,
    },
    /// An invalid model parameter or option (gamma <= 3/2, eta <= 0, non-finite values).
    #[error("invalid parameter: {0}")]
    InvalidParameter(#[from] ParamError),
    /// A model specification that makes no sense (e.g. a fixed gamma for GGX).
    #[error("invalid model: {0}")]
    InvalidSpec(String),
    /// The model is zero at every point whatever its parameters.
    #[error("sample `{sample}`: no microfacet connects any measured pair of directions")]
    NoSignal { sample: String },
    /// The optimiser failed from every starting point.
    #[error("sample `{sample}`, model {model}: optimizer failed: {reason}")]
    Optimizer {
        sample: String,
        model: &'static str,
        reason: String,
    },
}

/// A fit of one sample of a dataset that failed, with where.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{}: sample '{sample}', model {model}: {error}", file.display())]
pub struct DatasetFitError {
    /// The data file.
    pub file: PathBuf,
    pub sample: String,
    /// The model, as [`ModelSpec::label`] names it.
    pub model: String,
    pub error: Box<FitError>,
}

/// A sample checked and precomputed once, fitted by several models.
#[derive(Clone)]
struct Prepared<'a> {
    sample: &'a Sample,
    forward: Forward,
    /// Measured `L` of the usable points.
    l: Vec<f64>,
    w: Vec<f64>,
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
        let (mut l, mut w) = (Vec::new(), Vec::new());
        for (index, p) in sample.points.iter().enumerate() {
            if !(p.weight.is_finite() && p.weight >= 0.0) {
                return Err(invalid(
                    index,
                    format!("weight must be finite and >= 0, got {}", p.weight),
                ));
            }
            if p.weight == 0.0 {
                continue;
            }
            if !p.l.is_finite() {
                return Err(invalid(index, format!("L must be finite, got {}", p.l)));
            }
            if !theta_i_in_range(p.theta_i_deg) {
                return Err(invalid(
                    index,
                    format!(
                        "theta_i must be in {THETA_I_RANGE} degrees, got {}",
                        p.theta_i_deg
                    ),
                ));
            }
            if !theta_o_in_range(p.theta_o_deg) {
                return Err(invalid(
                    index,
                    format!(
                        "theta_o must be in {THETA_O_RANGE} degrees, got {}",
                        p.theta_o_deg
                    ),
                ));
            }
            pairs.push(pair_from_deg(p.theta_i_deg, p.theta_o_deg));
            l.push(p.l);
            w.push(p.weight);
        }
        let forward = Forward::in_plane(
            &pairs,
            opts.eta,
            opts.masking,
            opts.orders,
            opts.walks,
            opts.seed,
        )?;
        Ok(Self {
            sample,
            forward,
            l,
            w,
        })
    }
}

/// The shape parameters searched for one model specification.
#[derive(Debug, Clone, Copy)]
struct Shape {
    kind: ModelKind,
    gamma: Gamma<()>,
}

impl Shape {
    fn new(spec: ModelSpec) -> Result<Self, FitError> {
        if let Gamma::Fixed(g) = spec.gamma() {
            check_gamma(g)?;
        }
        Ok(Self {
            kind: spec.kind(),
            gamma: spec.gamma(),
        })
    }

    /// Number of searched coordinates.
    fn dims(&self) -> usize {
        if self.gamma.is_free() { 2 } else { 1 }
    }

    /// `(alpha, gamma)` of search coordinates, clamped to the search box.
    fn params(&self, x: &[f64]) -> (f64, Gamma) {
        let alpha = x[0].clamp(ALPHA_MIN.ln(), ALPHA_MAX.ln()).exp();
        let gamma = match self.gamma {
            Gamma::NotApplicable => Gamma::NotApplicable,
            Gamma::Fixed(g) => Gamma::Fixed(g),
            Gamma::Free(()) => Gamma::Free(
                1.5 + x[1]
                    .clamp(GAMMA_EXCESS_MIN.ln(), GAMMA_EXCESS_MAX.ln())
                    .exp(),
            ),
        };
        (alpha, gamma)
    }

    fn coords(&self, alpha: f64, gamma: Gamma) -> Vec<f64> {
        match gamma {
            Gamma::Free(g) => vec![alpha.ln(), (g - 1.5).ln()],
            Gamma::NotApplicable | Gamma::Fixed(_) => vec![alpha.ln()],
        }
    }

    /// The model at `(alpha, gamma, scale)` with the physics of `opts`.
    fn model(&self, alpha: f64, gamma: Gamma, scale: f64, opts: &FitOptions) -> Model {
        let walks = opts.orders == ScatteringOrders::All;
        Model {
            kind: self.kind,
            alpha,
            gamma,
            scale,
            eta: opts.eta,
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
}

impl Evaluator<'_, '_> {
    /// Unit-scale model values at `(alpha, gamma)`.
    fn unit_model(&self, alpha: f64, gamma: Gamma, m: &mut Vec<f64>) -> Result<(), FitError> {
        let ndf = self.shape.model(alpha, gamma, 1.0, &self.opts).ndf()?;
        self.prep.forward.unit_model(&ndf, m)?;
        Ok(())
    }

    /// Reduced cost and best amplitude at `(alpha, gamma)`.
    fn project(&self, alpha: f64, gamma: Gamma) -> Result<Projection, FitError> {
        let mut m = Vec::with_capacity(self.prep.forward.len());
        self.unit_model(alpha, gamma, &mut m)?;
        Ok(self.proj.project(&m, &mut Vec::with_capacity(m.len())))
    }

    /// Reduced cost at search coordinates `x` (1, the zero model's cost, if the model is
    /// invalid there; the clamped box makes that unreachable).
    fn cost(&self, x: &[f64]) -> f64 {
        let (alpha, gamma) = self.shape.params(x);
        self.project(alpha, gamma).map_or(1.0, |p| p.cost)
    }

    /// Starting points: the grid points whose cost is below that of all grid neighbours, best
    /// first, at most [`MAX_STARTS`].
    fn starts(&self) -> Vec<Vec<f64>> {
        let gammas: Vec<Gamma> = match self.shape.gamma {
            Gamma::NotApplicable => vec![Gamma::NotApplicable],
            Gamma::Fixed(g) => vec![Gamma::Fixed(g)],
            Gamma::Free(()) => GAMMA_GRID.iter().map(|&g| Gamma::Free(g)).collect(),
        };
        let (na, ng) = (ALPHA_GRID.len(), gammas.len());
        let costs: Vec<f64> = gammas
            .iter()
            .flat_map(|&g| ALPHA_GRID.iter().map(move |&a| (a, g)))
            .map(|(a, g)| self.cost(&self.shape.coords(a, g)))
            .collect();
        let at = |i: usize, j: usize| costs[j * na + i];
        let mut minima: Vec<(f64, usize, usize)> = Vec::new();
        for j in 0..ng {
            for i in 0..na {
                let c = at(i, j);
                let lower = |di: isize, dj: isize| {
                    let (ii, jj) = (i as isize + di, j as isize + dj);
                    if ii < 0 || jj < 0 || ii >= na as isize || jj >= ng as isize {
                        false
                    } else {
                        at(ii as usize, jj as usize) < c
                    }
                };
                if !(lower(-1, 0) || lower(1, 0) || lower(0, -1) || lower(0, 1)) {
                    minima.push((c, i, j));
                }
            }
        }
        minima.sort_by(|a, b| a.0.total_cmp(&b.0));
        minima
            .iter()
            .take(MAX_STARTS)
            .map(|&(_, i, j)| self.shape.coords(ALPHA_GRID[i], gammas[j]))
            .collect()
    }
}

/// Fits one model to one sample.
pub fn fit_sample(
    sample: &Sample,
    spec: ModelSpec,
    opts: &FitOptions,
) -> Result<FitResult, FitError> {
    let shape = Shape::new(spec)?;
    let prep = Prepared::new(sample, opts)?;
    fit_prepared(&prep, shape, opts)
}

/// Fits the four models of [`all_models`] to one sample.
pub fn fit_all(sample: &Sample, opts: &FitOptions) -> Result<Vec<FitResult>, FitError> {
    let prep = Prepared::new(sample, opts)?;
    all_models()
        .into_iter()
        .map(|spec| fit_prepared(&prep, Shape::new(spec)?, opts))
        .collect()
}

/// Fits every model of `specs` to every sample of `data` (in file order, then in the order of
/// `specs`), recording the data file in each result, and calls `progress(done, total)` after
/// each fit. Stops at the first fit that fails, saying which.
pub fn fit_dataset(
    data: &Dataset,
    specs: &[ModelSpec],
    opts: &FitOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<FitResult>, DatasetFitError> {
    let total = data.samples.len() * specs.len();
    let mut fits = Vec::with_capacity(total);
    for sample in &data.samples {
        let fail = |spec: &ModelSpec, error| DatasetFitError {
            file: data.source.clone(),
            sample: sample.name.clone(),
            model: spec.label(),
            error: Box::new(error),
        };
        let prep = match Prepared::new(sample, opts) {
            Ok(p) => p,
            Err(e) => return Err(fail(&specs[0], e)),
        };
        for spec in specs {
            let mut fit = Shape::new(*spec)
                .and_then(|shape| fit_prepared(&prep, shape, opts))
                .map_err(|e| fail(spec, e))?;
            fit.data = Some(data.source.display().to_string());
            fits.push(fit);
            progress(fits.len(), total);
        }
    }
    Ok(fits)
}

fn fit_prepared(prep: &Prepared, shape: Shape, opts: &FitOptions) -> Result<FitResult, FitError> {
    let sample = &prep.sample.name;
    let n = prep.l.len();
    let p = shape.dims() + 1;
    if n < p + 1 {
        return Err(FitError::TooFewPoints {
            sample: sample.clone(),
            n,
            params: p,
            needed: p + 1,
        });
    }
    if prep.l.iter().all(|&l| l == 0.0) {
        return Err(FitError::AllZero {
            sample: sample.clone(),
        });
    }
    let eval = Evaluator {
        prep,
        proj: Projected::new(opts.loss, &prep.l, &prep.w),
        shape,
        opts: *opts,
    };

    let mut best: Option<crate::optimize::Minimum> = None;
    let mut iterations = 0;
    let mut last_err = None;
    let starts = if prep.forward.has_walks() {
        // Multiple scattering is a correction to single scattering: start from the optimum of
        // the same model's single-scattering fit (height-correlated masking, the walk's order 1).
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
        vec![shape.coords(r.model.alpha, r.model.gamma)]
    } else {
        eval.starts()
    };
    for x0 in starts {
        match minimize(|x| eval.cost(x), &x0, opts.optimizer) {
            Ok(m) => {
                iterations += m.iterations;
                if best.as_ref().is_none_or(|b| m.cost < b.cost) {
                    best = Some(m);
                }
            }
            Err(e) => last_err = Some(e),
        }
    }
    let best = best.ok_or_else(|| FitError::Optimizer {
        sample: sample.clone(),
        model: shape.kind.name(),
        reason: last_err.map_or_else(|| "no starting point".into(), |e| e.to_string()),
    })?;

    let (alpha, gamma) = shape.params(&best.x);
    let mut m = Vec::new();
    eval.unit_model(alpha, gamma, &mut m)?;
    let projection = eval.proj.project(&m, &mut Vec::new());
    if m.iter().all(|&m| m == 0.0) {
        return Err(FitError::NoSignal {
            sample: sample.clone(),
        });
    }
    let scale = eval.proj.scale_of(projection.amplitude);
    let rmse_sqrt_l = (prep
        .l
        .iter()
        .zip(&m)
        .map(|(&l, &m)| (signed_sqrt(l) - (scale * m).sqrt()).powi(2))
        .sum::<f64>()
        / n as f64)
        .sqrt();
    let stderr = standard_errors(&eval, alpha, gamma, scale, &m)?;
    let known = |se: f64| se.is_finite().then_some(se);
    Ok(FitResult {
        sample: sample.clone(),
        model: shape.model(alpha, gamma, scale, opts),
        loss: opts.loss,
        optimizer: opts.optimizer,
        rmse_sqrt_l,
        n_points: n,
        alpha_stderr: known(stderr[0]),
        gamma_stderr: if shape.gamma.is_free() {
            known(stderr[1])
        } else {
            None
        },
        scale_stderr: known(stderr[stderr.len() - 1]),
        iterations,
        data: None,
        stfit_version: env!("CARGO_PKG_VERSION").to_owned(),
    })
}

/// Standard errors of `(alpha, [gamma], scale)` as in the module docs; `NaN` where the
/// curvature does not determine a parameter.
fn standard_errors(
    eval: &Evaluator,
    alpha: f64,
    gamma: Gamma,
    scale: f64,
    m: &[f64],
) -> Result<Vec<f64>, FitError> {
    let loss = eval.opts.loss;
    let t = |x: f64| Projected::transform(loss, x);
    let n = m.len();
    let sw: Vec<f64> = eval.proj.w.iter().map(|w| w.sqrt()).collect();

    // Columns of J (up to sign): d T(scale m_j) / d theta_k, times sqrt(w_j).
    let mut cols: Vec<Vec<f64>> = Vec::new();
    let mut fd_column = |a_plus: (f64, Gamma), a_minus: (f64, Gamma), h2: f64| {
        let (mut mp, mut mm) = (Vec::new(), Vec::new());
        eval.unit_model(a_plus.0, a_plus.1, &mut mp)?;
        eval.unit_model(a_minus.0, a_minus.1, &mut mm)?;
        cols.push(
            (0..n)
                .map(|j| sw[j] * (t(scale * mp[j]) - t(scale * mm[j])) / h2)
                .collect(),
        );
        Ok::<(), FitError>(())
    };
    // With the walk's orders >= 2 the model is piecewise smooth in the parameters (a walk's
    // discrete choices switch as they change): a wider step averages over those jumps.
    let rel_step = if eval.prep.forward.has_walks() {
        1e-2
    } else {
        1e-4
    };
    let ha = rel_step * alpha;
    fd_column((alpha + ha, gamma), (alpha - ha, gamma), 2.0 * ha)?;
    if let Gamma::Free(g) = gamma {
        let hg = rel_step * (g - 1.5);
        fd_column(
            (alpha, Gamma::Free(g + hg)),
            (alpha, Gamma::Free(g - hg)),
            2.0 * hg,
        )?;
    }
    cols.push(
        (0..n)
            .map(|j| {
                sw[j]
                    * match loss {
                        Loss::Sqrt => m[j].sqrt() / (2.0 * scale.sqrt()),
                        Loss::Linear => m[j],
                    }
            })
            .collect(),
    );

    let p = cols.len();
    let residuals: Vec<f64> = (0..n)
        .map(|j| sw[j] * (eval.proj.y[j] - t(scale * m[j])))
        .collect();
    Ok(sandwich_covariance(&cols, &residuals).map_or_else(
        || vec![f64::NAN; p],
        |cov| (0..p).map(|k| cov[k][k].sqrt()).collect(),
    ))
}

/// The HC1 heteroscedasticity-robust covariance of least-squares estimates,
/// `n/(n-p) (J^T J)^{-1} (sum_j r_j^2 J_j^T J_j) (J^T J)^{-1}`, from the Jacobian columns
/// `cols[k][j] = d r_j / d theta_k` (up to a common sign) and the residuals `r_j` at the
/// optimum; `None` if `J^T J` is numerically singular.
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
    let meat = outer(&|j| r[j] * r[j]);
    let dof = n as f64 / (n - p) as f64;
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
                        dof * s
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
