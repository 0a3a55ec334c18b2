//! Student-T with the continued fractions of Lambda interpolated: [`TabulatedStudentT`].
//!
//! For one NDF, Lambda's two incomplete-beta continued fractions are functions of one variable
//! each: `L(x) = beta_cf(nu/2, 1/2; x) = 2F1(a + 1/2, 1; a + 1; x)` below the switch point
//! `x_s = (a+1)/(a+2.5)` and `U(u) = beta_cf(1/2, nu/2; u) = 2F1(a + 1/2, 1; 3/2; u)` for
//! `u = 1 - x <= u_s = 1 - x_s` (`a = nu/2`). Both are analytic on the plane cut along
//! `[1, inf)`, so on a panel `[c - h, c + h]` whose distance to 1 is several half-widths an
//! interpolant at Chebyshev nodes converges geometrically, at the rate `rho^-n` of the
//! Bernstein ellipse through the branch point 1.
//! - `L` is tabulated in `u = 1 - x` on the binades `[2^-(j+1), 2^-j]` down to `u_s`, each cut
//!   into [`SUB`] equal panels: the nearest panel to the branch point `u = 0` has it at `2 SUB + 1
//!   = 9` half-widths, `rho = 17.9`.
//! - `U` is tabulated on [`UPPER_PANELS`] equal panels of `[0, u_s]` (`u_s < 1/2`, so 1 is at least
//!   9 half-widths away); their width `u_s / 4 < 0.4 / a` also keeps the `(1 - u)^-a` growth of
//!   `U` for large `a` below a factor 1.5 per panel.
//!
//! Each panel holds the [`COEFFS`] monomial coefficients, in the panel's variable
//! `t in [-1, 1]`, of the interpolant at `COEFFS` Chebyshev nodes of the exact fractions, and
//! is evaluated by Horner's rule: 12 multiply-adds against the 2 to 40 steps of the continued
//! fraction, with no division and no convergence test. The panel of `u` comes from its
//! exponent and leading mantissa bits; `t` from its mantissa, exactly.

use super::{BetaFractions, StudentT, beta_cf};
use crate::math::Vec3;
use crate::ndf::Ndf;
use rand::Rng;
use std::f64::consts::PI;

/// Coefficients per panel (degree 11): 10 leave 2e-13, 12 to 16 the exact fractions' own
/// rounding.
const COEFFS: usize = 12;

/// Panels per binade of `u` for the lower fraction.
const SUB: usize = 4;

/// Panels of `[0, u_s]` for the upper fraction.
const UPPER_PANELS: usize = 4;

/// Monomial coefficients of one panel's interpolant in `t in [-1, 1]`, constant term first.
type Panel = [f64; COEFFS];

/// The interpolated fractions of one Student-T NDF.
#[derive(Debug, Clone, PartialEq)]
struct FractionTable {
    /// Lower fraction: panel `SUB j + s` covers `u = 2^-(j+1) (1 + (s + (t+1)/2) / SUB)`.
    lower: Vec<Panel>,
    /// Upper fraction: panel `p` covers `u = (p + (t+1)/2) u_s / UPPER_PANELS`.
    upper: [Panel; UPPER_PANELS],
    /// `UPPER_PANELS / u_s`.
    upper_scale: f64,
}

impl FractionTable {
    /// The table of `ndf`'s fractions.
    fn new(ndf: &StudentT) -> Self {
        // 1 - x at the switch point: the end of the lower fraction's range in u and of the
        // upper fraction's.
        let u_s = 1.0 - ndf.x_switch;
        // Binades [2^-(j+1), 2^-j] that reach above u_s.
        let mut binades = 0;
        while 0.5f64.powi(binades) > u_s {
            binades += 1;
        }
        let mut lower = Vec::with_capacity(binades as usize * SUB);
        for j in 0..binades {
            let base = 0.5f64.powi(j + 1);
            for s in 0..SUB {
                lower.push(interpolate(|t| {
                    let u = base * (1.0 + (s as f64 + 0.5 * (t + 1.0)) / SUB as f64);
                    beta_cf(&ndf.cf_lower, 1.0 - u)
                }));
            }
        }
        let width = u_s / UPPER_PANELS as f64;
        let upper = std::array::from_fn(|p| {
            interpolate(|t| beta_cf(&ndf.cf_upper, width * (p as f64 + 0.5 * (t + 1.0))))
        });
        Self {
            lower,
            upper,
            upper_scale: 1.0 / width,
        }
    }
}

