//! The pieces every microfacet model shares, each written once: reflection and refraction about
//! a facet, Walter et al.'s (generalised) half vector and its Jacobian, and Smith
//! masking-shadowing. The rough BSDFs, the random walks' facets and the fitting engine all build
//! on them.
//!
//! Smith terms are written with `a(w) = 1 + Lambda(w') = sigma(w') / |w.z|`, where `w'` is `w`
//! flipped to the upper hemisphere ([`upper`]) and `sigma` the projected area: a direction
//! inside a dielectric is masked by the mirrored surface (Walter et al. 2007). One projected-area
//! evaluation per direction gives both the visible-normal density and G.

use super::{
    fresnel_dielectric_fraction, reflectance_fraction, reflectance_fraction_sin2, sin2_from_cos,
};
use crate::math::Vec3;
use crate::ndf::Ndf;
use crate::ndf::special::square_with_error;
use serde::{Deserialize, Serialize};

/// How the masking-shadowing term G combines the two directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Masking {
    /// `G1(wi) G1(wo)` (Walter et al. 2007; what the published fits used).
    #[default]
    Separable,
    /// Height-correlated Smith: `1/(1 + Lambda_i + Lambda_o)` for reflection and
    /// `B(1 + Lambda_i, 1 + Lambda_o)` (the Beta function) for transmission (Heitz 2014,
    /// section 5). The random walks' order-1 term is exactly this.
    Correlated,
}

impl Masking {
    /// The name used on the command line and in files: `separable` or `correlated`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Separable => "separable",
            Self::Correlated => "correlated",
        }
    }

    /// The Smith term of one direction with `a = 1 + Lambda(w')`, with what this masking
    /// needs precomputed (the log-gamma of the Beta function for [`Masking::Correlated`]).
    /// Callers that evaluate many pairs sharing directions compute it once per direction.
    #[inline]
    pub fn term(self, a: f64) -> SmithTerm {
        let ln_gamma = match self {
            Self::Separable => 0.0,
            Self::Correlated if a.is_finite() => statrs::function::gamma::ln_gamma(a),
            Self::Correlated => f64::INFINITY,
        };
        SmithTerm { a, ln_gamma }
    }

    /// `G` of a reflected (`reflect`) or transmitted pair from the terms of its two directions.
    #[inline]
    pub fn g(self, reflect: bool, i: SmithTerm, o: SmithTerm) -> f64 {
        match (self, reflect) {
            (Self::Separable, _) => 1.0 / (i.a * o.a),
            (Self::Correlated, true) => 1.0 / (i.a + o.a - 1.0),
            (Self::Correlated, false) => beta_from_terms(i, o),
        }
    }

    /// `G` for reflection from `a_i = 1 + Lambda(wi')` and `a_o = 1 + Lambda(wo')`.
    #[inline]
    pub fn g_reflection(self, a_i: f64, a_o: f64) -> f64 {
        // The reflected G depends on `a` alone: no log-gamma to compute.
        let term = |a| SmithTerm { a, ln_gamma: 0.0 };
        self.g(true, term(a_i), term(a_o))
    }

    /// `G` for transmission from `a_i = 1 + Lambda(wi')` and `a_o = 1 + Lambda(wo')`.
    #[inline]
    pub fn g_transmission(self, a_i: f64, a_o: f64) -> f64 {
        self.g(false, self.term(a_i), self.term(a_o))
    }
}

impl std::str::FromStr for Masking {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "separable" => Ok(Self::Separable),
            "correlated" => Ok(Self::Correlated),
            _ => Err(format!(
                "unknown masking '{s}' (expected separable or correlated)"
            )),
        }
    }
}

/// The Smith term of one direction: `a = 1 + Lambda(w')` and, for height-correlated masking,
/// `ln Gamma(a)` (see [`Masking::term`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmithTerm {
    a: f64,
    ln_gamma: f64,
}

impl SmithTerm {
    /// `1 + Lambda(w')`.
    pub fn a(&self) -> f64 {
        self.a
    }
}

