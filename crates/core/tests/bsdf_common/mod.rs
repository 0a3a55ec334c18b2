//! Shared helpers of the BSDF tests: test directions, quadrature over the sphere and a
//! chi-square goodness-of-fit test of a direction sampler against its pdf.

#![allow(dead_code)]

use std::f64::consts::PI;
use stfit_core::Vec3;
use stfit_core::math::{radians, spherical_direction};

/// A unit direction at polar angle `theta_deg` from +z (values above 90 point below the
/// surface) at a fixed, generic azimuth.
pub fn dir_deg(theta_deg: f64) -> Vec3 {
    spherical_direction(radians(theta_deg), 0.7)
}

/// The unit direction with `cos theta = c` and azimuth `phi`.
pub fn dir_cos_phi(c: f64, phi: f64) -> Vec3 {
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), c)
}

/// Integral of `f(w)` over the patch `c0 <= cos theta <= c1`, `p0 <= phi <= p1` (area
/// element `dc dphi`), by adaptive refinement: a cell's 3x3 Gauss-Legendre estimate is compared
/// with the sum over its four quadrants, and quadrants are refined until the two agree to `tol`
/// per unit area or `depth` levels are spent. Cliffs in the pdfs (facets at grazing angles,
/// the horizon) and narrow lobes defeat a fixed grid; this resolves them.
pub fn integrate_patch(
    f: &impl Fn(Vec3) -> f64,
    c: (f64, f64),
    p: (f64, f64),
    tol: f64,
    depth: u32,
) -> f64 {
    let coarse = gauss_3x3(f, c, p);
    refine(f, c, p, coarse, tol, depth)
}

fn gauss_3x3(f: &impl Fn(Vec3) -> f64, (c0, c1): (f64, f64), (p0, p1): (f64, f64)) -> f64 {
    const X: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let (cm, ch) = (0.5 * (c0 + c1), 0.5 * (c1 - c0));
    let (pm, ph) = (0.5 * (p0 + p1), 0.5 * (p1 - p0));
    let mut sum = 0.0;
    for (xa, wa) in X.iter().zip(W) {
        for (xb, wb) in X.iter().zip(W) {
            sum += wa * wb * f(dir_cos_phi(cm + xa * ch, pm + xb * ph));
        }
    }
    sum * ch * ph
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
    let parts = quads.map(|(c, p)| gauss_3x3(f, c, p));
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

/// Integral of `f(w)` over the whole sphere: a 32 x 64 grid in `(cos theta, phi)`, each cell
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

/// Outcome of [`chi_square_sphere`].
#[derive(Debug, Clone, Copy)]
pub struct ChiSquare {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
}

/// Pearson chi-square test of `n` draws of `sample` (each `None` when the draw fails) against
/// the density `pdf` (solid angle). Cells: `n_cos` x `n_phi` equal-area bins in
/// `(cos theta, phi)` over the whole sphere plus one cell for failed draws, whose expected
/// probability is `1 - integral pdf`. Each bin's probability is integrated by
/// [`integrate_patch`]. Cells expected to hold fewer than 5 draws are pooled into one.
pub fn chi_square_sphere(
    mut sample: impl FnMut() -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
    n: usize,
    n_cos: usize,
    n_phi: usize,
) -> ChiSquare {
    let cell = |w: Vec3| {
        let c = ((w.z + 1.0) * 0.5 * n_cos as f64).floor() as usize;
        let mut phi = w.y.atan2(w.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let p = (phi / (2.0 * PI) * n_phi as f64).floor() as usize;
        c.min(n_cos - 1) * n_phi + p.min(n_phi - 1)
    };
    let n_cells = n_cos * n_phi;
    let mut observed = vec![0.0f64; n_cells + 1];
    for _ in 0..n {
        match sample() {
            Some(w) => observed[cell(w)] += 1.0,
            None => observed[n_cells] += 1.0,
        }
    }
    let (dc, dp) = (2.0 / n_cos as f64, 2.0 * PI / n_phi as f64);
    let mut expected = vec![0.0f64; n_cells + 1];
    for i in 0..n_cos {
        for j in 0..n_phi {
            let c = -1.0 + i as f64 * dc;
            let p = j as f64 * dp;
            expected[i * n_phi + j] =
                n as f64 * integrate_patch(&pdf, (c, c + dc), (p, p + dp), TOL, DEPTH);
        }
    }
    let total: f64 = expected[..n_cells].iter().sum();
    expected[n_cells] = (n as f64 - total).max(0.0);
    chi_square(&observed, &expected)
}

/// Pearson chi-square of observed against expected counts, pooling cells expected to hold
/// fewer than 5 into one cell.
pub fn chi_square(observed: &[f64], expected: &[f64]) -> ChiSquare {
    let (mut stat, mut cells) = (0.0, 0usize);
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            stat += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if pool_e > 0.0 {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        cells += 1;
    } else if pool_o > 0.0 {
        // Draws where the pdf says none can be.
        stat = f64::INFINITY;
    }
    let dof = cells.saturating_sub(1).max(1);
    let p_value = if stat.is_finite() && stat > 0.0 {
        statrs::function::gamma::gamma_ur(0.5 * dof as f64, 0.5 * stat)
    } else if stat == 0.0 {
        1.0
    } else {
        0.0
    };
    ChiSquare {
        statistic: stat,
        dof,
        p_value,
    }
}