/// Monomial coefficients in `t` of the polynomial of degree `COEFFS - 1` that interpolates
/// `f` at the Chebyshev nodes `cos(pi (i + 1/2) / COEFFS)`: Chebyshev coefficients by the
/// discrete cosine transform, then `T_k` expanded by `T_k+1 = 2t T_k - T_k-1` (integer
/// coefficients, exact in f64).
fn interpolate(f: impl Fn(f64) -> f64) -> Panel {
    let n = COEFFS as f64;
    let angle = |i: usize| PI * (i as f64 + 0.5) / n;
    let values: Vec<f64> = (0..COEFFS).map(|i| f(angle(i).cos())).collect();
    let cheb: Vec<f64> = (0..COEFFS)
        .map(|k| {
            let sum: f64 = (0..COEFFS)
                .map(|i| values[i] * (k as f64 * angle(i)).cos())
                .sum();
            sum * if k == 0 { 1.0 / n } else { 2.0 / n }
        })
        .collect();
    let mut out = [0.0; COEFFS];
    let (mut prev, mut cur) = ([0.0; COEFFS], [0.0; COEFFS]);
    prev[0] = 1.0; // T_0
    cur[1] = 1.0; // T_1
    for (k, &c) in cheb.iter().enumerate() {
        let t_k = match k {
            0 => prev,
            1 => cur,
            _ => {
                let mut next = [0.0; COEFFS];
                for d in 0..COEFFS {
                    let up = if d > 0 { 2.0 * cur[d - 1] } else { 0.0 };
                    next[d] = up - prev[d];
                }
                (prev, cur) = (cur, next);
                cur
            }
        };
        for (o, t) in out.iter_mut().zip(t_k) {
            *o += c * t;
        }
    }
    out
}

/// `sum_k coeffs[k] t^k` by Horner's rule.
#[inline]
fn horner(coeffs: &Panel, t: f64) -> f64 {
    coeffs.iter().rev().fold(0.0, |acc, &c| acc * t + c)
}

impl BetaFractions for FractionTable {
    #[inline]
    fn lower(&self, _x: f64, u: f64) -> f64 {
        // u = 2^e * m with m in [1, 2); binade j = -1 - e, clamped to the table (u = 1 is the
        // top of binade 0, rounding may leave u a hair below u_s).
        let e = ((u.to_bits() >> 52) & 0x7ff) as i64 - 1023;
        let j = ((-1 - e).max(0) as usize).min(self.lower.len() / SUB - 1);
        // u 2^(j+1) in [1, 2], exactly (a power-of-two scaling).
        let m = u * f64::from_bits((1023 + j as u64 + 1) << 52);
        let z = (m - 1.0) * SUB as f64;
        let s = (z as usize).min(SUB - 1);
        horner(&self.lower[j * SUB + s], 2.0 * (z - s as f64) - 1.0)
    }

    #[inline]
    fn upper(&self, u: f64) -> f64 {
        let z = u * self.upper_scale;
        let p = (z as usize).min(UPPER_PANELS - 1);
        horner(&self.upper[p], 2.0 * (z - p as f64) - 1.0)
    }
}

/// A [`StudentT`] whose Lambda and sigma take the two incomplete-beta continued fractions from
/// piecewise polynomial interpolants built once (12 coefficients per panel, interpolating at
/// Chebyshev nodes), for batches of many directions: D and the sampler are the NDF's own.
///
/// Agrees with [`StudentT`]'s exact fractions to a few ulps (the interpolants are built
/// from them). Building evaluates the exact fractions about 140 times at gamma 2.8 (19 us,
/// criterion median of `cargo bench -p stfit-core --bench ndf -- build`), and Lambda at gamma
/// 2.8 and 60 degrees then takes 28.6 ns instead of 54.9 ns, so it pays from a few thousand
/// Lambda evaluations with one NDF. For gamma above [`TabulatedStudentT::MAX_GAMMA`] it is the
/// exact NDF, whose Lambda there comes from a Gauss rule, not from the fractions.
///
/// ```
/// use stfit_core::ndf::{Ndf, StudentT, TabulatedStudentT};
/// use stfit_core::Vec3;
///
/// let st = StudentT::new(0.45, 2.8)?;
/// let fast = TabulatedStudentT::new(st);
/// let w = Vec3::new(0.8, 0.0, 0.6);
/// assert!((fast.lambda(w) / st.lambda(w) - 1.0).abs() < 1e-14);
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct TabulatedStudentT {
    ndf: StudentT,
    table: Option<FractionTable>,
}

impl TabulatedStudentT {
    /// Shapes above this one have no table: [`StudentT`] computes Lambda there by a Gauss
    /// rule over its Gamma superposition ([`StudentT::QUADRATURE_GAMMA`]), not by the continued
    /// fractions that a table would interpolate (they lose up to 3.4e-7 of Lambda by gamma
    /// 1e8; the table of gamma 1e3 took 132 us to build and matched them, not Lambda).
    pub const MAX_GAMMA: f64 = StudentT::QUADRATURE_GAMMA;

    /// The tabulated form of `ndf`.
    pub fn new(ndf: StudentT) -> Self {
        let table =
            (ndf.gamma <= Self::MAX_GAMMA && ndf.limit.is_none()).then(|| FractionTable::new(&ndf));
        Self { ndf, table }
    }

