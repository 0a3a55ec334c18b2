//! The null-scattering random walk for any bounded NDF on the whole sphere; see
//! [`NullMicrosurface`].

use super::engine::{
    self, Flight, Hit, Start, Target, WalkEnd, WalkSample, Walker, mirrored_depth,
};
use super::estimate::{AlbedoEstimate, estimators};
use super::{Facet, MAX_BOUNCES, ScatteringOrders, VisibleNormals};
use crate::error::ParamError;
use crate::math::{Frame, Vec3, safe_sqrt};
use crate::sphere::SphereNdf;
use rand::{Rng, RngExt};
use rand_distr::Exp1;
use std::f64::consts::PI;

/// A microsurface with a full-sphere NDF `S` and facet BSDF `F`, evaluated and sampled by the
/// null-scattering walk. As a [`Bsdf`](crate::bsdf::Bsdf) it has the same semantics as
/// [`Microsurface`](super::Microsurface): `eval` and `pdf` are unbiased one-walk estimates,
/// `sample` fills `pdf` with one `pdf` estimate. Each `eval` or `pdf` call computes
/// `sigma(-wo)` by quadrature (tens of microseconds); `eval_many` does it once per direction.
/// The walk follows d'Eon 2023 (section 3 of the seed paper; theory section 7).
///
/// The microsurface is the half-space of depths `t >= 0` of the height-field walk, filled with
/// facets whose orientations follow a [`SphereNdf`] `D` (porous, granular or volumetric surfaces;
/// height fields are the special case `D = 0` below the horizon). A majorant `Dbar >= D`,
/// constant on the sphere (or, for height fields, on the upper hemisphere and zero below),
/// turns it into a homogeneous medium: seen from the direction `v` the light comes from, its
/// projected area is `sigma_bar(v)` (`majorant_sigma`: `pi Dbar`, or `pi Dbar (1 + v.z) / 2`),
/// so tentative collisions along `w` come at rate `sigma_bar / |w.z|` per unit depth, and the
/// normal of the facet met follows the majorant's visible normals about `v` (cosine-distributed,
/// or the spherical cap of GGX at alpha = 1 for the hemisphere). The collision is real with
/// probability `D(m) / Dbar` and null otherwise (the walker flies on unchanged). Real
/// collisions scatter with the facet BSDF exactly as in the height-field walk, including the
/// crossing to the mirrored surface for transmitting facets.
///
/// Next-event estimation is done at every tentative collision with the facet phase function
/// averaged over the sub-normalised density `max(0, wi_side . m) D(m) / sigma_bar` (its mass is
/// the probability that the collision is real), so no `sigma(wi)` is needed along the walk. The
/// escape probability toward `wo` from depth `t` is `exp(-t Lambda(wo))` with
/// `Lambda(wo) = sigma(-wo) / wo.z`, `sigma` from [`SphereNdf::sigma`] (quadrature, or the closed form of a [`HeightField`](crate::sphere::HeightField)), once per
/// target direction.
///
/// For a height-field NDF the walk reproduces the height-field walk. Its cost grows with
/// `sigma_bar / sigma`, the number of tentative collisions per real one, so it suits rough or
/// porous surfaces (roughness above about 0.4); for smooth height fields prefer
/// [`Microsurface`](super::Microsurface). Transmitting facets on a full-sphere NDF follow the
/// height-field walk's model of the mirrored surface below the interface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NullMicrosurface<S, F> {
    ndf: S,
    facet: F,
    orders: ScatteringOrders,
    max_bounces: u32,
    /// The majorant `Dbar`.
    bound: f64,
}

/// A tentative collision of the null-scattering walk, seen by next-event estimation: normals
/// with density `max(0, wi_side . m) D(m) / sigma_bar(wi_side)`, drawn from the majorant's
/// visible normals with weight `D(m) / Dbar` (see `majorant_sigma`).
#[derive(Debug, Clone, Copy)]
pub struct NullHit<'a, S> {
    ndf: &'a S,
    wi: Vec3,
    inside: bool,
    bound: f64,
}

impl<'a, S: SphereNdf> NullHit<'a, S> {
    /// A tentative collision of light arriving from `wi` on the given side, majorant `bound`
    /// (on the upper hemisphere if the NDF is a height field, else on the sphere).
    pub fn new(ndf: &'a S, wi: Vec3, inside: bool, bound: f64) -> Self {
        Self {
            ndf,
            wi,
            inside,
            bound,
        }
    }
}

