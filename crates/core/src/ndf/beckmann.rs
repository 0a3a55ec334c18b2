//! The Beckmann NDF.

use super::special::{FRAC_1_SQRT_PI, SQRT_PI, erfcx, erfcx_gap};
use super::{Ndf, cos2_sin2, lambda_on_sphere};
use crate::error::{ParamError, check_alpha};
use crate::math::Vec3;
use libm::{erf, erfc};
use rand::{Rng, RngExt};
use rand_distr::StandardNormal;
use std::f64::consts::FRAC_1_SQRT_2;

/// Beckmann: `D(u) = exp(-tan^2 theta / alpha^2) / (pi alpha^2 u^4)`; slopes are Gaussian with
/// standard deviation `alpha / sqrt(2)` per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Beckmann {
    alpha: f64,
    inv_alpha: f64,
}

impl Beckmann {
    /// A Beckmann NDF of roughness `alpha > 0`.
    pub fn new(alpha: f64) -> Result<Self, ParamError> {
        let alpha = check_alpha(alpha)?;
        Ok(Self {
            alpha,
            inv_alpha: 1.0 / alpha,
        })
    }

    /// The roughness alpha.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
}

/// Beckmann Lambda for an upward direction with `a = cot(theta) / alpha > 0`:
/// `(erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))`. For `a >= 4` it is evaluated as
/// `exp(-a^2) gap(a) / (2 a sqrt(pi))` ([`erfcx_gap`]) to avoid the cancellation of the two
/// terms.
#[inline]
pub(crate) fn lambda_beckmann_a(a: f64) -> f64 {
    if a < 4.0 {
        0.5 * (FRAC_1_SQRT_PI * (-a * a).exp() / a - erfc(a))
    } else {
        0.5 * FRAC_1_SQRT_PI * (-a * a).exp() * erfcx_gap(a) / a
    }
}

/// Beckmann projected area for `cos theta = c`, `sin theta = s`, valid on the whole sphere:
/// `sigma = c (1 + erf(a)) / 2 + s alpha exp(-a^2) / (2 sqrt(pi))` with `a = c / (s alpha)`.
/// Below the horizon the two terms nearly cancel; there it is evaluated as
/// `s alpha exp(-a^2) gap(|a|) / (2 sqrt(pi))`.
#[inline]
pub(crate) fn sigma_beckmann(c: f64, s: f64, alpha: f64) -> f64 {
    if s == 0.0 {
        return c.max(0.0);
    }
    let a = c / (s * alpha);
    let tail = 0.5 * s * alpha * FRAC_1_SQRT_PI * (-a * a).exp();
    if c >= 0.0 {
        0.5 * c * (1.0 + erf(a)) + tail
    } else {
        tail * erfcx_gap(-a)
    }
}

