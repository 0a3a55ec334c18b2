//! The single-scattering model evaluated on a whole sample, and the least-squares objective with
//! the calibration scale projected out.
//!
//! The model (theory section 8) is `L = scale * f_t(wi, wo) cos(theta_i) / eta^2` with Walter et
//! al.'s single-scattering `f_t` (theory section 5). With light from air (`n_i = 1`) into glass
//! (`n_o = eta`) and the half vector `h = normalize(-(wi + eta wo))`, flipped to `h.z > 0`:
//!
//! ```text
//! L / scale = K * G(wi, wo) * D(h),   K = |wi.h| |wo.h| (1 - F(wi.h)) / (|wo.z| (wi.h + eta wo.h)^2)
//! ```
//!
//! `K` and `h` do not depend on the NDF, so [`Geometry`] computes them once per sample; an
//! evaluation then costs one `D` per point and one Smith `Lambda` per distinct direction (the
//! Walter data share `theta_o` across incidences, and `theta_o` mirrored about 180 degrees has
//! the same `Lambda`).

use std::collections::HashMap;

use stfit_core::bsdf::{Masking, fresnel_dielectric};
use stfit_core::error::check_eta;
use stfit_core::ndf::{AnyNdf, Ndf};
use stfit_core::walk::{DielectricFacet, Microsurface, ScatteringOrders};
use stfit_core::{ParamError, Vec3};

use crate::model::{Loss, wi_from_deg, wo_from_deg};

/// NDF-independent geometry of one measured configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PointGeometry {
    /// Unit half vector with `h.z > 0`.
    h: Vec3,
    /// `K` of the module docs; zero when no facet connects `wi` to `wo`.
    k: f64,
    /// Index of `wi` in [`Geometry::dirs`].
    dir_i: usize,
    /// Index of `wo` mirrored to the upper hemisphere in [`Geometry::dirs`].
    dir_o: usize,
}

/// Per-sample precomputation of everything in the model that does not depend on the NDF.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    points: Vec<PointGeometry>,
    /// Distinct directions (mirrored to `z >= 0`, azimuth 0) whose Smith `Lambda` is needed.
    dirs: Vec<Vec3>,
}

impl Geometry {
    /// Geometry of the configurations `(theta_i_deg, theta_o_deg)` in the data convention
    /// (theory section 8) for glass of relative index `eta`.
    pub fn new(angles: impl IntoIterator<Item = (f64, f64)>, eta: f64) -> Result<Self, ParamError> {
        let eta = check_eta(eta)?;
        let mut dirs = Vec::new();
        let mut index: HashMap<(u64, u64), usize> = HashMap::new();
        let mut dir_index = |w: Vec3| -> usize {
            // Isotropy: Lambda depends on |cos| and |sin| only.
            let up = Vec3::new(w.x.abs().hypot(w.y), 0.0, w.z.abs());
            *index
                .entry((up.x.to_bits(), up.z.to_bits()))
                .or_insert_with(|| {
                    dirs.push(up);
                    dirs.len() - 1
                })
        };
        let points = angles
            .into_iter()
            .map(|(ti, to)| {
                let (wi, wo) = (wi_from_deg(ti), wo_from_deg(to));
                let (h, k) = transmission_factor(wi, wo, eta);
                PointGeometry {
                    h,
                    k,
                    dir_i: dir_index(wi),
                    dir_o: dir_index(wo),
                }
            })
            .collect();
        Ok(Self { points, dirs })
    }

    /// Number of configurations.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True when there are no configurations.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Writes the unit-scale model `f_t(wi, wo) cos(theta_i) / eta^2` of every configuration
    /// into `out` (resized to [`Geometry::len`]).
    pub fn unit_model(&self, ndf: &AnyNdf, masking: Masking, out: &mut Vec<f64>) {
        out.resize(self.points.len(), 0.0);
        match ndf {
            AnyNdf::Beckmann(n) => self.unit_model_with(n, masking, out),
            AnyNdf::Ggx(n) => self.unit_model_with(n, masking, out),
            AnyNdf::StudentT(n) => self.unit_model_with(n, masking, out),
        }
    }

