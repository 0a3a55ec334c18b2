//! stfit-validate: statistical validation of samplers of directions on the unit sphere, for
//! anyone who writes an NDF, a visible-normal sampler or a BSDF (as Mitsuba 3 ships `mi.chi2`).
//! stfit's own samplers are checked with it.
//!
//! The workflow for a sampler with claimed density `p(w)` (per unit solid angle):
//!
//! 1. Build bins with [`SphereBins`]: 2D cells in `(cos theta, phi)` measured in a frame around
//!    an axis. [`SphereBins::equal_mass`] places the edges at quantiles of the claimed density
//!    (computed from the density alone, never from the samples), so sharp lobes get
//!    resolution and every cell expects about the same count.
//! 2. Call [`chi_square`] with the samples and the density: it histograms the samples,
//!    integrates the density over every cell ([`SphereBins::integrate`]), pools cells whose
//!    expected count is below 5 and returns a [`ChiSquare`] with Pearson's statistic and its
//!    p-value. Compare `p_value` with a significance corrected for the number of cases
//!    ([`bonferroni`]); the `Display` of [`ChiSquare`] is a ready failure message.
//!
//! Cell integrals use tanh-sinh quadrature in theta (exact to rounding for integrable endpoint
//! singularities and steps at cell edges, such as a heavy-tailed NDF at the horizon when the
//! axis is +z: [`SphereBins::equal_mass`] always puts an edge at the frame's equator) and
//! composite Gauss-Legendre in phi. Inside a cell the density must be continuous (kinks such
//! as `max(0, w.wm)` are fine). The relative integration error per cell is then far below the
//! `1/sqrt(expected count)` resolution of the test.
//!
//! [`integrate_sphere`] integrates a density over the whole sphere (normalisation checks).
//!
//! Densities with a kink or a step along great circles (a visible-normal density has both:
//! `max(0, w.wm)` and the horizon) should declare them as `cuts` (the circles' normals); the
//! quadrature then splits there, which keeps it fast and accurate.
//!
//! ```
//! use rand::SeedableRng;
//! use stfit_core::Vec3;
//! use stfit_core::math::spherical_direction;
//! use stfit_core::ndf::{Ggx, Ndf};
//! use stfit_validate::{SphereBins, bonferroni, chi_square, integrate_sphere};
//!
//! let ndf = Ggx::new(0.3).unwrap();
//! let w = spherical_direction(1.0, 0.2);
//! let density = |wm: Vec3| ndf.d_visible(w, wm);
//! let cuts = [w, Vec3::z()];
//! assert!((integrate_sphere(Vec3::z(), density, &cuts) - 1.0).abs() < 1e-9);
//!
//! let mut rng = rand_pcg::Pcg64::seed_from_u64(1);
//! let samples: Vec<Vec3> = (0..20_000).map(|_| ndf.sample_visible(w, &mut rng)).collect();
//! let bins = SphereBins::equal_mass(Vec3::z(), 12, 12, density);
//! let result = chi_square(&bins, &samples, density, &cuts);
//! assert!(result.passes(bonferroni(0.01, 1)), "{result}");
//! ```

use rayon::prelude::*;
use statrs::function::gamma::gamma_ur;
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt;
use stfit_core::Vec3;
use stfit_core::math::Frame;
use stfit_core::quadrature::GaussLegendre;

/// Expected counts below this are pooled before the Pearson statistic is formed.
pub const MIN_EXPECTED: f64 = 5.0;

/// Bins of the unit sphere: strips in `cos theta` (theta measured from a frame's axis), each
/// split into cells in `phi` (measured from the frame's first tangent `s`, in `[0, 2 pi)`).
#[derive(Debug, Clone)]
pub struct SphereBins {
    frame: Frame,
    /// Increasing strip edges in `cos theta`, from -1 to 1.
    cos_edges: Vec<f64>,
    /// Per strip, increasing edges in `phi` from 0 to `2 pi`.
    phi_edges: Vec<Vec<f64>>,
    /// Index of the first cell of each strip (and the total cell count at the end).
    offsets: Vec<usize>,
}

impl SphereBins {
    /// `n_cos` strips of equal width in `cos theta` over `[-1, 1]`, each split into `n_phi`
    /// equal cells, in a frame around the unit vector `axis`.
    pub fn uniform(axis: Vec3, n_cos: usize, n_phi: usize) -> Self {
        let n_cos = n_cos.max(1);
        let n_phi = n_phi.max(1);
        let cos_edges = (0..=n_cos)
            .map(|i| -1.0 + 2.0 * i as f64 / n_cos as f64)
            .collect();
        let phi = (0..=n_phi)
            .map(|j| 2.0 * PI * j as f64 / n_phi as f64)
            .collect::<Vec<_>>();
        Self::from_edges(axis, cos_edges, vec![phi; n_cos])
    }