/// Projected area `sigma_bar(v)` seen from the unit `v` of the majorant: `pi Dbar` for the
/// constant `Dbar` on the sphere, `pi Dbar (1 + v.z) / 2` for `Dbar` on the upper hemisphere
/// (zero below), which suffices for height fields and wastes no tentative collisions on
/// normals below the horizon.
#[inline]
fn majorant_sigma(bound: f64, upper: bool, v: Vec3) -> f64 {
    if upper {
        0.5 * PI * bound * (1.0 + v.z)
    } else {
        PI * bound
    }
}

/// A drawn point of the spherical cap of [`Cap::sample`], from which the normal follows.
#[derive(Debug, Clone, Copy)]
struct CapSample {
    /// `sqrt(1 - z^2) cos phi`, `sqrt(1 - z^2) sin phi` and `z` of the cap point.
    c: Vec3,
    /// `1 / |c + v|`.
    inv_len: f64,
}

/// Visible normals of the constant NDF on the upper hemisphere (GGX at alpha = 1) seen from
/// the unit `v`: Dupuy and Benyoub 2023's spherical cap, with the azimuth of a uniform point of
/// the unit disk doubled (no trigonometry). Holds the per-direction quantities `v`, `|v_xy|`
/// and the unit azimuth of `v`.
#[derive(Debug, Clone, Copy)]
struct Cap {
    v: Vec3,
    vxy: f64,
    ex: f64,
    ey: f64,
}

impl Cap {
    #[inline]
    fn new(v: Vec3) -> Self {
        let vxy = v.x.hypot(v.y);
        let (ex, ey) = if vxy > 0.0 {
            (v.x / vxy, v.y / vxy)
        } else {
            (1.0, 0.0)
        };
        Self { v, vxy, ex, ey }
    }

    /// One visible normal as `m.z` and the cap point (the walk needs the whole normal, from
    /// [`Cap::normal`], only at real collisions); `None` in the measure-zero case `c = -v`.
    #[inline]
    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> Option<(f64, CapSample)> {
        let (x, y, r2) = loop {
            let x = 2.0 * rng.random::<f64>() - 1.0;
            let y = 2.0 * rng.random::<f64>() - 1.0;
            let r2 = x * x + y * y;
            if r2 < 1.0 && r2 > 0.0 {
                break (x, y, r2);
            }
        };
        let (cp, sp) = ((x * x - y * y) / r2, 2.0 * x * y / r2);
        let vz = self.v.z;
        let z = (1.0 - rng.random::<f64>()) * (1.0 + vz) - vz;
        let s = safe_sqrt(1.0 - z * z);
        let len2 = 2.0 + 2.0 * (s * cp * self.vxy + z * vz);
        if len2 <= 0.0 {
            return None;
        }
        let inv_len = 1.0 / len2.sqrt();
        Some((
            (z + vz) * inv_len,
            CapSample {
                c: Vec3::new(s * cp, s * sp, z),
                inv_len,
            },
        ))
    }

    /// The normal of a [`CapSample`] in world coordinates.
    #[inline]
    fn normal(&self, c: &CapSample) -> Vec3 {
        let (a, b) = (c.c.x, c.c.y);
        let cw = Vec3::new(a * self.ex - b * self.ey, a * self.ey + b * self.ex, c.c.z);
        (cw + self.v) * c.inv_len
    }
}

impl<S: SphereNdf> VisibleNormals for NullHit<'_, S> {
    #[inline]
    fn wi(&self) -> Vec3 {
        self.wi
    }

    #[inline]
    fn inside(&self) -> bool {
        self.inside
    }

    #[inline]
    fn density(&self, m: Vec3) -> f64 {
        let v = self.wi_side();
        let c = v.dot(&m);
        if c <= 0.0 {
            return 0.0;
        }
        c * self.ndf.d_cos(m.z.clamp(-1.0, 1.0))
            / majorant_sigma(self.bound, self.ndf.is_height_field(), v)
    }

    #[inline]
    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> (Vec3, f64) {
        let v = self.wi_side();
        let m = if self.ndf.is_height_field() {
            let cap = Cap::new(v);
            match cap.sample(rng) {
                Some((_, c)) => cap.normal(&c),
                None => return (v, 0.0),
            }
        } else {
            cosine_about(v, rng)
        };
        (m, self.ndf.d_cos(m.z.clamp(-1.0, 1.0)) / self.bound)
    }
}