    fn unit_model_with<N: Ndf>(&self, ndf: &N, masking: Masking, out: &mut [f64]) {
        let lambda: Vec<f64> = self.dirs.iter().map(|&w| ndf.lambda(w)).collect();
        match masking {
            Masking::Separable => {
                // G1 = 1 / (1 + Lambda) of each direction on its own side.
                let g1: Vec<f64> = lambda.iter().map(|l| 1.0 / (1.0 + l)).collect();
                for (p, o) in self.points.iter().zip(out.iter_mut()) {
                    *o = if p.k > 0.0 {
                        p.k * g1[p.dir_i] * g1[p.dir_o] * ndf.d(p.h)
                    } else {
                        0.0
                    };
                }
            }
            Masking::Correlated => {
                // Transmission: G = B(1 + Lambda_i, 1 + Lambda_o), via ln Gamma.
                let ln_g: Vec<f64> = lambda.iter().map(|&l| ln_gamma_or_inf(1.0 + l)).collect();
                for (p, o) in self.points.iter().zip(out.iter_mut()) {
                    let (li, lo) = (lambda[p.dir_i], lambda[p.dir_o]);
                    *o = if p.k > 0.0 && li.is_finite() && lo.is_finite() {
                        let ln_b = ln_g[p.dir_i] + ln_g[p.dir_o]
                            - statrs::function::gamma::ln_gamma(2.0 + li + lo);
                        p.k * ln_b.exp() * ndf.d(p.h)
                    } else {
                        0.0
                    };
                }
            }
        }
    }
}

/// The configurations of one incidence angle, for the random walk.
#[derive(Debug, Clone, PartialEq)]
struct WalkGroup {
    wi: Vec3,
    /// Seed of this incidence's walks: fixed, so every evaluation reuses the same random numbers.
    seed: u64,
    /// Indices of the configurations (into the order given to [`MultipleGeometry::new`]).
    index: Vec<usize>,
    wos: Vec<Vec3>,
}

/// The order >= 2 part of the model on a set of configurations, by the height-field random walk
/// (Heitz et al. 2016) on a dielectric microsurface with the NDF under test.
///
/// The configurations are grouped by incidence angle; every group runs one set of walks with
/// next-event estimation toward all its transmitted directions
/// ([`Microsurface::eval_many`](stfit_core::walk::Microsurface::eval_many)). Each group's seed is
/// fixed from the run's seed and the incidence angle (common random numbers), so the result is a
/// deterministic, piecewise smooth function of the NDF parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct MultipleGeometry {
    groups: Vec<WalkGroup>,
    len: usize,
    eta: f64,
    walks: u64,
}

impl MultipleGeometry {
    /// Groups `(theta_i_deg, theta_o_deg)` configurations (data convention) by incidence, for
    /// `walks` walks per incidence angle from seed `seed`.
    pub fn new(
        angles: impl IntoIterator<Item = (f64, f64)>,
        eta: f64,
        walks: u64,
        seed: u64,
    ) -> Result<Self, ParamError> {
        let eta = check_eta(eta)?;
        let mut groups: Vec<WalkGroup> = Vec::new();
        let mut by_angle: HashMap<u64, usize> = HashMap::new();
        let mut len = 0;
        for (j, (ti, to)) in angles.into_iter().enumerate() {
            let g = *by_angle.entry(ti.to_bits()).or_insert_with(|| {
                groups.push(WalkGroup {
                    wi: wi_from_deg(ti),
                    seed: incidence_seed(seed, ti),
                    index: Vec::new(),
                    wos: Vec::new(),
                });
                groups.len() - 1
            });
            groups[g].index.push(j);
            groups[g].wos.push(wo_from_deg(to));
            len = j + 1;
        }
        Ok(Self {
            groups,
            len,
            eta,
            walks,
        })
    }

