//! The microsurface BSDF: the height-field random walk over an NDF and a facet BSDF.

use super::{Facet, Incidence, MAX_BOUNCES, ScatteringOrders};
use crate::bsdf::{Bsdf, BsdfSample};
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
/// As a [`Bsdf`]:
/// - `eval(wi, wo)` is an unbiased estimate of `f(wi, wo) |wo.z|` from one walk with next-event
///   estimation at every hit;
/// - `sample(wi)` returns the exit direction of one walk with its throughput as `weight`;
///   its `pdf` field is filled by one [`Bsdf::pdf`] estimate (a second walk);
/// - `pdf(wi, wo)` is an unbiased estimate of the density of directions `sample` returns: the
///   same next-event estimation with each facet's sampling density in place of its BSDF (the
///   facet's [`Facet::phase_pdf`]). It is exact in expectation, not pointwise: an estimate may be
///   0 for a direction `sample` can return. For multiple importance sampling, compute it from
///   random numbers independent of the sample it weights.
///
/// Only the paths selected by [`ScatteringOrders`] contribute.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Microsurface<N, F> {
    ndf: N,
    facet: F,
    orders: ScatteringOrders,
    max_bounces: u32,
}

/// A direction returned by a walk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkSample {
    /// Exit direction (unit).
    pub wo: Vec3,
    /// Product of the facet sample weights along the path.
    pub weight: f64,
    /// Number of scattering events.
    pub order: u32,
}

/// How a random walk without next-event estimation ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WalkEnd {
    /// The walker left the microsurface; its order may or may not be selected.
    Escaped(WalkSample),
    /// The walker was about to scatter past the last selected order: it contributes nothing.
    Stopped,
    /// A facet absorbed the walker.
    Absorbed,
    /// The walker was about to scatter past the safety cap ([`MAX_BOUNCES`] unless set with
    /// [`Microsurface::with_max_bounces`]); `weight` is the throughput dropped.
    Truncated { weight: f64 },
}

/// A scattering event, as next-event estimation sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hit {
    pub inc: Incidence,
    /// Depth below the top of the surface on the walker's side (`-ln C1`).
    pub depth: f64,
    /// Throughput of the path up to this event (product of earlier facet weights).
    pub weight: f64,
    /// 1 for the first scattering event.
    pub order: u32,
}

impl Hit {
    /// Depths of the hit point below the tops of the upper and of the lower surface.
    #[inline]
    pub fn depths(&self) -> (f64, f64) {
        let other = mirrored_depth(self.depth);
        if self.inc.inside {
            (other, self.depth)
        } else {
            (self.depth, other)
        }
    }

    /// Depth of the hit point below the top of the lower surface if `inside`, else the upper.
    #[inline]
    pub fn depth_on(&self, inside: bool) -> f64 {
        if inside == self.inc.inside {
            self.depth
        } else {
            mirrored_depth(self.depth)
        }
    }
}

/// What every walk from one incident direction shares.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Start {
    /// Direction toward the light (`wi.z != 0`).
    pub wi: Vec3,
    /// `Lambda` of the first flight, into the surface on the light's side.
    pub lambda: f64,
}

/// A direction toward which next-event estimation is done, with its Smith Lambda.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Target {
    pub wo: Vec3,
    /// True for `wo.z < 0` (light leaving into the lower medium).
    pub inside: bool,
    /// `Lambda` of `wo` seen by the surface on its side (`wo` mirrored to `z > 0`).
    pub lambda: f64,
}

impl Target {
    /// A target direction, or `None` for a grazing `wo` (no light leaves exactly along the
    /// horizon).
    pub fn new<N: Ndf>(ndf: &N, wo: Vec3) -> Option<Self> {
        if wo.z == 0.0 || !wo.z.is_finite() {
            return None;
        }
        let inside = wo.z < 0.0;
        let up = if inside { -wo } else { wo };
        Some(Self {
            wo,
            inside,
            lambda: ndf.lambda(up),
        })
    }

    /// Probability `G1(wo, h) = C1(h)^Lambda(wo)` of leaving toward `wo` from a hit, given the
    /// hit's depths on the upper and lower surfaces.
    #[inline]
    pub fn escape(&self, depth_out: f64, depth_in: f64) -> f64 {
        let depth = if self.inside { depth_in } else { depth_out };
        (-depth * self.lambda).exp()
    }

    /// [`Target::escape`] from a hit.
    #[inline]
    pub fn escape_from(&self, hit: &Hit) -> f64 {
        (-hit.depth_on(self.inside) * self.lambda).exp()
    }
}

/// Depth of the same point below the top of the mirrored surface: `-ln(1 - exp(-t))`, since the
/// mirrored surface has height CDF `1 - C1(h)`. Evaluated without cancellation on either side of
/// `t = ln 2` (Maechler's log1mexp).
#[inline]
pub(crate) fn mirrored_depth(t: f64) -> f64 {
    let t = t.max(f64::MIN_POSITIVE);
    if t < std::f64::consts::LN_2 {
        -(-(-t).exp_m1()).ln()
    } else {
        -(-(-t).exp()).ln_1p()
    }
}

