//! The machinery shared by the random walks: walk outcomes, scattering events, next-event
//! estimation toward target directions, and the estimators built on them.

use super::ScatteringOrders;
use crate::math::Vec3;
use rand::Rng;

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
    /// The walker was about to scatter past the safety cap ([`MAX_BOUNCES`](super::MAX_BOUNCES) unless set with
    /// [`Microsurface::with_max_bounces`](super::Microsurface::with_max_bounces)); `weight` is the throughput dropped.
    Truncated { weight: f64 },
}

/// The flight that led to a scattering event, as next-event estimation averages over it.
///
/// Next-event estimation adds, for each flight of a walk, the expected contribution of the event
/// the flight ends in, given the walker's state before it: the probability that the flight hits
/// the surface, times the phase function there (which depends on the direction, not on the
/// depth), times the expected probability of leaving toward the target from the depth reached,
/// given a hit. This has the mean of the value at the depth drawn, without its `1 / Lambda`
/// tail: a walker travelling steeply upward sees few facets, so its visible-normal density is
/// large, but it rarely hits; the product of the two is bounded, their draws were not. The
/// product is formed as one visible-normal density normalised by `sigma / P(hit)`
/// ([`Hit::sigma_nee`]), which stays finite where both vanish.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Flight {
    /// The escape from the event's own depth (the null-scattering walk's tentative
    /// collisions).
    Sampled,
    /// Upward (in the frame of the walker's side) from depth `from` with rate `lambda >= 0`:
    /// the flight hits with probability `1 - exp(-from lambda)`.
    Up { from: f64, lambda: f64 },
    /// Downward from depth `from` with rate `rate = -Lambda >= 1`: the flight always hits.
    Down { from: f64, rate: f64 },
}

impl Flight {
    /// For an upward flight of optical depth `a = from lambda`: `exp(-a)` and
    /// [`hit_fraction`]`(a)`; `(0, 1)` for the others.
    #[inline]
    fn upward_terms(self) -> (f64, f64) {
        match self {
            Flight::Up { from, lambda } => {
                let a = from * lambda;
                ((-a).exp(), hit_fraction(a))
            }
            _ => (0.0, 1.0),
        }
    }
}

/// A scattering event, as next-event estimation sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hit {
    /// Unit direction back toward where the light came from.
    pub wi: Vec3,
    /// True when the walker is in the lower medium.
    pub inside: bool,
    /// Normaliser of the visible-normal density: `sigma(wi_side)` for the height-field walk,
    /// `pi Dbar` for a tentative collision of the null-scattering walk.
    pub sigma: f64,
    /// `sigma / P(hit)`, the normaliser that folds the probability that the flight hits into
    /// the phase function of next-event estimation ([`Flight`]); `sigma` where it always hits,
    /// and where the estimate is made only at the hits drawn ([`Start::at_hits`]).
    pub sigma_nee: f64,
    /// Depth below the top of the surface on the walker's side (`-ln C1`): of the hit, or, for
    /// a flight that left the surface, a depth drawn from the flight's hits (see [`Flight`]).
    pub depth: f64,
    /// The flight that ended here.
    pub flight: Flight,
    /// Throughput of the path up to this event (product of earlier facet weights).
    pub weight: f64,
    /// 1 for the first scattering event.
    pub order: u32,
}

/// `(1 - exp(-x)) / x` for `x >= 0` (1 at 0, 0 at infinity): the probability that a flight of
/// optical depth `x` hits, per unit depth.
#[inline]
pub(crate) fn hit_fraction(x: f64) -> f64 {
    if x > 0.0 { -(-x).exp_m1() / x } else { 1.0 }
}

/// What next-event estimation toward every target shares at one event; a target's expected
/// escape is [`Target::escape`] of it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Reach {
    inside: bool,
    flight: Flight,
    /// The event's depth on its own side.
    depth: f64,
    /// The event's depth below the top of the surface on the other side.
    mirrored: f64,
    /// For an upward flight of optical depth `a = from lambda`: `exp(-a)` and
    /// [`hit_fraction`]`(a)`.
    misses: f64,
    fraction: f64,
}

