//! Shared helpers of the BSDF tests: test directions, quadrature over the sphere and a
//! chi-square test of a direction sampler that may fail, built on `stfit_validate`.

#![allow(dead_code)]

use std::f64::consts::PI;
use stfit_core::Vec3;
use stfit_core::math::{radians, spherical_direction};
use stfit_validate::{self as validate, ChiSquare, SphereBins};

/// A unit direction at polar angle `theta_deg` from +z (values above 90 point below the
/// surface) at a fixed, generic azimuth.
pub fn dir_deg(theta_deg: f64) -> Vec3 {
    spherical_direction(radians(theta_deg), 0.7)
}

/// Pearson chi-square test of `n` draws of `sample` (each `None` when the draw fails) against
/// the density `pdf` (solid angle), on `n_cos` x `n_phi` equal-mass bins around +z
/// ([`SphereBins::equal_mass`]) with extra strip edges at the latitudes `cos_cuts`, plus one
/// cell for failed draws, whose expected probability is `1 - integral pdf`. The density need
/// not integrate to 1: its integral is the probability that a draw succeeds.
///
/// `cos_cuts` are latitudes where the density may be singular (integrably) or jump; cells are
/// integrated by [`integrate_patch`], not `SphereBins::integrate`, which needs a density
/// continuous inside each cell. A rough dielectric's transmission pdf jumps where the facet it
/// needs reaches the horizon, the latitude `wo.z = -(n_i / n_o) wi.z`, and is singular there
/// for Student-T with gamma < 2 (`D ~ (h.z)^(2 gamma - 4)`).
pub fn chi_square_sampler(
    mut sample: impl FnMut() -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64 + Sync,
    n: usize,
    (n_cos, n_phi): (usize, usize),
    cos_cuts: &[f64],
) -> ChiSquare {
    let bins = with_cuts(
        &SphereBins::equal_mass(Vec3::z(), n_cos, n_phi, &pdf),
        cos_cuts,
    );
    let draws: Vec<Option<Vec3>> = (0..n).map(|_| sample()).collect();
    let failed = draws.iter().filter(|d| d.is_none()).count();
    let (mut observed, non_finite) = bins.histogram(draws.into_iter().flatten());
    let mut expected: Vec<f64> = (0..bins.len())
        .map(|i| {
            let (c, p) = bins.cell_bounds(i);
            n as f64 * integrate_patch(&pdf, c, p, cos_cuts)
        })
        .collect();
    let total: f64 = expected.iter().sum();
    observed.push(failed as f64);
    // Kept positive: a quadrature total a hair above 1 must not turn a few failed draws
    // into "samples where the density is zero"; the cell is then pooled as a small one.
    expected.push((n as f64 - total).max(1e-3));
    let mut test = validate::pearson(&observed, &expected);
    test.non_finite = non_finite;
    if non_finite > 0 {
        test.p_value = 0.0;
    }
    test
}

/// `bins` (around +z) with each strip crossed by a latitude in `cos_cuts` split there, keeping
/// its phi edges.
fn with_cuts(bins: &SphereBins, cos_cuts: &[f64]) -> SphereBins {
    let mut strips: Vec<((f64, f64), Vec<f64>)> = Vec::new();
    for i in 0..bins.len() {
        let (c, p) = bins.cell_bounds(i);
        match strips.last_mut() {
            Some((last, edges)) if *last == c => edges.push(p.1),
            _ => strips.push((c, vec![p.0, p.1])),
        }
    }
    let mut cos_edges = vec![-1.0];
    let mut phi_edges = Vec::new();
    for ((c0, c1), edges) in strips {
        for &cut in cos_cuts {
            if c0 < cut && cut < c1 {
                cos_edges.push(cut);
                phi_edges.push(edges.clone());
            }
        }
        cos_edges.push(c1);
        phi_edges.push(edges);
    }
    let mut order: Vec<usize> = (0..phi_edges.len()).collect();
    order.sort_by(|&a, &b| cos_edges[a + 1].total_cmp(&cos_edges[b + 1]));
    let phi_edges = order.iter().map(|&k| phi_edges[k].clone()).collect();
    cos_edges.sort_by(f64::total_cmp);
    SphereBins::from_edges(Vec3::z(), cos_edges, phi_edges)
}

/// The unit direction with `cos theta = c` and azimuth `phi`.
pub fn dir_cos_phi(c: f64, phi: f64) -> Vec3 {
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), c)
}

