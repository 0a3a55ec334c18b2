//! The single-scattering directional albedo of a microfacet BSDF, by deterministic quadrature
//! over the facet normals.
//!
//! For light from `wi` (above the surface, `wi.z = mu > 0`) the albedo of the single-scattering
//! BSDF is, after the change of variables from the outgoing direction to the (generalised) half
//! vector `h` of each lobe (the Jacobians cancel against the BSDF's denominators),
//!
//! ```text
//! E(mu) = integral over h of (wi.h)_+ D(h) / mu * [ F(wi.h) G_r(wi, wo_r) [wo_r.z > 0]
//!                                        + (1 - F(wi.h)) G_t(wi, wo_t) [wo_t.z < 0] ] dh
//! ```
//!
//! with `wo_r`, `wo_t` the reflection and refraction of `wi` about `h`. The two terms are the
//! reflected and transmitted albedos. Facet normals are written `h = (sin theta cos phi,
//! sin theta sin phi, cos theta)` with `tan theta = alpha / tan(eps)`: `eps` runs from `pi/2`
//! (`h = z`) to 0 (horizontal facets) whatever the roughness, so that the same rule serves
//! `alpha = 1e-8` and `alpha = 4`.
//!
//! The integrand is smooth except on curves where a lobe switches on or off: the visibility
//! limit `wi.h = 0`, the facets that reflect (or, from the denser side, refract) `wi` into the
//! horizon, and the limits of total internal reflection. For a given `phi` all of them are roots
//! of quadratics in `tan theta` (`Cell::breaks`), so the `eps` range is cut there. Each piece is
//! mapped through `x = 3 s^2 - 2 s^3`, which makes the square-root behaviour of the Fresnel
//! factor at a total-internal-reflection limit smooth, and integrated by adaptive Gauss-Kronrod
//! (10-21, QUADPACK's error estimate) to an absolute tolerance on `E` (1e-7 by default), with a
//! relative floor at the integrand's rounding noise. Pieces whose ends differ by more than 16x
//! are first cut geometrically (near horizontal facets the integrand varies on the scale of
//! `eps` itself). On the piece that reaches horizontal facets the substitution is raised to a
//! power chosen from the tail of the NDF ([`TableNdf::tail_exponent`]), which removes the
//! integrable singularity of heavy-tailed Student-T distributions (gamma < 2).
//!
//! The azimuth `phi` runs over `[0, pi]` (the integrand is even in it) by Gauss-Legendre (16
//! nodes on a piece of length `pi / 2`, proportionally fewer but at least 12 on shorter ones;
//! one node at normal incidence, where nothing depends on `phi`) on pieces cut where the set of
//! breaks changes (`Cell::azimuth_cuts`):
//! `pi / 2`, where the visibility limit appears; from the denser side, where the
//! total-internal-reflection limits touch, reach vertical facets or meet the reflection into the
//! horizon; at grazing incidence a geometric sequence of cuts toward `pi / 2`, where the
//! breaks sweep across the facets within `|cos phi| ~ mu / sin(theta_i)`; and near the
//! critical angle, cuts where the total-internal-reflection limits cross the facets of
//! typical slope.
//!
//! Measured against the same quadrature with 4x the azimuth nodes and a 1e-11 tolerance, at
//! 672 cells per NDF spanning Cycles' grid (alpha 1e-8 to 1, mu 1e-4 to 1, eta 1.009 to 99.5,
//! both sides; `examples/quadrature_accuracy.rs`): the largest difference of `R` or `T` is
//! 3.0e-8 for GGX and 2.4e-6 for Beckmann (at `mu = 1e-4`).

use std::f64::consts::{FRAC_PI_2, PI};
use stfit_core::Vec3;
use stfit_core::bsdf::{Masking, SmithTerm, fresnel_dielectric, reflect, refract};
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT};
use stfit_core::quadrature::GaussLegendre;
use stfit_core::walk::ConductorFacet;

/// A height-field NDF as the albedo quadrature needs it: its roughness, which scales the facet
/// slopes, and how heavy the tail of its slopes is.
pub trait TableNdf: Ndf {
    /// The roughness alpha.
    fn alpha(&self) -> f64;

    /// The exponent `k` with which the projected area of facets steeper than `tan theta = t`,
    /// weighted by their slope, falls for large `t` (`t^-k`): `2 gamma - 3` for Student-T
    /// (1 for GGX), `None` for Beckmann's Gaussian tail.
    fn tail_exponent(&self) -> Option<f64>;
}