    /// Bins from explicit edges: `cos_edges` increasing from -1 to 1; `phi_edges[i]`
    /// increasing from 0 to `2 pi` for strip `i`. Panics if the edges are malformed (a
    /// programming error in a test, not a run-time input).
    pub fn from_edges(axis: Vec3, cos_edges: Vec<f64>, phi_edges: Vec<Vec<f64>>) -> Self {
        assert!(cos_edges.len() >= 2 && phi_edges.len() == cos_edges.len() - 1);
        assert!(cos_edges[0] == -1.0 && *cos_edges.last().unwrap() == 1.0);
        assert!(cos_edges.windows(2).all(|e| e[0] < e[1]));
        for p in &phi_edges {
            assert!(p.len() >= 2 && p[0] == 0.0 && *p.last().unwrap() == 2.0 * PI);
            assert!(p.windows(2).all(|e| e[0] < e[1]));
        }
        let mut offsets = Vec::with_capacity(phi_edges.len() + 1);
        let mut total = 0;
        for p in &phi_edges {
            offsets.push(total);
            total += p.len() - 1;
        }
        offsets.push(total);
        Self {
            frame: Frame::from_normal(axis.normalize()),
            cos_edges,
            phi_edges,
            offsets,
        }
    }

    /// Bins adapted to `density` (per unit solid angle, on the whole sphere): about `n_cos`
    /// strips of equal probability in `cos theta` around `axis`, each cut into about `n_phi`
    /// cells of equal probability in `phi`, plus an edge at the frame's equator
    /// (`cos theta = 0`). With `axis = +z` that edge is the horizon, where microfacet densities
    /// have their steps and singularities. Edges depend on the density only, so a chi-square
    /// test on these bins is valid; quantiles come from a coarse quadrature and need not be
    /// exact.
    pub fn equal_mass(
        axis: Vec3,
        n_cos: usize,
        n_phi: usize,
        density: impl Fn(Vec3) -> f64 + Sync,
    ) -> Self {
        let frame = Frame::from_normal(axis.normalize());
        let n_cos = n_cos.max(1);
        let n_phi = n_phi.max(1);
        // Marginal in theta on a fine uniform grid (midpoint in theta, trapezoid in phi).
        const NT: usize = 2048;
        const NP: usize = 128;
        let dt = PI / NT as f64;
        let strip_mass: Vec<f64> = (0..NT)
            .into_par_iter()
            .map(|i| {
                let theta = (i as f64 + 0.5) * dt;
                let (st, ct) = theta.sin_cos();
                let ring: f64 = (0..NP)
                    .map(|j| {
                        let phi = 2.0 * PI * (j as f64 + 0.5) / NP as f64;
                        let (sp, cp) = phi.sin_cos();
                        density(frame.to_world(Vec3::new(st * cp, st * sp, ct))).max(0.0)
                    })
                    .sum();
                ring * st * dt * 2.0 * PI / NP as f64
            })
            .collect();
        // Theta edges at quantiles, then cos edges (increasing), with the equator added.
        let theta_edges = quantile_edges(&strip_mass, 0.0, PI, n_cos);
        let mut cos_edges: Vec<f64> = theta_edges.iter().rev().map(|t| t.cos()).collect();
        cos_edges[0] = -1.0;
        *cos_edges.last_mut().unwrap() = 1.0;
        cos_edges.push(0.0);
        cos_edges.sort_by(f64::total_cmp);
        cos_edges.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        if cos_edges.len() < 2 || cos_edges[0] != -1.0 {
            cos_edges = vec![-1.0, 0.0, 1.0];
        }
        // Phi edges per strip at quantiles of the strip's phi marginal.
        const MP: usize = 512;
        const MT: usize = 8;
        let phi_edges = cos_edges
            .par_windows(2)
            .map(|e| {
                let (t0, t1) = (e[1].acos(), e[0].acos());
                let mass: Vec<f64> = (0..MP)
                    .map(|j| {
                        let phi = 2.0 * PI * (j as f64 + 0.5) / MP as f64;
                        let (sp, cp) = phi.sin_cos();
                        (0..MT)
                            .map(|k| {
                                let theta = t0 + (t1 - t0) * (k as f64 + 0.5) / MT as f64;
                                let (st, ct) = theta.sin_cos();
                                st * density(frame.to_world(Vec3::new(st * cp, st * sp, ct)))
                                    .max(0.0)
                            })
                            .sum::<f64>()
                    })
                    .collect();
                let mut p = quantile_edges(&mass, 0.0, 2.0 * PI, n_phi);
                p.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
                p[0] = 0.0;
                *p.last_mut().unwrap() = 2.0 * PI;
                if p.len() < 2 {
                    p = vec![0.0, 2.0 * PI];
                }
                p
            })
            .collect();
        Self::from_edges(frame.n, cos_edges, phi_edges)
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        *self.offsets.last().unwrap()
    }

