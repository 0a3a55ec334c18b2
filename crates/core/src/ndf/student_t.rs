//! The Student-T NDF of Ribardiere et al. 2017 in d'Eon's (alpha, gamma) parameterisation.

use super::Beckmann;
use super::beckmann::{open_uniform, sample_visible_beckmann, sample_visible_beckmann_in_frame};
use super::special::{FRAC_1_SQRT_PI, erfc_and_gauss, erfcx_gap};
use super::{Ndf, cos2_sin2, lambda_on_sphere};
use crate::error::{ParamError, check_alpha, check_gamma};
use crate::math::Vec3;
use rand::Rng;
use rand_distr::{Distribution, Gamma};
use statrs::function::gamma::ln_gamma;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// Student-T: `D(u) = (g-1)^g alpha^(2g-2) / (pi u^4 (alpha^2 (g-1) + tan^2 theta)^g)` with
/// shape `g = gamma > 3/2`. Slopes along one axis are `(alpha/sqrt 2) T_nu`, `nu = 2g - 2`.
/// `gamma = 2` is GGX; `gamma -> inf` tends to Beckmann with the same alpha, within a relative
/// `O(x^2 / gamma)` (`x = tan^2 theta / alpha^2`): above [`StudentT::BECKMANN_LIMIT`] (1e8),
/// where that is below 5e-6 for every normal that matters, D, Lambda, sigma and the sampler
/// are Beckmann's. Below it, the logarithms are `log1p` for gamma > 1e3 and the ratios of Gamma
/// functions asymptotic for large arguments, so that no digit is lost on the way to the limit.
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
    /// `nu / 2` is 1 or 2 (gamma 2 or 3): the continued fraction of `I_(1-x)(1/2, nu/2)`
    /// terminates.
    terminating_cf: bool,
    /// Student t pdf at 0: `Gamma((nu+1)/2) / (sqrt(nu pi) Gamma(nu/2)) = 1 / (sqrt(nu) B(nu/2, 1/2))`.
    t_norm: f64,
    /// `alpha sqrt(g-1)`: `alpha_m = alpha sqrt(g-1) / sqrt(m)` in the Gamma superposition.
    alpha_g1: f64,
    /// Weight constant of part 1 of the tilted mixing density (theory section 4):
    /// `W1 = s * w1_scale / (1+k)^(g-3/2)`.
    w1_scale: f64,
    /// `Gamma(g-1, 1)`: the mixing density of the superposition.
    mix: Gamma<f64>,
    /// `Gamma(g-3/2 (+1 if g-3/2 < 1), 1)`: part 1, boosted to shape >= 1 so that tiny `m`
    /// can be drawn in log space.
    part1: Gamma<f64>,
    /// gamma > 1e3: `ln(1 + x)` by `log1p`, whose rounding is not multiplied by gamma.
    exact_log: bool,
    /// The Beckmann limit, for gamma above [`StudentT::BECKMANN_LIMIT`].
    limit: Option<Beckmann>,
}

/// `ln(Gamma(a + 1/2) / Gamma(a))` for `a > 0`, to a relative 1e-15: the asymptotic series
/// `ln(a)/2 - 1/(8a) + 1/(192 a^3) - 1/(640 a^5)` for `a >= 1e3` (where the difference of two
/// `ln_gamma` of size `a ln a` would cancel most digits), the difference below.
fn ln_gamma_half_ratio(a: f64) -> f64 {
    if a >= 1e3 {
        let r = 1.0 / a;
        let r2 = r * r;
        0.5 * a.ln() - r * (0.125 - r2 * (1.0 / 192.0 - r2 / 640.0))
    } else {
        ln_gamma(a + 0.5) - ln_gamma(a)
    }
}

