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
        if self.inside {
            (other, self.depth)
        } else {
            (self.depth, other)
        }
    }

    /// Depth of the hit point below the top of the lower surface if `inside`, else the upper.
    #[inline]
    pub fn depth_on(&self, inside: bool) -> f64 {
        if inside == self.inside {
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
    /// `Lambda` of the first flight, into the surface on the light's side (height-field walk).
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

    /// One walk, calling `visit` at every event where next-event estimation applies (scattering
    /// events of order up to the last selected one), before the walker moves on.
    fn walk<R: Rng + ?Sized>(
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
    w.walk(&w.start(wi), rng, |_, _| {})
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
    w.walk(&w.start(wi), rng, |hit, rng| {
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