    /// True if there are no cells (never the case for bins built by the constructors).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The frame whose third axis the bins' theta is measured from.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// `(cos theta range, phi range)` of cell `index`, in the bins' frame.
    pub fn cell_bounds(&self, index: usize) -> ((f64, f64), (f64, f64)) {
        let strip = self.offsets.partition_point(|&o| o <= index) - 1;
        let j = index - self.offsets[strip];
        let p = &self.phi_edges[strip];
        (
            (self.cos_edges[strip], self.cos_edges[strip + 1]),
            (p[j], p[j + 1]),
        )
    }

    /// The cell containing the unit vector `w`, or `None` if `w` is not finite.
    pub fn cell_of(&self, w: Vec3) -> Option<usize> {
        let l = self.frame.to_local(w);
        if !(l.x.is_finite() && l.y.is_finite() && l.z.is_finite()) {
            return None;
        }
        let c = l.z.clamp(-1.0, 1.0);
        let n_strips = self.phi_edges.len();
        let strip = (self.cos_edges.partition_point(|&e| e <= c)).clamp(1, n_strips) - 1;
        let mut phi = l.y.atan2(l.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let p = &self.phi_edges[strip];
        let j = p.partition_point(|&e| e <= phi).clamp(1, p.len() - 1) - 1;
        Some(self.offsets[strip] + j)
    }

    /// Counts of `samples` per cell; also returns the number of non-finite samples (which
    /// fall in no cell).
    pub fn histogram(&self, samples: impl IntoIterator<Item = Vec3>) -> (Vec<f64>, usize) {
        let mut counts = vec![0.0; self.len()];
        let mut bad = 0;
        for w in samples {
            match self.cell_of(w) {
                Some(i) => counts[i] += 1.0,
                None => bad += 1,
            }
        }
        (counts, bad)
    }

    /// Integral of `density` (per unit solid angle) over every cell, in cell order.
    ///
    /// `cuts` lists normals `n` of great circles `{v : v.n = 0}` across which the density may
    /// have a kink or a step (for a visible-normal density: `w` for the `max(0, w.wm)` factor
    /// and `+z` for the horizon). The quadrature splits at them, which makes it both fast and
    /// accurate; without them a kink crossing a cell costs many adaptive subdivisions.
    /// At most four cuts are used. Adaptive tanh-sinh in theta, adaptive 8-point
    /// Gauss-Legendre in phi; cells in parallel.
    pub fn integrate(&self, density: impl Fn(Vec3) -> f64 + Sync, cuts: &[Vec3]) -> Vec<f64> {
        let ts = tanh_sinh_rule();
        let cuts: Vec<Vec3> = cuts.iter().map(|n| self.frame.to_local(*n)).collect();
        (0..self.len())
            .into_par_iter()
            .map(|i| {
                let ((c0, c1), (p0, p1)) = self.cell_bounds(i);
                integrate_cell(&self.frame, c0, c1, p0, p1, &cuts, &ts, &density)
            })
            .collect()
    }
}

/// Edges (`n + 1` of them, increasing from `lo` to `hi`) at the quantiles of a histogram
/// `mass` of equal-width cells over `[lo, hi]`, interpolated linearly within a cell. Falls back
/// to uniform edges for a histogram without mass.
fn quantile_edges(mass: &[f64], lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let total: f64 = mass.iter().sum();
    let width = (hi - lo) / mass.len() as f64;
    if total.is_nan() || total <= 0.0 {
        return (0..=n)
            .map(|i| lo + (hi - lo) * i as f64 / n as f64)
            .collect();
    }
    let mut edges = vec![lo];
    let mut acc = 0.0;
    let mut k = 1;
    for (i, &m) in mass.iter().enumerate() {
        while k < n && acc + m >= total * k as f64 / n as f64 {
            let target = total * k as f64 / n as f64;
            let frac = if m > 0.0 { (target - acc) / m } else { 0.0 };
            edges.push(lo + (i as f64 + frac.clamp(0.0, 1.0)) * width);
            k += 1;
        }
        acc += m;
    }
    edges.push(hi);
    edges.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    edges
}

/// A quadrature rule on `(0, 1)`: nodes as `(t, 1 - t)` (so nodes near 1 keep their
/// distance to the endpoint) and weights.
struct Rule {
    nodes: Vec<(f64, f64)>,
    weights: Vec<f64>,
    /// The 8-point Gauss-Legendre rule of the phi integrals.
    gl: GaussLegendre,
}

/// Tanh-sinh (double exponential) rule on `(0, 1)`, step `h = 1/4`, with nodes out to the
/// smallest representable distances from the ends (about 1e-300), not truncated by weight:
/// a singularity like `d^-0.8` at an end keeps mass at distances far below 1e-18.
fn tanh_sinh_rule() -> Rule {
    let h = 0.25;
    let mut nodes = Vec::new();
    let mut weights = Vec::new();
    for k in -40i32..=40 {
        let x = k as f64 * h;
        let u = FRAC_PI_2 * x.sinh();
        // t = (1 + tanh u) / 2 and 1 - t, both without cancellation.
        let t = 1.0 / (1.0 + (-2.0 * u).exp());
        let one_minus_t = 1.0 / (1.0 + (2.0 * u).exp());
        let w = 0.5 * h * FRAC_PI_2 * x.cosh() / (u.cosh() * u.cosh());
        if t < 1e-300 || one_minus_t < 1e-300 || !(w > 0.0 && w.is_finite()) {
            continue;
        }
        nodes.push((t, one_minus_t));
        weights.push(w);
    }
    Rule {
        nodes,
        weights,
        gl: GaussLegendre::new(8),
    }
}

/// Relative and absolute (probability) tolerances of the adaptive cell quadrature, and the
/// bisection depth limit.
const REL_TOL: f64 = 1e-9;
const ABS_TOL: f64 = 1e-13;
const MAX_DEPTH: u32 = 12;

/// Adaptive Gauss-Legendre: the rule on `(a, b)` against the sum over its halves, bisecting
/// until they agree; `whole` is the rule's estimate on `(a, b)`.
fn adaptive_gl(
    gl: &GaussLegendre,
    f: &impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    whole: f64,
    abs: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let left = gl.integrate(a, m, f);
    let right = gl.integrate(m, b, f);
    let sum = left + right;
    if depth == 0 || (sum - whole).abs() <= (REL_TOL * sum.abs()).max(abs) {
        return sum;
    }
    adaptive_gl(gl, f, a, m, left, 0.5 * abs, depth - 1)
        + adaptive_gl(gl, f, m, b, right, 0.5 * abs, depth - 1)
}

/// Tanh-sinh on the sub-interval `(x0, x1)` of `(0, len)`; `g(d, from_end)` evaluates the
/// integrand at distance `d` from the start (or, if `from_end`, from the end) of `(0, len)`.
fn ts_on(ts: &Rule, g: &impl Fn(f64, bool) -> f64, x0: f64, x1: f64, len: f64) -> f64 {
    let h = x1 - x0;
    let mut sum = 0.0;
    for (&(t, omt), &w) in ts.nodes.iter().zip(&ts.weights) {
        let from_start = x0 + h * t;
        let from_end = (len - x1) + h * omt;
        let v = if from_start <= from_end {
            g(from_start, false)
        } else {
            g(from_end, true)
        };
        sum += w * v;
    }
    sum * h
}

/// Adaptive tanh-sinh: bisects `(x0, x1)` until the rule on it agrees with the sum over its
/// halves; keeps tanh-sinh's resolution of singularities at the ends of `(0, len)`.
#[allow(clippy::too_many_arguments)]
fn adaptive_ts(
    ts: &Rule,
    g: &impl Fn(f64, bool) -> f64,
    x0: f64,
    x1: f64,
    len: f64,
    whole: f64,
    abs: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (x0 + x1);
    let left = ts_on(ts, g, x0, m, len);
    let right = ts_on(ts, g, m, x1, len);
    let sum = left + right;
    if depth == 0 || (sum - whole).abs() <= (REL_TOL * sum.abs()).max(abs) {
        return sum;
    }
    adaptive_ts(ts, g, x0, m, len, left, 0.5 * abs, depth - 1)
        + adaptive_ts(ts, g, m, x1, len, right, 0.5 * abs, depth - 1)
}

/// `(cos, sin)` of a polar angle given by its cosine.
#[inline]
fn cs(c: f64) -> (f64, f64) {
    (c, (1.0 - c * c).max(0.0).sqrt())
}

/// Integral over the cell `cos theta in (c_lo, c_hi)`, `phi in (p0, p1)` of a frame (cuts
/// given in that frame's local coordinates): splits theta at the rings tangent to each cut
/// circle and phi at the ring's crossings with the cut circles, then integrates the pieces.
#[allow(clippy::too_many_arguments)]
fn integrate_cell(
    frame: &Frame,
    c_lo: f64,
    c_hi: f64,
    p0: f64,
    p1: f64,
    cuts: &[Vec3],
    ts: &Rule,
    f: &(impl Fn(Vec3) -> f64 + ?Sized),
) -> f64 {
    // Theta break points as (cos, sin), from the top edge (largest cos) down.
    let mut breaks = vec![cs(c_hi)];
    for n in cuts {
        let rho = n.x.hypot(n.y);
        let r = rho.hypot(n.z);
        if r == 0.0 {
            continue;
        }
        // Rings tangent to the cut circle: cos theta = +-rho / r.
        for c in [rho / r, -rho / r] {
            if c < c_hi && c > c_lo {
                breaks.push((c, n.z.abs() / r));
            }
        }
    }
    breaks.push(cs(c_lo));
    breaks.sort_by(|a, b| b.0.total_cmp(&a.0));
    breaks
        .windows(2)
        .map(|e| integrate_patch(frame, e[0], e[1], p0, p1, cuts, ts, f))
        .sum()
}

/// Integral of `f` over the patch between the polar angles with `(cos, sin)` `top` and `bottom`
/// (top has the smaller angle), `phi in (p0, p1)`, with the solid-angle element
/// `sin theta dtheta dphi`: adaptive tanh-sinh in theta around adaptive Gauss-Legendre in phi,
/// split at the cut circles. Theta nodes are placed relative to the nearer patch edge with
/// exact edge cosines, so a singularity on an edge such as the equator (`cos theta = 0`
/// exactly) is resolved down to the smallest positive doubles.
#[allow(clippy::too_many_arguments)]
fn integrate_patch(
    frame: &Frame,
    top: (f64, f64),
    bottom: (f64, f64),
    p0: f64,
    p1: f64,
    cuts: &[Vec3],
    ts: &Rule,
    f: &(impl Fn(Vec3) -> f64 + ?Sized),
) -> f64 {
    let (ca, sa) = top;
    let (cb, sb) = bottom;
    let len = sb.atan2(cb) - sa.atan2(ca);
    if !(len > 0.0 && p1 > p0) {
        return 0.0;
    }
    let ring = |d: f64, from_end: bool| {
        let (sd, cd) = d.sin_cos();
        let (ct, st) = if from_end {
            (cb * cd + sb * sd, sb * cd - cb * sd)
        } else {
            (ca * cd - sa * sd, sa * cd + ca * sd)
        };
        let st = st.max(0.0);
        let fp = |phi: f64| {
            let (sp, cp) = phi.sin_cos();
            f(frame.to_world(Vec3::new(st * cp, st * sp, ct)))
        };
        // Break points in phi: crossings of this ring with the cut circles.
        let mut pb = [0.0; 10];
        let mut npb = 0;
        pb[npb] = p0;
        npb += 1;
        // At most four cut circles cross a ring (documented on the public functions).
        for n in cuts.iter().take(4) {
            let rho = n.x.hypot(n.y);
            if rho * st == 0.0 {
                continue;
            }
            let q = -ct * n.z / (rho * st);
            if q.abs() < 1.0 {
                let base = n.y.atan2(n.x);
                let d = q.acos();
                for phi in [base + d, base - d] {
                    let phi = phi.rem_euclid(2.0 * PI);
                    if phi > p0 && phi < p1 {
                        pb[npb] = phi;
                        npb += 1;
                    }
                }
            }
        }
        pb[npb] = p1;
        npb += 1;
        let pb = &mut pb[..npb];
        pb.sort_by(f64::total_cmp);
        let total: f64 = pb
            .windows(2)
            .map(|e| {
                let whole = ts.gl.integrate(e[0], e[1], &fp);
                adaptive_gl(&ts.gl, &fp, e[0], e[1], whole, ABS_TOL, MAX_DEPTH)
            })
            .sum();
        st * total
    };
    let whole = ts_on(ts, &ring, 0.0, len, len);
    adaptive_ts(ts, &ring, 0.0, len, len, whole, ABS_TOL, MAX_DEPTH)
}

/// Integral of `density` (per unit solid angle) over the whole sphere, for normalisation
/// checks. Theta (around `axis`) is split at the frame's equator and into 24 panels per
/// hemisphere, and further at the `cuts` (normals of great circles where the density has a
/// kink or step, see [`SphereBins::integrate`]); each piece is integrated by adaptive tanh-sinh,
/// phi by adaptive Gauss-Legendre. Steps and integrable singularities are best placed on the
/// frame's equator (use `axis = +z` for microfacet NDFs, whose horizon is there).
pub fn integrate_sphere(axis: Vec3, density: impl Fn(Vec3) -> f64 + Sync, cuts: &[Vec3]) -> f64 {
    let frame = Frame::from_normal(axis.normalize());
    let ts = tanh_sinh_rule();
    let cuts: Vec<Vec3> = cuts.iter().map(|n| frame.to_local(*n)).collect();
    const PANELS: usize = 24;
    // Panel edges uniform in theta, as exact cosines (0 at the equator, +-1 at the poles).
    let cos_edges: Vec<f64> = (0..=2 * PANELS)
        .map(|i| match i {
            0 => -1.0,
            PANELS => 0.0,
            _ if i == 2 * PANELS => 1.0,
            _ => -(PI * i as f64 / (2 * PANELS) as f64).cos(),
        })
        .collect();
    cos_edges
        .par_windows(2)
        .map(|e| integrate_cell(&frame, e[0], e[1], 0.0, 2.0 * PI, &cuts, &ts, &density))
        .sum()
}

/// The per-case significance for `n_cases` tests sharing an overall significance `alpha`.
pub fn bonferroni(alpha: f64, n_cases: usize) -> f64 {
    alpha / n_cases.max(1) as f64
}

/// One cell of a chi-square test, for failure reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellReport {
    /// Index in [`SphereBins`] order (of the first cell, for a pooled group).
    pub index: usize,
    /// Observed count.
    pub observed: f64,
    /// Expected count.
    pub expected: f64,
    /// `(observed - expected)^2 / expected`.
    pub contribution: f64,
}

