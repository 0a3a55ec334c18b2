//! The forward model of a sample: the model value at every measured direction pair for a given
//! NDF, with everything that does not depend on the NDF computed once.
//!
//! Every value is `q_j * f(wi_j, wo_j)` with `f` the rough dielectric's BSDF (Walter et al.
//! 2007, reflection or transmission by the sides of the directions; theory section 5) and `q_j`
//! the measured quantity per unit BSDF value (`cos(theta_i) / eta^2` for the in-plane `L` of
//! [`crate::conventions`]). For one pair, with `h` the half vector,
//!
//! ```text
//! f |wo.z| = K * G(wi, wo) * D(h),   K = |wi.h| |d omega_h / d omega_o| (F or 1 - F) / |wi.z|
//! ```
//!
//! ([`HalfVector::walter_factor`]). `K` and `h` do not depend on the NDF, so [`Geometry`]
//! computes them once; an evaluation then costs one `D` per point and one Smith `Lambda` per
//! distinct direction (measurement grids share directions across incidences, and isotropy
//! makes directions with the same `|cos|` and `|sin|` equivalent).
//!
//! For all orders the walk's orders >= 2 are added: one set of walks per incident direction
//! with next-event estimation toward all its outgoing directions
//! ([`stfit_core::walk::eval_pairs`]), seeded per direction (common random numbers).

use std::collections::HashMap;

use stfit_core::bsdf::{HalfVector, Masking, fresnel_dielectric};
use stfit_core::error::check_eta;
use stfit_core::ndf::{AnyNdf, Ndf};
use stfit_core::walk::{DielectricFacet, Microsurface, ScatteringOrders, eval_pairs};
use stfit_core::{ParamError, Vec3};

use crate::conventions::l_per_bsdf;
use crate::fit::FitError;

/// NDF-independent geometry of one measured configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PointGeometry {
    /// Unit half vector with `h.z > 0`.
    h: Vec3,
    /// `K q / |wo.z|` (module docs): the model value is this times `G D(h)`; zero when no facet
    /// connects `wi` to `wo`.
    k: f64,
    reflect: bool,
    /// Index of `wi` in [`Geometry::dirs`].
    dir_i: usize,
    /// Index of `wo` in [`Geometry::dirs`].
    dir_o: usize,
}

/// Per-sample precomputation of the single-scattering model for everything that does not
/// depend on the NDF.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Geometry {
    points: Vec<PointGeometry>,
    /// Distinct directions, mirrored to `z >= 0` at azimuth 0, whose Smith `Lambda` is needed.
    dirs: Vec<Vec3>,
}

