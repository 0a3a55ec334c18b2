//! The forward model of a sample: the model value at every measured direction pair for a given
//! NDF and glass index, with everything that depends on neither computed once.
//!
//! Every value is `q_j * f(wi_j, wo_j)` with `f` the rough dielectric's BSDF (Walter et al.
//! 2007, reflection or transmission by the sides of the directions, light from either side;
//! theory section 5) and `q_j` the measured quantity per unit BSDF value: `cos(theta_i) / eta^2`
//! for the `L` of an in-plane point, 1 for the BSDF of a general point
//! ([`crate::data::Quantity`]). For one pair, with `h` the half vector,
//!
//! ```text
//! f |wo.z| = K * G(wi, wo) * D(h),   K = |wi.h| |d omega_h / d omega_o| (F or 1 - F) / |wi.z|
//! ```
//!
//! ([`HalfVector::walter_factor`]). `K` and `h` do not depend on the NDF, so they are computed
//! once per glass index (once per fit when eta is fixed); an evaluation then costs one `D` per
//! point and one Smith `Lambda` per distinct direction (measurement grids share directions
//! across incidences, and isotropy makes directions with the same `|cos|` and `|sin|`
//! equivalent).
//!
//! For all orders the walk's orders >= 2 are added: one set of walks per incident direction
//! with next-event estimation toward all its outgoing directions
//! ([`stfit_core::walk::eval_pairs`]), seeded per direction (common random numbers).

use std::collections::HashMap;
use std::marker::PhantomData;
use std::sync::OnceLock;

use stfit_core::bsdf::{HalfVector, Masking};
use stfit_core::error::check_eta;
use stfit_core::ndf::{AnyNdf, Ndf, WithNdf};
use stfit_core::walk::{
    DielectricFacet, Estimator, Microsurface, ScatteringOrders, WalkCost, check_walks_from_wo,
    chunk_walks, eval_pairs_batched, pilot_seed,
};
use stfit_core::{ParamError, Vec3};

use crate::data::Quantity;
use crate::fit::FitError;

/// The eta-dependent geometry of one measured configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PointTerms {
    /// Unit half vector with `h.z > 0`.
    h: Vec3,
    /// `K q / |wo.z|` (module docs): the model value is this times `G D(h)`; zero when no facet
    /// connects `wi` to `wo`.
    k: f64,
    reflect: bool,
}

/// The per-point terms of one glass index.
#[derive(Debug, Clone, PartialEq)]
struct Terms {
    eta: f64,
    points: Vec<PointTerms>,
}

/// The model of a set of measured configurations for any NDF of a family and any glass index:
/// single scattering with the chosen masking, or all orders (height-correlated single
/// scattering plus the walk's orders >= 2).
#[derive(Debug, Clone)]
pub struct Forward {
    pairs: Vec<(Vec3, Vec3)>,
    quantity: Vec<Quantity>,
    /// Per pair, the indices of `wi` and `wo` in `dirs`.
    dir_index: Vec<(usize, usize)>,
    /// Distinct directions, mirrored to `z >= 0` at azimuth 0, whose Smith `Lambda` is needed.
    dirs: Vec<Vec3>,
    masking: Masking,
    orders: ScatteringOrders,
    walks: u64,
    walks_from_wo: f64,
    seed: u64,
    /// The terms of the last glass index used, kept for the next evaluation at that index.
    cache: OnceLock<Terms>,
}

