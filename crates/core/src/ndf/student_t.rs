//! The Student-T NDF of Ribardiere et al. 2017 in d'Eon's (alpha, gamma) parameterisation.

use super::Beckmann;
use super::beckmann::{open_uniform, sample_visible_beckmann, sample_visible_beckmann_in_frame};
use super::special::{FRAC_1_SQRT_PI, erfc_and_gauss, erfcx_gap};
use super::{Ndf, cos2_sin2, lambda_on_sphere};
use crate::error::{ParamError, check_alpha, check_gamma};
use crate::math::Vec3;
use rand::Rng;
use rand_distr::{Distribution, Gamma};
use std::f64::consts::{FRAC_1_SQRT_2, PI};

mod table;
pub use table::TabulatedStudentT;

/// Student-T: `D(u) = (g-1)^g alpha^(2g-2) / (pi u^4 (alpha^2 (g-1) + tan^2 theta)^g)` with
/// shape `g = gamma > 3/2`. Slopes along one axis are `(alpha/sqrt 2) T_nu`, `nu = 2g - 2`.
/// `gamma = 2` is GGX; `gamma -> inf` tends to Beckmann with the same alpha, within a relative
/// `O(x^2 / gamma)` (`x = tan^2 theta / alpha^2`): above [`StudentT::BECKMANN_LIMIT`] (1e8),
/// where that is below 5e-6 for every normal that matters, D, Lambda, sigma and the sampler
/// are Beckmann's. Below it, the logarithms are `log1p` for gamma > 1e3, the ratios of Gamma
/// functions asymptotic for large arguments, and Lambda and sigma for gamma above
/// [`StudentT::QUADRATURE_GAMMA`] a Gauss rule over the Gamma superposition, so that no digit
/// is lost on the way to the limit.
///
/// ```
/// use stfit_core::ndf::{Ggx, Ndf, StudentT};
/// use stfit_core::Vec3;
///
/// // gamma = 2 is exactly GGX; larger gamma shortens the tail toward Beckmann.
/// let st = StudentT::new(0.4, 2.0)?;
/// let ggx = Ggx::new(0.4)?;
/// let wm = Vec3::new(0.6, 0.0, 0.8);
/// assert!((st.d(wm) / ggx.d(wm) - 1.0).abs() < 1e-12);
/// let w = Vec3::new(0.9, 0.0, (1.0f64 - 0.81).sqrt());
/// assert!((st.lambda(w) / ggx.lambda(w) - 1.0).abs() < 1e-10);
/// // The shape must exceed 3/2 (a finite mean slope).
/// assert!(StudentT::new(0.4, 1.5).is_err());
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudentT {
    alpha: f64,
    gamma: f64,
    /// `1 / (pi alpha^2)`: `D(u) = d_scale / u^4 * (1 + tan^2 / ((g-1) alpha^2))^-g`.
    d_scale: f64,
    /// `1 / ((g-1) alpha^2)`.
    inv_a2g1: f64,
    /// Degrees of freedom `nu = 2g - 2` of the 1D slope distribution.
    nu: f64,
    /// `1 / nu` and `1 / (nu - 1)`.
    inv_nu: f64,
    inv_nu_m1: f64,
    /// Student t pdf at 0: `Gamma((nu+1)/2) / (sqrt(nu pi) Gamma(nu/2)) = 1 / (sqrt(nu) B(nu/2, 1/2))`.
    t_norm: f64,
    /// `alpha sqrt(g-1)`: `alpha_m = alpha sqrt(g-1) / sqrt(m)` in the Gamma superposition.
    alpha_g1: f64,
    /// Weight constant of part 1 of the tilted mixing density (theory section 4):
    /// `W1 = s * w1_scale / (1+k)^(g-3/2)`.
    w1_scale: f64,
    /// `(a + 1) / (a + 2.5)` with `a = nu/2`: below it `I_x(a, 1/2)` takes the lower
    /// continued fraction, above it the upper one (`x = nu / (nu + k^2)`).
    x_switch: f64,
    /// Coefficients of the continued fractions of `I_x(nu/2, 1/2)` and `I_(1-x)(1/2, nu/2)`.
    cf_lower: CfCoefficients,
    cf_upper: CfCoefficients,
    /// `Gamma(g-1, 1)`: the mixing density of the superposition.
    mix: Gamma<f64>,
    /// `Gamma(g-3/2 (+1 if g-3/2 < 1), 1)`: part 1, boosted to shape >= 1 so that tiny `m`
    /// can be drawn in log space.
    part1: Gamma<f64>,
    /// `Gamma(g-5/2, 1)` for gamma >= 7/2: the proposal of the sampler below the horizon
    /// where the visibility gap is small (see [`StudentT::sample_visible`]).
    below: Option<Gamma<f64>>,
    /// gamma > 1e3: `ln(1 + x)` by `log1p`, whose rounding is not multiplied by gamma.
    exact_log: bool,
    /// gamma itself for an integer gamma up to [`StudentT::MAX_POWER`]: the powers of D and
    /// of the Student t pdf are then integer powers (and a square root), not `exp(g ln ...)`.
    int_gamma: Option<i32>,
    /// The Beckmann limit, for gamma above [`StudentT::BECKMANN_LIMIT`].
    limit: Option<Beckmann>,
    /// For gamma above [`StudentT::QUADRATURE_GAMMA`]: Lambda and sigma by the Gauss rule of
    /// the Gamma superposition ([`GammaGauss`]) instead of the continued fractions.
    gauss: Option<GammaGauss>,
}

/// Points of the Gauss rule of [`GammaGauss`].
const GAUSS_POINTS: usize = 12;

/// The `GAUSS_POINTS`-point generalized Gauss-Laguerre rule of the `Gamma(g - 3/2, 1)`
/// distribution (weight `x^(g-5/2) e^-x`, normalised to total weight 1), stored as
/// `(sqrt(x_j), w_j)`: `E[f(X)] ~ sum_j w_j f(x_j)`, exact for polynomials of degree 23.
/// Nodes come from the Jacobi matrix of the Laguerre polynomials `L^(a)`, `a = g - 5/2`
/// (diagonal `2i + 1 + a`, off-diagonal `sqrt(i (i + a))`), shifted by `a` so that its
/// eigenvalues, the offsets `x_j - a` of size `sqrt(a)`, keep their digits; they are found by
/// Sturm-sequence bisection, and each weight is `1 / sum_k p_k(x_j)^2` with the orthonormal
/// polynomials `p_k` of the three-term recurrence (Golub and Welsch 1969).
#[derive(Debug, Clone, Copy, PartialEq)]
struct GammaGauss {
    nodes: [(f64, f64); GAUSS_POINTS],
}