impl<N: Ndf, F: Facet> Microsurface<N, F> {
    /// A microsurface with the given NDF and facet BSDF, returning all scattering orders.
    pub fn new(ndf: N, facet: F) -> Self {
        Self {
            ndf,
            facet,
            orders: ScatteringOrders::All,
            max_bounces: MAX_BOUNCES,
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
        if max_bounces == 0 || max_bounces == u32::MAX {
            return Err(ParamError::OutOfRange {
                name: "max_bounces",
                value: f64::from(max_bounces),
                expected: "in [1, 2^32 - 2]",
            });
        }
        Ok(Self {
            max_bounces,
            ..self
        })
    }

    /// The safety cap on scattering events per walk.
    pub fn max_bounces(&self) -> u32 {
        self.max_bounces
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

    /// The start of walks from `wi` (`wi.z != 0`), shared by every walk from `wi`.
    #[inline]
    pub(crate) fn start(&self, wi: Vec3) -> Start {
        let inside = wi.z < 0.0;
        let ws = if inside { wi } else { -wi };
        Start {
            wi,
            lambda: self.ndf.lambda(ws),
        }
    }

    /// The random walk of light arriving from `start.wi`, calling `visit` at every scattering
    /// event up to the last selected order, before the walker scatters there.
    #[inline]
    pub(crate) fn walk<R: Rng + ?Sized>(
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
            if ws.z > 0.0 {
                // Escape probability exp(-depth Lambda) = G1(w, h).
                let next = depth - flight / lambda;
                if next.is_nan() || next <= 0.0 {
                    return WalkEnd::Escaped(WalkSample {
                        wo: w,
                        weight,
                        order,
                    });
                }
                depth = next;
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
            // sigma(-ws) = ws.z Lambda(ws), by sigma(v) = v.z (1 + Lambda(v)) and
            // Lambda(-v) = -1 - Lambda(v).
            let wi_side = -ws;
            let sigma = ws.z * lambda;
            let sigma = if sigma.is_finite() && sigma > 0.0 {
                sigma
            } else {
                self.ndf.sigma(wi_side)
            };
            let inc = Incidence {
                wi: -w,
                inside,
                sigma,
            };
            visit(
                &Hit {
                    inc,
                    depth,
                    weight,
                    order,
                },
                rng,
            );
            // Scatter at a visible facet (outward normal m).
            let m = self.ndf.sample_visible(wi_side, rng);
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

    /// One random walk from `wi` without next-event estimation (`wi.z != 0`). The exit order of
    /// an `Escaped` walk may lie outside the selected orders; see [`Microsurface::sample_walk`].
    pub fn random_walk<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> WalkEnd {
        if wi.z == 0.0 {
            return WalkEnd::Absorbed;
        }
        self.walk(&self.start(wi), rng, |_, _| {})
    }

    /// The exit of one random walk from `wi` if its order is selected: the fast core of
    /// [`Bsdf::sample`] without its pdf estimate.
    #[inline]
    pub fn sample_walk<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<WalkSample> {
        match self.random_walk(wi, rng) {
            WalkEnd::Escaped(s) if self.orders.includes(s.order) && s.weight > 0.0 => Some(s),
            _ => None,
        }
    }
}

impl<N: Ndf, F: Facet> Bsdf for Microsurface<N, F> {
    fn eval<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, rng: &mut R) -> f64 {
        let Some(target) = Target::new(&self.ndf, wo) else {
            return 0.0;
        };
        if wi.z == 0.0 {
            return 0.0;
        }
        let mut sum = 0.0;
        self.walk(&self.start(wi), rng, |hit, rng| {
            if !self.orders.includes(hit.order) {
                return;
            }
            let p = self.facet.phase(&self.ndf, &hit.inc, wo, rng);
            if p > 0.0 {
                sum += hit.weight * p * target.escape_from(hit);
            }
        });
        sum
    }

    fn sample<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<BsdfSample> {
        let s = self.sample_walk(wi, rng)?;
        let pdf = self.pdf(wi, s.wo, rng);
        Some(BsdfSample {
            wo: s.wo,
            weight: s.weight,
            pdf,
            delta: false,
        })
    }

    fn pdf<R: Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, rng: &mut R) -> f64 {
        let Some(target) = Target::new(&self.ndf, wo) else {
            return 0.0;
        };
        if wi.z == 0.0 {
            return 0.0;
        }
        let mut sum = 0.0;
        self.walk(&self.start(wi), rng, |hit, rng| {
            if !self.orders.includes(hit.order) {
                return;
            }
            let p = self.facet.phase_pdf(&self.ndf, &hit.inc, wo, rng);
            if p > 0.0 {
                sum += p * target.escape_from(hit);
            }
        });
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