    /// The NDF.
    pub fn ndf(&self) -> &StudentT {
        &self.ndf
    }
}

impl Ndf for TabulatedStudentT {
    #[inline]
    fn d(&self, wm: Vec3) -> f64 {
        self.ndf.d(wm)
    }

    #[inline]
    fn lambda(&self, w: Vec3) -> f64 {
        match &self.table {
            Some(t) => self.ndf.lambda_by(w, t),
            None => self.ndf.lambda(w),
        }
    }

    #[inline]
    fn sigma(&self, w: Vec3) -> f64 {
        match &self.table {
            Some(t) => self.ndf.sigma_by(w, t),
            None => self.ndf.sigma(w),
        }
    }

    #[inline]
    fn sample_visible<R: Rng + ?Sized>(&self, w: Vec3, rng: &mut R) -> Vec3 {
        self.ndf.sample_visible(w, rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interpolated fractions against the exact ones over a dense sweep of each
    /// fraction's whole range, for shapes from near 3/2 to 1e3 (beyond `MAX_GAMMA`, where no table
    /// is built any more, as a check of the interpolation itself). The differences are the
    /// exact fractions' own rounding (they stay the same with 16 coefficients as with 12): a
    /// few ulps, growing for the lower fraction with gamma as its steps grow and as its
    /// argument `x = 1 - u` nears 1, where an ulp of `x` is a larger part of `1 - x`.
    #[test]
    fn interpolants_match_the_exact_fractions() {
        for (gamma, tol) in [
            (1.51, 1e-14),
            (1.6, 1e-14),
            (2.0, 1e-14),
            (2.8, 1e-14),
            (3.0, 1e-14),
            (4.5, 1e-14),
            (7.5, 1e-14),
            (10.0, 1e-14),
            (33.3, 3e-14),
            (100.0, 1e-13),
            (400.0, 3e-13),
            (1e3, 6e-13),
        ] {
            let st = StudentT::new(0.45, gamma).unwrap();
            let table = FractionTable::new(&st);
            let u_s = 1.0 - st.x_switch;
            let (mut worst_lower, mut worst_upper) = (0.0f64, 0.0f64);
            for i in 0..=20_000 {
                // u from 1 down to u_s, log-spaced, for the lower fraction.
                let u = (u_s.ln() * i as f64 / 20_000.0).exp();
                let x = 1.0 - u;
                if x < st.x_switch {
                    let exact = beta_cf(&st.cf_lower, x);
                    worst_lower = worst_lower.max((table.lower(x, u) / exact - 1.0).abs());
                }
                let v = u_s * i as f64 / 20_000.0;
                let exact = beta_cf(&st.cf_upper, v);
                worst_upper = worst_upper.max((table.upper(v) / exact - 1.0).abs());
            }
            assert!(
                worst_lower < tol && worst_upper < 1e-14,
                "gamma {gamma}: lower {worst_lower:e}, upper {worst_upper:e}"
            );
        }
    }

    /// Lambda and sigma of the tabulated NDF equal the exact NDF's over directions from the
    /// pole to below the horizon, to `1e-13 (1 + k^2)` with `k = |cot| / s`: in the tail the two
    /// terms of `excess` cancel to `1/k^2` of their size, which scales the fractions' few-ulp
    /// differences. At gamma 1000 the two terms also cancel near the horizon, and both forms
    /// are off by about 5e-13 (sigma at z = -0.648: mpmath 2.8328388000062923e-4, exact
    /// 2.8328388000048920e-4, tabulated 2.8328388000079060e-4: both were the fractions then;
    /// now both are the Gauss rule), so the bound is 1e-12 there. Above `MAX_GAMMA` it is the
    /// exact NDF.
    #[test]
    fn lambda_and_sigma_match_the_exact_ndf() {
        for gamma in [1.6, 2.0, 2.8, 3.0, 7.5, 50.0, 1e3, 2e3] {
            let st = StudentT::new(0.45, gamma).unwrap();
            let fast = TabulatedStudentT::new(st);
            assert_eq!(fast.table.is_none(), gamma > TabulatedStudentT::MAX_GAMMA);
            for i in 0..=2000 {
                let z = -1.0 + 2.0 * i as f64 / 2000.0;
                let sin = (1.0 - z * z).sqrt();
                let w = Vec3::new(sin, 0.0, z);
                let k = z.abs() / (sin * 0.45 * std::f64::consts::FRAC_1_SQRT_2);
                let tol = if gamma > 100.0 { 1e-12 } else { 1e-13 } * (1.0 + k * k);
                for (a, b, what) in [
                    (fast.lambda(w), st.lambda(w), "Lambda"),
                    (fast.sigma(w), st.sigma(w), "sigma"),
                ] {
                    assert!(
                        a == b || ((a - b) / b).abs() < tol,
                        "gamma {gamma}, z {z}: {what} {a} against {b}"
                    );
                }
            }
        }
    }
}