/// The Beta function `B(a_i, a_o) = Gamma(a_i) Gamma(a_o) / Gamma(a_i + a_o)` from the terms'
/// log-gammas (arguments >= 1); zero when either is infinite (a grazing direction).
///
/// While both arguments are below [`STIRLING_FROM`] the log-gammas are small and their sum is
/// exact to a few ulps. Above, `ln Gamma(b) - ln Gamma(a + b)` (`b` the larger) is taken from
/// Stirling's series as a difference in closed form, `-(b - 1/2) ln(1 + a/b) - a ln(a + b) + a`
/// plus the series' small corrections: the difference of two log-gammas of size `b ln b`
/// would keep their rounding, a relative `1e-16 b ln b` of B (1e-5 at `Lambda = 5e9`, which
/// alpha 100 reaches at `|z| = 1e-8`, and Student-T near gamma 3/2 at ordinary angles).
#[inline]
fn beta_from_terms(i: SmithTerm, o: SmithTerm) -> f64 {
    if !i.a.is_finite() || !o.a.is_finite() {
        return 0.0;
    }
    let (s, l) = if i.a <= o.a { (i, o) } else { (o, i) };
    if l.a < STIRLING_FROM {
        return (s.ln_gamma + l.ln_gamma - statrs::function::gamma::ln_gamma(s.a + l.a)).exp();
    }
    let (a, b) = (s.a, l.a);
    let sum = a + b;
    // ln Gamma(b) - ln Gamma(a + b) + a ln(a + b) - a.
    let tail = -(b - 0.5) * (a / b).ln_1p() + stirling_correction(b) - stirling_correction(sum);
    let ln_beta = if a < STIRLING_FROM {
        s.ln_gamma + tail - a * sum.ln() + a
    } else {
        // ln Gamma(a) - a ln(a + b) + a by Stirling too: no term of size a ln a is formed.
        0.5 * ((2.0 * std::f64::consts::PI).ln() - sum.ln())
            + (a - 0.5) * (a / sum).ln()
            + stirling_correction(a)
            + tail
    };
    ln_beta.exp()
}

/// Arguments from which [`beta_from_terms`] takes log-gamma differences from Stirling's series.
const STIRLING_FROM: f64 = 10.0;

/// `ln Gamma(z) - ((z - 1/2) ln z - z + ln(2 pi) / 2)` for `z >= STIRLING_FROM`, by Stirling's
/// series to `z^-13` (the next term is below 3e-17 at `z = 10`).
#[inline]
fn stirling_correction(z: f64) -> f64 {
    let r = 1.0 / z;
    let r2 = r * r;
    r * (1.0 / 12.0
        - r2 * (1.0 / 360.0
            - r2 * (1.0 / 1260.0
                - r2 * (1.0 / 1680.0
                    - r2 * (1.0 / 1188.0 - r2 * (691.0 / 360_360.0 - r2 / 156.0))))))
}

/// `w` flipped to the upper hemisphere (`-w` when `w.z < 0`): the direction from which a
/// surface seen from below is seen as the same height field from above. For an isotropic NDF
/// this is equivalent to mirroring across the tangent plane.
#[inline]
pub(crate) fn upper(w: Vec3) -> Vec3 {
    if w.z < 0.0 { -w } else { w }
}

/// Projected area of the microsurface seen from the side of `w`: `sigma(upper(w))`.
#[inline]
pub(crate) fn projected_area<N: Ndf>(ndf: &N, w: Vec3) -> f64 {
    ndf.sigma(upper(w))
}

/// Mirror reflection of `w` about the unit normal `n` (either orientation): `2 (w.n) n - w`.
#[inline]
pub fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    n * (2.0 * w.dot(&n)) - w
}

/// Refraction of the unit `w` through an interface with unit normal `n`, index `eta` on the
/// side `-n` points to and 1 on the side of `n` (a relative index; `eta < 1` is allowed). `w`
/// may be on either side. Returns the unit refracted direction, pointing away from the
/// interface on the other side, or `None` under total internal reflection.
#[inline]
pub fn refract(w: Vec3, n: Vec3, eta: f64) -> Option<Vec3> {
    refract_with_fresnel(w, n, eta, 1.0 / eta).map(|(wt, _)| wt)
}

/// [`refract`] with `inv_eta = 1 / eta` precomputed, also returning the Fresnel reflectance of
/// the interface for `w` as a fraction `(num, den)` ([`fresnel_dielectric_fraction`]): one
/// square root, the transmitted cosine, serves both. The refracted direction
/// `(cos_i n - w) / eta_t - cos_t n` is unit up to the rounding of its inputs; one Newton step
/// for `1/|v|` about 1 removes that rounding (to second order) without a square root or a
/// division.
#[inline]
pub(crate) fn refract_with_fresnel(
    w: Vec3,
    n: Vec3,
    eta: f64,
    inv_eta: f64,
) -> Option<(Vec3, (f64, f64))> {
    let cos_i = w.dot(&n);
    // eta_t: index of the transmission side over that of the incident side.
    let (eta_t, inv_eta_t, n, cos_i) = if cos_i >= 0.0 {
        (eta, inv_eta, n, cos_i)
    } else {
        (inv_eta, eta, -n, -cos_i)
    };
    let cos_i = cos_i.min(1.0);
    let sin2_t = sin2_from_cos(cos_i) * (inv_eta_t * inv_eta_t);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let v = (n * cos_i - w) * inv_eta_t - n * cos_t;
    let wt = v * (1.5 - 0.5 * v.norm_squared());
    Some((wt, fresnel_dielectric_fraction(cos_i, cos_t, eta_t)))
}