impl Forward {
    /// The model of the pairs `(wi, wo)` whose measured quantities are `quantity`; for `orders`
    /// all, `walks` walks per incident direction from `seed`.
    pub fn new(
        pairs: &[(Vec3, Vec3)],
        quantity: Vec<Quantity>,
        masking: Masking,
        orders: ScatteringOrders,
        walks: u64,
        seed: u64,
    ) -> Result<Self, FitError> {
        crate::options::check_orders(orders, masking)?;
        assert_eq!(pairs.len(), quantity.len(), "one quantity per pair");
        let mut dirs = Vec::new();
        let mut index: HashMap<(u64, u64), usize> = HashMap::new();
        let mut dir_of = |w: Vec3| -> usize {
            // Isotropy: Lambda depends on |cos| and |sin| only.
            let up = Vec3::new(w.x.hypot(w.y), 0.0, w.z.abs());
            *index
                .entry((up.x.to_bits(), up.z.to_bits()))
                .or_insert_with(|| {
                    dirs.push(up);
                    dirs.len() - 1
                })
        };
        let dir_index = pairs
            .iter()
            .map(|&(wi, wo)| (dir_of(wi), dir_of(wo)))
            .collect();
        Ok(Self {
            pairs: pairs.to_vec(),
            quantity,
            dir_index,
            dirs,
            masking,
            orders,
            walks,
            walks_from_wo: 0.0,
            seed,
            cache: OnceLock::new(),
        })
    }

    /// The same model whose walk term walks, for each measured direction `wo`, `fraction` as
    /// many walks from `wo` as from each incident direction
    /// ([`Microsurface::with_walks_from_wo`]). The default is 0: the term from walks from
    /// each incident direction alone. Toward the few dozen directions measured per incidence
    /// those are as accurate for their cost as the bidirectional estimate, which pays a set of
    /// walks per direction (`cargo run --release -p stfit-fit --example surrogate_band`).
    pub fn with_walks_from_wo(self, fraction: f64) -> Result<Self, ParamError> {
        Ok(Self {
            walks_from_wo: check_walks_from_wo(fraction)?,
            cache: OnceLock::new(),
            ..self
        })
    }

    /// The model of in-plane measurements of `L` (the Walter convention,
    /// [`crate::conventions`]) at the pairs `(wi, wo)`.
    pub fn in_plane(
        pairs: &[(Vec3, Vec3)],
        masking: Masking,
        orders: ScatteringOrders,
        walks: u64,
        seed: u64,
    ) -> Result<Self, FitError> {
        let quantity = vec![Quantity::L; pairs.len()];
        Self::new(pairs, quantity, masking, orders, walks, seed)
    }

    /// Number of configurations.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// True when there are no configurations.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The single-scattering part of an all-orders model (height-correlated: the walk's order
    /// 1), or a single-scattering model itself.
    pub fn single_part(&self) -> Self {
        Self {
            orders: ScatteringOrders::Single,
            ..self.clone()
        }
    }

    /// Whether the model includes the walk's orders >= 2.
    pub fn has_walks(&self) -> bool {
        self.orders == ScatteringOrders::All
    }

    /// The glass indices strictly between `lo` and `hi` at which a transmission pair's
    /// refraction half vector is horizontal ([`HalfVector::horizontal_eta`]), ascending and
    /// distinct: between two of them the single-scattering model is smooth in eta, across
    /// one it can jump.
    pub fn horizontal_etas(&self, lo: f64, hi: f64) -> Vec<f64> {
        let mut etas: Vec<f64> = self
            .pairs
            .iter()
            .filter_map(|&(wi, wo)| HalfVector::horizontal_eta(wi, wo))
            .filter(|&e| e > lo && e < hi)
            .collect();
        etas.sort_by(f64::total_cmp);
        etas.dedup();
        etas
    }

    /// Per pair, the glass index above which it is totally internally reflected
    /// ([`HalfVector::total_reflection_eta`]: reflection pairs inside the glass), else `None`.
    pub fn total_reflection_etas(&self) -> Vec<Option<f64>> {
        self.pairs
            .iter()
            .map(|&(wi, wo)| HalfVector::total_reflection_eta(wi, wo))
            .collect()
    }

    /// The measured quantity per unit BSDF value of pair `j` for glass index `eta`.
    fn q(&self, j: usize, eta: f64) -> f64 {
        match self.quantity[j] {
            Quantity::L => crate::conventions::l_per_bsdf(self.pairs[j].0, eta),
            Quantity::Bsdf => 1.0,
        }
    }

