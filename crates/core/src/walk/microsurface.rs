//! The microsurface BSDF: the height-field random walk over an NDF and a facet BSDF.

use super::engine::{
    self, Flight, Hit, Start, Target, WalkEnd, WalkSample, Walker, hit_fraction, mirrored_depth,
};
use super::{Facet, HeightFieldHit, MAX_BOUNCES, ScatteringOrders, WALKS_FROM_WO};
use crate::error::ParamError;
use crate::math::Vec3;
use crate::ndf::Ndf;
use rand::{Rng, RngExt};
use rand_distr::Exp1;

/// A Smith microsurface with NDF `N` and facet BSDF `F`, evaluated and sampled by the
/// height-field random walk (Heitz et al. 2016; see the [module documentation](super)).
///
/// Light may arrive from either side (`wi.z < 0` is light from inside the lower medium). With a
/// [`DielectricFacet`](super::DielectricFacet) the walk crosses the interface; with opaque facets
/// the lower side sees a two-sided sheet. A microsurface is itself a [`Facet`]: a
/// `Microsurface<N, Microsurface<M, F>>` has bi-scale roughness.
///
/// As a [`Bsdf`](crate::bsdf::Bsdf):
/// - `eval(wi, wo)` is an unbiased estimate of `f(wi, wo) |wo.z|` from one walk with next-event
///   estimation at every hit;
/// - `sample(wi)` returns the exit direction of one walk with its throughput as `weight`;
///   its `pdf` field is filled by one [`Bsdf::pdf`](crate::bsdf::Bsdf::pdf) estimate (a second walk);
/// - `pdf(wi, wo)` is an unbiased estimate of the density of directions `sample` returns: the
///   same next-event estimation with each facet's sampling density in place of its BSDF (the
///   facet's [`Facet::phase_pdf`]). It is exact in expectation, not pointwise: an estimate may be
///   0 for a direction `sample` can return. For multiple importance sampling, compute it from
///   random numbers independent of the sample it weights.
///
/// Only the paths selected by [`ScatteringOrders`] contribute.
///
/// ```
/// use stfit_core::bsdf::{AnalyticBsdf, Masking, RoughDielectric};
/// use stfit_core::ndf::Ggx;
/// use stfit_core::walk::{DielectricFacet, Estimator, Microsurface};
/// use stfit_core::{ScatteringOrders, Vec3};
///
/// let ggx = Ggx::new(0.5)?;
/// let surface = Microsurface::new(ggx, DielectricFacet::new(1.5)?);
/// let wi = Vec3::new(0.6, 0.0, 0.8);
/// let wo = Vec3::new(-0.3, 0.0, -(0.91f64).sqrt());
/// // The walk's order 1 is the analytic BSDF with height-correlated masking.
/// let single = surface.with_orders(ScatteringOrders::Single);
/// let e = single.eval_many(wi, &[wo], 50_000, 3)[0];
/// let exact = RoughDielectric::new(ggx, 1.5, Masking::Correlated)?.f_cos(wi, wo);
/// assert!((e.mean - exact).abs() < 5.0 * e.stderr, "{} vs {exact}", e.mean);
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
///
/// Variance: one `eval` is heavy-tailed. A walker that hits the surface while travelling
/// steeply upward sees few facets (small `sigma`), so its phase function is large, while such
/// hits are rare; and some directions are reached mostly through rare paths (backward
/// transmission, straight through at normal incidence). One `eval` converges slowly there; the
/// batch estimates ([`Estimator`](super::Estimator)) average over every flight and walk from
/// both ends (module documentation). For Student-T with `gamma < 7/4`,
/// `D` grows toward vertical facets fast enough (as `cos^(2 gamma - 4)`) that the phase
/// function at an event whose half vector nears the horizon has infinite variance over the
/// walker's directions; the bidirectional estimate tempers it at a path's ends, not at the
/// events between: means converge, standard errors understate the error. Sampling (`sample`,
/// `albedo`) has no such issue: every walk has a bounded weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Microsurface<N, F> {
    ndf: N,
    facet: F,
    orders: ScatteringOrders,
    max_bounces: u32,
    walks_from_wo: f64,
}