impl Geometry {
    /// The geometry of the pairs `(wi, wo)` for glass of relative index `eta`, with `q[j]` the
    /// measured quantity per unit BSDF value of pair `j`.
    pub fn new(pairs: &[(Vec3, Vec3)], q: &[f64], eta: f64) -> Result<Self, ParamError> {
        let eta = check_eta(eta)?;
        let mut dirs = Vec::new();
        let mut index: HashMap<(u64, u64), usize> = HashMap::new();
        let mut dir_index = |w: Vec3| -> usize {
            // Isotropy: Lambda depends on |cos| and |sin| only.
            let up = Vec3::new(w.x.hypot(w.y), 0.0, w.z.abs());
            *index
                .entry((up.x.to_bits(), up.z.to_bits()))
                .or_insert_with(|| {
                    dirs.push(up);
                    dirs.len() - 1
                })
        };
        let points = pairs
            .iter()
            .zip(q)
            .map(|(&(wi, wo), &q)| {
                let (h, k, reflect) = match HalfVector::new(wi, wo, eta) {
                    Some(hv) => {
                        let f = fresnel_dielectric(hv.cos_ih, eta);
                        (hv.h, hv.walter_factor(wi.z, f) * q / wo.z.abs(), hv.reflect)
                    }
                    None => (Vec3::z(), 0.0, wi.z * wo.z > 0.0),
                };
                PointGeometry {
                    h,
                    k,
                    reflect,
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

    /// Writes the unit-scale single-scattering model of every configuration into `out`
    /// (resized to [`Geometry::len`]).
    pub fn unit_model(&self, ndf: &AnyNdf, masking: Masking, out: &mut Vec<f64>) {
        out.resize(self.points.len(), 0.0);
        match ndf {
            AnyNdf::Beckmann(n) => self.unit_model_with(n, masking, out),
            AnyNdf::Ggx(n) => self.unit_model_with(n, masking, out),
            AnyNdf::StudentT(n) => self.unit_model_with(n, masking, out),
        }
    }

    fn unit_model_with<N: Ndf>(&self, ndf: &N, masking: Masking, out: &mut [f64]) {
        // One Smith term per distinct direction: a = 1 + Lambda.
        let terms: Vec<_> = self
            .dirs
            .iter()
            .map(|&w| masking.term(1.0 + ndf.lambda(w)))
            .collect();
        for (p, o) in self.points.iter().zip(out.iter_mut()) {
            *o = if p.k > 0.0 {
                p.k * masking.g(p.reflect, terms[p.dir_i], terms[p.dir_o]) * ndf.d(p.h)
            } else {
                0.0
            };
        }
    }
}

/// The orders >= 2 term of the model, by the height-field random walk (Heitz et al. 2016) on a
/// dielectric microsurface with the NDF under test.
#[derive(Debug, Clone, PartialEq)]
struct WalkTerm {
    pairs: Vec<(Vec3, Vec3)>,
    /// `q / |wo.z|` per pair: the walk estimates `f |wo.z|`.
    factor: Vec<f64>,
    eta: f64,
    walks: u64,
    seed: u64,
}

impl WalkTerm {
    /// Adds the unit-scale orders >= 2 model of every configuration to `out`.
    fn add_unit_model(&self, ndf: &AnyNdf, out: &mut [f64]) -> Result<(), ParamError> {
        let surface = Microsurface::new(*ndf, DielectricFacet::new(self.eta)?)
            .with_orders(ScatteringOrders::Multiple);
        let est = eval_pairs(&surface, &self.pairs, self.walks, self.seed);
        for ((o, e), f) in out.iter_mut().zip(est).zip(&self.factor) {
            *o += e.mean * f;
        }
        Ok(())
    }
}

/// The model of a set of measured configurations for any NDF of a family: single scattering
/// with the chosen masking, or all orders (height-correlated single scattering plus the walk's
/// orders >= 2).
#[derive(Debug, Clone, PartialEq)]
pub struct Forward {
    geometry: Geometry,
    masking: Masking,
    walk: Option<WalkTerm>,
}

impl Forward {
    /// The model of the pairs `(wi, wo)` with quantity per unit BSDF value `q`, for glass of
    /// index `eta`; for `orders` all, `walks` walks per incident direction from `seed`.
    pub fn new(
        pairs: &[(Vec3, Vec3)],
        q: Vec<f64>,
        eta: f64,
        masking: Masking,
        orders: ScatteringOrders,
        walks: u64,
        seed: u64,
    ) -> Result<Self, FitError> {
        crate::options::check_orders(orders, masking)?;
        let geometry = Geometry::new(pairs, &q, eta)?;
        let walk = (orders == ScatteringOrders::All).then(|| WalkTerm {
            pairs: pairs.to_vec(),
            factor: pairs
                .iter()
                .zip(&q)
                .map(|((_, wo), q)| q / wo.z.abs())
                .collect(),
            eta,
            walks,
            seed,
        });
        Ok(Self {
            geometry,
            masking,
            walk,
        })
    }

    /// The model of in-plane measurements of `L` (the Walter convention,
    /// [`crate::conventions`]) at the pairs `(wi, wo)`.
    pub fn in_plane(
        pairs: &[(Vec3, Vec3)],
        eta: f64,
        masking: Masking,
        orders: ScatteringOrders,
        walks: u64,
        seed: u64,
    ) -> Result<Self, FitError> {
        let q = pairs.iter().map(|(wi, _)| l_per_bsdf(*wi, eta)).collect();
        Self::new(pairs, q, eta, masking, orders, walks, seed)
    }

    /// Number of configurations.
    pub fn len(&self) -> usize {
        self.geometry.len()
    }

    /// True when there are no configurations.
    pub fn is_empty(&self) -> bool {
        self.geometry.is_empty()
    }

    /// The single-scattering part of an all-orders model (height-correlated: the walk's order
    /// 1), or a single-scattering model itself.
    pub fn single_part(&self) -> Self {
        Self {
            geometry: self.geometry.clone(),
            masking: self.masking,
            walk: None,
        }
    }

    /// Whether the model includes the walk's orders >= 2.
    pub fn has_walks(&self) -> bool {
        self.walk.is_some()
    }

    /// Writes the unit-scale model of every configuration into `out` (resized to
    /// [`Forward::len`]).
    pub fn unit_model(&self, ndf: &AnyNdf, out: &mut Vec<f64>) -> Result<(), ParamError> {
        self.geometry.unit_model(ndf, self.masking, out);
        if let Some(walk) = &self.walk {
            walk.add_unit_model(ndf, out)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conventions::pair_from_deg;
    use stfit_core::bsdf::{AnalyticBsdf, RoughDielectric};
    use stfit_core::ndf::{Beckmann, Ggx, StudentT};

    /// The precomputed geometry reproduces the core's rough dielectric, `f cos(theta_i) /
    /// eta^2` per pair, for every NDF and masking, on a grid sharing directions.
    #[test]
    fn geometry_matches_the_rough_dielectric() {
        let pairs: Vec<_> = [0.0, 30.0, 60.0, 80.0]
            .iter()
            .flat_map(|&ti| (0..40).map(move |j| pair_from_deg(ti, 100.0 + 4.0 * j as f64)))
            .collect();
        let eta = 1.51;
        let ndfs: [AnyNdf; 4] = [
            Beckmann::new(0.3).unwrap().into(),
            Ggx::new(0.3).unwrap().into(),
            StudentT::new(0.3, 1.7).unwrap().into(),
            StudentT::new(0.3, 6.0).unwrap().into(),
        ];
        for masking in [Masking::Separable, Masking::Correlated] {
            let fwd =
                Forward::in_plane(&pairs, eta, masking, ScatteringOrders::Single, 0, 0).unwrap();
            assert!(fwd.geometry.dirs.len() < pairs.len());
            for ndf in ndfs {
                let mut m = Vec::new();
                fwd.unit_model(&ndf, &mut m).unwrap();
                let bsdf = RoughDielectric::new(ndf, eta, masking).unwrap();
                for (&(wi, wo), &m) in pairs.iter().zip(&m) {
                    let l = bsdf.f_cos(wi, wo) / wo.z.abs() * wi.z / (eta * eta);
                    assert!(
                        (m - l).abs() <= 1e-13 * l.abs().max(1e-300),
                        "{ndf:?} {masking:?} {wi:?} {wo:?}: {m} vs {l}"
                    );
                }
            }
        }
    }
}