    /// The per-point terms for `eta`.
    fn terms(&self, eta: f64) -> Terms {
        let points = self
            .pairs
            .iter()
            .enumerate()
            .map(|(j, &(wi, wo))| match HalfVector::new(wi, wo, eta) {
                Some(hv) => {
                    let f = hv.dielectric_fresnel(eta);
                    PointTerms {
                        h: hv.h,
                        k: hv.walter_factor(wi.z, f) * self.q(j, eta) / wo.z.abs(),
                        reflect: hv.reflect,
                    }
                }
                None => PointTerms {
                    h: Vec3::z(),
                    k: 0.0,
                    reflect: wi.z * wo.z > 0.0,
                },
            })
            .collect();
        Terms { eta, points }
    }

    /// Writes the unit-scale model of every configuration for glass of relative index `eta`
    /// into `out` (resized to [`Forward::len`]).
    pub fn unit_model(&self, ndf: &AnyNdf, eta: f64, out: &mut Vec<f64>) -> Result<(), ParamError> {
        let eta = check_eta(eta)?;
        out.resize(self.pairs.len(), 0.0);
        let cached = self.cache.get_or_init(|| self.terms(eta));
        let fresh;
        let terms = if cached.eta == eta {
            cached
        } else {
            fresh = self.terms(eta);
            &fresh
        };
        match ndf {
            AnyNdf::Beckmann(n) => self.single_with(n, terms, out),
            AnyNdf::Ggx(n) => self.single_with(n, terms, out),
            AnyNdf::StudentT(n) => self.single_with(n, terms, out),
        }
        if self.has_walks() {
            self.add_walks(ndf, eta, out)?;
        }
        Ok(())
    }

    fn single_with<N: Ndf>(&self, ndf: &N, terms: &Terms, out: &mut [f64]) {
        let masking = self.single_masking();
        // One Smith term per distinct direction: a = 1 + Lambda.
        let smith: Vec<_> = self
            .dirs
            .iter()
            .map(|&w| masking.term(1.0 + ndf.lambda(w)))
            .collect();
        for ((p, &(i, o)), out) in terms.points.iter().zip(&self.dir_index).zip(out) {
            *out = if p.k > 0.0 {
                p.k * masking.g(p.reflect, smith[i], smith[o]) * ndf.d(p.h)
            } else {
                0.0
            };
        }
    }

    /// The masking of the single-scattering term: the model's, which for all orders is
    /// height-correlated (the walk's order 1).
    fn single_masking(&self) -> Masking {
        if self.has_walks() {
            Masking::Correlated
        } else {
            self.masking
        }
    }

    /// Adds the unit-scale orders >= 2 of every configuration to `out`: the height-field random
    /// walk (Heitz et al. 2016) on a dielectric microsurface of the NDF.
    fn add_walks(&self, ndf: &AnyNdf, eta: f64, out: &mut [f64]) -> Result<(), ParamError> {
        let term = self.walk_term(ndf, eta)?;
        for (o, v) in out.iter_mut().zip(term.values) {
            *o += v;
        }
        Ok(())
    }

    /// Runs `task` on the microsurface whose walks give the orders >= 2 term
    /// ([`Forward::walk_term`]), built on the concrete NDF ([`OnWalkSurface`]).
    fn on_walk_surface<R>(
        &self,
        ndf: &AnyNdf,
        eta: f64,
        task: impl FnOnce(&dyn Estimator) -> R,
    ) -> Result<R, ParamError> {
        ndf.with(OnWalkSurface {
            facet: DielectricFacet::new(eta)?,
            walks_from_wo: self.walks_from_wo,
            task,
            output: PhantomData,
        })
    }