/// Knuth's two-sum: the rounded sum `s` of `a` and `b` and its rounding error `e`,
/// `a + b = s + e` exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `|w|^2 - 1` to a relative rounding of its own size: the squares with their rounding errors
/// (Dekker's product), summed by two-sums, and 1 subtracted from the leading part (exact when
/// it is within a factor 2 of 1, Sterbenz).
#[inline]
fn norm2_minus_1(w: Vec3) -> f64 {
    let (px, ex) = square_with_error(w.x);
    let (py, ey) = square_with_error(w.y);
    let (pz, ez) = square_with_error(w.z);
    let (s1, e1) = two_sum(px, py);
    let (s2, e2) = two_sum(s1, pz);
    (s2 - 1.0) + (((ex + ey) + ez) + (e1 + e2))
}

/// `wi / |wi| + wo / |wo|` given `v = wi + wo` (rounded once per component; exact where the
/// components nearly cancel): `v + wi s_i + wo s_o` with `s = 1/|w| - 1 =
/// expm1(-ln1p(|w|^2 - 1) / 2)` from [`norm2_minus_1`], so that what remains of the near
/// cancellation is the corrections' own rounding (1e-16 of `|s|`).
#[inline]
fn unit_sum(wi: Vec3, wo: Vec3, v: Vec3) -> Vec3 {
    v + (wi * inv_norm_minus_1(wi) + wo * inv_norm_minus_1(wo))
}

/// `1 / |w| - 1` to its own relative rounding: `expm1(-ln1p(|w|^2 - 1) / 2)` with
/// [`norm2_minus_1`].
#[inline]
fn inv_norm_minus_1(w: Vec3) -> f64 {
    (-0.5 * norm2_minus_1(w).ln_1p()).exp_m1()
}

/// `sin^2` of the angle between `wi` and the reflection half vector of `(wi, wo)`:
/// `|wi/|wi| - wo/|wo||^2 / 4` (the half-angle identity `sin^2(t/2) = (1 - cos t) / 2`),
/// from the differences of the components, which keep their relative accuracy where the two
/// directions are close (near normal incidence on the facet), and the unit-length corrections
/// of [`unit_sum`]: no dot product near 1 is subtracted from 1.
#[inline]
fn reflection_sin2(wi: Vec3, wo: Vec3) -> f64 {
    let d = (wi - wo) + (wi * inv_norm_minus_1(wi) - wo * inv_norm_minus_1(wo));
    (0.25 * d.norm_squared()).min(1.0)
}

/// Walter et al. 2007's half vector of a pair of directions, with the cosines and indices of
/// refraction that the microfacet BSDF and its sampling density need.
///
/// For reflection `h = normalize(wi + wo)`; for refraction the generalised half vector
/// `h = -normalize(n_i wi + n_o wo)` (eq. 16), with `n_i`, `n_o` the indices on the sides of
/// `wi` and `wo`. Either way the facet of normal `h` sends light from `wi` to `wo`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfVector {
    /// The unit half vector (orientation chosen by the constructor).
    pub h: Vec3,
    /// `wi.h` and `wo.h`.
    pub cos_ih: f64,
    pub cos_oh: f64,
    /// Indices of refraction on the sides of `wi` and `wo`.
    pub n_i: f64,
    pub n_o: f64,
    /// True for reflection (both directions on one side of the interface).
    pub reflect: bool,
}

impl HalfVector {
    /// The half vector of `wi` and `wo` at a macro-surface with index 1 above (z > 0) and `eta`
    /// below: reflection when both are on one side, transmission otherwise; `h` flipped to
    /// `h.z > 0`. `None` for grazing directions and when no facet connects the pair (either
    /// direction on the back of `h`).
    #[inline]
    pub fn new(wi: Vec3, wo: Vec3, eta: f64) -> Option<Self> {
        let (ci, co) = (wi.z, wo.z);
        if ci == 0.0 || co == 0.0 {
            return None;
        }
        let index = |c: f64| if c > 0.0 { 1.0 } else { eta };
        let hv = Self::of_pair(wi, wo, index(ci), index(co), ci * co > 0.0, Vec3::z())?;
        // Each direction must lie on the same side of the facet as of the macro-surface.
        if hv.cos_ih * ci <= 0.0 || hv.cos_oh * co <= 0.0 {
            return None;
        }
        Some(hv)
    }