impl Hit {
    /// The quantities every target's expected escape from this event needs.
    #[inline]
    pub fn reach(&self) -> Reach {
        let (misses, fraction) = self.flight.upward_terms();
        Reach {
            inside: self.inside,
            flight: self.flight,
            depth: self.depth,
            mirrored: mirrored_depth(self.depth),
            misses,
            fraction,
        }
    }
}

/// What every walk from one incident direction shares.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Start {
    /// Direction toward the light (`wi.z != 0`).
    pub wi: Vec3,
    /// `Lambda` of the first flight, into the surface on the light's side (height-field walk).
    pub lambda: f64,
    /// Whether next-event estimation on upward flights is made only at the hits drawn
    /// ([`Start::at_hits`]).
    pub at_hits: bool,
}

impl Start {
    /// The same start with next-event estimation on upward flights made only at the hits
    /// drawn, or averaged over the whole flight ([`Flight`]). Averaged, a flight that rarely
    /// hits still costs a phase function per target; at a hit drawn, the estimate is the phase
    /// function itself with the escape averaged over the depths of the hits: the draw,
    /// Rao-Blackwellised in depth, at the draw's cost. Walks from `wi` alone are estimated at
    /// the hits drawn: toward one target (`Bsdf::eval`, the benchmark's 16 directions) the
    /// whole-flight average cost 40 to 60% more instructions for 10 to 30% less variance, and
    /// toward many targets it costs more. Bidirectional estimates need the average: their
    /// weights leave out the depths of a path's ends.
    pub fn at_hits(self, at_hits: bool) -> Self {
        Self { at_hits, ..self }
    }
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
    /// horizon). `lambda(up)` is the Smith Lambda of the upward direction `up` (`wo` mirrored to
    /// `z > 0`): the escape rate per unit depth.
    pub fn new(wo: Vec3, lambda: impl FnOnce(Vec3) -> f64) -> Option<Self> {
        if wo.z == 0.0 || !wo.z.is_finite() {
            return None;
        }
        let inside = wo.z < 0.0;
        let up = if inside { -wo } else { wo };
        Some(Self {
            wo,
            inside,
            lambda: lambda(up),
        })
    }

    /// The expected probability of leaving toward `wo` from where the event's flight ends,
    /// given that it hits: `E[G1(wo, h) | hit]` with `G1(wo, h) = C1(h)^Lambda(wo)` (see
    /// [`Flight`]). With `t` the depth reached, `G1` is `exp(-t Lambda(wo))` on the walker's
    /// side and `(1 - exp(-t))^Lambda(wo)` on the other. In closed form on the walker's side:
    /// - upward from `t0` at rate `L`, with `a = t0 L`, `b = t0 Lambda(wo)` and `phi(x) =
    ///   (1 - exp(-x)) / x`: `exp(-min(a, b)) phi(|a - b|) / phi(a)` (`exp(-b)` for infinite
    ///   `L`, where the flight hits in place);
    /// - downward from `t0` at rate `r`: `exp(-t0 Lambda(wo)) r / (r + Lambda(wo))`.
    ///
    /// On the other side: the escape from the event's depth, which the walk draws from the
    /// flight's hits.
    #[inline]
    pub fn escape(&self, r: &Reach) -> f64 {
        if self.inside != r.inside {
            return (-r.mirrored * self.lambda).exp();
        }
        self.same_side(r.flight, r.depth, r.misses, r.fraction)
    }

    /// [`Target::escape`] from a hit, computing only what this target needs (no mirrored
    /// depth on the walker's side, no exponentials for a downward flight).
    #[inline]
    pub fn escape_from(&self, hit: &Hit) -> f64 {
        if self.inside != hit.inside {
            return (-mirrored_depth(hit.depth) * self.lambda).exp();
        }
        let (misses, fraction) = hit.flight.upward_terms();
        self.same_side(hit.flight, hit.depth, misses, fraction)
    }