impl<N: Ndf, F: Facet> Microsurface<N, F> {
    /// A microsurface with the given NDF and facet BSDF, returning all scattering orders.
    pub fn new(ndf: N, facet: F) -> Self {
        Self {
            ndf,
            facet,
            orders: ScatteringOrders::All,
            max_bounces: MAX_BOUNCES,
            walks_from_wo: WALKS_FROM_WO,
        }
    }

    /// The same microsurface restricted to the given scattering orders.
    pub fn with_orders(self, orders: ScatteringOrders) -> Self {
        Self { orders, ..self }
    }

    /// The same microsurface with another safety cap on the number of scattering events per
    /// walk (default [`MAX_BOUNCES`]); walks that reach it end as [`WalkEnd::Truncated`] and the
    /// estimators report the flux they drop. For tests of that accounting: real paths need no cap.
    pub fn with_max_bounces(self, max_bounces: u32) -> Result<Self, ParamError> {
        Ok(Self {
            max_bounces: engine::check_max_bounces(max_bounces)?,
            ..self
        })
    }

    /// The safety cap on scattering events per walk.
    pub fn max_bounces(&self) -> u32 {
        self.max_bounces
    }

    /// The same microsurface whose [`Estimator`](super::Estimator) walks, for each direction
    /// `wo` it estimates, `fraction` as many walks from `wo` as it walks from `wi` (default
    /// [`WALKS_FROM_WO`]), in `[0, 16]`; 0 estimates from `wi` alone. The walks from `wo`
    /// serve one direction each, those from `wi` every `wo` at once: see
    /// [`bidirectional`](super) estimation in the module documentation.
    pub fn with_walks_from_wo(self, fraction: f64) -> Result<Self, ParamError> {
        Ok(Self {
            walks_from_wo: super::check_walks_from_wo(fraction)?,
            ..self
        })
    }

    /// Walks from each `wo` per walk from `wi` of the batch estimates.
    pub fn walks_from_wo(&self) -> f64 {
        self.walks_from_wo
    }

    /// The NDF.
    pub fn ndf(&self) -> &N {
        &self.ndf
    }

    /// The facet BSDF.
    pub fn facet(&self) -> &F {
        &self.facet
    }

    /// The selected scattering orders.
    pub fn orders(&self) -> ScatteringOrders {
        self.orders
    }

    /// One random walk from `wi` without next-event estimation (`wi.z != 0`). The exit order of
    /// an `Escaped` walk may lie outside the selected orders; see [`Microsurface::sample_walk`].
    pub fn random_walk<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> WalkEnd {
        engine::random_walk(self, wi, rng)
    }

    /// Projected area `sigma(-ws)` of the facets a walker travelling along `ws` (in the frame
    /// of its side) can meet, given `lambda = Lambda(ws)`: `ws.z Lambda(ws)`, by
    /// `sigma(v) = v.z (1 + Lambda(v))` and `Lambda(-v) = -1 - Lambda(v)`, or the NDF's own
    /// where that product is not a positive number (at the horizon).
    #[inline]
    fn sigma_seen(&self, ws: Vec3, lambda: f64) -> f64 {
        let sigma = ws.z * lambda;
        if sigma.is_finite() && sigma > 0.0 {
            sigma
        } else {
            self.ndf.sigma(-ws)
        }
    }

    /// `sigma(-ws) / P(hit)` for a walker travelling upward along `ws` from depth `from`
    /// ([`Flight`]): with `a = from Lambda(ws)`, `P(hit) = a phi(a)` and `sigma(-ws) = ws.z
    /// Lambda(ws)`, so it is `ws.z / (from phi(a))`, finite as `Lambda` vanishes (`phi` is
    /// [`hit_fraction`]).
    #[inline]
    fn sigma_per_hit(&self, ws: Vec3, lambda: f64, from: f64) -> f64 {
        let a = from * lambda;
        let p = a * hit_fraction(a);
        if p >= 0.5 {
            self.sigma_seen(ws, lambda) / p
        } else {
            ws.z / (from * hit_fraction(a))
        }
    }