    /// Adds the unit-scale order >= 2 model `f_multi(wi, wo) cos(theta_i) / eta^2` of every
    /// configuration to `out` (of length the number of configurations).
    pub fn add_unit_model(&self, ndf: &AnyNdf, out: &mut [f64]) -> Result<(), ParamError> {
        assert_eq!(out.len(), self.len, "one output per configuration");
        let surface = Microsurface::new(*ndf, DielectricFacet::new(self.eta)?)
            .with_orders(ScatteringOrders::Multiple);
        let radiance = 1.0 / (self.eta * self.eta);
        for g in &self.groups {
            let est = surface.eval_many(g.wi, &g.wos, self.walks, g.seed);
            for ((&j, wo), e) in g.index.iter().zip(&g.wos).zip(est) {
                // eval_many estimates f |wo.z|; L wants f cos(theta_i).
                out[j] += e.mean / wo.z.abs() * g.wi.z * radiance;
            }
        }
        Ok(())
    }
}

/// The walk seed of one incidence angle: the run's seed mixed with the angle's bits
/// (SplitMix64 finaliser), so each incidence has its own stream whatever the grouping order.
fn incidence_seed(seed: u64, theta_i_deg: f64) -> u64 {
    let mut z = seed ^ theta_i_deg.to_bits().wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn ln_gamma_or_inf(x: f64) -> f64 {
    if x.is_finite() {
        statrs::function::gamma::ln_gamma(x)
    } else {
        f64::INFINITY
    }
}

/// Half vector and NDF-independent factor `K` for light from air at `wi` (`wi.z > 0`)
/// transmitted to `wo` inside glass (`wo.z < 0`); `K = 0` when no facet connects them.
fn transmission_factor(wi: Vec3, wo: Vec3, eta: f64) -> (Vec3, f64) {
    let (ci, co) = (wi.z, wo.z);
    let h = -(wi + wo * eta);
    let len = h.norm();
    if len.is_nan() || len <= 0.0 || ci.is_nan() || ci <= 0.0 || co.is_nan() || co >= 0.0 {
        return (Vec3::z(), 0.0);
    }
    let mut h = h / len;
    if h.z < 0.0 {
        h = -h;
    }
    let (di, d_o) = (wi.dot(&h), wo.dot(&h));
    // Each direction must lie on the same side of the facet as of the macro-surface.
    if di * ci <= 0.0 || d_o * co <= 0.0 {
        return (h, 0.0);
    }
    let f = fresnel_dielectric(di, eta);
    let denom = di + eta * d_o;
    (h, (di * d_o).abs() * (1.0 - f) / (co.abs() * denom * denom))
}

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
    use crate::model::{ModelKind, ModelParams};

    #[test]
    fn unit_model_matches_l_single() {
        let angles: Vec<(f64, f64)> = [0.0, 30.0, 60.0, 80.0]
            .iter()
            .flat_map(|&ti| (0..40).map(move |j| (ti, 100.0 + 4.0 * j as f64)))
            .collect();
        let geom = Geometry::new(angles.iter().copied(), 1.51).unwrap();
        assert!(geom.dirs.len() < angles.len());
        for (kind, gamma) in [
            (ModelKind::Beckmann, 0.0),
            (ModelKind::Ggx, 0.0),
            (ModelKind::StudentT, 1.7),
            (ModelKind::StudentT, 6.0),
        ] {
            for masking in [Masking::Separable, Masking::Correlated] {
                let params = ModelParams {
                    kind,
                    alpha: 0.3,
                    gamma,
                    scale: 1.0,
                };
                let mut m = Vec::new();
                geom.unit_model(&params.ndf().unwrap(), masking, &mut m);
                for (&(ti, to), &m) in angles.iter().zip(&m) {
                    let l = params.l_single(ti, to, 1.51, masking).unwrap();
                    assert!(
                        (m - l).abs() <= 1e-13 * l.abs().max(1e-300),
                        "{kind:?} {masking:?} ({ti}, {to}): {m} vs {l}"
                    );
                }
            }
        }
    }

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