/// The outcome of a Pearson chi-square goodness-of-fit test.
#[derive(Debug, Clone, PartialEq)]
pub struct ChiSquare {
    /// Pearson's statistic over the pooled cells.
    pub statistic: f64,
    /// Degrees of freedom: pooled cells minus one.
    pub dof: usize,
    /// Probability of a statistic at least this large if the samples follow the density.
    /// Zero if samples fell where the density integrates to zero, or were not finite.
    pub p_value: f64,
    /// Number of samples (finite or not).
    pub samples: usize,
    /// Samples that were not finite vectors.
    pub non_finite: usize,
    /// Samples in cells whose integrated density is zero.
    pub in_empty_cells: f64,
    /// Cells before pooling.
    pub cells: usize,
    /// Cells pooled into one group because their expected count was below [`MIN_EXPECTED`].
    pub pooled: usize,
    /// Sum of the expected counts divided by the sample count: the density's integral over
    /// the sphere, 1 for a normalised density.
    pub expected_total: f64,
    /// The largest contributions to the statistic, largest first (up to 5).
    pub worst: Vec<CellReport>,
}

impl ChiSquare {
    /// True if the test does not reject at `significance` (for example
    /// `bonferroni(0.01, n_cases)`).
    pub fn passes(&self, significance: f64) -> bool {
        self.p_value >= significance
    }
}