    /// The glass index at which the refraction half vector of the transmission pair `(wi, wo)`
    /// (one direction above the macro-surface, one below) lies in the macro-surface:
    /// `|w_above.z| / |w_below.z|`, where `(n_i wi + n_o wo).z = 0`. Where the pair has a
    /// refracting facet on one side of this index, that facet turns horizontal at it and the
    /// pair has none on the other side ([`HalfVector::new`] is `None`): the single-scattering
    /// BSDF of the pair jumps there from `D` at horizontal facets (not zero for GGX and for
    /// Student-T with `gamma <= 2`) to zero. `None` for a reflection pair or a grazing
    /// direction.
    pub fn horizontal_eta(wi: Vec3, wo: Vec3) -> Option<f64> {
        if wi.z * wo.z >= 0.0 {
            return None;
        }
        let (above, below) = if wi.z > 0.0 { (wi, wo) } else { (wo, wi) };
        Some(above.z / -below.z)
    }

    /// The glass index above which the reflection pair `(wi, wo)` inside the glass (both
    /// directions below the macro-surface) is totally internally reflected: `1 / sin(theta_ih)`,
    /// with `theta_ih` the angle from either direction to the pair's half vector (above it,
    /// `eta sin(theta_ih) > 1` leaves the facet no refracted ray). Just below it the pair's
    /// Fresnel factor, and with it its single-scattering BSDF, differs from its value at the
    /// index by about the square root of the distance to it: a slope in eta that is infinite
    /// at the index. `None` for other pairs and for a retro-reflection (`wi = wo`).
    pub fn total_reflection_eta(wi: Vec3, wo: Vec3) -> Option<f64> {
        if wi.z >= 0.0 || wo.z >= 0.0 {
            return None;
        }
        let sin2 = reflection_sin2(wi, wo);
        (sin2 > 0.0).then(|| 1.0 / sin2.sqrt())
    }

    /// The half vector for given indices and lobe, oriented so that `h.toward > 0` (`toward`
    /// not perpendicular to it); `None` for a zero or non-finite vector.
    #[inline]
    pub fn of_pair(
        wi: Vec3,
        wo: Vec3,
        n_i: f64,
        n_o: f64,
        reflect: bool,
        toward: Vec3,
    ) -> Option<Self> {
        let v = Self::unnormalised(wi, wo, n_i, n_o, reflect);
        let len = v.norm();
        if len == 0.0 || !len.is_finite() {
            return None;
        }
        let h = if v.dot(&toward) < 0.0 {
            -v / len
        } else {
            v / len
        };
        Some(Self {
            h,
            cos_ih: wi.dot(&h),
            cos_oh: wo.dot(&h),
            n_i,
            n_o,
            reflect,
        })
    }

    /// The half vector before normalisation and orientation: `wi + wo` for reflection,
    /// `-(n_i wi + n_o wo)` for refraction.
    ///
    /// For reflection the sum is that of the unit directions `wi / |wi| + wo / |wo|`: where
    /// `wi` and `wo` nearly oppose each other (grazing specular reflection) the sum is small,
    /// and the inputs' departure from unit length (an ulp) tilts it by that ulp over `|wi +
    /// wo|`: at `|z| = 1e-8` and alpha 1e-8 the computed half vector was wrong by 100% of its
    /// tilt. There ([`unit_sum`]) each direction is scaled by `1 / |w|` from its squared norm
    /// computed exactly, and the corrections `w (1/|w| - 1)` are added to the exact-ish sum.
    #[inline(always)]
    pub(crate) fn unnormalised(wi: Vec3, wo: Vec3, n_i: f64, n_o: f64, reflect: bool) -> Vec3 {
        if reflect {
            let v = wi + wo;
            // Where |v| >= 1/2 a norm off by ulps moves v by ulps of itself: nothing to correct.
            if v.norm_squared() < 0.25 {
                unit_sum(wi, wo, v)
            } else {
                v
            }
        } else {
            -(wi * n_i + wo * n_o)
        }
    }

    /// The half vector from its oriented unnormalised form `v`, `v_i = wi.v`, `v_o = wo.v` and
    /// `inv_len = 1 / |v|`, for callers that test the signs of `v_i`, `v_o` before paying for
    /// the normalisation.
    #[inline]
    pub(crate) fn from_scaled(
        v: Vec3,
        v_i: f64,
        v_o: f64,
        inv_len: f64,
        n_i: f64,
        n_o: f64,
        reflect: bool,
    ) -> Self {
        Self {
            h: v * inv_len,
            cos_ih: v_i * inv_len,
            cos_oh: v_o * inv_len,
            n_i,
            n_o,
            reflect,
        }
    }