    /// Estimated wall time, in seconds, of [`Forward::walk_term`] on rayon's current pool, from
    /// a pilot run of the same walks ([`WalkCost::measure_pairs`]: random numbers of its own,
    /// at most a sixteenth of the run's work); 0 for single scattering.
    pub fn walk_seconds(&self, ndf: &AnyNdf, eta: f64) -> Result<f64, ParamError> {
        if !self.has_walks() {
            return Ok(0.0);
        }
        let cost = self.on_walk_surface(ndf, eta, |surface| {
            WalkCost::measure_pairs(surface, &self.pairs, self.walks, pilot_seed(self.seed))
        })?;
        Ok(cost.seconds(self.walks))
    }

    /// The unit-scale orders >= 2 term of every configuration, in the measured quantity, from
    /// `walks` walks per incident direction ([`Forward::new`]), with its per-chunk means
    /// ([`WalkTerm`]).
    pub fn walk_term(&self, ndf: &AnyNdf, eta: f64) -> Result<WalkTerm, ParamError> {
        let est = self.on_walk_surface(ndf, eta, |surface| {
            eval_pairs_batched(surface, &self.pairs, self.walks, self.seed)
        })?;
        let mut term = WalkTerm {
            values: Vec::with_capacity(est.len()),
            group: Vec::with_capacity(est.len()),
            batches: Vec::with_capacity(est.len()),
            batch_walks: chunk_walks(self.walks),
        };
        for (j, e) in est.into_iter().enumerate() {
            // The walk estimates f |wo.z|.
            let unit = self.q(j, eta) / self.pairs[j].1.z.abs();
            term.values.push(e.estimate.mean * unit);
            term.group.push(e.group);
            term.batches
                .push(e.batch_means.iter().map(|b| b * unit).collect());
        }
        Ok(term)
    }
}

/// A task on the microsurface of a [`Forward`]'s orders >= 2 term (orders multiple, dielectric
/// facets, the model's walks from each `wo`), run by [`AnyNdf::with`] on the concrete NDF: the
/// walks then run code compiled for that NDF, with `D`, `Lambda` and the visible-normal
/// sampler inlined, rather than a match on the NDF's family at each of their calls. The same
/// arithmetic, so the same results bit for bit.
struct OnWalkSurface<T, R> {
    facet: DielectricFacet,
    walks_from_wo: f64,
    task: T,
    output: PhantomData<fn() -> R>,
}

impl<T: FnOnce(&dyn Estimator) -> R, R> WithNdf for OnWalkSurface<T, R> {
    type Output = Result<R, ParamError>;

    fn run<N: Ndf>(self, ndf: N) -> Self::Output {
        let surface = Microsurface::new(ndf, self.facet)
            .with_orders(ScatteringOrders::Multiple)
            .with_walks_from_wo(self.walks_from_wo)?;
        Ok((self.task)(&surface))
    }
}

/// The orders >= 2 term of every configuration of a [`Forward`] (unit scale, in the measured
/// quantity) from one set of walks per incident direction, with what its Monte Carlo error is
/// made of: `batches[j][c]` is the term of configuration `j` from the walks of chunk `c` alone
/// (`batch_walks[c]` walks), `values[j]` their walk-weighted mean. Configurations of one
/// `group` share their walks (correlated errors); groups are independent.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkTerm {
    pub values: Vec<f64>,
    pub group: Vec<usize>,
    pub batches: Vec<Vec<f64>>,
    pub batch_walks: Vec<u64>,
}

impl WalkTerm {
    /// The Monte Carlo variance of a linear functional `sum_j a_j values[j]` of the term,
    /// estimated from the independent batches (chunks of walks) of every group:
    /// `B/(B-1) sum_groups sum_c (n_c/N)^2 (sum_{j in group} a_j (batch_jc - value_j))^2`.
    /// Zero when there is a single batch (no estimate of the spread).
    pub fn variance_of(&self, a: &[f64]) -> f64 {
        let b = self.batch_walks.len();
        if b < 2 {
            return 0.0;
        }
        let n: f64 = self.batch_walks.iter().sum::<u64>() as f64;
        let groups = self.group.iter().copied().max().map_or(0, |g| g + 1);
        let mut dev = vec![vec![0.0; b]; groups];
        for (j, &g) in self.group.iter().enumerate() {
            if a[j] == 0.0 {
                continue;
            }
            for (c, d) in dev[g].iter_mut().enumerate() {
                *d += a[j] * (self.batches[j][c] - self.values[j]);
            }
        }
        let sum: f64 = dev
            .iter()
            .flat_map(|d| {
                d.iter()
                    .zip(&self.batch_walks)
                    .map(|(d, &nc)| (nc as f64 / n * d).powi(2))
            })
            .sum();
        sum * b as f64 / (b - 1) as f64
    }