impl TableNdf for Beckmann {
    fn alpha(&self) -> f64 {
        Beckmann::alpha(self)
    }
    fn tail_exponent(&self) -> Option<f64> {
        None
    }
}

impl TableNdf for Ggx {
    fn alpha(&self) -> f64 {
        Ggx::alpha(self)
    }
    fn tail_exponent(&self) -> Option<f64> {
        Some(1.0)
    }
}

impl TableNdf for StudentT {
    fn alpha(&self) -> f64 {
        StudentT::alpha(self)
    }
    fn tail_exponent(&self) -> Option<f64> {
        Some(2.0 * self.gamma() - 3.0)
    }
}

/// What a facet does with the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Interface {
    /// A dielectric interface; `eta_rel` is the index on the far side over the index on the
    /// light's side (`eta` for light from outside, `1 / eta` for light inside the glass).
    Dielectric { eta_rel: f64 },
    /// An opaque mirror or Fresnel conductor.
    Conductor(ConductorFacet),
}

/// The Smith masking of the single-scattering BSDF whose albedo is tabulated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TableMasking {
    /// Height-correlated: `1 / (1 + Lambda_i + Lambda_o)` for reflection and
    /// `B(1 + Lambda_i, 1 + Lambda_o)` for transmission. The random walks' first order.
    #[default]
    Correlated,
    /// Height-correlated reflection form `1 / (1 + Lambda_i + Lambda_o)` for both lobes, as
    /// Blender Cycles' BSDF and its energy tables use it.
    ReflectionForm,
    /// `G1(wi) G1(wo)` for both lobes (Walter et al. 2007).
    Separable,
}

impl TableMasking {
    /// The name used on the command line and in the files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Correlated => "correlated",
            Self::ReflectionForm => "reflection-form",
            Self::Separable => "separable",
        }
    }

    /// The Smith term of a direction with `a = 1 + Lambda`, as [`TableMasking::g_transmission`]
    /// needs it (with the log-gamma of the Beta function only for `Correlated`).
    #[inline]
    fn term(self, a: f64) -> SmithTerm {
        match self {
            Self::Correlated => Masking::Correlated.term(a),
            Self::ReflectionForm | Self::Separable => Masking::Separable.term(a),
        }
    }

    /// `G` of the reflected lobe from `a = 1 + Lambda` of both directions.
    #[inline]
    fn g_reflection(self, a_i: f64, a_o: f64) -> f64 {
        match self {
            Self::Separable => Masking::Separable.g_reflection(a_i, a_o),
            Self::Correlated | Self::ReflectionForm => Masking::Correlated.g_reflection(a_i, a_o),
        }
    }

    /// `G` of the transmitted lobe from the [`TableMasking::term`] of the light's direction
    /// and `a = 1 + Lambda` of the outgoing one.
    #[inline]
    fn g_transmission(self, i: SmithTerm, a_o: f64) -> f64 {
        match self {
            Self::Separable => Masking::Separable.g(false, i, self.term(a_o)),
            Self::Correlated => Masking::Correlated.g(false, i, self.term(a_o)),
            Self::ReflectionForm => Masking::Correlated.g_reflection(i.a(), a_o),
        }
    }
}

/// Fractions of the incident flux a BSDF reflects and transmits.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Albedo {
    pub reflected: f64,
    pub transmitted: f64,
}

impl Albedo {
    /// `reflected + transmitted`.
    pub fn total(&self) -> f64 {
        self.reflected + self.transmitted
    }

    /// The albedo moved into what it can be, as a merge of shards accepts it within
    /// `tolerance`: negative parts raised to 0, then [`Albedo::at_most_one`].
    pub(crate) fn into_range(self, tolerance: f64) -> Albedo {
        Albedo {
            reflected: self.reflected.max(0.0),
            transmitted: self.transmitted.max(0.0),
        }
        .at_most_one(tolerance)
    }