impl fmt::Display for ChiSquare {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "chi2 = {:.2} with {} dof, p = {:.3e}; {} samples in {} cells ({} pooled), \
             density integral {:.6}",
            self.statistic,
            self.dof,
            self.p_value,
            self.samples,
            self.cells,
            self.pooled,
            self.expected_total
        )?;
        if self.non_finite > 0 {
            write!(f, "; {} non-finite samples", self.non_finite)?;
        }
        if self.in_empty_cells > 0.0 {
            write!(
                f,
                "; {} samples where the density is zero",
                self.in_empty_cells
            )?;
        }
        for c in &self.worst {
            write!(
                f,
                "\n  cell {}: observed {}, expected {:.2}, contributes {:.2}",
                c.index, c.observed, c.expected, c.contribution
            )?;
        }
        Ok(())
    }
}

/// Pearson's chi-square test of observed counts against expected counts (same order and
/// length). Cells with expected count below [`MIN_EXPECTED`] are pooled into one group (merged
/// with the smallest remaining cell if the group itself stays below it). Observed counts in
/// cells with zero expectation make the p-value 0.
pub fn pearson(observed: &[f64], expected: &[f64]) -> ChiSquare {
    assert_eq!(observed.len(), expected.len());
    let n: f64 = observed.iter().sum();
    let expected_total = expected.iter().sum::<f64>() / n.max(1.0);
    let in_empty_cells: f64 = observed
        .iter()
        .zip(expected)
        .filter(|&(_, &e)| e.is_nan() || e <= 0.0)
        .map(|(&o, _)| o)
        .sum();
    // Pool small cells.
    let mut groups: Vec<(usize, f64, f64)> = Vec::new();
    let mut pool = (usize::MAX, 0.0, 0.0);
    let mut pooled = 0;
    for (i, (&o, &e)) in observed.iter().zip(expected).enumerate() {
        let e = e.max(0.0);
        if e < MIN_EXPECTED {
            pool = (pool.0.min(i), pool.1 + o, pool.2 + e);
            pooled += 1;
        } else {
            groups.push((i, o, e));
        }
    }
    if pooled > 0 {
        if pool.2 >= MIN_EXPECTED || groups.is_empty() {
            groups.push(pool);
        } else {
            let k = (0..groups.len())
                .min_by(|&a, &b| groups[a].2.total_cmp(&groups[b].2))
                .unwrap();
            groups[k].1 += pool.1;
            groups[k].2 += pool.2;
        }
    }
    let mut worst: Vec<CellReport> = groups
        .iter()
        .filter(|g| g.2 > 0.0)
        .map(|&(index, observed, expected)| CellReport {
            index,
            observed,
            expected,
            contribution: (observed - expected).powi(2) / expected,
        })
        .collect();
    let statistic: f64 = worst.iter().map(|c| c.contribution).sum();
    worst.sort_by(|a, b| b.contribution.total_cmp(&a.contribution));
    worst.truncate(5);
    let dof = groups.len().saturating_sub(1);
    let p_value = if in_empty_cells > 0.0 || !statistic.is_finite() {
        0.0
    } else if dof == 0 {
        1.0
    } else {
        gamma_ur(0.5 * dof as f64, 0.5 * statistic)
    };
    ChiSquare {
        statistic,
        dof,
        p_value,
        samples: n as usize,
        non_finite: 0,
        in_empty_cells,
        cells: observed.len(),
        pooled,
        expected_total,
        worst,
    }
}