impl GammaGauss {
    /// The rule of `Gamma(shape, 1)`, `shape > 1`.
    fn new(shape: f64) -> Self {
        const N: usize = GAUSS_POINTS;
        let a = shape - 1.0;
        // Shifted Jacobi matrix: diagonal 2i + 1, off-diagonal b[i] = sqrt(i (i + a)) between
        // rows i - 1 and i.
        let diag: [f64; N] = std::array::from_fn(|i| 2.0 * i as f64 + 1.0);
        let off: [f64; N] = std::array::from_fn(|i| (i as f64 * (i as f64 + a)).sqrt());
        // Number of eigenvalues below `t` (Sturm sequence of the LDL^T pivots).
        let below = |t: f64| {
            let mut count = 0;
            let mut q = 1.0;
            for i in 0..N {
                q = diag[i] - t - if i > 0 { off[i] * off[i] / q } else { 0.0 };
                if q == 0.0 {
                    q = -f64::EPSILON * (off[i] + diag[i].abs() + t.abs());
                }
                if q < 0.0 {
                    count += 1;
                }
            }
            count
        };
        // Gershgorin bounds of the spectrum.
        let bound = 2.0 * off[N - 1] + 2.0 * N as f64;
        let nodes = std::array::from_fn(|j| {
            // The (j+1)-th smallest eigenvalue: the point where `below` passes j.
            let (mut lo, mut hi) = (-bound, bound);
            loop {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if below(mid) > j {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let t = 0.5 * (lo + hi);
            // Orthonormal polynomials at t: b[k+1] p[k+1] = (t - d[k]) p[k] - b[k] p[k-1].
            let (mut p0, mut p1, mut sum) = (0.0, 1.0, 1.0);
            for k in 0..N - 1 {
                let p2 = ((t - diag[k]) * p1 - off[k] * p0) / off[k + 1];
                (p0, p1) = (p1, p2);
                sum += p2 * p2;
            }
            ((a + t).sqrt(), 1.0 / sum)
        });
        Self { nodes }
    }

    /// `E[gap(r sqrt(X))]`, `X ~ Gamma(g - 3/2, 1)`, with the visibility gap [`erfcx_gap`].
    #[inline]
    fn mean_gap(&self, r: f64) -> f64 {
        let (mut sum, mut total) = (0.0, 0.0);
        for &(sqrt_x, w) in &self.nodes {
            sum += w * erfcx_gap(r * sqrt_x);
            total += w;
        }
        sum / total
    }
}

/// `ln(Gamma(a + 1/2) / Gamma(a))` for `a > 0`, to a few ulps: the asymptotic series
/// `ln(b)/2 - 1/(8b) + 1/(192 b^3) - 1/(640 b^5) + 17/(14336 b^7) - 31/(18432 b^9)` at
/// `b = a + n >= 20` (truncation below 2e-17 there), brought down to `a` by the recurrence
/// `Gamma(b + 1/2) / Gamma(b) = Gamma(b + 3/2) / Gamma(b + 1) * b / (b + 1/2)`, whose factors
/// are multiplied out and taken in one logarithm. A difference of two `ln_gamma` values
/// (each of size `a ln a`) would lose their rounding: 1e-12 of Lambda at gamma = 50.
fn ln_gamma_half_ratio(a: f64) -> f64 {
    const SHIFT: f64 = 20.0;
    let (mut num, mut den, mut b) = (1.0, 1.0, a);
    while b < SHIFT {
        num *= b;
        den *= b + 0.5;
        b += 1.0;
    }
    let r = 1.0 / b;
    let r2 = r * r;
    let series = r
        * (-0.125
            + r2 * (1.0 / 192.0
                + r2 * (-1.0 / 640.0 + r2 * (17.0 / 14336.0 - r2 * 31.0 / 18432.0))));
    0.5 * b.ln() + series + (num / den).ln()
}

impl StudentT {
    /// Above this shape Student-T is evaluated and sampled as its Beckmann limit: they differ
    /// by a relative `x^2 / (2 gamma)` < 5e-6 wherever `D` exceeds `e^-30` of its peak (and
    /// Lambda by less than 1e-6 for `cot / alpha <= 4`).
    pub const BECKMANN_LIMIT: f64 = 1e8;

    /// Integer shapes up to this one take D's power `(1 + x)^-g` and the t pdf's
    /// `(1 + q)^(1/2 - g)` by repeated squaring (a relative error of a few ulps times
    /// `log2 g`) rather than by a logarithm and an exponential.
    pub const MAX_POWER: i32 = 16;

    /// Above this shape Lambda and sigma are computed by a Gauss rule over the Gamma
    /// superposition (`StudentT::tail_by_superposition`) rather than by the incomplete-beta
    /// continued fractions, whose two terms cancel there: at gamma 1e8 those lost 3.4e-7 of
    /// Lambda (1e-9 at gamma 1e6). Below it the fractions are kept as they were.
    pub const QUADRATURE_GAMMA: f64 = 100.0;

    /// A Student-T NDF with roughness `alpha` and shape `gamma` in their supported ranges
    /// ([`check_alpha`], [`check_gamma`]; typed errors otherwise).
    pub fn new(alpha: f64, gamma: f64) -> Result<Self, ParamError> {
        let alpha = check_alpha(alpha)?;
        let gamma = check_gamma(gamma)?;
        let nu = 2.0 * gamma - 2.0;
        let g1 = gamma - 1.0;
        // f_nu(0) = Gamma(g - 1/2) / (sqrt(nu pi) Gamma(g - 1)).
        let t_norm = ln_gamma_half_ratio(g1).exp() / (nu * PI).sqrt();
        let shape1 = gamma - 1.5;
        let w1_scale =
            alpha * g1.sqrt() * 0.5 * FRAC_1_SQRT_PI * (-ln_gamma_half_ratio(shape1)).exp();
        let boosted = if shape1 < 1.0 { shape1 + 1.0 } else { shape1 };
        let param = |name, value| ParamError::OutOfRange {
            name,
            value,
            expected: "a valid Gamma shape",
        };
        Ok(Self {
            alpha,
            gamma,
            d_scale: 1.0 / (PI * alpha * alpha),
            inv_a2g1: 1.0 / (g1 * alpha * alpha),
            nu,
            inv_nu: 1.0 / nu,
            inv_nu_m1: 1.0 / (nu - 1.0),
            x_switch: (0.5 * nu + 1.0) / (0.5 * nu + 2.5),
            cf_lower: CfCoefficients::new(0.5 * nu, 0.5),
            cf_upper: CfCoefficients::new(0.5, 0.5 * nu),
            t_norm,
            alpha_g1: alpha * g1.sqrt(),
            w1_scale,
            mix: Gamma::new(g1, 1.0).map_err(|_| param("gamma", gamma))?,
            part1: Gamma::new(boosted, 1.0).map_err(|_| param("gamma", gamma))?,
            below: if gamma >= 3.5 {
                Some(Gamma::new(gamma - 2.5, 1.0).map_err(|_| param("gamma", gamma))?)
            } else {
                None
            },
            exact_log: gamma > 1e3,
            int_gamma: (gamma.fract() == 0.0 && gamma <= f64::from(Self::MAX_POWER))
                .then_some(gamma as i32),
            limit: if gamma > Self::BECKMANN_LIMIT {
                Some(Beckmann::new(alpha)?)
            } else {
                None
            },
            gauss: (gamma > Self::QUADRATURE_GAMMA).then(|| GammaGauss::new(shape1)),
        })
    }

    /// `ln(1 + x)`: the plain logarithm of the rounded sum (absolute error 1e-16, fast) while
    /// gamma times that error is negligible, `log1p` above.
    #[inline]
    fn ln_1p(&self, x: f64) -> f64 {
        if self.exact_log {
            x.ln_1p()
        } else {
            (1.0 + x).ln()
        }
    }

    /// The roughness alpha.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The shape gamma.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// `E[(T - k)_+]` for a Student t variate `T` with `nu` degrees of freedom, `k >= 0`:
    /// `(nu + k^2)/(nu - 1) f_nu(k) - k S_nu(k)` with the pdf `f_nu` and upper tail `S_nu`,
    /// so that `Lambda = (s/mu) excess(mu/s)` with `s = alpha/sqrt 2` (theory section 3).
    /// `S_nu(k) = I_x(nu/2, 1/2) / 2` with `x = nu/(nu+k^2)` by the incomplete-beta
    /// continued fraction (evaluated by `fractions`), whose prefactor
    /// `x^(nu/2) (1-x)^(1/2) / B` equals `f_nu(k) k`, so only one power is taken.
    #[inline]
    fn excess_by<F: BetaFractions>(&self, k: f64, fractions: &F) -> f64 {
        if k > 1e100 {
            return 0.0;
        }
        let nu = self.nu;
        let q = k * k * self.inv_nu;
        let x = 1.0 / (1.0 + q);
        // 1 - x without cancellation.
        let u = q * x;
        // f = t_norm (1 + q)^-(g - 1/2) = t_norm x^(g - 1) sqrt(x). Otherwise the power is
        // only exponentiated: ln of the rounded 1 + q (absolute error 1e-16, so a relative
        // (nu + 1)/2 * 1e-16 in f) is as good as log1p here, and several times faster in glibc.
        let f = match self.int_gamma {
            Some(g) => self.t_norm * int_pow(x, g - 1) * x.sqrt(),
            None => self.t_norm * (-0.5 * (nu + 1.0) * self.ln_1p(q)).exp(),
        };
        // The continued fraction of I_(1-x)(1/2, a) terminates after `a - 1` steps when
        // `a = g - 1` is an integer: prefer it for gamma = 2 and 3 where x >= 1/2 (there
        // I_x(a, 1/2) > 0.1, so `1/2 - ...` loses at most one digit).
        let terminating = matches!(self.int_gamma, Some(2 | 3));
        let upper = if terminating && x >= 0.5 {
            0.5 - f * k * beta_cf_terminating(&self.cf_upper, u)
        } else if x < self.x_switch {
            f * k * fractions.lower(x, u) * self.inv_nu
        } else {
            0.5 - f * k * fractions.upper(u)
        };
        (nu + k * k) * self.inv_nu_m1 * f - k * upper
    }

    /// Lambda of `w` with the continued fractions evaluated by `fractions`.
    #[inline]
    fn lambda_by<F: BetaFractions>(&self, w: Vec3, fractions: &F) -> f64 {
        if let Some(b) = &self.limit {
            return b.lambda(w);
        }
        if let Some(gauss) = &self.gauss {
            return lambda_on_sphere(w, |c, s2| {
                let sin = s2.sqrt();
                self.tail_by_superposition(c, sin, gauss) / c
            });
        }
        lambda_on_sphere(w, |c, s2| {
            // Lambda = (s/mu) excess(mu/s) = excess(k) / k with k = c / (s sin), k and 1/k
            // from one division.
            let ss = self.alpha * FRAC_1_SQRT_2 * s2.sqrt();
            let d = 1.0 / (c * ss);
            self.excess_by(c * c * d, fractions) * (ss * ss * d)
        })
    }

    /// sigma of `w` with the continued fractions evaluated by `fractions`.
    #[inline]
    fn sigma_by<F: BetaFractions>(&self, w: Vec3, fractions: &F) -> f64 {
        if let Some(b) = &self.limit {
            return b.sigma(w);
        }
        let (c, sin) = crate::math::cos_sin_theta(w);
        if sin == 0.0 {
            return c.max(0.0);
        }
        let tail = match &self.gauss {
            Some(gauss) => self.tail_by_superposition(c.abs(), sin, gauss),
            None => {
                let s = self.alpha * FRAC_1_SQRT_2;
                let k = c.abs() / (sin * s);
                sin * s * self.excess_by(k, fractions)
            }
        };
        if c > 0.0 { c + tail } else { tail }
    }

    /// `|c| Lambda(w')` for `w'` the upward direction with `cos = c >= 0`, `sin > 0` (the
    /// projected area beyond `max(0, w.z)`: `sigma = max(0, w.z) + tail`), by the Gamma
    /// superposition (theory sections 2 to 4). With `m ~ Gamma(g-1)` and the Beckmann
    /// argument `a(m) = sqrt(k m)`, `k = mu^2 / (alpha^2 (g-1))`, Beckmann's
    /// `Lambda_B = exp(-a^2) gap(a) / (2 a sqrt(pi))` ([`erfcx_gap`]) averaged over `m` is
    /// `c Lambda = W1 E[gap(sqrt(k X / (1+k)))]` with `X ~ Gamma(g - 3/2, 1)` and `W1 = sin
    /// alpha sqrt(g-1) Gamma(g-3/2) / (2 sqrt(pi) Gamma(g-1) (1+k)^(g-3/2))`, part 1's weight
    /// of the sampler: the exponential is taken into the Gamma density exactly, and what is
    /// left, the gap, varies slowly over the bulk of `X` (width `sqrt(g)` at `g`), so
    /// [`GammaGauss`] integrates it to rounding. Nothing cancels.
    #[inline]
    fn tail_by_superposition(&self, c: f64, sin: f64, gauss: &GammaGauss) -> f64 {
        let sqrt_k = c / (sin * self.alpha_g1);
        let k = sqrt_k * sqrt_k;
        // sqrt(k / (1 + k)), also where k under- or overflows.
        let r = if k > 1.0 {
            1.0 / (1.0 + 1.0 / k).sqrt()
        } else {
            sqrt_k / (1.0 + k).sqrt()
        };
        let w1 = sin * self.w1_scale * (-(self.gamma - 1.5) * k.ln_1p()).exp();
        if w1 == 0.0 {
            return 0.0;
        }
        w1 * gauss.mean_gap(r)
    }

    /// Draws `sqrt(m)` from part 1 of the tilted mixing density: `m ~ Gamma(g - 3/2,
    /// rate 1 + k)`, given `ln_1p_k = ln(1 + k)` (to an absolute 1e-16). For shape `< 1`,
    /// `m = X U^(1/shape)` with `X ~ Gamma(shape + 1)`, formed in log space because
    /// `U^(1/shape)` underflows for gamma near 3/2.
    #[inline]
    fn draw_sqrt_m_part1<R: Rng + ?Sized>(&self, k: f64, ln_1p_k: f64, rng: &mut R) -> f64 {
        let shape1 = self.gamma - 1.5;
        let x = self.part1.sample(rng);
        if shape1 < 1.0 {
            (0.5 * (x.ln() - ln_1p_k + open_uniform(rng).ln() / shape1)).exp()
        } else {
            (x / (1.0 + k)).sqrt()
        }
    }
}

/// The two incomplete-beta continued fractions of Lambda, `beta_cf` of `(nu/2, 1/2)` and of
/// `(1/2, nu/2)`: evaluated exactly by the [`StudentT`] itself, or interpolated by a
/// [`table::FractionTable`].
trait BetaFractions {
    /// The fraction of `I_x(nu/2, 1/2)` at `x` below the switch point, given `u = 1 - x`
    /// (formed without cancellation).
    fn lower(&self, x: f64, u: f64) -> f64;

    /// The fraction of `I_u(1/2, nu/2)` at `u = 1 - x`, `x` at or above the switch point.
    fn upper(&self, u: f64) -> f64;
}

impl BetaFractions for StudentT {
    #[inline]
    fn lower(&self, x: f64, _u: f64) -> f64 {
        beta_cf(&self.cf_lower, x)
    }

    #[inline]
    fn upper(&self, u: f64) -> f64 {
        beta_cf(&self.cf_upper, u)
    }
}

/// `x^n` for `1 <= n <= StudentT::MAX_POWER` by binary exponentiation (at most 4 squarings),
/// inline: `f64::powi` is a call into the compiler's runtime library.
#[inline]
fn int_pow(x: f64, n: i32) -> f64 {
    let (mut result, mut base, mut n) = (1.0, x, n);
    while n > 0 {
        if n & 1 == 1 {
            result *= base;
        }
        base *= base;
        n >>= 1;
    }
    result
}

/// Continued fraction of the regularised incomplete beta function (the one of Numerical
/// Recipes' `betacf`): `I_x(a, b) = x^a (1-x)^b / (a B(a, b)) * beta_cf(a, b, x)` with
/// `beta_cf = 1 / (1 + d1 / (1 + d2 / (1 + ...)))`, `d_m = c_m x`, converging fast for
/// `x < (a+1)/(a+b+2)`. Evaluated by the forward (Wallis) recurrence of the convergents
/// ([`BetaCf`]), two terms per step, with the `c_m` of `(a, b)` from `coefficients`; the
/// convergents are renormalised and tested every [`CF_STEPS`] steps rather than after every
/// step.
#[inline]
fn beta_cf(coefficients: &CfCoefficients, x: f64) -> f64 {
    let mut cf = BetaCf::new(coefficients, x);
    let mut h = cf.value();
    while cf.m < 10_000 {
        for _ in 0..CF_STEPS {
            cf.step();
        }
        let hn = cf.renormalise();
        // Successive tested convergents within an ulp: the fraction converges at least
        // geometrically here, so what is left is rounding (a 1e-16 test demanded exact
        // equality and ran on through rounding noise).
        if (hn - h).abs() <= f64::EPSILON * hn.abs() {
            return hn;
        }
        h = hn;
    }
    h
}

/// [`beta_cf`] for a positive integer `b`, where `d_2b = 0` ends the fraction: its value is
/// the convergent after `d_2b-1`, `b - 1` steps, with no test.
#[inline]
fn beta_cf_terminating(coefficients: &CfCoefficients, x: f64) -> f64 {
    let mut cf = BetaCf::new(coefficients, x);
    while (cf.m as f64) < coefficients.b {
        cf.step();
    }
    cf.value()
}

/// Steps (pairs of terms) of [`beta_cf`] between renormalisations and convergence tests:
/// 2 keeps the chain of dependent operations short while the fractions of Lambda, which
/// converge in 2 to 20 steps, run at most one step past convergence.
const CF_STEPS: u32 = 2;

/// Steps of the continued fraction whose coefficients are tabulated: the fractions of Lambda
/// take fewer for all but the largest shapes (99% of uniformly distributed directions within
/// 22 steps at gamma = 10), and later steps compute theirs.
const CF_TABLE: usize = 24;

/// The coefficients `d_m = c_m x` of the incomplete-beta continued fraction of `(a, b)`:
/// `c_1 = -(a + b) / (a + 1)`, and for step `m >= 1` `c_2m = m (b - m) / ((a - 1 + 2m)(a + 2m))`
/// and `c_2m+1 = -(a + m)(a + b + m) / ((a + 2m)(a + 1 + 2m))`, tabulated for the first
/// [`CF_TABLE`] steps so that a step of the fraction has no division.
#[derive(Clone, Copy, PartialEq)]
struct CfCoefficients {
    a: f64,
    b: f64,
    c1: f64,
    /// `(c_2m, c_2m+1)` of step `m = k + 1`.
    steps: [(f64, f64); CF_TABLE],
}

impl std::fmt::Debug for CfCoefficients {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "CfCoefficients(a = {}, b = {})", self.a, self.b)
    }
}