    /// The albedo with `reflected` and `transmitted` scaled by `1 / total` where the total
    /// exceeds 1 by at most `tolerance`. A single-scattering albedo is at most 1 exactly
    /// (every masking here has `G <= G1(wi)`, and the visible normals of `wi` integrate to 1);
    /// the quadrature's rounding lifts near-specular cells above it (`1 + 9e-16` at Beckmann
    /// alpha 1e-8, mu 1e-4, eta 100), which would make `1 - E` negative. A larger excess is
    /// left as it is, to show.
    pub(crate) fn at_most_one(self, tolerance: f64) -> Albedo {
        let total = self.total();
        if total > 1.0 && total <= 1.0 + tolerance {
            // The larger part as 1 minus the smaller, so that the sum rounds to 1, not above.
            if self.reflected >= self.transmitted {
                let transmitted = self.transmitted / total;
                Albedo {
                    reflected: 1.0 - transmitted,
                    transmitted,
                }
            } else {
                let reflected = self.reflected / total;
                Albedo {
                    reflected,
                    transmitted: 1.0 - reflected,
                }
            }
        } else {
            self
        }
    }

    #[inline]
    fn add_scaled(&mut self, o: Albedo, w: f64) {
        self.reflected += w * o.reflected;
        self.transmitted += w * o.transmitted;
    }
}

/// The rules of the albedo quadrature: Gauss-Legendre over the azimuth, with `phi_nodes` on
/// a piece of length `pi / 2` (proportionally fewer on shorter pieces, at least
/// [`MIN_PHI_NODES`]); Gauss-Legendre over the cosine range of [`average`], `mu_nodes` over
/// [0, 1] (a piece of length `l` gets `ceil(mu_nodes l) + 2`, at least [`MIN_MU_NODES`], and
/// its cosines' albedos are computed with half the azimuth nodes, at least
/// [`MIN_AVERAGE_PHI_NODES`], on every piece); and adaptive
/// Gauss-Kronrod (10-21) over the facet tilt, bisecting until the estimated error of each
/// azimuth's integral, carried to `E`, is below `tolerance`.
#[derive(Debug, Clone, PartialEq)]
pub struct Quadrature {
    /// `rules[n - 1]` has `n` nodes.
    rules: Vec<GaussLegendre>,
    phi_nodes: usize,
    /// Fewest azimuth nodes on a piece.
    phi_least: usize,
    mu_nodes: usize,
    tolerance: f64,
}

/// Fewest nodes on a piece of the cosine range of [`average`].
pub const MIN_MU_NODES: usize = 4;

/// Fewest nodes on a piece of the azimuth range.
pub const MIN_PHI_NODES: usize = 12;

/// Fewest azimuth nodes on a piece for the albedos of [`average`].
pub const MIN_AVERAGE_PHI_NODES: usize = 8;

impl Quadrature {
    /// A quadrature with the given numbers of nodes and tilt tolerance (absolute, on the
    /// albedo).
    pub fn new(phi_nodes: usize, mu_nodes: usize, tolerance: f64) -> Self {
        let phi_nodes = phi_nodes.max(MIN_PHI_NODES);
        let mu_nodes = mu_nodes.max(MIN_MU_NODES);
        Self {
            rules: (1..=phi_nodes.max(mu_nodes))
                .map(GaussLegendre::new)
                .collect(),
            phi_nodes,
            phi_least: MIN_PHI_NODES,
            mu_nodes,
            tolerance,
        }
    }

    /// The rule for a piece of length `len` of the cosine range.
    fn mu_rule(&self, len: f64) -> &GaussLegendre {
        let n = (self.mu_nodes as f64 * len).ceil() as usize + 2;
        &self.rules[n.clamp(MIN_MU_NODES, self.mu_nodes) - 1]
    }

    /// The rule for a piece of length `len` of the azimuth range.
    fn phi_rule(&self, len: f64) -> &GaussLegendre {
        let n = (self.phi_nodes as f64 * len / FRAC_PI_2).ceil() as usize;
        &self.rules[n.clamp(self.phi_least, self.phi_nodes) - 1]
    }

    /// The rule of the albedos that [`average`] integrates: half the azimuth nodes, at least
    /// [`MIN_AVERAGE_PHI_NODES`] per piece (their errors average out over the cosines).
    fn for_average(&self) -> Self {
        let phi_nodes = (self.phi_nodes / 2).max(MIN_AVERAGE_PHI_NODES);
        Self {
            phi_nodes,
            phi_least: phi_nodes,
            ..self.clone()
        }
    }
}