    /// `|d omega_h / d omega_o|`, the Jacobian of the half-vector map: `1 / (4 |wo.h|)` for
    /// reflection (Walter et al. 2007, eq. 14) and `n_o^2 |wo.h| / (n_i wi.h + n_o wo.h)^2` for
    /// refraction (eq. 17).
    #[inline]
    pub fn jacobian(&self) -> f64 {
        let (num, den) = self.jacobian_fraction();
        num / den
    }

    /// [`HalfVector::jacobian`] as a fraction `(num, den)`.
    #[inline]
    fn jacobian_fraction(&self) -> (f64, f64) {
        if self.reflect {
            (1.0, 4.0 * self.cos_oh.abs())
        } else {
            let denom = self.n_i * self.cos_ih + self.n_o * self.cos_oh;
            (self.n_o * self.n_o * self.cos_oh.abs(), denom * denom)
        }
    }

    /// `|d omega_h / d omega_o|` times the lobe's Fresnel weight (`F` or `1 - F`, `F = F(wi.h)`)
    /// at a dielectric interface of index `eta` on the side `-h` points to and 1 on the side of
    /// `h` (`inv_eta = 1 / eta`), with one division. For refraction `wo` is the refraction of
    /// `wi` about `h` (the defining property of the generalised half vector), so `|wo.h|` is
    /// the transmitted cosine and Fresnel needs no square root.
    #[inline]
    pub(crate) fn dielectric_weight(&self, eta: f64, inv_eta: f64) -> f64 {
        let (f_num, f_den) = if self.reflect {
            reflectance_fraction(self.cos_ih, eta, inv_eta)
        } else {
            let eta_t = if self.cos_ih >= 0.0 { eta } else { inv_eta };
            fresnel_dielectric_fraction(self.cos_ih.abs(), self.cos_oh.abs(), eta_t)
        };
        let lobe = if self.reflect { f_num } else { f_den - f_num };
        let (j_num, j_den) = self.jacobian_fraction();
        lobe * j_num / (f_den * j_den)
    }

    /// The unpolarised Fresnel reflectance `F(wi.h)` of the facet `h` of a dielectric interface
    /// of index `eta` below (1 above). For reflection from `wi.h` alone. For refraction from
    /// `wi.h` and `wo.h`, the incident and transmitted cosines of the pair (the Fresnel formula
    /// is the same read from either end): Snell's law on the rounded `wi.h` would decide total
    /// internal reflection by rounding where `wo` leaves the facet at grazing, 0 one way and
    /// the full value the other (`f(wi, wo) / n_o^2 = f(wo, wi) / n_i^2` failed there).
    #[inline]
    pub fn dielectric_fresnel(&self, eta: f64) -> f64 {
        self.dielectric_fresnel_by(eta, || sin2_from_cos(self.cos_ih.abs().min(1.0)))
    }

    /// [`HalfVector::dielectric_fresnel`] of the pair `(wi, wo)` it was made from: for
    /// reflection the incident `sin^2` comes from the difference of the two directions
    /// (`reflection_sin2`), not from `1 - (wi.h)^2`, which inherits the absolute rounding of
    /// the dot product and of `h` (relative `1e-16 / sin^2`). Near the critical angle of eta
    /// 100 or 0.01 (`sin^2 = 1e-4`) the transmitted cosine `sqrt(1 - sin^2 / eta_t^2)`
    /// magnifies that: 1.7e-6 of F was lost within 1e-9 of the critical sine, 3.7e-10 now
    /// (what the rounding of `sin^2 / eta_t^2` itself leaves).
    #[inline]
    pub fn dielectric_fresnel_of(&self, wi: Vec3, wo: Vec3, eta: f64) -> f64 {
        self.dielectric_fresnel_by(eta, || reflection_sin2(wi, wo))
    }

    #[inline]
    fn dielectric_fresnel_by(&self, eta: f64, sin2_i: impl FnOnce() -> f64) -> f64 {
        if self.reflect {
            let (num, den) = reflectance_fraction_sin2(self.cos_ih, sin2_i(), eta, 1.0 / eta);
            return num / den;
        }
        let eta_t = if self.cos_ih >= 0.0 { eta } else { 1.0 / eta };
        let (num, den) = fresnel_dielectric_fraction(
            self.cos_ih.abs().min(1.0),
            self.cos_oh.abs().min(1.0),
            eta_t,
        );
        num / den
    }