impl StudentT {
    /// Above this shape Student-T is evaluated and sampled as its Beckmann limit: they differ
    /// by a relative `x^2 / (2 gamma)` < 5e-6 wherever `D` exceeds `e^-30` of its peak (and
    /// Lambda by less than 1e-6 for `cot / alpha <= 4`), while the incomplete-beta continued
    /// fraction of Lambda stops converging in its iteration cap from about 1e8.
    pub const BECKMANN_LIMIT: f64 = 1e8;

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
            terminating_cf: g1 == 1.0 || g1 == 2.0,
            t_norm,
            alpha_g1: alpha * g1.sqrt(),
            w1_scale,
            mix: Gamma::new(g1, 1.0).map_err(|_| param("gamma", gamma))?,
            part1: Gamma::new(boosted, 1.0).map_err(|_| param("gamma", gamma))?,
            exact_log: gamma > 1e3,
            limit: if gamma > Self::BECKMANN_LIMIT {
                Some(Beckmann::new(alpha)?)
            } else {
                None
            },
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
    /// continued fraction, whose prefactor `x^(nu/2) (1-x)^(1/2) / B` equals `f_nu(k) k`, so
    /// only one power is taken.
    #[inline]
    fn excess(&self, k: f64) -> f64 {
        if k > 1e100 {
            return 0.0;
        }
        let nu = self.nu;
        let q = k * k * self.inv_nu;
        // The power is only exponentiated: ln of the rounded 1 + q (absolute error 1e-16, so
        // a relative (nu + 1)/2 * 1e-16 in f) is as good as log1p here, and several times
        // faster in glibc.
        let f = self.t_norm * (-0.5 * (nu + 1.0) * self.ln_1p(q)).exp();
        let a = 0.5 * nu;
        let x = 1.0 / (1.0 + q);
        // The continued fraction of I_(1-x)(1/2, a) terminates after `a` steps when
        // `a = g - 1` is an integer: prefer it for gamma = 2 and 3 where x >= 1/2 (there
        // I_x(a, 1/2) > 0.1, so `1/2 - ...` loses at most one digit).
        let terminating = self.terminating_cf && x >= 0.5;
        let upper = if x < (a + 1.0) / (a + 2.5) && !terminating {
            f * k * beta_cf(a, 0.5, x) * self.inv_nu
        } else {
            0.5 - f * k * beta_cf(0.5, a, q * x)
        };
        (nu + k * k) * self.inv_nu_m1 * f - k * upper
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

/// Continued fraction of the regularised incomplete beta function (the one of Numerical
/// Recipes' `betacf`): `I_x(a, b) = x^a (1-x)^b / (a B(a, b)) * beta_cf(a, b, x)` with
/// `beta_cf = 1 / (1 + d1 / (1 + d2 / (1 + ...)))`, converging fast for
/// `x < (a+1)/(a+b+2)`. Evaluated by the forward (Wallis) recurrence, renormalised once per
/// pair of terms: one division per pair instead of Lentz's four.
#[inline]
fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    let qab = a + b;
    let qap = a + 1.0;
    let qam = a - 1.0;
    // Convergents A/B; (a0, b0) one step behind.
    let (mut a0, mut b0) = (1.0, 1.0);
    let d1 = -qab * x / qap;
    let (mut a1, mut b1) = (1.0, 1.0 + d1);
    let mut h = a1 / b1;
    for m in 1..10_000 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let even = m * (b - m) * x / ((qam + m2) * (a + m2));
        let (a2, b2) = (a1 + even * a0, b1 + even * b0);
        let odd = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        let (a3, b3) = (a2 + odd * a1, b2 + odd * b1);
        let r = 1.0 / b3;
        let hn = a3 * r;
        // Renormalise so that the convergents stay near 1.
        (a0, b0, a1, b1) = (a2 * r, b2 * r, hn, 1.0);
        // Successive convergents within an ulp: the fraction converges at least
        // geometrically here, so what is left is rounding (a 1e-16 test demanded exact
        // equality and ran on through rounding noise, up to 50% more terms).
        if (hn - h).abs() <= f64::EPSILON * hn.abs() {
            return hn;
        }
        h = hn;
    }
    h
}

impl Ndf for StudentT {
    /// `exp(-2 ln cos^2 - g ln(1 + tan^2 / ((g-1) alpha^2))) / (pi alpha^2)`; in log form so
    /// that `cos^-4` cannot overflow at grazing normals (where D diverges like
    /// `cos^(2g-4)` for g < 2).
    fn d(&self, wm: Vec3) -> f64 {
        if let Some(b) = &self.limit {
            return b.d(wm);
        }
        let Some((u2, sin2)) = cos2_sin2(wm) else {
            return 0.0;
        };
        // ln of the rounded 1 + tan^2/((g-1) alpha^2) costs a relative g * 1e-16 in D: as
        // good as log1p, at a fraction of its time, for gamma <= 1e3 (`Self::ln_1p`).
        self.d_scale * (-2.0 * u2.ln() - self.gamma * self.ln_1p(sin2 / u2 * self.inv_a2g1)).exp()
    }

    /// Closed form with the regularised incomplete beta function (theory section 3).
    fn lambda(&self, w: Vec3) -> f64 {
        if let Some(b) = &self.limit {
            return b.lambda(w);
        }
        lambda_on_sphere(w, |c, s2| {
            // Lambda = (s/mu) excess(mu/s) = excess(k) / k with k = c / (s sin), k and 1/k
            // from one division.
            let ss = self.alpha * FRAC_1_SQRT_2 * s2.sqrt();
            let d = 1.0 / (c * ss);
            self.excess(c * c * d) * (ss * ss * d)
        })
    }

    /// `c + sin * s * excess(|mu| / s)` above the horizon, `sin * s * excess(|mu| / s)` below,
    /// with `s = alpha / sqrt 2`; no cancellation on either side.
    fn sigma(&self, w: Vec3) -> f64 {
        if let Some(b) = &self.limit {
            return b.sigma(w);
        }
        let (c, sin) = crate::math::cos_sin_theta(w);
        if sin == 0.0 {
            return c.max(0.0);
        }
        let s = self.alpha * FRAC_1_SQRT_2;
        let k = c.abs() / (sin * s);
        let tail = sin * s * self.excess(k);
        if c > 0.0 { c + tail } else { tail }
    }

    /// Exact, for every gamma > 3/2 and every direction, by the Gamma superposition
    /// (theory section 4): draw the mixing variable `m` from `Gamma(g-1)` tilted by the
    /// Beckmann projected area `sigma_B(w; alpha_m)`, then a Beckmann visible normal at
    /// `alpha_m = alpha sqrt((g-1)/m)`. With `k = mu^2 / (alpha^2 (g-1))`, `a(m) = sqrt(k m)`:
    /// above the horizon the tilted density is part 1 (weight `W1`, `Gamma(g-3/2, rate 1+k)`)
    /// plus `Gamma(g-1)` thinned by `(1 + erf(a))/2` (weight `c`); below it, part 1 thinned by
    /// `1 - sqrt(pi) a erfcx(a)`.
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