impl Default for Quadrature {
    /// The rule the tables use: 16 azimuths per piece, 16 cosines over [0, 1], tolerance 1e-7.
    fn default() -> Self {
        Self::new(16, 16, 1e-7)
    }
}

/// `x = 3 s^2 - 2 s^3` and its derivative: maps [0, 1] onto itself with zero slope at both
/// ends, so that `sqrt(x)`-type endpoint behaviour becomes smooth in `s`.
#[inline]
fn smoothstep(s: f64) -> (f64, f64) {
    (s * s * (3.0 - 2.0 * s), 6.0 * s * (1.0 - s))
}

/// Calls `f(x, weight)` at the nodes of `rule` mapped to `[a, b]` with zero slope (nodes
/// crowding quadratically) at the ends marked in `crowd`: [`smoothstep`] for both ends,
/// `s^2` or `1 - (1 - s)^2` for one.
#[inline]
fn panel(rule: &GaussLegendre, a: f64, b: f64, crowd: (bool, bool), mut f: impl FnMut(f64, f64)) {
    let len = b - a;
    for (x, w) in rule.points() {
        let s = 0.5 * (x + 1.0);
        let (y, dy) = match crowd {
            (true, true) => smoothstep(s),
            (true, false) => (s * s, 2.0 * s),
            (false, true) => (s * (2.0 - s), 2.0 * (1.0 - s)),
            (false, false) => (s, 1.0),
        };
        f(a + len * y, 0.5 * w * len * dy);
    }
}

/// A piece of the facet-tilt range as a map from `s` in [0, 1] to `(eps, d eps / d s)`.
#[derive(Debug, Clone, Copy)]
enum Piece {
    /// `eps = lo + (hi - lo) smoothstep(s)`.
    Smooth { lo: f64, hi: f64 },
    /// `eps = hi smoothstep(s)^p`: nodes crowd toward horizontal facets like `s^(2p)`.
    Power { hi: f64, p: i32 },
}

impl Piece {
    #[inline]
    fn map(self, s: f64) -> (f64, f64) {
        let (y, dy) = smoothstep(s);
        match self {
            Self::Smooth { lo, hi } => (lo + (hi - lo) * y, (hi - lo) * dy),
            Self::Power { hi, p } => {
                let yp = y.powi(p - 1);
                (hi * yp * y, hi * f64::from(p) * yp * dy)
            }
        }
    }
}

/// Abscissae of the 21-point Kronrod rule on [-1, 1] (non-negative half, decreasing; the odd
/// entries are the 10-point Gauss nodes), and the Kronrod and Gauss weights (QUADPACK `qk21`).
const XGK: [f64; 11] = [
    0.995_657_163_025_808_1,
    0.973_906_528_517_171_7,
    0.930_157_491_355_708_2,
    0.865_063_366_688_984_5,
    0.780_817_726_586_416_9,
    0.679_409_568_299_024_4,
    0.562_757_134_668_604_7,
    0.433_395_394_129_247_2,
    0.294_392_862_701_460_2,
    0.148_874_338_981_631_2,
    0.0,
];
const WGK: [f64; 11] = [
    0.011_694_638_867_371_874,
    0.032_558_162_307_964_73,
    0.054_755_896_574_352,
    0.075_039_674_810_919_95,
    0.093_125_454_583_697_6,
    0.109_387_158_802_297_64,
    0.123_491_976_262_065_85,
    0.134_709_217_311_473_33,
    0.142_775_938_577_060_08,
    0.147_739_104_901_338_5,
    0.149_445_554_002_916_9,
];
const WG: [f64; 5] = [
    0.066_671_344_308_688_14,
    0.149_451_349_150_580_6,
    0.219_086_362_515_982_04,
    0.269_266_719_309_996_36,
    0.295_524_224_714_752_87,
];

/// Deepest bisection of a piece: intervals of `2^-30` of it.
const MAX_DEPTH: u32 = 30;