    /// The exit of one random walk from `wi` if its order is selected: the fast core of
    /// [`Bsdf::sample`](crate::bsdf::Bsdf::sample) without its pdf estimate.
    #[inline]
    pub fn sample_walk<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<WalkSample> {
        engine::sample_walk(self, wi, rng)
    }
}

impl<N: Ndf, F: Facet> Walker for Microsurface<N, F> {
    #[inline]
    fn orders(&self) -> ScatteringOrders {
        self.orders
    }

    #[inline]
    fn target(&self, wo: Vec3) -> Option<Target> {
        Target::new(wo, |up| self.ndf.lambda(up))
    }

    #[inline]
    fn start(&self, wi: Vec3) -> Start {
        let inside = wi.z < 0.0;
        let ws = if inside { wi } else { -wi };
        Start {
            wi,
            lambda: self.ndf.lambda(ws),
            at_hits: false,
        }
    }

    /// The height-field walk: free flights in depth with rate `|Lambda|`, exact visible-normal
    /// sampling at every hit. Next-event estimation averages over every flight
    /// ([`Flight::Up`], [`Flight::Down`]).
    #[inline]
    fn walk<const NEE: bool, R: Rng + ?Sized>(
        &self,
        start: &Start,
        rng: &mut R,
        mut visit: impl FnMut(&Hit, &mut R),
    ) -> WalkEnd {
        let last = self.orders.last_order();
        let mut w = -start.wi;
        let mut inside = start.wi.z < 0.0;
        let mut depth = 0.0f64;
        let mut weight = 1.0f64;
        let mut order = 0u32;
        loop {
            // Travel along w in the frame of the surface on the walker's side.
            let ws = if inside { -w } else { w };
            let lambda = if order == 0 {
                start.lambda
            } else {
                self.ndf.lambda(ws)
            };
            let flight: f64 = rng.sample(Exp1);
            // Whether the event this flight may end in is visited (see `Walker::walk`).
            let visited = NEE && order < last && order < self.max_bounces;
            let from = depth;
            if ws.z > 0.0 {
                // Escape probability exp(-depth Lambda) = G1(w, h): the walker escapes unless
                // depth Lambda > flight (NaN at depth 0 with Lambda infinite escapes), a test
                // that needs no division, so the branch does not wait for it. Where the two
                // differ by rounding the walker stays, at the top (depth 0) at the least.
                let hits = depth * lambda > flight;
                if !hits {
                    if visited && from > 0.0 && !start.at_hits {
                        // The event the flight would have ended in, at a depth drawn from the
                        // flight's hits: given that the walker escaped, flight - a is a fresh
                        // Exp(1), so exp(a - flight) is a uniform that places it (no random
                        // number drawn, so walks with and without NEE draw the same numbers).
                        let a = from * lambda;
                        let u = (a - flight).exp();
                        // The fraction of `from` the truncated exponential climbs.
                        let climb = if a > 1e-12 {
                            -(-u * a * hit_fraction(a)).ln_1p() / a
                        } else {
                            u
                        };
                        visit(
                            &Hit {
                                wi: -w,
                                inside,
                                sigma: self.sigma_seen(ws, lambda),
                                sigma_nee: self.sigma_per_hit(ws, lambda, from),
                                depth: (from * (1.0 - climb)).max(0.0),
                                flight: Flight::Up { from, lambda },
                                weight,
                                order: order + 1,
                            },
                            rng,
                        );
                    }
                    return WalkEnd::Escaped(WalkSample {
                        wo: w,
                        weight,
                        order,
                    });
                }
                depth = (depth - flight / lambda).max(0.0);
            } else {
                // Downward (Lambda <= -1) the walker always hits; at the horizon it hits in place.
                depth -= flight / lambda;
            }
            order += 1;
            if order > last {
                return WalkEnd::Stopped;
            }
            if order > self.max_bounces {
                return WalkEnd::Truncated { weight };
            }
            if visited {
                let sigma = self.sigma_seen(ws, lambda);
                let (sigma_nee, flight) = if ws.z > 0.0 {
                    (
                        if start.at_hits {
                            sigma
                        } else {
                            self.sigma_per_hit(ws, lambda, from)
                        },
                        Flight::Up { from, lambda },
                    )
                } else {
                    (
                        sigma,
                        Flight::Down {
                            from,
                            rate: -lambda,
                        },
                    )
                };
                visit(
                    &Hit {
                        wi: -w,
                        inside,
                        sigma,
                        sigma_nee,
                        depth,
                        flight,
                        weight,
                        order,
                    },
                    rng,
                );
            }
            // Scatter at a visible facet (outward normal m).
            // After the first flight the sampler takes what it shares with Lambda from the
            // flight's; at the first, Lambda(wi) is itself on the critical path, and the
            // sampler computes its own in parallel.
            let m = if order == 1 {
                self.ndf.sample_visible(-ws, rng)
            } else {
                self.ndf.sample_visible_after(-ws, lambda, rng)
            };
            let Some(s) = self.facet.scatter(-w, m, rng) else {
                return WalkEnd::Absorbed;
            };
            weight *= s.weight;
            let now_inside = s.wo.dot(&m) < 0.0;
            if now_inside != inside {
                depth = mirrored_depth(depth);
                inside = now_inside;
            }
            w = s.wo;
        }
    }

