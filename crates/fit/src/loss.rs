//! The least-squares loss of one sample, with the calibration scale projected out (variable
//! projection): for given shape parameters the best scale is found in closed form (`sqrt` and
//! `linear` losses) or by a one-dimensional Gauss-Newton solve (`log` loss), so the optimisers
//! search only the shape.
//!
//! Weights enter only through their ratios (`data-format.md`): they are divided by their
//! largest value on construction, so any positive common factor, however large or small, gives
//! the same fit.

use crate::options::{Loss, Parameter};

/// `sign(x) sqrt(|x|)`: the square root extended to negative (noise-subtracted) values.
#[inline]
pub fn signed_sqrt(x: f64) -> f64 {
    x.abs().sqrt().copysign(x)
}

/// The weighted least-squares problem of one sample under one loss: the measured values `v_j`
/// seen through the loss's transform `T` (`y_j = T(v_j)`), weights `w_j`, and the model
/// `T(scale m_j)` with `m_j` the unit-scale model.
#[derive(Debug, Clone)]
pub struct Projected {
    pub loss: Loss,
    /// `T(v_j)`.
    pub y: Vec<f64>,
    /// The weights divided by the largest.
    pub w: Vec<f64>,
    /// The absolute floor of the log loss (zero for the others).
    pub floor: f64,
    /// The scale, if held fixed.
    pub fixed_scale: Option<f64>,
    /// The normaliser of the cost: `sum w y^2` (the zero model's cost) for `sqrt` and
    /// `linear`, `sum w` for `log` (whose cost is then the weighted mean square).
    pub norm: f64,
}

/// The best scale and the reduced cost of one model evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    pub scale: f64,
    /// Residual sum of squares `sum w (y - T(scale m))^2` divided by [`Projected::norm`].
    pub cost: f64,
}

impl Projected {
    /// The problem for measured values `v` with weights `w` (finite, >= 0, not all zero);
    /// `log_floor` is the log loss's floor relative to the largest value.
    pub fn new(loss: Loss, v: &[f64], w: &[f64], log_floor: f64, scale: Parameter) -> Self {
        let w_max = w.iter().copied().fold(0.0, f64::max);
        let w: Vec<f64> = w.iter().map(|&w| w / w_max).collect();
        let floor = match loss {
            Loss::Log => log_floor * v.iter().copied().fold(0.0, f64::max),
            Loss::Sqrt | Loss::Linear => 0.0,
        };
        let mut p = Self {
            loss,
            y: Vec::new(),
            w,
            floor,
            fixed_scale: match scale {
                Parameter::Fixed(s) => Some(s),
                Parameter::Free => None,
            },
            norm: 1.0,
        };
        p.y = v.iter().map(|&v| p.transform(v)).collect();
        p.norm = match loss {
            Loss::Log => p.w.iter().sum(),
            Loss::Sqrt | Loss::Linear => p.y.iter().zip(&p.w).map(|(y, w)| w * y * y).sum(),
        };
        if p.norm.is_nan() || p.norm <= 0.0 {
            p.norm = 1.0;
        }
        p
    }

    /// The quantity the loss compares: `sqrt(v)`, `v` or `ln(v + floor)`.
    #[inline]
    pub fn transform(&self, v: f64) -> f64 {
        match self.loss {
            Loss::Sqrt => signed_sqrt(v),
            Loss::Linear => v,
            Loss::Log => (v.max(0.0) + self.floor).ln(),
        }
    }

    /// `d T(scale m) / d scale`.
    #[inline]
    pub fn d_transform_d_scale(&self, scale: f64, m: f64) -> f64 {
        match self.loss {
            Loss::Sqrt => m.sqrt() / (2.0 * scale.sqrt()),
            Loss::Linear => m,
            Loss::Log => m / (scale * m + self.floor),
        }
    }