/// `integral_a^b f(s) ds` by the Gauss-Kronrod (10-21) rule, with QUADPACK's error estimate
/// (`qk21`: `resasc min(1, (200 |K21 - G10| / resasc)^1.5)`, `resasc` the integral of
/// `|f - mean|`; the larger over the two lobes) and the integral of `|f|` (the larger lobe).
#[inline]
fn kronrod(f: &mut impl FnMut(f64) -> Albedo, a: f64, b: f64) -> (Albedo, f64, f64) {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    // values[2j], values[2j + 1]: the pair at +-XGK[j]; values[20]: the centre.
    let mut values = [[0.0f64; 2]; 21];
    for j in 0..10 {
        let x = half * XGK[j];
        let (l, r) = (f(mid - x), f(mid + x));
        values[2 * j] = [l.reflected, l.transmitted];
        values[2 * j + 1] = [r.reflected, r.transmitted];
    }
    let c = f(mid);
    values[20] = [c.reflected, c.transmitted];
    let kronrod_weight = |i: usize| WGK[i / 2];
    let gauss_weight = |i: usize| {
        let j = i / 2;
        if i < 20 && j % 2 == 1 { WG[j / 2] } else { 0.0 }
    };
    let mut out = [0.0f64; 2];
    let (mut err, mut abs) = (0.0f64, 0.0f64);
    for lobe in 0..2 {
        let (mut k, mut g, mut k_abs) = (0.0, 0.0, 0.0);
        for (i, v) in values.iter().enumerate() {
            k += kronrod_weight(i) * v[lobe];
            k_abs += kronrod_weight(i) * v[lobe].abs();
            g += gauss_weight(i) * v[lobe];
        }
        let mean = 0.5 * k;
        let resasc: f64 = values
            .iter()
            .enumerate()
            .map(|(i, v)| kronrod_weight(i) * (v[lobe] - mean).abs())
            .sum();
        let e = (k - g).abs();
        let e = if resasc > 0.0 && e > 0.0 {
            resasc * (200.0 * e / resasc).powf(1.5).min(1.0)
        } else {
            e
        };
        out[lobe] = half * k;
        err = err.max(half * e);
        abs = abs.max(half * k_abs);
    }
    (
        Albedo {
            reflected: out[0],
            transmitted: out[1],
        },
        err,
        abs,
    )
}

/// Relative accuracy below which an interval is not bisected whatever the tolerance: the
/// rounding noise of the integrand (the Fresnel factor near a total-internal-reflection limit
/// at extreme indices is computed with a relative error up to about 1e-7).
const NOISE_FLOOR: f64 = 1e-7;

/// `integral_a^b f` by [`kronrod`], bisecting while the error estimate exceeds both `tol`
/// (halved with each bisection) and [`NOISE_FLOOR`] times the integral of `|f|`.
fn adaptive(f: &mut impl FnMut(f64) -> Albedo, a: f64, b: f64, tol: f64, depth: u32) -> Albedo {
    let (sum, err, abs) = kronrod(f, a, b);
    if err <= tol.max(NOISE_FLOOR * abs) || depth >= MAX_DEPTH {
        return sum;
    }
    let m = 0.5 * (a + b);
    let mut left = adaptive(f, a, m, 0.5 * tol, depth + 1);
    left.add_scaled(adaptive(f, m, b, 0.5 * tol, depth + 1), 1.0);
    left
}

/// The single-scattering albedo of light arriving at cosine `mu` in (0, 1] on the upper side,
/// split into reflection and transmission (see the [module documentation](self)).
pub fn single_scattering<N: TableNdf>(
    ndf: &N,
    interface: Interface,
    masking: TableMasking,
    mu: f64,
    rule: &Quadrature,
) -> Albedo {
    let cell = Cell::new(ndf, interface, masking, mu);
    let mut sum = Albedo::default();
    // E = (2 / mu) sum of w I(phi) with the weights summing to pi.
    let tol = rule.tolerance * mu / (2.0 * PI);
    if cell.wi.x == 0.0 {
        // Normal incidence: the integrand does not depend on the azimuth.
        sum.add_scaled(cell.azimuth(0.0, tol), PI);
    }
    let cuts = if cell.wi.x == 0.0 {
        Vec::new()
    } else {
        cell.azimuth_cuts()
    };
    for piece in cuts.windows(2) {
        // The integrand is smooth and even about phi = 0 and pi: no crowding there.
        let crowd = (piece[0] > 0.0, piece[1] < PI);
        panel(
            rule.phi_rule(piece[1] - piece[0]),
            piece[0],
            piece[1],
            crowd,
            |phi, w| {
                sum.add_scaled(cell.azimuth(phi, tol), w);
            },
        );
    }
    let scale = 2.0 / mu;
    Albedo {
        reflected: scale * sum.reflected,
        transmitted: scale * sum.transmitted,
    }
    .at_most_one(rule.tolerance)
}