    /// [`Target::escape`] on the walker's side, given [`Flight::upward_terms`].
    #[inline]
    fn same_side(&self, flight: Flight, depth: f64, misses: f64, fraction: f64) -> f64 {
        match flight {
            Flight::Sampled => (-depth * self.lambda).exp(),
            Flight::Down { from, rate } => {
                (-from * self.lambda).exp() * rate / (rate + self.lambda)
            }
            Flight::Up { from, lambda } => {
                let (a, b) = (from * lambda, from * self.lambda);
                let eb = (-b).exp();
                if !a.is_finite() {
                    return eb;
                }
                let d = (a - b).abs();
                // exp(-min(a, b)) phi(|a - b|): from the difference of the two exponentials
                // where that loses at most a few ulps, else without cancellation.
                let both = if d >= 0.5 {
                    (eb - misses).abs() / d
                } else {
                    eb.max(misses) * hit_fraction(d)
                };
                both / fraction
            }
        }
    }
}

/// Depth of the same point below the top of the mirrored surface: `-ln(1 - exp(-t))`, since the
/// mirrored surface has height CDF `1 - C1(h)`. Evaluated to an ulp or two without
/// cancellation and with one fast logarithm on either side of `t = ln 2` (where glibc's
/// `expm1` and `log1p` are several times slower than its `exp` and `log`):
/// - below, as `-ln t - ln((1 - exp(-t))/t)`, the second term by its Bernoulli series
///   `-t/2 + sum B_2k t^2k / (2k (2k)!)` (eight terms leave 2e-17 at `t = ln 2`); both terms
///   are positive;
/// - above, with `e = exp(-t) <= 1/2`, `1 - e = y + lo` exactly (Fast2Sum), and
///   `ln(1 - e) = ln y + lo/y` where dropping the `1/y` costs at most `2 e |lo|`, an ulp of
///   the result.
#[inline]
pub(crate) fn mirrored_depth(t: f64) -> f64 {
    let t = t.max(f64::MIN_POSITIVE);
    if t < std::f64::consts::LN_2 {
        -t.ln() - ln_expm1_ratio(t)
    } else {
        let e = (-t).exp();
        let y = 1.0 - e;
        let lo = (1.0 - y) - e;
        -(y.ln() + lo)
    }
}

/// `ln((1 - exp(-t)) / t)` for `0 < t <= ln 2`: `-t/2 + sum_k B_2k t^2k / (2k (2k)!)` (Bernoulli
/// numbers `B_2k`), eight terms.
#[inline]
#[allow(clippy::excessive_precision)]
fn ln_expm1_ratio(t: f64) -> f64 {
    const C: [f64; 8] = [
        4.166_666_666_666_666_666_7e-2,
        -3.472_222_222_222_222_222_2e-4,
        5.511_463_844_797_178_130_5e-6,
        -1.033_399_470_899_470_899_5e-7,
        2.087_675_698_786_809_897_9e-9,
        -4.403_491_782_239_577_654_0e-11,
        9.558_954_664_774_770_594_9e-13,
        -2.118_550_185_201_614_291_8e-14,
    ];
    let z = t * t;
    let p = C.iter().rev().fold(0.0, |acc, &c| acc * z + c);
    -0.5 * t + z * p
}

/// Validates a safety cap on scattering events per walk: at least 1, and below `u32::MAX`
/// (which the walk reserves as "no last order").
pub(crate) fn check_max_bounces(max_bounces: u32) -> Result<u32, crate::error::ParamError> {
    if max_bounces == 0 || max_bounces == u32::MAX {
        return Err(crate::error::ParamError::OutOfRange {
            name: "max_bounces",
            value: f64::from(max_bounces),
            expected: "in [1, 2^32 - 2]",
        });
    }
    Ok(max_bounces)
}

/// A random walk on a microsurface, as the estimators use it.
pub(crate) trait Walker: Sync {
    /// The selected scattering orders.
    fn orders(&self) -> ScatteringOrders;

    /// Next-event target toward `wo` (`None` for grazing `wo`).
    fn target(&self, wo: Vec3) -> Option<Target>;