impl CfCoefficients {
    fn new(a: f64, b: f64) -> Self {
        let mut steps = [(0.0, 0.0); CF_TABLE];
        for (k, s) in steps.iter_mut().enumerate() {
            *s = Self::compute(a, b, k as u32 + 1);
        }
        Self {
            a,
            b,
            c1: -(a + b) / (a + 1.0),
            steps,
        }
    }

    /// `(c_2m, c_2m+1)` of step `m`.
    #[inline]
    fn compute(a: f64, b: f64, m: u32) -> (f64, f64) {
        let m = f64::from(m);
        let m2 = 2.0 * m;
        (
            m * (b - m) / ((a - 1.0 + m2) * (a + m2)),
            -(a + m) * (a + b + m) / ((a + m2) * (a + 1.0 + m2)),
        )
    }

    /// `(c_2m, c_2m+1)` of step `m >= 1`.
    #[inline]
    fn step(&self, m: u32) -> (f64, f64) {
        match self.steps.get(m as usize - 1) {
            Some(&c) => c,
            None => Self::compute(self.a, self.b, m),
        }
    }
}

/// The convergents `A/B` of the incomplete-beta continued fraction at `x`, `(a0, b0)` one
/// term behind `(a1, b1)`, and the index `m` of the next step.
struct BetaCf<'a> {
    coefficients: &'a CfCoefficients,
    x: f64,
    m: u32,
    a0: f64,
    b0: f64,
    a1: f64,
    b1: f64,
}