/// The cosine-weighted average `E_avg = 2 integral_0^1 E(mu) mu dmu` of [`single_scattering`],
/// by Gauss-Legendre in `mu` (after a smoothstep substitution) on pieces split where the
/// structure of the integrand changes with `mu` when light is in the denser medium.
pub fn average<N: TableNdf>(
    ndf: &N,
    interface: Interface,
    masking: TableMasking,
    rule: &Quadrature,
) -> Albedo {
    let mut sum = Albedo::default();
    let inner = rule.for_average();
    for piece in mu_cuts(interface).windows(2) {
        let (a, b) = (piece[0], piece[1]);
        panel(rule.mu_rule(b - a), a, b, (true, true), |mu, w| {
            sum.add_scaled(
                single_scattering(ndf, interface, masking, mu, &inner),
                2.0 * mu * w,
            );
        });
    }
    sum.at_most_one(rule.tolerance)
}

/// The cosines in [0, 1] where the azimuth cuts of [`Cell::azimuth_cuts`] appear or vanish,
/// with both ends: for light in the denser medium (`kappa^2 = 1 - eta_rel^2`), the critical
/// angle `mu = kappa`, `mu = eta_rel` (where a total-internal-reflection limit can reach
/// vertical facets) and `mu = 2 kappa eta_rel` (where the reflection into the horizon can meet
/// such a limit).
fn mu_cuts(interface: Interface) -> Vec<f64> {
    let mut cuts = vec![0.0, 1.0];
    if let Interface::Dielectric { eta_rel } = interface {
        if eta_rel < 1.0 {
            let kappa = (1.0 - eta_rel * eta_rel).sqrt();
            cuts.extend(
                [kappa, eta_rel, 2.0 * kappa * eta_rel]
                    .into_iter()
                    .filter(|&c| c > 0.0 && c < 1.0),
            );
        }
    }
    cuts.sort_unstable_by(f64::total_cmp);
    cuts.dedup();
    cuts
}

/// Largest `|cos phi|` of the azimuth cuts that resolve grazing incidence.
const SCALE_CUT: f64 = 0.25;

/// Ratio of consecutive `|cos phi|` of those cuts.
const AZIMUTH_GRADING: f64 = 4.0;

/// Ratio of the ends of the graded pieces of the facet-tilt range.
const GRADING: f64 = 16.0;

/// One albedo integral: the incident direction and what every facet shares.
struct Cell<'a, N> {
    ndf: &'a N,
    interface: Interface,
    masking: TableMasking,
    wi: Vec3,
    /// `1 + Lambda(wi)`, and its Smith term for the transmitted lobe.
    a_i: f64,
    term_i: SmithTerm,
    alpha: f64,
    /// Power of the substitution on the piece that reaches horizontal facets.
    tail_power: i32,
}

impl<'a, N: TableNdf> Cell<'a, N> {
    fn new(ndf: &'a N, interface: Interface, masking: TableMasking, mu: f64) -> Self {
        let wi = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
        // With the slope-weighted tail falling like t^-k, the integrand in eps behaves like
        // eps^(k-1) near 0; `eps = b y^p`, `y ~ 3 s^2` makes it `s^(2pk - 1)`: p >= 2/k gives
        // at least s^3.
        let tail_power = match ndf.tail_exponent() {
            Some(k) => (2.0 / k).ceil().clamp(1.0, 64.0) as i32,
            None => 1,
        };
        let a_i = ndf.sigma(wi) / mu;
        Self {
            ndf,
            interface,
            masking,
            wi,
            a_i,
            term_i: masking.term(a_i),
            alpha: ndf.alpha(),
            tail_power,
        }
    }