/// A unit vector drawn with density `max(0, v . m) / pi` about the unit vector `v`.
#[inline]
fn cosine_about<R: Rng + ?Sized>(v: Vec3, rng: &mut R) -> Vec3 {
    Frame::from_normal(v).to_world(cosine_local(rng))
}

/// A unit vector drawn with density `max(0, z) / pi` (Malley: a uniform point of the unit disk,
/// by rejection from the square, lifted to the hemisphere; no trigonometry).
#[inline]
fn cosine_local<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        let r2 = x * x + y * y;
        if r2 < 1.0 {
            return Vec3::new(x, y, safe_sqrt(1.0 - r2));
        }
    }
}

/// Largest majorant `Dbar` of a null-scattering walk's NDF. The walk tests about `Dbar`
/// tentative collisions per real event where `D` is broad (`pi Dbar` against a projected
/// area of order 1), so its cost grows with the peak: about 1 ms per walk at `Dbar = 3.2e3`
/// (Beckmann alpha 0.01), 10 ms at `3.5e4` (alpha 0.003), and a minute at alpha 1e-4. The limit
/// keeps a walk within milliseconds; the height-field walk serves smaller alpha.
pub const MAX_NULL_MAJORANT: f64 = 1e4;

impl<S: SphereNdf, F: Facet> NullMicrosurface<S, F> {
    /// A microsurface with the given NDF and facet BSDF, all scattering orders. Fails if the NDF
    /// has no finite positive majorant (Student-T with gamma < 2), or one above
    /// [`MAX_NULL_MAJORANT`].
    pub fn new(ndf: S, facet: F) -> Result<Self, ParamError> {
        let bound = ndf.majorant();
        if bound == f64::INFINITY {
            return Err(ParamError::Unbounded {
                name: "the NDF's peak",
                expected: "a null walk needs a finite one as its majorant: Student-T with \
                           gamma >= 2",
            });
        }
        if !(bound.is_finite() && bound > 0.0) {
            return Err(ParamError::OutOfRange {
                name: "NDF majorant",
                value: bound,
                expected: "a finite majorant > 0",
            });
        }
        if bound > MAX_NULL_MAJORANT {
            return Err(ParamError::OutOfRange {
                name: "NDF peak of the null walk",
                value: bound,
                expected: "at most 1e4: tentative collisions per event grow with the peak, \
                           1/(pi alpha^2) for height fields (alpha >= 0.0057), kappa/(2 pi) for vmf",
            });
        }
        Ok(Self {
            ndf,
            facet,
            orders: ScatteringOrders::All,
            max_bounces: MAX_BOUNCES,
            bound,
        })
    }

    /// The same microsurface restricted to the given scattering orders.
    pub fn with_orders(self, orders: ScatteringOrders) -> Self {
        Self { orders, ..self }
    }

    /// The same microsurface with another safety cap on real scattering events per walk (see
    /// [`Microsurface::with_max_bounces`](super::Microsurface::with_max_bounces)).
    pub fn with_max_bounces(self, max_bounces: u32) -> Result<Self, ParamError> {
        Ok(Self {
            max_bounces: engine::check_max_bounces(max_bounces)?,
            ..self
        })
    }

    /// The NDF.
    pub fn ndf(&self) -> &S {
        &self.ndf
    }

    /// The facet BSDF.
    pub fn facet(&self) -> &F {
        &self.facet
    }

    /// The majorant `Dbar` of the NDF.
    pub fn majorant(&self) -> f64 {
        self.bound
    }

    /// The selected scattering orders.
    pub fn orders(&self) -> ScatteringOrders {
        self.orders
    }

    /// One walk from `wi` without next-event estimation.
    pub fn random_walk<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> WalkEnd {
        engine::random_walk(self, wi, rng)
    }

    /// The exit of one walk from `wi` if its order is selected.
    pub fn sample_walk<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<WalkSample> {
        engine::sample_walk(self, wi, rng)
    }
}

impl<S: SphereNdf, F: Facet> Walker for NullMicrosurface<S, F> {
    #[inline]
    fn orders(&self) -> ScatteringOrders {
        self.orders
    }