    /// How the transformed model moves with the unit-scale model over a change `dm > 0` of
    /// it: the secant `(T(scale (m + dm)) - T(scale m)) / dm`. It is `d T(scale m) / d m` for
    /// `dm << m` and stays finite where the derivative does not (the square root at `m -> 0`);
    /// 0 for `dm <= 0`.
    #[inline]
    pub fn model_slope(&self, scale: f64, m: f64, dm: f64) -> f64 {
        if dm > 0.0 {
            (self.transform(scale * (m + dm)) - self.transform(scale * m)) / dm
        } else {
            0.0
        }
    }

    /// The weighted residual sum of squares of the model `m` at `scale`.
    fn rss(&self, m: &[f64], scale: f64) -> f64 {
        self.y
            .iter()
            .zip(m)
            .zip(&self.w)
            .map(|((y, &m), w)| {
                let r = y - self.transform(scale * m);
                w * r * r
            })
            .sum()
    }

    /// The best scale for the unit-scale model `m` (or the fixed one) and the reduced cost.
    pub fn project(&self, m: &[f64]) -> Projection {
        match self.loss {
            Loss::Sqrt => {
                // T(scale m) = c sqrt(m) with c = sqrt(scale): one square root per point.
                let q: Vec<f64> = m.iter().map(|&m| signed_sqrt(m)).collect();
                self.project_amplitude(&q, |s| s.sqrt(), |c| c * c)
            }
            Loss::Linear => self.project_amplitude(m, |s| s, |c| c),
            Loss::Log => {
                let scale = self.fixed_scale.unwrap_or_else(|| self.log_scale(m));
                Projection {
                    scale,
                    cost: self.rss(m, scale) / self.norm,
                }
            }
        }
    }

    /// The projection of a loss whose transformed model is linear in an amplitude `c`,
    /// `T(scale m_j) = c q_j` (`sqrt` and `linear`): the fixed scale's amplitude
    /// (`amplitude(scale)`), or the linear least-squares one, clamped at 0, whose scale is
    /// `scale_of(c)`.
    fn project_amplitude(
        &self,
        q: &[f64],
        amplitude: impl Fn(f64) -> f64,
        scale_of: impl Fn(f64) -> f64,
    ) -> Projection {
        let c = match self.fixed_scale {
            Some(s) => amplitude(s),
            None => {
                let (mut syq, mut sqq) = (0.0, 0.0);
                for ((y, q), w) in self.y.iter().zip(q).zip(&self.w) {
                    syq += w * y * q;
                    sqq += w * q * q;
                }
                if sqq > 0.0 && syq > 0.0 {
                    syq / sqq
                } else {
                    0.0
                }
            }
        };
        let rss: f64 = self
            .y
            .iter()
            .zip(q)
            .zip(&self.w)
            .map(|((y, q), w)| {
                let r = y - c * q;
                w * r * r
            })
            .sum();
        Projection {
            scale: self.fixed_scale.unwrap_or_else(|| scale_of(c)),
            cost: rss / self.norm,
        }
    }