    /// The azimuths in `[0, pi]` where the set of [`Cell::breaks`] changes, in increasing order
    /// with both ends: `pi / 2`, where the visibility limit appears; and, from the denser side
    /// (`kappa^2 = 1 - eta_rel^2 > mu^2`), where the total-internal-reflection limits touch
    /// (`b^2 = kappa^2 - c^2`, also where refraction into the horizon starts) and where one of
    /// them reaches vertical facets (`b^2 = kappa^2`).
    fn azimuth_cuts(&self) -> Vec<f64> {
        let mut cuts = vec![0.0, FRAC_PI_2, PI];
        let (s, c) = (self.wi.x, self.wi.z);
        // At grazing incidence the breaks change over azimuths with |b| from c / s (the
        // reflection into the horizon) and c / (alpha s) (the visibility limit across the
        // facets of typical slope) up to about s; near the critical angle the limits of total
        // internal reflection sweep across the facets of typical slope for |b| ~ alpha. Cut
        // geometrically over that range.
        let mut b = c.min(c / self.alpha);
        while b < SCALE_CUT * s {
            let phi = (b / s).acos();
            cuts.extend([phi, PI - phi]);
            b *= AZIMUTH_GRADING;
        }
        if let Interface::Dielectric { eta_rel } = self.interface {
            let kappa = (1.0 - eta_rel * eta_rel).max(0.0).sqrt();
            if eta_rel < 1.0 && self.alpha < 0.5 * s && (c - kappa).abs() < 2.0 * self.alpha {
                for b in [self.alpha / 16.0, self.alpha / 4.0, self.alpha] {
                    if b < s {
                        let phi = (b / s).acos();
                        cuts.extend([phi, PI - phi]);
                    }
                }
            }
        }
        if let Interface::Dielectric { eta_rel } = self.interface {
            let kappa2 = 1.0 - eta_rel * eta_rel;
            if eta_rel < 1.0 {
                for b2 in [kappa2 - c * c, kappa2] {
                    if b2 > 0.0 && b2 < s * s {
                        let phi = (b2.sqrt() / s).acos();
                        cuts.extend([phi, PI - phi]);
                    }
                }
                // Where the reflection into the horizon meets a total-internal-reflection limit.
                let b = (2.0 * kappa2 - c * c) / (4.0 * kappa2 - c * c).sqrt();
                if b.abs() < s {
                    cuts.push((b / s).acos());
                }
            }
        }
        cuts.sort_unstable_by(f64::total_cmp);
        cuts
    }

    /// The integral over facet tilts at azimuth `phi` of the integrand of the module
    /// documentation, in `eps`.
    fn azimuth(&self, phi: f64, tol: f64) -> Albedo {
        let (sin_phi, cos_phi) = phi.sin_cos();
        let (ts, t_end) = self.breaks(cos_phi);
        // Pieces in eps, from pi/2 (t = 0) down to eps_end.
        let mut eps: [f64; 8] = [0.0; 8];
        eps[0] = FRAC_PI_2;
        let mut n = 1;
        for &t in ts.iter().flatten() {
            eps[n] = self.alpha.atan2(t);
            n += 1;
        }
        let eps_end = t_end.map_or(0.0, |t| self.alpha.atan2(t));
        eps[1..n].sort_unstable_by(|a, b| b.total_cmp(a));
        eps[n] = eps_end;
        let mut sum = Albedo::default();
        let mut piece = |p: Piece| {
            let mut f = |s: f64| {
                let (e, de) = p.map(s);
                let mut v = self.facet(e, cos_phi, sin_phi);
                v.reflected *= de;
                v.transmitted *= de;
                v
            };
            sum.add_scaled(adaptive(&mut f, 0.0, 1.0, tol, 0), 1.0);
        };
        for k in 0..n {
            let (mut hi, lo) = (eps[k], eps[k + 1]);
            if hi <= lo {
                continue;
            }
            if lo == 0.0 {
                piece(Piece::Power {
                    hi,
                    p: self.tail_power,
                });
                continue;
            }
            // Near a break close to horizontal facets the integrand varies on the scale of
            // eps itself: grade the piece geometrically toward it.
            while hi > GRADING * lo {
                let mid = hi / GRADING;
                piece(Piece::Smooth { lo: mid, hi });
                hi = mid;
            }
            piece(Piece::Smooth { lo, hi });
        }
        sum
    }