impl<'a> BetaCf<'a> {
    /// The convergents after `d1`.
    #[inline]
    fn new(coefficients: &'a CfCoefficients, x: f64) -> Self {
        Self {
            coefficients,
            x,
            m: 1,
            a0: 1.0,
            b0: 1.0,
            a1: 1.0,
            b1: 1.0 + coefficients.c1 * x,
        }
    }

    /// Adds `d_2m` and `d_2m+1`. Between renormalisations `|B|` grows by at most a factor 2 per
    /// term (`|d| < 1` here), far from overflow.
    #[inline]
    fn step(&mut self) {
        let (ce, co) = self.coefficients.step(self.m);
        let (even, odd) = (ce * self.x, co * self.x);
        let (a2, b2) = (self.a1 + even * self.a0, self.b1 + even * self.b0);
        (self.a1, self.b1) = (a2 + odd * self.a1, b2 + odd * self.b1);
        (self.a0, self.b0) = (a2, b2);
        self.m += 1;
    }

    /// The current convergent.
    #[inline]
    fn value(&self) -> f64 {
        self.a1 / self.b1
    }

    /// Scales the convergents so that `B = 1`, returning the current convergent.
    #[inline]
    fn renormalise(&mut self) -> f64 {
        let r = 1.0 / self.b1;
        let h = self.a1 * r;
        (self.a0, self.b0, self.a1, self.b1) = (self.a0 * r, self.b0 * r, h, 1.0);
        h
    }
}