    #[inline(always)]
    fn phase<R: Rng + ?Sized>(&self, hit: &Hit, wo: Vec3, pdf: bool, rng: &mut R) -> f64 {
        let vis = HeightFieldHit::reached(&self.ndf, hit.wi, hit.inside, hit.sigma, hit.sigma_nee);
        if pdf {
            self.facet.phase_pdf(&vis, wo, rng)
        } else {
            self.facet.phase(&vis, wo, rng)
        }
    }
}

engine::walk_bsdf!(Microsurface<N: Ndf, F: Facet>);

#[cfg(test)]
mod tests {
    use super::mirrored_depth;

    #[test]
    fn mirrored_depth_is_an_involution() {
        for t in [1e-9, 0.01, 0.5, 1.0, 3.0, 30.0] {
            let back = mirrored_depth(mirrored_depth(t));
            assert!((back - t).abs() <= 1e-12 * t.max(1.0), "{t} -> {back}");
            // C1 + C1' = 1.
            let sum = (-t).exp() + (-mirrored_depth(t)).exp();
            assert!((sum - 1.0).abs() < 1e-15);
        }
    }

    /// `-ln(1 - exp(-t))` against mpmath (60 digits) on both sides of `ln 2`, from the top
    /// of the surface (`t = 1e-300`) to deep below it (`t = 700`, where the result is
    /// `exp(-t)` itself).
    #[test]
    // 0.6931 and 0.6932 bracket ln 2 on purpose.
    #[allow(clippy::excessive_precision, clippy::approx_constant)]
    fn mirrored_depth_matches_high_precision_references() {
        let refs = [
            (1e-300, 690.775_527_898_213_71),
            (1e-9, 20.723_265_837_446_411),
            (0.01, 4.610_166_019_324_896_9),
            (0.3, 1.350_225_612_814_846_7),
            (0.6931, 0.693_194_363_346_000_89),
            (0.6932, 0.693_094_363_909_636_51),
            (1.0, 0.458_675_145_387_081_89),
            (3.0, 0.051_069_180_942_701_587),
            (30.0, 9.357_622_968_840_612_4e-14),
            (700.0, 9.859_676_543_759_770_9e-305),
        ];
        for (t, r) in refs {
            let d = mirrored_depth(t);
            assert!(
                ((d - r) / r).abs() < 4.5e-16,
                "mirrored_depth({t}) = {d}, want {r}"
            );
        }
    }
}