    /// The facet slopes `t = tan theta` at azimuth `phi` where a lobe switches (strictly inside
    /// the visible range), and the end of the visible range (`None`: it reaches horizontal
    /// facets). With `b = sin theta_i cos phi`, `c = mu`, `wi.h = (b t + c) / sqrt(1 + t^2)`:
    /// - visibility ends at `b t + c = 0`;
    /// - the reflection of `wi` reaches the horizon at `c t^2 - 2 b t - c = 0`;
    /// - light in the denser medium (`eta_rel < 1`, `kappa^2 = 1 - eta_rel^2`) is totally
    ///   reflected where `wi.h < kappa`, bounded by `(b^2 - kappa^2) t^2 + 2 b c t + c^2 - kappa^2
    ///   = 0`, and refracted into the horizon at `c^2 t^2 - 2 b c t + kappa^2 - c^2 = 0` with
    ///   `t <= b / c`.
    fn breaks(&self, cos_phi: f64) -> ([Option<f64>; 5], Option<f64>) {
        let c = self.wi.z;
        let b = self.wi.x * cos_phi;
        let t_end = (b < 0.0).then(|| c / -b);
        let visible = |t: f64| t > 0.0 && t.is_finite() && t_end.is_none_or(|e| t < e);
        let keep = |t: f64| visible(t).then_some(t);
        let root = (b * b + c * c).sqrt();
        let t_reflect = if b >= 0.0 {
            (b + root) / c
        } else {
            c / (root - b)
        };
        let mut ts = [keep(t_reflect), None, None, None, None];
        let denser = match self.interface {
            Interface::Dielectric { eta_rel } if eta_rel < 1.0 => Some(eta_rel),
            _ => None,
        };
        if let Some(eta_rel) = denser {
            let kappa2 = 1.0 - eta_rel * eta_rel;
            let kappa = kappa2.sqrt();
            // wi.h = kappa (not -kappa: b t + c > 0 on the visible range).
            let on_limit = |t: f64| visible(t) && b * t + c > 0.0;
            let [r1, r2] = quadratic_roots(b * b - kappa2, 2.0 * b * c, c * c - kappa2);
            ts[1] = r1.filter(|&t| on_limit(t));
            ts[2] = r2.filter(|&t| on_limit(t));
            let disc = b * b + c * c - kappa2;
            if b > 0.0 && c < kappa && disc >= 0.0 {
                ts[3] = keep((kappa2 - c * c) / (c * (b + disc.sqrt())));
            }
        }
        (ts, t_end)
    }

    /// The integrand at facet tilt `eps` and azimuth `(cos phi, sin phi)`, with the Jacobian
    /// `sin theta d theta / d eps` (the factor `2 / mu` is applied by the caller).
    #[inline]
    fn facet(&self, eps: f64, cos_phi: f64, sin_phi: f64) -> Albedo {
        let (c_eps, s_eps) = (eps.sin(), eps.cos());
        let a = self.alpha;
        let r2 = a * a * s_eps * s_eps + c_eps * c_eps;
        let r = r2.sqrt();
        let (sin_t, cos_t) = (a * s_eps / r, c_eps / r);
        let jacobian = a * a * s_eps / (r2 * r);
        let h = Vec3::new(sin_t * cos_phi, sin_t * sin_phi, cos_t);
        let wi = self.wi;
        let c_h = wi.dot(&h);
        if c_h <= 0.0 {
            return Albedo::default();
        }
        let d = self.ndf.d(h);
        if d == 0.0 {
            return Albedo::default();
        }
        let m = jacobian * d * c_h;
        let a_o = |wo: Vec3| self.ndf.sigma(Vec3::new(wo.x, wo.y, wo.z.abs())) / wo.z.abs();
        let mut out = Albedo::default();
        let f = match self.interface {
            Interface::Dielectric { eta_rel } => fresnel_dielectric(c_h, eta_rel),
            Interface::Conductor(facet) => facet.reflectance(c_h),
        };
        let wo = reflect(wi, h);
        if wo.z > 0.0 && f > 0.0 {
            out.reflected = m * f * self.masking.g_reflection(self.a_i, a_o(wo));
        }
        if let Interface::Dielectric { eta_rel } = self.interface {
            match refract(wi, h, eta_rel) {
                Some(wo) if f < 1.0 && wo.z < 0.0 => {
                    out.transmitted =
                        m * (1.0 - f) * self.masking.g_transmission(self.term_i, a_o(wo));
                }
                _ => {}
            }
        }
        out
    }
}

/// The real roots of `a x^2 + b x + c = 0` (of `b x + c` when `a = 0`), computed without
/// cancellation.
fn quadratic_roots(a: f64, b: f64, c: f64) -> [Option<f64>; 2] {
    if a == 0.0 {
        return [(b != 0.0).then(|| -c / b), None];
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return [None, None];
    }
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    if q == 0.0 {
        return [Some(0.0), None];
    }
    [Some(q / a), Some(c / q)]
}