impl Ndf for StudentT {
    /// `(1 + tan^2 / ((g-1) alpha^2))^-g / (pi alpha^2 cos^4)`: the power by one exponential
    /// (by `int_pow` for integer shapes up to [`StudentT::MAX_POWER`]), divided by `cos^4`
    /// where neither leaves the normal range (`cos^2 > 1e-100` and the power above
    /// `e^-700`), and otherwise all in log form, `exp(-2 ln cos^2 - g ln(...))`, so that
    /// `cos^-4` cannot overflow at grazing normals (where D diverges like `cos^(2g-4)` for
    /// g < 2).
    fn d(&self, wm: Vec3) -> f64 {
        if let Some(b) = &self.limit {
            return b.d(wm);
        }
        let Some((u2, sin2)) = cos2_sin2(wm) else {
            return 0.0;
        };
        let inv_u2 = 1.0 / u2;
        let x = sin2 * inv_u2 * self.inv_a2g1;
        if u2 > 1e-100 {
            // (1 + x)^-g by int_pow for integer shapes; `e` below 700 keeps exp(-e) normal.
            if let Some(g) = self.int_gamma {
                let p = int_pow(1.0 + x, g);
                if p < 1e300 {
                    return self.d_scale * (inv_u2 * inv_u2) / p;
                }
            } else {
                let e = self.gamma * self.ln_1p(x);
                if e < 700.0 {
                    return self.d_scale * (-e).exp() * (inv_u2 * inv_u2);
                }
            }
        }
        // ln of the rounded 1 + tan^2/((g-1) alpha^2) costs a relative g * 1e-16 in D: as
        // good as log1p, at a fraction of its time, for gamma <= 1e3 (`Self::ln_1p`).
        // Below wm.z = 7.5e-155 `1 / u2` overflows and `u2` loses bits as a subnormal, so
        // ln(u2) is taken as 2 ln(wm.z), and ln(1 + x) as ln(x) where x is that large.
        let ln_u2 = 2.0 * wm.z.ln();
        let ln_1p_x = if x < 1e300 {
            self.ln_1p(x)
        } else {
            (sin2 * self.inv_a2g1).ln() - ln_u2
        };
        self.d_scale * (-2.0 * ln_u2 - self.gamma * ln_1p_x).exp()
    }