    /// `Lambda(up) = sigma(-up) / up.z`: the rate per unit depth of real collisions along `-up`.
    fn target(&self, wo: Vec3) -> Option<Target> {
        Target::new(wo, |up| self.ndf.sigma(-up) / up.z)
    }

    #[inline]
    fn start(&self, wi: Vec3) -> Start {
        Start {
            wi,
            lambda: 0.0,
            at_hits: false,
        }
    }

    fn walk<const NEE: bool, R: Rng + ?Sized>(
        &self,
        start: &Start,
        rng: &mut R,
        mut visit: impl FnMut(&Hit, &mut R),
    ) -> WalkEnd {
        let last = self.orders.last_order();
        let upper = self.ndf.is_height_field();
        let mut w = -start.wi;
        let mut inside = start.wi.z < 0.0;
        let mut depth = 0.0f64;
        let mut weight = 1.0f64;
        let mut real = 0u32;
        // Per direction (changed only by real collisions): the direction in the frame of the
        // surface on the walker's side, the depth per unit exponential flight, and the frame of
        // the cosine lobe of tentative normals about `-ws`.
        let mut ws = if inside { -w } else { w };
        let mut rate = majorant_sigma(self.bound, upper, -ws);
        let mut step = ws.z.abs() / rate;
        let mut lobe = Frame::from_normal(-ws);
        let mut cap = Cap::new(-ws);
        loop {
            // Fly to the next tentative collision.
            let flight: f64 = rng.sample(Exp1);
            let dt = flight * step;
            if ws.z > 0.0 {
                depth -= dt;
                if depth.is_nan() || depth <= 0.0 {
                    return WalkEnd::Escaped(WalkSample {
                        wo: w,
                        weight,
                        order: real,
                    });
                }
            } else {
                depth += dt;
            }
            if NEE && real < last {
                visit(
                    &Hit {
                        wi: -w,
                        inside,
                        sigma: rate,
                        sigma_nee: rate,
                        depth,
                        flight: Flight::Sampled,
                        weight,
                        order: real + 1,
                    },
                    rng,
                );
            }
            // Real with probability D(m) / Dbar for a visible normal m of the majorant; D needs
            // only m.z, the full normal only a real collision.
            let m = if upper {
                let Some((mz, c)) = cap.sample(rng) else {
                    continue;
                };
                if rng.random::<f64>() * self.bound >= self.ndf.d_cos(mz.clamp(-1.0, 1.0)) {
                    continue;
                }
                cap.normal(&c)
            } else {
                let local = cosine_local(rng);
                let mz = lobe.s.z * local.x + lobe.t.z * local.y + lobe.n.z * local.z;
                if rng.random::<f64>() * self.bound >= self.ndf.d_cos(mz.clamp(-1.0, 1.0)) {
                    continue;
                }
                lobe.to_world(local)
            };
            real += 1;
            if real > last {
                return WalkEnd::Stopped;
            }
            if real > self.max_bounces {
                return WalkEnd::Truncated { weight };
            }
            let Some(s) = self.facet.scatter(-w, m, rng) else {
                return WalkEnd::Absorbed;
            };
            weight *= s.weight;
            let now_inside = s.wo.dot(&m) < 0.0;
            if now_inside != inside {
                depth = mirrored_depth(depth);
                inside = now_inside;
            }
            // Renormalised: rounding in the facet frames would otherwise compound over the
            // thousands of real collisions of a near-isotropic NDF.
            w = s.wo.normalize();
            ws = if inside { -w } else { w };
            rate = majorant_sigma(self.bound, upper, -ws);
            step = ws.z.abs() / rate;
            if upper {
                cap = Cap::new(-ws);
            } else {
                lobe = Frame::from_normal(-ws);
            }
        }
    }

    #[inline]
    fn phase<R: Rng + ?Sized>(&self, hit: &Hit, wo: Vec3, pdf: bool, rng: &mut R) -> f64 {
        let vis = NullHit::new(&self.ndf, hit.wi, hit.inside, self.bound);
        if pdf {
            self.facet.phase_pdf(&vis, wo, rng)
        } else {
            self.facet.phase(&vis, wo, rng)
        }
    }
}

engine::walk_bsdf!(NullMicrosurface<S: SphereNdf, F: Facet>);

estimators!(NullMicrosurface<S: SphereNdf, F: Facet>);