    /// What walks from `wi` (`wi.z != 0`) share.
    fn start(&self, wi: Vec3) -> Start;

    /// One walk. With `NEE`, `visit` is called for next-event estimation at every event of
    /// order up to the last selected one, before the walker moves on, and, where the walk
    /// averages over flights ([`Flight::Up`]), also for a flight that leaves the surface, at a
    /// depth drawn from the flight's hits; without, it is never called and the walk does no
    /// work for it.
    fn walk<const NEE: bool, R: Rng + ?Sized>(
        &self,
        start: &Start,
        rng: &mut R,
        visit: impl FnMut(&Hit, &mut R),
    ) -> WalkEnd;

    /// The facet phase function at `hit` toward `wo` (its sampling density if `pdf`), or an
    /// unbiased estimate of it.
    fn phase<R: Rng + ?Sized>(&self, hit: &Hit, wo: Vec3, pdf: bool, rng: &mut R) -> f64;
}

/// One walk from `wi` without next-event estimation.
pub(crate) fn random_walk<W: Walker, R: Rng + ?Sized>(w: &W, wi: Vec3, rng: &mut R) -> WalkEnd {
    if wi.z == 0.0 {
        return WalkEnd::Absorbed;
    }
    w.walk::<false, _>(&w.start(wi), rng, |_, _| {})
}

/// The exit of one walk from `wi` if its order is selected.
pub(crate) fn sample_walk<W: Walker, R: Rng + ?Sized>(
    w: &W,
    wi: Vec3,
    rng: &mut R,
) -> Option<WalkSample> {
    match random_walk(w, wi, rng) {
        WalkEnd::Escaped(s) if w.orders().includes(s.order) && s.weight > 0.0 => Some(s),
        _ => None,
    }
}

/// One next-event estimate of `f(wi, wo) |wo.z|` (or, if `pdf`, of the density of sampled exit
/// directions).
pub(crate) fn nee_walk<W: Walker, R: Rng + ?Sized>(
    w: &W,
    wi: Vec3,
    wo: Vec3,
    pdf: bool,
    rng: &mut R,
) -> f64 {
    let Some(target) = w.target(wo) else {
        return 0.0;
    };
    if wi.z == 0.0 {
        return 0.0;
    }
    let orders = w.orders();
    let mut sum = 0.0;
    w.walk::<true, _>(&w.start(wi).at_hits(true), rng, |hit, rng| {
        if !orders.includes(hit.order) {
            return;
        }
        let p = w.phase(hit, wo, pdf, rng);
        if p > 0.0 {
            let weight = if pdf { 1.0 } else { hit.weight };
            sum += weight * p * target.escape_from(hit);
        }
    });
    sum
}

/// Implements [`Bsdf`](crate::bsdf::Bsdf) for a walk type through its [`Walker`]: `eval` and
/// `pdf` are one next-event walk each, `sample` one walk whose `pdf` field is filled by a
/// second, independent `pdf` walk.
macro_rules! walk_bsdf {
    ($ty:ident < $($g:ident : $b:path),* >) => {
        impl<$($g: $b),*> $crate::bsdf::Bsdf for $ty<$($g),*> {
            fn eval<R: rand::Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, rng: &mut R) -> f64 {
                $crate::walk::engine::nee_walk(self, wi, wo, false, rng)
            }

            fn sample<R: rand::Rng + ?Sized>(
                &self,
                wi: Vec3,
                rng: &mut R,
            ) -> Option<$crate::bsdf::BsdfSample> {
                let s = $crate::walk::engine::sample_walk(self, wi, rng)?;
                let pdf = $crate::walk::engine::nee_walk(self, wi, s.wo, true, rng);
                Some($crate::bsdf::BsdfSample {
                    wo: s.wo,
                    weight: s.weight,
                    pdf,
                    delta: false,
                })
            }

            fn pdf<R: rand::Rng + ?Sized>(&self, wi: Vec3, wo: Vec3, rng: &mut R) -> f64 {
                $crate::walk::engine::nee_walk(self, wi, wo, true, rng)
            }
        }
    };
}
pub(crate) use walk_bsdf;