    /// The Monte Carlo standard error of `values[j]` ([`WalkTerm::variance_of`] of the
    /// functional picking configuration `j`).
    pub fn stderr_at(&self, j: usize) -> f64 {
        let mut a = vec![0.0; self.values.len()];
        a[j] = 1.0;
        self.variance_of(&a).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conventions::{pair_from_deg, spherical_from_deg};
    use stfit_core::bsdf::{AnalyticBsdf, RoughDielectric};
    use stfit_core::ndf::{Beckmann, Ggx, StudentT};

    fn ndfs() -> [AnyNdf; 4] {
        [
            Beckmann::new(0.3).unwrap().into(),
            Ggx::new(0.3).unwrap().into(),
            StudentT::new(0.3, 1.7).unwrap().into(),
            StudentT::new(0.3, 6.0).unwrap().into(),
        ]
    }

    /// The precomputed geometry reproduces the core's rough dielectric, `f cos(theta_i) /
    /// eta^2` per in-plane pair, for every NDF and masking, on a grid sharing directions.
    #[test]
    fn in_plane_model_matches_the_rough_dielectric() {
        let pairs: Vec<_> = [0.0, 30.0, 60.0, 80.0]
            .iter()
            .flat_map(|&ti| (0..40).map(move |j| pair_from_deg(ti, 100.0 + 4.0 * j as f64)))
            .collect();
        let eta = 1.51;
        for masking in [Masking::Separable, Masking::Correlated] {
            let fwd = Forward::in_plane(&pairs, masking, ScatteringOrders::Single, 0, 0).unwrap();
            assert!(fwd.dirs.len() < pairs.len());
            for ndf in ndfs() {
                let mut m = Vec::new();
                fwd.unit_model(&ndf, eta, &mut m).unwrap();
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

    /// General pairs (reflection and transmission, light from either side, out of plane) are
    /// the BSDF itself, at any glass index, the cached one or another.
    #[test]
    fn general_model_is_the_bsdf_at_any_eta() {
        let mut pairs = Vec::new();
        for ti in [10.0, 50.0, 130.0, 170.0] {
            for to in [20.0, 60.0, 85.0, 95.0, 120.0, 160.0] {
                for po in [0.0, 70.0, 180.0] {
                    pairs.push((spherical_from_deg(ti, 180.0), spherical_from_deg(to, po)));
                }
            }
        }
        let q = vec![Quantity::Bsdf; pairs.len()];
        let fwd = Forward::new(
            &pairs,
            q,
            Masking::Separable,
            ScatteringOrders::Single,
            0,
            0,
        )
        .unwrap();
        for eta in [1.51, 1.33, 1.51, 2.2] {
            for ndf in ndfs() {
                let mut m = Vec::new();
                fwd.unit_model(&ndf, eta, &mut m).unwrap();
                let bsdf = RoughDielectric::new(ndf, eta, Masking::Separable).unwrap();
                let mut nonzero = 0;
                for (&(wi, wo), &m) in pairs.iter().zip(&m) {
                    let f = bsdf.f_cos(wi, wo) / wo.z.abs();
                    assert!((m - f).abs() <= 1e-13 * f.abs().max(1e-300), "{m} vs {f}");
                    nonzero += usize::from(f > 0.0);
                }
                assert!(nonzero > pairs.len() / 2);
            }
        }
    }
}