/// Integral of `f(w)` over the patch `c0 <= cos theta <= c1`, `p0 <= phi <= p1` (area element
/// `dc dphi`). The patch is first cut into sub-cells at most [`MAX_CELL`] wide in `cos theta`
/// and `phi`; each sub-cell's 3x3 Simpson estimate is compared with the sum over its four
/// quadrants, and quadrants are refined until the two agree to [`TOL`] per unit area or
/// [`DEPTH`] levels are spent. Simpson's nodes include the cell's edges, so a region where the
/// density is non-zero is noticed whenever it touches an edge, however thin its sliver inside
/// the cell: cliffs in the pdfs defeat open rules and fixed grids. A row of sub-cells along an
/// edge listed in `cos_cuts` (a latitude where `f` may have an integrable singularity
/// `|c - cut|^p`, `p > -1`) is integrated in `t` with `c = cut +- L t^8`, which makes the
/// integrand bounded for `p >= -7/8`.
pub fn integrate_patch(
    f: &impl Fn(Vec3) -> f64,
    (c0, c1): (f64, f64),
    (p0, p1): (f64, f64),
    cos_cuts: &[f64],
) -> f64 {
    let nc = ((c1 - c0) / MAX_CELL).ceil().max(1.0) as usize;
    let np = ((p1 - p0) / MAX_CELL).ceil().max(1.0) as usize;
    let (dc, dp) = ((c1 - c0) / nc as f64, (p1 - p0) / np as f64);
    let edge = |k: usize, n: usize, lo: f64, hi: f64, d: f64| {
        if k == n { hi } else { lo + k as f64 * d }
    };
    let mut sum = 0.0;
    for i in 0..nc {
        let (a, b) = (edge(i, nc, c0, c1, dc), edge(i + 1, nc, c0, c1, dc));
        let (sing_a, sing_b) = (cos_cuts.contains(&a), cos_cuts.contains(&b));
        for j in 0..np {
            let p = (edge(j, np, p0, p1, dp), edge(j + 1, np, p0, p1, dp));
            sum += match (sing_a, sing_b) {
                (false, false) => adaptive(&|c, phi| f(dir_cos_phi(c, phi)), (a, b), p),
                (true, false) => clustered(f, a, b - a, p),
                (false, true) => clustered(f, b, a - b, p),
                (true, true) => {
                    let m = 0.5 * (a + b);
                    clustered(f, a, m - a, p) + clustered(f, b, m - b, p)
                }
            };
        }
    }
    sum
}

/// Integral over the row between the latitude `cut` and `cut + len` (`len` of either sign),
/// with `c = cut + len t^8`.
fn clustered(f: &impl Fn(Vec3) -> f64, cut: f64, len: f64, p: (f64, f64)) -> f64 {
    let g = |t: f64, phi: f64| {
        let t7 = t.powi(7);
        8.0 * len.abs() * t7 * f(dir_cos_phi(cut + len * t7 * t, phi))
    };
    adaptive(&g, (0.0, 1.0), p)
}

/// Largest sub-cell, in `cos theta` and in `phi`, of [`integrate_patch`].
const MAX_CELL: f64 = 0.05;

/// Refinement tolerance (per unit area) and depth of the quadratures.
const TOL: f64 = 1e-4;
const DEPTH: u32 = 6;

/// Adaptive 2D Simpson of `g(u, v)` over a rectangle.
fn adaptive(g: &impl Fn(f64, f64) -> f64, u: (f64, f64), v: (f64, f64)) -> f64 {
    let coarse = simpson_3x3(g, u, v);
    refine(g, u, v, coarse, DEPTH)
}

fn simpson_3x3(g: &impl Fn(f64, f64) -> f64, (u0, u1): (f64, f64), (v0, v1): (f64, f64)) -> f64 {
    const X: [f64; 3] = [0.0, 0.5, 1.0];
    const W: [f64; 3] = [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0];
    let (du, dv) = (u1 - u0, v1 - v0);
    let mut sum = 0.0;
    for (xa, wa) in X.iter().zip(W) {
        for (xb, wb) in X.iter().zip(W) {
            sum += wa * wb * g(u0 + xa * du, v0 + xb * dv);
        }
    }
    sum * du * dv
}

fn refine(
    g: &impl Fn(f64, f64) -> f64,
    (u0, u1): (f64, f64),
    (v0, v1): (f64, f64),
    coarse: f64,
    depth: u32,
) -> f64 {
    let (um, vm) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
    let quads = [
        ((u0, um), (v0, vm)),
        ((u0, um), (vm, v1)),
        ((um, u1), (v0, vm)),
        ((um, u1), (vm, v1)),
    ];
    let parts = quads.map(|(u, v)| simpson_3x3(g, u, v));
    let fine: f64 = parts.iter().sum();
    if depth == 0 || (fine - coarse).abs() <= TOL * (u1 - u0) * (v1 - v0) {
        return fine;
    }
    quads
        .iter()
        .zip(parts)
        .map(|(&(u, v), part)| refine(g, u, v, part, depth - 1))
        .sum()
}

/// Integral of `f(w)` over the whole sphere: 32 strips in `cos theta`, also split at the
/// latitudes `cos_cuts`, by 64 in phi, each cell integrated by [`integrate_patch`].
pub fn integrate_sphere(f: impl Fn(Vec3) -> f64, cos_cuts: &[f64]) -> f64 {
    let (n_cos, n_phi) = (32, 64);
    let mut edges: Vec<f64> = (0..=n_cos)
        .map(|i| -1.0 + 2.0 * i as f64 / n_cos as f64)
        .chain(cos_cuts.iter().copied())
        .collect();
    edges.sort_by(f64::total_cmp);
    edges.dedup();
    let dp = 2.0 * PI / n_phi as f64;
    let mut sum = 0.0;
    for c in edges.windows(2) {
        for j in 0..n_phi {
            let p = (j as f64 * dp, (j + 1) as f64 * dp);
            sum += integrate_patch(&f, (c[0], c[1]), p, cos_cuts);
        }
    }
    sum
}