    /// Closed form with the regularised incomplete beta function (theory section 3).
    fn lambda(&self, w: Vec3) -> f64 {
        self.lambda_by(w, self)
    }

    /// `c + sin * s * excess(|mu| / s)` above the horizon, `sin * s * excess(|mu| / s)` below,
    /// with `s = alpha / sqrt 2`; no cancellation on either side.
    fn sigma(&self, w: Vec3) -> f64 {
        self.sigma_by(w, self)
    }

    /// Exact, for every gamma > 3/2 and every direction, by the Gamma superposition
    /// (theory section 4): draw the mixing variable `m` from `Gamma(g-1)` tilted by the
    /// Beckmann projected area `sigma_B(w; alpha_m)`, then a Beckmann visible normal at
    /// `alpha_m = alpha sqrt((g-1)/m)`. With `k = mu^2 / (alpha^2 (g-1))`, `a(m) = sqrt(k m)`:
    /// above the horizon the tilted density is part 1 (weight `W1`, `Gamma(g-3/2, rate 1+k)`)
    /// plus `Gamma(g-1)` thinned by `(1 + erf(a))/2` (weight `c`); below it, part 1 thinned by
    /// the visibility gap `1 - sqrt(pi) a erfcx(a)`, or, where the gap is small (gamma >= 7/2
    /// and `k (g - 5/2) > 1 + k`, the mean `a^2` of the proposal above 1), `Gamma(g-5/2, rate
    /// 1+k)` thinned by `2 a^2` times the gap, whose acceptance tends to 1 as `a` grows (at
    /// gamma 1e8 the first form accepted 1 draw in 1e8).
    fn sample_visible<R: Rng + ?Sized>(&self, w: Vec3, rng: &mut R) -> Vec3 {
        if let Some(b) = &self.limit {
            return b.sample_visible(w, rng);
        }
        let c = w.z;
        let sin = (w.x * w.x + w.y * w.y).sqrt();
        if sin == 0.0 && c <= 0.0 {
            return Vec3::z();
        }
        let inv_sin = 1.0 / sin;
        let cot = c * inv_sin;
        let k = cot * cot * self.inv_a2g1;
        // ln(1 + k) is only ever exponentiated (times at most gamma), so the absolute error
        // 1e-16 of the plain logarithm is as good as log1p's relative one for gamma <= 1e3.
        let ln_1p_k = self.ln_1p(k);
        let w1 = sin * self.w1_scale * (-(self.gamma - 1.5) * ln_1p_k).exp();
        let sqrt_m = loop {
            if c >= 0.0 {
                if w1.is_finite() && open_uniform(rng) * (w1 + c) < w1 {
                    break self.draw_sqrt_m_part1(k, ln_1p_k, rng);
                }
                // Thinning: accept with probability `1 - erfc(a)/2 >= 1/2`, so a uniform
                // above 1/2 accepts without evaluating erfc.
                let m = self.mix.sample(rng);
                let v = open_uniform(rng);
                if m > 0.0 && (v >= 0.5 || v >= 0.5 * erfc_and_gauss((k * m).sqrt()).0) {
                    break m.sqrt();
                }
            } else if let Some(below) = self
                .below
                .as_ref()
                .filter(|_| k * (self.gamma - 2.5) > 1.0 + k)
            {
                // Where a^2 = k m is large, the gap is about 1 / (2 a^2), so part 1 is thinned
                // heavily; m ~ Gamma(g - 5/2, rate 1 + k) carries that 1 / m already and is
                // accepted with `2 a^2 gap(a) < 1` (by erfcx(a) > 2 / (sqrt(pi) (a + sqrt(a^2
                // + 2))), Abramowitz and Stegun 7.1.13), which tends to 1.
                let m = below.sample(rng) / (1.0 + k);
                let a2 = k * m;
                if m > 0.0 && open_uniform(rng) < 2.0 * a2 * erfcx_gap(a2.sqrt()) {
                    break m.sqrt();
                }
            } else {
                let sqrt_m = self.draw_sqrt_m_part1(k, ln_1p_k, rng);
                if open_uniform(rng) < erfcx_gap(k.sqrt() * sqrt_m) {
                    break sqrt_m;
                }
            }
        };
        let inv_alpha_m = sqrt_m / self.alpha_g1;
        if sin > 0.0 {
            sample_visible_beckmann_in_frame(cot, w.x * inv_sin, w.y * inv_sin, inv_alpha_m, rng)
        } else {
            sample_visible_beckmann(w, inv_alpha_m, rng)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Gauss rule of `Gamma(shape, 1)` has total weight 1 and integrates the moments
    /// `E[X^k] = shape (shape + 1) ... (shape + k - 1)` exactly up to degree 23 (here checked to
    /// degree 20, relative 1e-13), for shapes from just above the switch to the Beckmann limit.
    #[test]
    fn gamma_gauss_rule_integrates_moments_exactly() {
        for shape in [98.5, 150.0, 1e3, 1e5, 1e8] {
            let rule = GammaGauss::new(shape);
            let total: f64 = rule.nodes.iter().map(|&(_, w)| w).sum();
            assert!(
                (total - 1.0).abs() < 1e-14,
                "shape {shape}: total weight {total}"
            );
            // Moments of X / shape, to stay in range.
            let mut exact = 1.0;
            for k in 1..=20 {
                exact *= (shape + f64::from(k) - 1.0) / shape;
                let quad: f64 = rule
                    .nodes
                    .iter()
                    .map(|&(sx, w)| w * (sx * sx / shape).powi(k))
                    .sum();
                assert!(
                    (quad / exact - 1.0).abs() < 1e-13,
                    "shape {shape}, k {k}: {quad} against {exact}"
                );
            }
        }
    }

    /// Above `QUADRATURE_GAMMA` Lambda and sigma (on both sides of the horizon) match mpmath
    /// (60 digits; `Lambda = Gamma(g-3/2) / (2 sqrt(pi k) Gamma(g-1) (1+k)^(g-3/2))
    /// E[gap(sqrt(k X/(1+k)))]`, `X ~ Gamma(g-3/2)`, by adaptive quadrature, which agrees with
    /// the closed form of theory section 3 to 50 digits where mpmath's `betainc` converges) to
    /// 5e-14 at alpha 0.45 up to gamma 1e8. The continued fractions were off by up to 3.4e-7
    /// there (Lambda 7.96e-18 at gamma 1e8, alpha 1, 10 degrees) and took 50 us.
    #[test]
    // Directions at 45 degrees are written out as the other rows are.
    #[allow(clippy::excessive_precision, clippy::approx_constant)]
    fn lambda_for_large_gamma_matches_high_precision_references() {
        let refs = [
            (
                1e4,
                0.9987523388778446,
                0.04993761694389225,
                2.0702274843093299,
            ),
            (
                1e4,
                0.7071067811865475,
                0.7071067811865476,
                7.2945721741561958e-5,
            ),
            (
                1e4,
                0.48564293117863205,
                0.8741572761215378,
                2.3126324859852582e-10,
            ),
            (
                1e4,
                0.19611613513818402,
                0.9805806756909201,
                5.3284040259443385e-58,
            ),
            (
                1e6,
                0.9578262852211514,
                0.2873478855663454,
                0.098421311057135498,
            ),
            (
                1e6,
                0.7071067811865475,
                0.7071067811865476,
                7.2800628973969761e-5,
            ),
            (
                1e6,
                0.48564293117863205,
                0.8741572761215378,
                2.2780244383869223e-10,
            ),
            (
                1e6,
                0.19611613513818402,
                0.9805806756909201,
                2.4755749594195585e-58,
            ),
            (
                1e8,
                0.9987523388778446,
                0.04993761694389225,
                2.0701326665408478,
            ),
            (
                1e8,
                0.9578262852211514,
                0.2873478855663454,
                0.098421180488753751,
            ),
            (
                1e8,
                0.7071067811865475,
                0.7071067811865476,
                7.2799179229206603e-5,
            ),
            (
                1e8,
                0.48564293117863205,
                0.8741572761215378,
                2.2776806699417546e-10,
            ),
            (
                1e8,
                0.19611613513818402,
                0.9805806756909201,
                2.456518267351367e-58,
            ),
        ];
        for (gamma, x, z, r) in refs {
            let st = StudentT::new(0.45, gamma).unwrap();
            let w = Vec3::new(x, 0.0, z);
            let below = Vec3::new(x, 0.0, -z);
            for (v, want, what) in [
                (st.lambda(w), r, "Lambda"),
                (TabulatedStudentT::new(st).lambda(w), r, "tabulated Lambda"),
                (st.sigma(below), z * r, "sigma below"),
                (st.sigma(w) - z, z * r, "sigma above - z"),
            ] {
                let err = ((v - want) / want).abs();
                // sigma above the horizon is z + tail: the tail is recovered to the rounding
                // of the sum.
                let tol = if what == "sigma above - z" {
                    5e-14f64.max(4.0 * f64::EPSILON * z / want)
                } else {
                    5e-14
                };
                assert!(
                    err < tol,
                    "gamma {gamma}, w = ({x}, 0, {z}): {what} {v}, want {want} ({err:e})"
                );
            }
        }
    }

    /// D of integer shapes (integer powers) and of the others (one exponential) agree with
    /// the log form `exp(-2 ln cos^2 - g ln1p(x)) / (pi alpha^2)` from the pole to grazing
    /// normals, where the log form takes over (both below 1e-290 where D becomes subnormal).
    #[test]
    fn d_power_forms_match_the_log_form() {
        for gamma in [2.0, 3.0, 16.0, 17.0, 2.8, 1.6] {
            let st = StudentT::new(0.45, gamma).unwrap();
            for k in 0..200 {
                let theta = 0.5 * PI * (1.0 - (-(k as f64) * 0.2).exp());
                let wm = Vec3::new(theta.sin(), 0.0, theta.cos());
                let (u2, sin2) = (wm.z * wm.z, wm.x * wm.x);
                let x = sin2 / u2 / ((gamma - 1.0) * 0.45 * 0.45);
                let r = (-2.0 * u2.ln() - gamma * x.ln_1p()).exp() / (PI * 0.45 * 0.45);
                let d = st.d(wm);
                assert!(
                    (d - r).abs() <= 1e-13 * r || (d < 1e-290 && r < 1e-290),
                    "gamma {gamma}, theta {theta}: D {d}, log form {r}"
                );
            }
        }
    }

    /// Near the horizon, down to the normal range of `cos^2` (1.5e-162), D keeps its value
    /// where `1 / cos^2` overflows (below 7.5e-155): it was 0 there, for gamma = 2 unlike GGX
    /// and for gamma < 2 where it diverges. There `tan^2` dwarfs `alpha^2 (g-1)`, so
    /// `D = (g-1)^g alpha^(2g-2) cos^(2g-4) / (pi sin^(2g))` to rounding.
    #[test]
    fn d_near_the_horizon_is_its_power_law() {
        use crate::ndf::Ggx;
        let ggx = Ggx::new(0.3).unwrap();
        for gamma in [1.6, 1.9, 2.0, 2.5, 3.0, 17.5] {
            let st = StudentT::new(0.3, gamma).unwrap();
            for z in [1e-150f64, 8e-155, 7e-155, 1e-158, 1e-161, 1.6e-162] {
                let s = (1.0 - z * z).sqrt();
                let wm = Vec3::new(0.6 * s, 0.8 * s, z);
                let ln_d = gamma * (gamma - 1.0).ln()
                    + (2.0 * gamma - 2.0) * 0.3f64.ln()
                    + (2.0 * gamma - 4.0) * z.ln()
                    - PI.ln();
                let (d, r) = (st.d(wm), ln_d.exp());
                assert!(
                    (d - r).abs() <= 1e-12 * r || (r < 1e-300 && d < 1e-300),
                    "gamma {gamma}, z {z}: D {d}, power law {r}"
                );
                if gamma == 2.0 {
                    assert!((d / ggx.d(wm) - 1.0).abs() < 1e-13, "z {z}: {d} vs GGX");
                }
            }
        }
    }

    /// Lambda against mpmath (120 digits: the closed form by mpmath's `betainc`, checked
    /// against direct quadrature of `integral_k^inf (t - k) f_nu(t) dt` to 1e-7) for alpha
    /// 0.45, from grazing to near-normal directions and for shapes on both sides of the
    /// terminating fractions (gamma 2 and 3), through the `log1p` regime (gamma > 1e3).
    /// Each row is `(gamma, w.x, w.z, Lambda)` at the f64 direction `(w.x, 0, w.z)`. Up to
    /// gamma = 50 Lambda is within 1e-13. At gamma = 2000 (nearly Beckmann, where the two terms
    /// of `excess` cancel to about `1 / k^2` of their size in the tail, `k = cot / s`, and left
    /// 1e-12 at Lambda = 1e-56) it comes from the Gauss rule of the superposition.
    #[test]
    // Directions at 45 degrees are written out as the other rows are.
    #[allow(clippy::excessive_precision, clippy::approx_constant)]
    fn lambda_matches_high_precision_references() {
        let refs = [
            (
                1.6,
                0.9987523388778446,
                0.04993761694389225,
                12.089035730313429,
            ),
            (
                1.6,
                0.9578262852211514,
                0.2873478855663454,
                1.7326293259715267,
            ),
            (
                1.6,
                0.7071067811865475,
                0.7071067811865476,
                0.42212714341051752,
            ),
            (
                1.6,
                0.48564293117863205,
                0.8741572761215378,
                0.20913125877858882,
            ),
            (
                1.6,
                0.19611613513818402,
                0.9805806756909201,
                0.061447817593604572,
            ),
            (
                1.6,
                0.02499219116020307,
                0.9996876464081228,
                0.0050684628697415594,
            ),
            (
                2.0,
                0.9987523388778446,
                0.04993761694389225,
                4.0276925690687066,
            ),
            (
                2.0,
                0.9578262852211514,
                0.2873478855663454,
                0.40138781886599744,
            ),
            (
                2.0,
                0.7071067811865475,
                0.7071067811865476,
                0.048292804986532708,
            ),
            (
                2.0,
                0.48564293117863205,
                0.8741572761215378,
                0.015388203202207565,
            ),
            (
                2.0,
                0.19611613513818402,
                0.9805806756909201,
                0.0020209158989294541,
            ),
            (
                2.0,
                0.02499219116020307,
                0.9996876464081228,
                3.1639623934197304e-5,
            ),
            (
                2.8,
                0.9987523388778446,
                0.04993761694389225,
                2.8113916090390428,
            ),
            (
                2.8,
                0.9578262852211514,
                0.2873478855663454,
                0.20828642705533551,
            ),
            (
                2.8,
                0.7071067811865475,
                0.7071067811865476,
                0.0094140117378212822,
            ),
            (
                2.8,
                0.48564293117863205,
                0.8741572761215378,
                0.0013523045603122265,
            ),
            (
                2.8,
                0.19611613513818402,
                0.9805806756909201,
                3.6939312919153285e-5,
            ),
            (
                2.8,
                0.02499219116020307,
                0.9996876464081228,
                2.0967231609856092e-8,
            ),
            (
                3.0,
                0.9987523388778446,
                0.04993761694389225,
                2.7113678449506239,
            ),
            (
                3.0,
                0.9578262852211514,
                0.2873478855663454,
                0.19290232815573398,
            ),
            (
                3.0,
                0.7071067811865475,
                0.7071067811865476,
                0.0072440100830413471,
            ),
            (
                3.0,
                0.48564293117863205,
                0.8741572761215378,
                0.00086730334047116274,
            ),
            (
                3.0,
                0.19611613513818402,
                0.9805806756909201,
                1.6140755024147699e-5,
            ),
            (
                3.0,
                0.02499219116020307,
                0.9996876464081228,
                4.0035031987832134e-9,
            ),
            (
                7.5,
                0.9987523388778446,
                0.04993761694389225,
                2.2287671090500419,
            ),
            (
                7.5,
                0.9578262852211514,
                0.2873478855663454,
                0.1208993371519059,
            ),
            (
                7.5,
                0.7071067811865475,
                0.7071067811865476,
                0.00065287970166486615,
            ),
            (
                7.5,
                0.48564293117863205,
                0.8741572761215378,
                4.3695766552367652e-6,
            ),
            (
                7.5,
                0.19611613513818402,
                0.9805806756909201,
                3.3849776866959959e-11,
            ),
            (
                7.5,
                0.02499219116020307,
                0.9996876464081228,
                8.0071143571724829e-23,
            ),
            (
                50.0,
                0.9987523388778446,
                0.04993761694389225,
                2.0896910755421991,
            ),
            (
                50.0,
                0.9578262852211514,
                0.2873478855663454,
                0.10114857864799942,
            ),
            (
                50.0,
                0.7071067811865475,
                0.7071067811865476,
                0.00010729305284208449,
            ),
            (
                50.0,
                0.48564293117863205,
                0.8741572761215378,
                3.0274719813392371e-9,
            ),
            (
                50.0,
                0.19611613513818402,
                0.9805806756909201,
                1.1280690708878238e-30,
            ),
            (
                50.0,
                0.02499219116020307,
                0.9996876464081228,
                2.1006556031467768e-112,
            ),
            (
                2000.0,
                0.9987523388778446,
                0.04993761694389225,
                2.0706070824219465,
            ),
            (
                2000.0,
                0.9578262852211514,
                0.2873478855663454,
                0.098487176980777853,
            ),
            (
                2000.0,
                0.7071067811865475,
                0.7071067811865476,
                7.3534345419140834e-5,
            ),
            (
                2000.0,
                0.48564293117863205,
                0.8741572761215378,
                2.4572152106003501e-10,
            ),
            (
                2000.0,
                0.19611613513818402,
                0.9805806756909201,
                1.0469146721005882e-56,
            ),
        ];
        for (gamma, x, z, r) in refs {
            let st = StudentT::new(0.45, gamma).unwrap();
            let w = Vec3::new(x, 0.0, z);
            // The exact fractions, and the interpolated ones of TabulatedStudentT.
            for (l, form) in [
                (st.lambda(w), "exact"),
                (TabulatedStudentT::new(st).lambda(w), "tabulated"),
            ] {
                let err = ((l - r) / r).abs();
                let tol = 1e-13;
                assert!(
                    err < tol,
                    "gamma {gamma}, w = ({x}, 0, {z}), {form}: Lambda {l}, want {r}"
                );
            }
        }
    }
}
