//! Shared helpers of the BSDF tests: test directions, quadrature over the sphere and a
//! chi-square test of a direction sampler that may fail, built on `stfit_core::validate`.

#![allow(dead_code)]

use std::f64::consts::PI;
use stfit_core::Vec3;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::validate::{self, ChiSquare, SphereBins};

/// A unit direction at polar angle `theta_deg` from +z (values above 90 point below the
/// surface) at a fixed, generic azimuth.
pub fn dir_deg(theta_deg: f64) -> Vec3 {
    spherical_direction(radians(theta_deg), 0.7)
}

/// Pearson chi-square test of `n` draws of `sample` (each `None` when the draw fails) against
/// the density `pdf` (solid angle), on `n_cos` x `n_phi` equal-mass bins around +z
/// ([`SphereBins::equal_mass`]) plus one cell for failed draws, whose expected probability is
/// `1 - integral pdf`. The density need not integrate to 1: its integral is the probability
/// that a draw succeeds.
///
/// Cells are integrated by [`integrate_patch`], not `SphereBins::integrate`: the latter needs a
/// density continuous inside each cell, and a rough dielectric's pdf is not (with GGX, the
/// transmission pdf drops to zero where the facet it needs reaches the horizon, a curve across
/// cells), which sends its adaptive quadrature to full depth for minutes.
pub fn chi_square_sampler(
    mut sample: impl FnMut() -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64 + Sync,
    n: usize,
    n_cos: usize,
    n_phi: usize,
) -> ChiSquare {
    let bins = SphereBins::equal_mass(Vec3::z(), n_cos, n_phi, &pdf);
    let draws: Vec<Option<Vec3>> = (0..n).map(|_| sample()).collect();
    let failed = draws.iter().filter(|d| d.is_none()).count();
    let (mut observed, non_finite) = bins.histogram(draws.into_iter().flatten());
    let frame = *bins.frame();
    let local_pdf = |l: Vec3| pdf(frame.to_world(l));
    let mut expected: Vec<f64> = (0..bins.len())
        .map(|i| {
            let (c, p) = bins.cell_bounds(i);
            n as f64 * integrate_patch(&local_pdf, c, p, TOL, DEPTH)
        })
        .collect();
    let total: f64 = expected.iter().sum();
    observed.push(failed as f64);
    expected.push((n as f64 - total).max(0.0));
    let mut test = validate::pearson(&observed, &expected);
    test.non_finite = non_finite;
    if non_finite > 0 {
        test.p_value = 0.0;
    }
    test
}

/// The unit direction with `cos theta = c` and azimuth `phi`.
pub fn dir_cos_phi(c: f64, phi: f64) -> Vec3 {
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), c)
}

/// Integral of `f(w)` over the patch `c0 <= cos theta <= c1`, `p0 <= phi <= p1` (area
/// element `dc dphi`). The patch is first cut into sub-cells at most [`MAX_CELL`] wide in
/// `cos theta` and `phi`; each sub-cell's 3x3 Simpson estimate is compared with the sum over
/// its four quadrants, and quadrants are refined until the two agree to `tol` per unit area or
/// `depth` levels are spent. Simpson's nodes include the cell's edges, so a region where the
/// density is non-zero is noticed whenever it touches an edge, however thin its sliver inside
/// the cell: cliffs in the pdfs (with GGX at large roughness the transmission pdf jumps from
/// zero to its peak where the facet it needs reaches the horizon) defeat open rules and fixed
/// grids.
pub fn integrate_patch(
    f: &impl Fn(Vec3) -> f64,
    (c0, c1): (f64, f64),
    (p0, p1): (f64, f64),
    tol: f64,
    depth: u32,
) -> f64 {
    let nc = ((c1 - c0) / MAX_CELL).ceil().max(1.0) as usize;
    let np = ((p1 - p0) / MAX_CELL).ceil().max(1.0) as usize;
    let (dc, dp) = ((c1 - c0) / nc as f64, (p1 - p0) / np as f64);
    let mut sum = 0.0;
    for i in 0..nc {
        let c = (
            c0 + i as f64 * dc,
            if i + 1 == nc {
                c1
            } else {
                c0 + (i + 1) as f64 * dc
            },
        );
        for j in 0..np {
            let p = (
                p0 + j as f64 * dp,
                if j + 1 == np {
                    p1
                } else {
                    p0 + (j + 1) as f64 * dp
                },
            );
            let coarse = simpson_3x3(f, c, p);
            sum += refine(f, c, p, coarse, tol, depth);
        }
    }
    sum
}

/// Largest sub-cell, in `cos theta` and in `phi`, of [`integrate_patch`].
const MAX_CELL: f64 = 0.05;

fn simpson_3x3(f: &impl Fn(Vec3) -> f64, (c0, c1): (f64, f64), (p0, p1): (f64, f64)) -> f64 {
    const X: [f64; 3] = [0.0, 0.5, 1.0];
    const W: [f64; 3] = [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0];
    let (dc, dp) = (c1 - c0, p1 - p0);
    let mut sum = 0.0;
    for (xa, wa) in X.iter().zip(W) {
        for (xb, wb) in X.iter().zip(W) {
            sum += wa * wb * f(dir_cos_phi(c0 + xa * dc, p0 + xb * dp));
        }
    }
    sum * dc * dp
}

fn refine(
    f: &impl Fn(Vec3) -> f64,
    (c0, c1): (f64, f64),
    (p0, p1): (f64, f64),
    coarse: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let (cm, pm) = (0.5 * (c0 + c1), 0.5 * (p0 + p1));
    let quads = [
        ((c0, cm), (p0, pm)),
        ((c0, cm), (pm, p1)),
        ((cm, c1), (p0, pm)),
        ((cm, c1), (pm, p1)),
    ];
    let parts = quads.map(|(c, p)| simpson_3x3(f, c, p));
    let fine: f64 = parts.iter().sum();
    if depth == 0 || (fine - coarse).abs() <= tol * (c1 - c0) * (p1 - p0) {
        return fine;
    }
    quads
        .iter()
        .zip(parts)
        .map(|(&(c, p), part)| refine(f, c, p, part, tol, depth - 1))
        .sum()
}

/// Integral of `f(w)` over the whole sphere (steps inside cells allowed): a 32 x 64 grid in `(cos theta, phi)`, each cell
/// integrated by [`integrate_patch`].
pub fn integrate_sphere(f: impl Fn(Vec3) -> f64) -> f64 {
    let (n_cos, n_phi) = (32, 64);
    let (dc, dp) = (2.0 / n_cos as f64, 2.0 * PI / n_phi as f64);
    let mut sum = 0.0;
    for i in 0..n_cos {
        for j in 0..n_phi {
            let c = -1.0 + i as f64 * dc;
            let p = j as f64 * dp;
            sum += integrate_patch(&f, (c, c + dc), (p, p + dp), TOL, DEPTH);
        }
    }
    sum
}

/// Refinement tolerance (per unit area) and depth of the quadratures.
const TOL: f64 = 1e-4;
const DEPTH: u32 = 6;