    /// The Fresnel weight of the lobe: `F` for reflection, `1 - F` for refraction, given the
    /// reflectance `f = F(wi.h)`.
    #[inline]
    pub fn lobe_weight(&self, f: f64) -> f64 {
        if self.reflect { f } else { 1.0 - f }
    }

    /// Walter et al. 2007's microfacet BSDF (eqs. 20 and 21) times `|wo.z|`, without its `G D`:
    /// `f(wi, wo) |wo.z| = walter_factor * G * D(h)` with
    /// `walter_factor = |wi.h| |d omega_h / d omega_o| (F or 1 - F) / |wi.z|`, which is
    /// `F / (4 |wi.z|)` for reflection and
    /// `|wi.h| |wo.h| n_o^2 (1 - F) / (|wi.z| (n_i wi.h + n_o wo.h)^2)` for refraction.
    ///
    /// Reflection takes `F / (4 |wi.z|)` as written, not `|wi.h| / (4 |wo.h|)` times it: the
    /// two cosines are equal for unit vectors, but near grazing specular reflection both are
    /// about `|wi.z|` while a direction's norm, off 1 by its rounding (or by the 1e-6 that
    /// inputs may be off), tilts `h` by that error over `|wi + wo|`: at `|z| = 1e-8` their
    /// ratio came out 0.29 for exactly rounded unit vectors.
    #[inline]
    pub fn walter_factor(&self, wi_z: f64, f: f64) -> f64 {
        if self.reflect {
            return 0.25 * f / wi_z.abs();
        }
        self.cos_ih.abs() * self.jacobian() * self.lobe_weight(f) / wi_z.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reflection half vector of nearly opposed grazing directions is that of the unit
    /// directions the f64 inputs stand for (mpmath, 50 digits: `normalize(wi/|wi| + wo/|wo|)`),
    /// to 1e-14 of its tilt: the plain sum was off by 9.6, 0.11 and 0.48 times the tilt in these
    /// cases (0.48, 0.11 and 0.24 of an alpha of 1e-8), from the inputs' ulp-sized departures
    /// from unit length.
    #[test]
    #[allow(clippy::excessive_precision)]
    fn grazing_reflection_half_vector_is_that_of_the_unit_directions() {
        let cases = [
            (
                Vec3::new(1.0, 0.0, 1e-8),
                Vec3::new(-0.9999999999999999, 0.0, 1.1e-8),
                5.0000000000000007e-10,
            ),
            (
                Vec3::new(1.0, 0.0, 1e-8),
                Vec3::new(-0.9999999999999996, 0.0, 3e-8),
                1.0000000000000001e-8,
            ),
            (
                Vec3::new(0.9999999999999998, 0.0, 1.9999999999999997e-08),
                Vec3::new(-1.0, 0.0, 1e-8),
                -4.9999999999999995e-9,
            ),
        ];
        for (wi, wo, hx) in cases {
            let hv = HalfVector::new(wi, wo, 1.5).expect("a reflection pair");
            assert!(
                (hv.h.x - hx).abs() <= 1e-14 * hx.abs(),
                "{wi:?} {wo:?}: h.x {} against {hx}",
                hv.h.x
            );
        }
    }

    /// Reflection Fresnel within 1e-5, 1e-7 and 1e-9 (relative) of the critical sine of eta 100
    /// seen from inside (facet tilted 0.3 rad), against mpmath (50 digits, unit directions of
    /// the f64 inputs): the incident `sin^2` from the directions' difference keeps F to 1e-12,
    /// 1e-11 and 2e-10; through `1 - (wi.h)^2` it was off by 2.4e-8, 6.3e-7 and 1.7e-6.
    #[test]
    #[allow(clippy::excessive_precision)]
    fn reflection_fresnel_near_the_critical_angle_keeps_its_digits() {
        let cases = [
            (
                Vec3::new(-0.30505869993472845, 0.0, -0.9523335495477062),
                Vec3::new(-0.2859521612195141, 0.0, -0.9582438945768916),
                0.57285182966003227,
                1e-12,
            ),
            (
                Vec3::new(-0.3050587942204627, 0.0, -0.95233351934538),
                Vec3::new(-0.2859520663486236, 0.0, -0.9582439228875664),
                0.91803823757348005,
                1e-11,
            ),
            (
                Vec3::new(-0.30505879516332, 0.0, -0.9523335190433567),
                Vec3::new(-0.28595206539991463, 0.0, -0.9582439231706732),
                0.99113386472021529,
                2e-10,
            ),
        ];
        for (wi, wo, want, tol) in cases {
            let hv = HalfVector::new(wi, wo, 100.0).expect("a reflection pair");
            let f = hv.dielectric_fresnel_of(wi, wo, 100.0);
            assert!(
                ((f - want) / want).abs() < tol,
                "{wi:?}: F {f} against {want}"
            );
        }
        // From a given cosine, sin^2 = (1 - c)(1 + c): 4.5e-10 to 6.1e-10 were lost by 1 - c^2.
        for (c, want) in [
            (0.99995000125, 0.5145740969995484),
            (0.9999500012499, 0.51457576543830952),
            (0.99995000124999, 0.51457426365126925),
        ] {
            let f = super::super::fresnel_dielectric(-c, 100.0);
            assert!(
                ((f - want) / want).abs() < 5e-13,
                "cos {c}: F {f} against {want}"
            );
        }
    }

    /// Refraction obeys Snell's law, leaves on the other side, is unit to rounding and round
    /// trips; the Fresnel fraction returned with it is `fresnel_dielectric`, the same from both
    /// sides of the refraction.
    #[test]
    fn refraction_obeys_snell_and_round_trips() {
        let m = Vec3::new(0.3, -0.2, 0.9).normalize();
        let wi = Vec3::new(-0.5, 0.1, 0.7).normalize();
        for eta in [1.51, 1.0 / 1.51] {
            let Some((wt, (num, den))) = refract_with_fresnel(wi, m, eta, 1.0 / eta) else {
                continue;
            };
            assert_eq!(refract(wi, m, eta), Some(wt));
            let (si, st) = (wi.cross(&m).norm(), wt.cross(&m).norm());
            assert!((si - eta * st).abs() < 1e-12);
            assert!(wt.dot(&m) < 0.0);
            assert!((wt.norm() - 1.0).abs() < 1e-15);
            let f = num / den;
            assert!((f - super::super::fresnel_dielectric(wi.dot(&m), eta)).abs() < 1e-15);
            let (back, (num, den)) = refract_with_fresnel(wt, m, eta, 1.0 / eta).unwrap();
            assert!((back - wi).norm() < 1e-12);
            assert!((num / den - f).abs() < 1e-15);
        }
    }

    /// `dielectric_weight` is the Jacobian times the Fresnel weight of the lobe, for
    /// reflection and refraction from both sides, with the transmitted cosine taken from `wo`.
    #[test]
    fn dielectric_weight_is_jacobian_times_fresnel_weight() {
        let eta = 1.51;
        let m = Vec3::new(0.2, 0.1, 0.95).normalize();
        for wi in [Vec3::new(-0.4, 0.3, 0.8), Vec3::new(0.3, -0.2, -0.9)] {
            let wi = wi.normalize();
            let wt = refract(wi, m, eta).unwrap();
            for wo in [wt, reflect(wi, m)] {
                let hv = HalfVector::new(wi, wo, eta).unwrap();
                let f = super::super::fresnel_dielectric(hv.cos_ih, eta);
                let expected = hv.jacobian() * hv.lobe_weight(f);
                let got = hv.dielectric_weight(eta, 1.0 / eta);
                assert!(
                    (got - expected).abs() < 1e-13 * expected,
                    "{got} vs {expected}"
                );
            }
        }
    }

    /// The half vector of a refracted pair is the facet normal that refracts `wi` into `wo`.
    #[test]
    fn refraction_half_vector_is_the_refracting_facet() {
        let m = Vec3::new(0.2, 0.1, 0.95).normalize();
        let wi = Vec3::new(-0.4, 0.3, 0.8).normalize();
        let wo = refract(wi, m, 1.5).unwrap();
        let hv = HalfVector::new(wi, wo, 1.5).unwrap();
        assert!((hv.h - m).norm() < 1e-12, "{:?} vs {m:?}", hv.h);
        assert!(!hv.reflect);
    }

    /// Above its `total_reflection_eta` a reflection pair inside the glass is totally
    /// reflected (Fresnel factor 1) and below it is not; pairs that are not reflections inside
    /// the glass, and a retro-reflection, have no such index.
    #[test]
    fn total_reflection_eta_is_where_the_pair_turns_totally_reflected() {
        let wi = Vec3::new(0.5, 0.1, -0.8).normalize();
        for wo in [
            Vec3::new(-0.6, -0.1, -0.5).normalize(),
            Vec3::new(-0.2, 0.3, -0.9).normalize(),
        ] {
            let onset = HalfVector::total_reflection_eta(wi, wo).unwrap();
            assert!(onset > 1.0 && onset < 3.0, "{onset}");
            let f = |eta: f64| {
                HalfVector::new(wi, wo, eta)
                    .unwrap()
                    .dielectric_fresnel(eta)
            };
            assert_eq!(f(onset * (1.0 + 1e-9)), 1.0);
            assert!(f(onset * (1.0 - 1e-6)) < 1.0);
            assert!(f(onset * 0.9) < 0.5);
        }
        let up = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
        let wo = Vec3::new(-0.6, -0.1, -0.5).normalize();
        assert_eq!(HalfVector::total_reflection_eta(up(wi), up(wo)), None);
        assert_eq!(HalfVector::total_reflection_eta(up(wi), wo), None);
        assert_eq!(HalfVector::total_reflection_eta(wi, wi), None);
    }

    /// Across its `horizontal_eta` a transmission pair gains or loses its refracting facet,
    /// which is nearly horizontal there, with light from above or from below; reflection
    /// pairs have no such index.
    #[test]
    fn horizontal_eta_is_where_refraction_of_the_pair_starts_or_ends() {
        let above = Vec3::new(0.5, 0.1, 0.8).normalize();
        // Refraction ends below the index for this pair, starts below it for the other.
        let pairs = [
            Vec3::new(-0.6, -0.1, -0.5).normalize(),
            Vec3::new(-0.2, 0.0, -0.8).normalize(),
        ];
        for (k, below) in pairs.into_iter().enumerate() {
            for (wi, wo) in [(above, below), (below, above)] {
                let eta = HalfVector::horizontal_eta(wi, wo).unwrap();
                assert!((eta - above.z / -below.z).abs() < 1e-15);
                let (lower, upper) = (
                    HalfVector::new(wi, wo, eta * (1.0 - 1e-9)),
                    HalfVector::new(wi, wo, eta * (1.0 + 1e-9)),
                );
                let hv = if k == 0 {
                    assert!(lower.is_none());
                    upper.unwrap()
                } else {
                    assert!(upper.is_none());
                    lower.unwrap()
                };
                assert!(!hv.reflect && hv.h.z > 0.0 && hv.h.z < 1e-8, "{:?}", hv.h);
            }
        }
        assert_eq!(HalfVector::horizontal_eta(above, Vec3::z()), None);
        assert_eq!(
            HalfVector::horizontal_eta(Vec3::new(1.0, 0.0, 0.0), pairs[0]),
            None
        );
    }

    /// The Beta function of the correlated transmission masking: `B(1, b) = 1 / b`, and
    /// `B(2, 3) = 1/12`; zero for a grazing direction.
    #[test]
    fn correlated_transmission_is_the_beta_function() {
        let m = Masking::Correlated;
        assert!((m.g_transmission(1.0, 4.0) - 0.25).abs() < 1e-13);
        assert!((m.g_transmission(2.0, 3.0) - 1.0 / 12.0).abs() < 1e-13);
        assert_eq!(m.g_transmission(f64::INFINITY, 2.0), 0.0);
        assert!((m.g_reflection(2.0, 3.0) - 0.25).abs() < 1e-15);
        assert!((Masking::Separable.g_transmission(2.0, 3.0) - 1.0 / 6.0).abs() < 1e-15);
    }

    /// The Beta function keeps its digits where an argument is large (a grazing direction, or
    /// Student-T near gamma 3/2): `B(1, b) = 1/b`, and mpmath's values (40 digits) on both
    /// sides of the switch to Stirling's series.
    #[test]
    // mpmath's values are written to 20 digits, as printed.
    #[allow(clippy::excessive_precision)]
    fn correlated_transmission_is_exact_for_large_arguments() {
        let m = Masking::Correlated;
        for b in [10.0, 123.456, 3.2e7, 5e9, 1e15, 5e301] {
            let g = m.g_transmission(1.0, b);
            assert!((g * b - 1.0).abs() < 1e-13, "B(1, {b}) = {g}");
            if b < 1e100 {
                let g = m.g_transmission(b, 2.0);
                assert!((g * b * (b + 1.0) - 1.0).abs() < 1e-13, "B({b}, 2) = {g}");
            }
        }
        for (a, b, beta) in [
            (1.7, 3.2e7, 1.5835663858704621256e-13),
            (25.3, 4e9, 1.8973220817908864273e-219),
            (12.0, 15.0, 8.6286935122579220035e-9),
            (10.0, 10.0, 1.0825088224469029423e-6),
            (9.99, 10.01, 1.0825202068574784311e-6),
            (300.0, 300.5, 3.4883687432535679623e-182),
            (3.0, 1e15, 1.999999999999994e-45),
        ] {
            let g = m.g_transmission(a, b);
            let rel = (g / beta - 1.0).abs();
            assert!(
                rel < 1e-13,
                "B({a}, {b}) = {g}, expected {beta} (relative {rel:.1e})"
            );
            assert_eq!(g.to_bits(), m.g_transmission(b, a).to_bits());
        }
    }
}