/// A uniform variate strictly inside `(0, 1)`: `(k + 1/2) 2^-53` with `k` uniform.
#[inline]
pub(crate) fn open_uniform<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    ((rng.random::<u64>() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
}

/// Draws a Beckmann visible normal seen from the unit direction `w`, for roughness
/// `1 / inv_alpha` (the inverse is passed so that the Student-T mixture can reach
/// arbitrarily large roughness without overflow). Exact for every `w` with `sigma(w) > 0`;
/// returns `+z` for `w = -z`, where nothing is visible.
///
/// Stretching to alpha = 1 (Heitz and d'Eon 2014): with `s = sin theta`, the stretched
/// direction has `cot theta' = a = w.z / (alpha s)`. In the frame rotated to the azimuth of
/// `w` the visible slopes of the unit-roughness surface have density proportional to
/// `(a - x)_+ exp(-x^2 - y^2)` (slope convention `(-wm.x/wm.z, -wm.y/wm.z)`): the x-slope is
/// drawn by inverting its CDF ([`visible_slope_x`]), the y-slope is `N(0, 1/2)`. The slopes
/// are rotated back to the azimuth of `w` and scaled by alpha.
#[inline]
pub(crate) fn sample_visible_beckmann<R: Rng + ?Sized>(
    w: Vec3,
    inv_alpha: f64,
    rng: &mut R,
) -> Vec3 {
    let s = (w.x * w.x + w.y * w.y).sqrt();
    let u = open_uniform(rng);
    let y = rng.sample::<f64, _>(StandardNormal) * FRAC_1_SQRT_2;
    let a = if s > 0.0 {
        w.z * inv_alpha / s
    } else if w.z > 0.0 {
        f64::INFINITY
    } else {
        return Vec3::z();
    };
    let x = visible_slope_x(a, u);
    let (cp, sp) = if s > 0.0 {
        (w.x / s, w.y / s)
    } else {
        (1.0, 0.0)
    };
    // Facet normal (-alpha * slope, 1) / norm, written as (-slope, 1/alpha) / norm.
    let m = Vec3::new(-(cp * x - sp * y), -(sp * x + cp * y), inv_alpha);
    m / m.norm()
}

/// Inverts the CDF of the visible x-slope of the unit-roughness Beckmann surface seen from
/// `cot theta = a`: density proportional to `(a - x)_+ exp(-x^2)` on `x < a`. `u` in `(0, 1)`;
/// `a = +inf` gives the plain `N(0, 1/2)` quantile. Valid for every real `a`; for `a < 0`
/// (below the horizon) the far tail is solved in the distance `a - x` to the visibility limit.
#[inline]
pub(crate) fn visible_slope_x(a: f64, u: f64) -> f64 {
    if a >= 0.0 {
        if a == f64::INFINITY {
            return statrs::function::erf::erf_inv(2.0 * u - 1.0);
        }
        slope_above(a, u)
    } else {
        a - slope_below(-a, u)
    }
}

/// `ln G(x)`, `(ln G)'(x)` for `G(x) = exp(-x^2)/2 + a sqrt(pi)/2 erfc(-x)`, `a >= 0`: the
/// unnormalised CDF of the visible x-slope (`G' = (a - x) exp(-x^2)`).
#[inline]
fn ln_cdf_above(a: f64, x: f64) -> (f64, f64) {
    if x <= 0.0 {
        let b = 1.0 + a * SQRT_PI * erfcx(-x);
        (-x * x + (0.5 * b).ln(), 2.0 * (a - x) / b)
    } else {
        let e = (-x * x).exp();
        let g = 0.5 * e + 0.5 * a * SQRT_PI * (1.0 + erf(x));
        (g.ln(), (a - x) * e / g)
    }
}

/// Halley's step for `h = 0` with `h' = d1` and `h'' = d1 * dlp - d1^2`, where `dlp` is the
/// log-derivative of the density; falls back to Newton where the Halley denominator is unsafe.
/// Returns the step and the relative step size below which the next iterate is converged to
/// rounding (Halley is cubic, Newton quadratic).
#[inline]
fn halley_step(h: f64, d1: f64, dlp: f64) -> (f64, f64) {
    let d2 = d1 * dlp - d1 * d1;
    let den = 2.0 * d1 * d1 - h * d2;
    if den > d1 * d1 {
        (2.0 * h * d1 / den, 1e-6)
    } else {
        (h / d1, 1e-9)
    }
}

/// Quantile `u` of the x-slope for `a >= 0`: solves `ln G(x) = ln u + ln G(a)` on
/// `[-sqrt(-ln u), min(a, x_gauss)]` (both bounds are exact: `G(x)/G(a) <= exp(-x^2)` for
/// `x <= 0`, and the visible slope is stochastically smaller than the unconditioned Gaussian
/// slope) by Halley's method with a bisection safeguard. `ln G` is concave (log-concave
/// density), so the iteration cannot wander.
fn slope_above(a: f64, u: f64) -> f64 {
    let ln_u = u.ln();
    let target = ln_u + ln_cdf_above(a, a).0;
    let mut lo = -(-ln_u).sqrt();
    let mut hi = a;
    let mut x = lo;
    if a > 0.5 {
        let xg = statrs::function::erf::erf_inv(2.0 * u - 1.0);
        if xg < hi {
            hi = xg.max(lo);
            x = hi;
        }
    }
    for _ in 0..100 {
        let (lg, d1) = ln_cdf_above(a, x);
        let h = lg - target;
        if h == 0.0 {
            return x;
        }
        if h > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let dlp = -1.0 / (a - x) - 2.0 * x;
        let (step, done) = halley_step(h, d1, dlp);
        let xn = x - step;
        if !(xn > lo && xn < hi) {
            x = 0.5 * (lo + hi);
            if hi - lo <= 1e-15 * (1.0 + x.abs()) {
                return x;
            }
            continue;
        }
        if step.abs() <= done * (1.0 + x.abs()) {
            return xn;
        }
        x = xn;
    }
    x
}

/// Quantile of the distance `y = a - x >= 0` for `a = -n < 0`: survival `S(y) = u` with
/// `ln S(y) = -y (y + 2n) + ln((y + n gap(y + n)) / (y + n)) - ln gap(n)` (density in `y`
/// proportional to `y exp(-(y + n)^2)`, no cancellation or underflow however far below the
/// horizon), by Halley's method from the exact upper bound `y (y + 2n) = -ln u - ln gap(n)`.
fn slope_below(n: f64, u: f64) -> f64 {
    let ln_u = u.ln();
    let ln_gap_n = erfcx_gap(n).ln();
    let l = -ln_u - ln_gap_n;
    let mut lo = 0.0;
    let mut hi = l / (n + (n * n + l).sqrt());
    let mut y = hi;
    for _ in 0..100 {
        let v = y + n;
        let b = y + n * erfcx_gap(v);
        let h = -y * (y + 2.0 * n) + (b / v).ln() - ln_gap_n - ln_u;
        if h == 0.0 {
            return y;
        }
        if h > 0.0 {
            lo = y;
        } else {
            hi = y;
        }
        let d1 = -2.0 * y * v / b;
        let dlp = 1.0 / y - 2.0 * v;
        let (step, done) = halley_step(h, d1, dlp);
        let yn = y - step;
        if !(yn > lo && yn < hi) {
            y = 0.5 * (lo + hi);
            if hi - lo <= 1e-15 * y {
                return y;
            }
            continue;
        }
        if step.abs() <= done * y {
            return yn;
        }
        y = yn;
    }
    y
}

impl Ndf for Beckmann {
    /// `exp(-tan^2 / alpha^2 - 2 ln cos^2) / (pi alpha^2)`: zero, not NaN, at grazing normals.
    fn d(&self, wm: Vec3) -> f64 {
        let Some((u2, sin2)) = cos2_sin2(wm) else {
            return 0.0;
        };
        let ia2 = self.inv_alpha * self.inv_alpha;
        (-sin2 / u2 * ia2 - 2.0 * u2.ln()).exp() * ia2 * std::f64::consts::FRAC_1_PI
    }

    fn lambda(&self, w: Vec3) -> f64 {
        let inv_alpha = self.inv_alpha;
        lambda_on_sphere(w, |mu| lambda_beckmann_a(mu * inv_alpha))
    }

    fn sigma(&self, w: Vec3) -> f64 {
        let (c, s) = crate::math::cos_sin_theta(w);
        sigma_beckmann(c, s, self.alpha)
    }

    /// Exact: stretched visible-slope CDF inversion ([`visible_slope_x`]), valid on the whole
    /// sphere including below the horizon.
    fn sample_visible<R: Rng + ?Sized>(&self, w: Vec3, rng: &mut R) -> Vec3 {
        sample_visible_beckmann(w, self.inv_alpha, rng)
    }
}