/// Chi-square goodness of fit of `samples` against `density` (per unit solid angle,
/// normalised to 1 over the sphere) on `bins`; `cuts` as in [`SphereBins::integrate`].
/// Non-finite samples make the p-value 0.
pub fn chi_square(
    bins: &SphereBins,
    samples: &[Vec3],
    density: impl Fn(Vec3) -> f64 + Sync,
    cuts: &[Vec3],
) -> ChiSquare {
    let (observed, non_finite) = bins.histogram(samples.iter().copied());
    let n = samples.len() as f64;
    let expected: Vec<f64> = bins
        .integrate(density, cuts)
        .iter()
        .map(|p| p * n)
        .collect();
    let mut r = pearson(&observed, &expected);
    r.samples = samples.len();
    r.non_finite = non_finite;
    if non_finite > 0 {
        r.p_value = 0.0;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;
    use stfit_core::math::spherical_direction;

    const INV_4PI: f64 = 1.0 / (4.0 * PI);

    fn uniform_sphere(rng: &mut Pcg64) -> Vec3 {
        let z: f64 = 1.0 - 2.0 * rng.random::<f64>();
        let phi = 2.0 * PI * rng.random::<f64>();
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// A von Mises-Fisher lobe of concentration `kappa` around `mu` (exact sampler).
    fn vmf(mu: Vec3, kappa: f64, rng: &mut Pcg64) -> Vec3 {
        let u: f64 = rng.random();
        let c = 1.0 + (u + (1.0 - u) * (-2.0 * kappa).exp()).ln() / kappa;
        let phi = 2.0 * PI * rng.random::<f64>();
        let s = (1.0 - c * c).max(0.0).sqrt();
        Frame::from_normal(mu).to_world(Vec3::new(s * phi.cos(), s * phi.sin(), c))
    }

    fn vmf_pdf(mu: Vec3, kappa: f64) -> impl Fn(Vec3) -> f64 + Sync {
        let norm = kappa / (2.0 * PI * (1.0 - (-2.0 * kappa).exp()));
        move |w: Vec3| norm * (kappa * (w.dot(&mu) - 1.0)).exp()
    }

    #[test]
    fn integrate_sphere_matches_known_integrals() {
        let z = Vec3::z();
        assert!((integrate_sphere(z, |_| INV_4PI, &[]) - 1.0).abs() < 1e-12);
        // A sharp off-axis lobe.
        let mu = spherical_direction(1.1, 0.4);
        let i = integrate_sphere(z, vmf_pdf(mu, 2000.0), &[]);
        assert!((i - 1.0).abs() < 1e-8, "{i}");
        // An integrable singularity on the equator: |cos|^(-0.8) / (2 pi * 2 * 5).
        let i = integrate_sphere(z, |w| w.z.abs().powf(-0.8) / (20.0 * PI), &[]);
        assert!((i - 1.0).abs() < 1e-5, "{i}");
        // A step at the equator.
        let i = integrate_sphere(z, |w| if w.z > 0.0 { 1.0 / (2.0 * PI) } else { 0.0 }, &[]);
        assert!((i - 1.0).abs() < 1e-12, "{i}");
        // A clamped cosine lobe around an oblique axis, cut by the horizon: the kink and the
        // step are declared as cuts.
        let v = spherical_direction(1.2, 0.3);
        let lobe = |w: Vec3| if w.z > 0.0 { w.dot(&v).max(0.0) } else { 0.0 };
        let i = integrate_sphere(z, lobe, &[v, z]);
        // Exact: integral over the upper hemisphere of max(0, w.v), by an independent
        // fine quadrature in the frame of v (where the kink is the equator).
        let j = integrate_sphere(
            v,
            |w| if w.z > 0.0 { w.dot(&v).max(0.0) } else { 0.0 },
            &[z],
        );
        assert!((i - j).abs() < 1e-10 * j, "{i} vs {j}");
        assert!((integrate_sphere(z, |w| w.dot(&v).max(0.0) / PI, &[v]) - 1.0).abs() < 1e-10);
    }

    #[test]
    fn cell_integrals_sum_to_one_and_match_areas() {
        let bins = SphereBins::uniform(spherical_direction(0.3, 1.0), 7, 5);
        let p = bins.integrate(|_| INV_4PI, &[]);
        assert_eq!(p.len(), 35);
        for &pi in &p {
            assert!((pi - 1.0 / 35.0).abs() < 1e-13, "{pi}");
        }
        let mu = spherical_direction(0.8, 2.0);
        let bins = SphereBins::equal_mass(Vec3::z(), 12, 12, vmf_pdf(mu, 500.0));
        let total: f64 = bins.integrate(vmf_pdf(mu, 500.0), &[]).iter().sum();
        assert!((total - 1.0).abs() < 1e-9, "{total}");
    }

    #[test]
    fn cells_are_found_consistently() {
        let bins = SphereBins::equal_mass(Vec3::z(), 10, 9, vmf_pdf(Vec3::x(), 30.0));
        let mut rng = Pcg64::seed_from_u64(3);
        for _ in 0..1000 {
            let w = uniform_sphere(&mut rng);
            let i = bins.cell_of(w).unwrap();
            let ((c0, c1), (p0, p1)) = bins.cell_bounds(i);
            let l = bins.frame().to_local(w);
            let phi = l.y.atan2(l.x).rem_euclid(2.0 * PI);
            assert!(c0 <= l.z && l.z <= c1 && p0 <= phi && phi <= p1);
        }
        assert_eq!(bins.cell_of(Vec3::new(f64::NAN, 0.0, 1.0)), None);
    }

    #[test]
    fn exact_samplers_pass() {
        let mut rng = Pcg64::seed_from_u64(1);
        let samples: Vec<Vec3> = (0..100_000).map(|_| uniform_sphere(&mut rng)).collect();
        let bins = SphereBins::uniform(Vec3::z(), 20, 20);
        let r = chi_square(&bins, &samples, |_| INV_4PI, &[]);
        assert!(r.passes(1e-3), "{r}");
        assert!((r.expected_total - 1.0).abs() < 1e-12);

        let mu = spherical_direction(1.4, -0.5);
        let samples: Vec<Vec3> = (0..100_000).map(|_| vmf(mu, 5000.0, &mut rng)).collect();
        let bins = SphereBins::equal_mass(Vec3::z(), 20, 20, vmf_pdf(mu, 5000.0));
        let r = chi_square(&bins, &samples, vmf_pdf(mu, 5000.0), &[]);
        assert!(r.passes(1e-3), "{r}");
    }

    #[test]
    fn wrong_samplers_fail() {
        let mut rng = Pcg64::seed_from_u64(2);
        // Uniform in z over the sphere's area is right; uniform in theta is not.
        let samples: Vec<Vec3> = (0..100_000)
            .map(|_| spherical_direction(PI * rng.random::<f64>(), 2.0 * PI * rng.random::<f64>()))
            .collect();
        let bins = SphereBins::uniform(Vec3::z(), 20, 20);
        let r = chi_square(&bins, &samples, |_| INV_4PI, &[]);
        assert!(r.p_value < 1e-12, "{r}");

        // A lobe 5% too wide.
        let mu = spherical_direction(0.9, 0.5);
        let samples: Vec<Vec3> = (0..100_000).map(|_| vmf(mu, 900.0, &mut rng)).collect();
        let pdf = vmf_pdf(mu, 1000.0);
        let bins = SphereBins::equal_mass(Vec3::z(), 20, 20, &pdf);
        let r = chi_square(&bins, &samples, &pdf, &[]);
        assert!(r.p_value < 1e-6, "{r}");

        // Samples where the density is zero.
        let r = chi_square(
            &SphereBins::uniform(Vec3::z(), 10, 10),
            &[Vec3::z(), -Vec3::z()],
            |w| if w.z > 0.0 { 1.0 / (2.0 * PI) } else { 0.0 },
            &[],
        );
        assert_eq!(r.p_value, 0.0);
        assert!(r.to_string().contains("density is zero"), "{r}");
    }

    #[test]
    fn pearson_pools_small_cells() {
        let r = pearson(&[10.0, 1.0, 2.0, 0.0, 9.0], &[10.0, 1.0, 1.5, 0.5, 10.0]);
        assert_eq!(r.pooled, 3);
        assert_eq!(r.dof, 1);
        // Cells 1-3 pool to (3, 3), too small, so they join cell 0: (13, 13); cell 4 gives 0.1.
        assert!((r.statistic - 0.1).abs() < 1e-12, "{r}");
    }
}
