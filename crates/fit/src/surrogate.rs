//! A quadratic surrogate of the orders >= 2 term of an all-orders fit, in the fit's search
//! coordinates `x` (`ln alpha`, `ln(gamma - 3/2)`, `ln(eta - 1)`, those that are searched).
//!
//! The walk estimate of the term (the exact estimator, [`crate::forward::Forward::walk_term`])
//! costs one set of walks per incident direction; a fit evaluates its cost a few hundred times.
//! The term is smooth in the parameters and a small correction to single scattering, so the fit
//! instead interpolates, for every configuration `j`, the walk estimates at `1 + 2p + p(p-1)/2`
//! parameter points (`p` searched coordinates) around a centre `c` with steps `h`:
//!
//! ```text
//! f_j(c + u h) = a_j + sum_i b_ji u_i + sum_i d_ji u_i^2 + sum_{i<k} e_jik u_i u_k
//! ```
//!
//! at the nodes `u = 0`, `u = +-e_i` and `u = e_i + e_k` (`e_i` the unit vectors), which fix the
//! coefficients exactly:
//! `a = f(0)`, `b_i = (f(e_i) - f(-e_i))/2`, `d_i = (f(e_i) + f(-e_i))/2 - f(0)`,
//! `e_ik = f(e_i + e_k) - a - b_i - b_k - d_i - d_k`. Every node uses the same random numbers
//! (the walks are seeded per incident direction), so the surrogate is a smooth, deterministic
//! function whose node values are exactly the slow estimator's. Inside the nodes' span
//! (`|u_i| <= 1`) its interpolation error is third order in `h`; the fit recentres it at its
//! optimum until the optimum lies inside (`crate::fit`).

use rayon::prelude::*;

use crate::fit::FitError;
use crate::forward::WalkTerm;

/// The nodes of the quadratic design in `p` dimensions, in units of the steps: the centre, the
/// `2p` axis points `+-e_i`, and the `p(p-1)/2` diagonal points `e_i + e_k`, in that order.
pub(crate) fn nodes(p: usize) -> Vec<Vec<f64>> {
    let unit = |i: usize, s: f64| {
        let mut u = vec![0.0; p];
        u[i] = s;
        u
    };
    let mut out = vec![vec![0.0; p]];
    for i in 0..p {
        out.push(unit(i, 1.0));
        out.push(unit(i, -1.0));
    }
    for i in 0..p {
        for k in i + 1..p {
            let mut u = unit(i, 1.0);
            u[k] = 1.0;
            out.push(u);
        }
    }
    out
}

/// The quadratic surrogate of the orders >= 2 term of every configuration (module docs).
#[derive(Debug, Clone)]
pub struct Surrogate {
    center: Vec<f64>,
    step: Vec<f64>,
    /// Per configuration: `a`, then `b_i`, then `d_i`, then `e_ik` (`i < k`, row-major).
    coef: Vec<Vec<f64>>,
}

impl Surrogate {
    /// The surrogate around `center` with `step`s, from `term(x)`, the walk term at search
    /// coordinates `x` (evaluated at every node, in parallel).
    pub fn build(
        center: &[f64],
        step: &[f64],
        term: impl Fn(&[f64]) -> Result<WalkTerm, FitError> + Sync,
    ) -> Result<Self, FitError> {
        let p = center.len();
        assert_eq!(step.len(), p, "one step per coordinate");
        let at: Vec<Vec<f64>> = nodes(p)
            .iter()
            .map(|u| (0..p).map(|i| center[i] + u[i] * step[i]).collect())
            .collect();
        let values: Vec<Vec<f64>> = at
            .par_iter()
            .map(|x| term(x).map(|t| t.values))
            .collect::<Result<_, _>>()?;
        let n = values[0].len();
        let coef = (0..n)
            .map(|j| {
                let f = |node: usize| values[node][j];
                let a = f(0);
                let b: Vec<f64> = (0..p)
                    .map(|i| (f(1 + 2 * i) - f(2 + 2 * i)) / 2.0)
                    .collect();
                let d: Vec<f64> = (0..p)
                    .map(|i| (f(1 + 2 * i) + f(2 + 2 * i)) / 2.0 - a)
                    .collect();
                let mut c = vec![a];
                c.extend(&b);
                c.extend(&d);
                let mut node = 1 + 2 * p;
                for i in 0..p {
                    for k in i + 1..p {
                        c.push(f(node) - a - b[i] - b[k] - d[i] - d[k]);
                        node += 1;
                    }
                }
                c
            })
            .collect();
        Ok(Self {
            center: center.to_vec(),
            step: step.to_vec(),
            coef,
        })
    }

    /// The design's coordinates `u = (x - center) / step`.
    fn units(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(&self.center)
            .zip(&self.step)
            .map(|((x, c), h)| (x - c) / h)
            .collect()
    }

    /// Whether `x` lies in the span of the nodes (`|u_i| <= 1`), where the surrogate
    /// interpolates rather than extrapolates.
    pub fn spans(&self, x: &[f64]) -> bool {
        self.units(x).iter().all(|u| u.abs() <= 1.0 + 1e-12)
    }

    /// Adds the surrogate term at search coordinates `x` to `out` (one value per
    /// configuration).
    pub fn add_to(&self, x: &[f64], out: &mut [f64]) {
        let u = self.units(x);
        let p = u.len();
        // The basis in the order of the coefficients.
        let mut basis = vec![1.0];
        basis.extend(&u);
        basis.extend(u.iter().map(|u| u * u));
        for i in 0..p {
            for k in i + 1..p {
                basis.push(u[i] * u[k]);
            }
        }
        for (o, c) in out.iter_mut().zip(&self.coef) {
            *o += c.iter().zip(&basis).map(|(c, b)| c * b).sum::<f64>();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The design reproduces every quadratic exactly, at and between the nodes, in one to
    /// three dimensions.
    #[test]
    fn quadratics_are_reproduced() {
        for p in 1..=3 {
            let center = vec![0.3; p];
            let step = vec![0.1; p];
            // f_j(x) = j + sum_i (i+1) x_i + sum_i x_i^2 + x_0 x_last.
            let f = |x: &[f64], j: usize| {
                j as f64
                    + x.iter()
                        .enumerate()
                        .map(|(i, x)| (i + 1) as f64 * x + x * x)
                        .sum::<f64>()
                    + if p > 1 { x[0] * x[p - 1] } else { 0.0 }
            };
            let s = Surrogate::build(&center, &step, |x| {
                let values = (0..3).map(|j| f(x, j)).collect();
                Ok(WalkTerm {
                    values,
                    group: vec![0; 3],
                    batches: vec![vec![]; 3],
                    batch_walks: vec![],
                })
            })
            .unwrap();
            for x in [vec![0.3; p], vec![0.35; p], vec![0.22; p]] {
                let mut out = vec![0.0; 3];
                s.add_to(&x, &mut out);
                for (j, o) in out.iter().enumerate() {
                    assert!((o - f(&x, j)).abs() < 1e-12, "p {p} x {x:?}: {o}");
                }
                assert!(s.spans(&x));
            }
            assert!(!s.spans(&vec![0.45; p]));
        }
    }
}