    /// The log loss's best scale by Gauss-Newton in `c = ln(scale)`: the residual
    /// `y - ln(e^c m + floor)` has derivative `-p`, `p = e^c m / (e^c m + floor)` in [0, 1),
    /// so the steps are well conditioned; a step that raises the cost is halved.
    fn log_scale(&self, m: &[f64]) -> f64 {
        let sm: f64 = m.iter().zip(&self.w).map(|(m, w)| w * m).sum();
        if sm.is_nan() || sm <= 0.0 {
            return 0.0;
        }
        // Start from the ratio of the values' and the model's weighted sums.
        let sv: f64 = self
            .y
            .iter()
            .zip(&self.w)
            .map(|(y, w)| w * (y.exp() - self.floor).max(0.0))
            .sum();
        let mut c = (sv.max(f64::MIN_POSITIVE) / sm).ln();
        let mut cost = self.rss(m, c.exp());
        for _ in 0..100 {
            let s = c.exp();
            let (mut g, mut h) = (0.0, 0.0);
            for ((y, &m), w) in self.y.iter().zip(m).zip(&self.w) {
                let sm = s * m;
                let p = sm / (sm + self.floor);
                let r = y - (sm + self.floor).ln();
                g += w * r * p;
                h += w * p * p;
            }
            if h.is_nan() || h <= 0.0 {
                break;
            }
            let mut step = g / h;
            let mut improved = false;
            for _ in 0..60 {
                let next = self.rss(m, (c + step).exp());
                if next <= cost {
                    c += step;
                    cost = next;
                    improved = true;
                    break;
                }
                step *= 0.5;
            }
            if !improved || step.abs() < 1e-13 {
                break;
            }
        }
        c.exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The slope over a change `dm` is the derivative of `T(scale m)` for `dm << m` under every
    /// loss, and stays finite for the square root at a model of 0 or below f64's normal range.
    #[test]
    fn model_slope_is_the_derivative_and_finite_at_zero() {
        let (scale, m, floor) = (0.8_f64, 0.3_f64, 1e-3);
        let derivative = |loss| match loss {
            Loss::Sqrt => (scale / m).sqrt() / 2.0,
            Loss::Linear => scale,
            Loss::Log => scale / (scale * m + floor),
        };
        for loss in [Loss::Sqrt, Loss::Linear, Loss::Log] {
            let p = Projected::new(loss, &[1.0], &[1.0], floor, Parameter::Free);
            let s = p.model_slope(scale, m, 1e-9);
            assert!((s / derivative(loss) - 1.0).abs() < 1e-6, "{loss:?}: {s}");
            assert_eq!(p.model_slope(scale, m, 0.0), 0.0);
        }
        let p = Projected::new(Loss::Sqrt, &[1.0], &[1.0], floor, Parameter::Free);
        for m in [0.0, 1e-310, 1e-300] {
            let s = p.model_slope(scale, m, 1e-6);
            assert!(s.is_finite() && s > 0.0, "m {m}: {s}");
            // One standard error moves sqrt(scale m) by at most sqrt(scale dm).
            assert!(s * 1e-6 <= (scale * 1e-6_f64).sqrt() * (1.0 + 1e-12));
        }
    }

    /// Exact data give back their scale and zero cost under every loss, free or fixed.
    #[test]
    fn projection_recovers_the_scale_of_exact_data() {
        let m = [0.5, 1.0, 2.0, 0.0, 1e-4];
        let v: Vec<f64> = m.iter().map(|m| 3.0 * m).collect();
        let w = [1.0; 5];
        for loss in [Loss::Sqrt, Loss::Linear, Loss::Log] {
            let p = Projected::new(loss, &v, &w, 1e-3, Parameter::Free);
            let proj = p.project(&m);
            assert!((proj.scale - 3.0).abs() < 1e-10, "{loss:?}: {}", proj.scale);
            assert!(proj.cost < 1e-20, "{loss:?}: {}", proj.cost);
            let fixed = Projected::new(loss, &v, &w, 1e-3, Parameter::Fixed(3.0)).project(&m);
            assert_eq!(fixed.scale, 3.0);
            assert!(fixed.cost < 1e-20);
        }
    }

    /// Only ratios of weights matter: a common factor of 1e-300 or 1e300 changes nothing.
    #[test]
    fn a_common_weight_factor_changes_nothing() {
        let m = [0.5, 1.0, 2.0, 0.3];
        let v = [1.4, 3.3, 5.8, 1.0];
        let w = [1.0, 2.0, 0.5, 1.0];
        for loss in [Loss::Sqrt, Loss::Linear, Loss::Log] {
            let base = Projected::new(loss, &v, &w, 1e-3, Parameter::Free).project(&m);
            for k in [1e-300, 1e300] {
                let wk: Vec<f64> = w.iter().map(|w| w * k).collect();
                let p = Projected::new(loss, &v, &wk, 1e-3, Parameter::Free).project(&m);
                assert!((p.scale / base.scale - 1.0).abs() < 1e-12, "{loss:?} x {k}");
                assert!((p.cost / base.cost - 1.0).abs() < 1e-12, "{loss:?} x {k}");
            }
        }
    }
}
