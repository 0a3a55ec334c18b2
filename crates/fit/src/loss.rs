//! The least-squares loss of one sample with the calibration scale projected out (variable
//! projection): for given shape parameters the best scale is linear least squares, so the
//! optimisers search only the shape.

use crate::options::Loss;

/// `sign(x) sqrt(|x|)`: the square root extended to negative (noise-subtracted) values.
#[inline]
pub fn signed_sqrt(x: f64) -> f64 {
    x.abs().sqrt().copysign(x)
}

/// The weighted least-squares problem of one sample under one loss: data `y_j` (`sqrt(L_j)` or
/// `L_j`), weights `w_j`, and the model `y_j ~ c q_j` with `q_j` the unit-scale model
/// transformed like the data and `c >= 0` the amplitude (`sqrt(scale)` or `scale`).
///
/// For given shape parameters the best amplitude is linear least squares,
/// `c* = max(0, sum w y q / sum w q^2)` (variable projection), so the optimiser searches only
/// the shape. The reduced cost is normalised by `sum w y^2`, so it lies in `[0, 1]`.
#[derive(Debug, Clone)]
pub struct Projected {
    pub loss: Loss,
    pub y: Vec<f64>,
    pub w: Vec<f64>,
    /// `sum w y^2`, the cost of the zero model.
    pub syy: f64,
}

/// The best amplitude and the reduced cost of one model evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// `sqrt(scale)` (sqrt loss) or `scale` (linear loss).
    pub amplitude: f64,
    /// Residual sum of squares `sum w (y - c q)^2` divided by `sum w y^2`.
    pub cost: f64,
}

impl Projected {
    /// The problem for measured values `l` with weights `w`.
    pub fn new(loss: Loss, l: &[f64], w: &[f64]) -> Self {
        let y: Vec<f64> = l.iter().map(|&l| Self::transform(loss, l)).collect();
        let syy = y.iter().zip(w).map(|(y, w)| w * y * y).sum();
        Self {
            loss,
            y,
            w: w.to_vec(),
            syy,
        }
    }

    /// The quantity the loss compares: `sqrt(L)` or `L`.
    #[inline]
    pub fn transform(loss: Loss, l: f64) -> f64 {
        match loss {
            Loss::Sqrt => signed_sqrt(l),
            Loss::Linear => l,
        }
    }

    /// The model scale for an amplitude.
    pub fn scale_of(&self, amplitude: f64) -> f64 {
        match self.loss {
            Loss::Sqrt => amplitude * amplitude,
            Loss::Linear => amplitude,
        }
    }

    /// Projects the unit-scale model `m` (untransformed) onto the data; `q` is scratch space.
    pub fn project(&self, m: &[f64], q: &mut Vec<f64>) -> Projection {
        q.clear();
        q.extend(m.iter().map(|&m| Self::transform(self.loss, m)));
        let (mut syq, mut sqq) = (0.0, 0.0);
        for ((y, q), w) in self.y.iter().zip(q.iter()).zip(&self.w) {
            syq += w * y * q;
            sqq += w * q * q;
        }
        let c = if sqq > 0.0 && syq > 0.0 {
            syq / sqq
        } else {
            0.0
        };
        // The residual sum directly (not syy - syq^2/sqq) keeps near-exact fits accurate.
        let rss: f64 = self
            .y
            .iter()
            .zip(q.iter())
            .zip(&self.w)
            .map(|((y, q), w)| {
                let r = y - c * q;
                w * r * r
            })
            .sum();
        Projection {
            amplitude: c,
            cost: if self.syy > 0.0 { rss / self.syy } else { 0.0 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_recovers_amplitude_of_exact_data() {
        let m = [0.5, 1.0, 2.0, 0.0];
        let l: Vec<f64> = m.iter().map(|m| 3.0 * m).collect();
        let w = [1.0; 4];
        for loss in [Loss::Sqrt, Loss::Linear] {
            let p = Projected::new(loss, &l, &w);
            let proj = p.project(&m, &mut Vec::new());
            assert!((p.scale_of(proj.amplitude) - 3.0).abs() < 1e-12);
            assert!(proj.cost < 1e-24);
        }
    }
}
