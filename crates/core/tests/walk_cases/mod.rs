//! Test cases shared by the walk tests.
#![allow(dead_code)]

use rand::SeedableRng;
use rand_pcg::Pcg64;
use statrs::function::gamma::gamma_ur;
use std::f64::consts::PI;
use stfit_core::Vec3;
use stfit_core::math::spherical_direction;
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};
use stfit_core::walk::{Estimate, WalkSample};

/// Student-T shapes under test: below GGX's 2, near the published fits, near Beckmann.
pub const GAMMAS: [f64; 3] = [1.6, 3.0, 10.0];

/// Every NDF family under test (Beckmann, GGX, Student-T for each of [`GAMMAS`]) at each of the
/// given roughnesses.
pub fn ndfs(alphas: &[f64]) -> Vec<AnyNdf> {
    let mut out = Vec::new();
    for &a in alphas {
        out.push(Beckmann::new(a).unwrap().into());
        out.push(Ggx::new(a).unwrap().into());
        for g in GAMMAS {
            out.push(StudentT::new(a, g).unwrap().into());
        }
    }
    out
}

/// GGX at each of the given roughnesses.
pub fn ggx(alphas: &[f64]) -> Vec<AnyNdf> {
    alphas
        .iter()
        .map(|&a| Ggx::new(a).unwrap().into())
        .collect()
}

/// A spread of unit directions on both hemispheres, in and out of the plane of incidence.
pub fn directions() -> Vec<Vec3> {
    [
        (0.15, 0.0),
        (0.7, 3.1),
        (1.2, 2.0),
        (1.3, 0.4),
        (2.2, 0.0),
        (2.6, 3.3),
        (1.85, 1.2),
        (3.0, 5.0),
    ]
    .iter()
    .map(|&(t, p)| spherical_direction(t, p))
    .collect()
}

/// Bins in `cos theta` over [-1, 1] and in `|phi|` over [0, pi] (the light is in the x-z plane,
/// so the exit distribution is symmetric in `phi`).
pub const NZ: usize = 16;
pub const NP: usize = 8;
/// Gauss-Legendre nodes and weights on [-1, 1], three points.
const GL: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

pub fn bin_of(w: Vec3) -> usize {
    let iz = (((w.z + 1.0) * 0.5 * NZ as f64) as usize).min(NZ - 1);
    let ip = ((w.y.atan2(w.x).abs() / PI * NP as f64) as usize).min(NP - 1);
    iz * NP + ip
}

/// `sample` agrees with `eval`: the chi-square p-value of the weighted histogram of `n` walk
/// exits drawn by `sample` against the integral over each bin of the `eval` estimates that
/// `eval_many` returns at the bins' Gauss-Legendre nodes (one batch of walks). `validate`
/// integrates deterministic densities; `eval` is a Monte Carlo estimate, so the statistic
/// includes the estimates' standard errors and the sample weights.
pub fn sample_eval_p_value(
    mut sample: impl FnMut(&mut Pcg64) -> Option<WalkSample>,
    eval_many: impl FnOnce(&[Vec3]) -> Vec<Estimate>,
    n: u64,
) -> f64 {
    // Quadrature nodes per bin and their weights (dz dphi, both signs of phi).
    let (dz, dp) = (2.0 / NZ as f64, PI / NP as f64);
    let mut nodes = Vec::new();
    let mut weights = Vec::new();
    for iz in 0..NZ {
        for ip in 0..NP {
            for (xz, wz) in GL {
                for (xp, wp) in GL {
                    let z = -1.0 + dz * (iz as f64 + 0.5 + 0.5 * xz);
                    let phi = dp * (ip as f64 + 0.5 + 0.5 * xp);
                    nodes.push(spherical_direction(z.clamp(-1.0, 1.0).acos(), phi));
                    weights.push(2.0 * 0.25 * wz * wp * dz * dp);
                }
            }
        }
    }
    let est = eval_many(&nodes);
    let per_bin = GL.len() * GL.len();
    let expected: Vec<(f64, f64)> = (0..NZ * NP)
        .map(|b| {
            let r = b * per_bin..(b + 1) * per_bin;
            let mean: f64 = r.clone().map(|k| weights[k] * est[k].mean).sum();
            // Upper bound on the standard error (the nodes share walks).
            let se: f64 = r.map(|k| weights[k] * est[k].stderr).sum();
            (mean * n as f64, se * n as f64)
        })
        .collect();
    // Sums of sample weights and of their squares per bin.
    let mut sum_w = vec![0.0f64; NZ * NP];
    let mut sum_w2 = vec![0.0f64; NZ * NP];
    let mut rng = Pcg64::seed_from_u64(5);
    for _ in 0..n {
        if let Some(s) = sample(&mut rng) {
            let b = bin_of(s.wo);
            sum_w[b] += s.weight;
            sum_w2[b] += s.weight * s.weight;
        }
    }
    // Variance of a bin's weight sum: expected mass times the observed mean square weight per
    // unit weight (Pearson's `e` for unit weights), plus the error of the expectation.
    let variance = |o: f64, o2: f64, e: f64, se: f64| {
        let w = if o > 0.0 { o2 / o } else { 1.0 };
        e * w + se * se
    };
    // Pool the bins expecting fewer than 5 counts into one.
    let (mut chi2, mut dof) = (0.0, 0usize);
    let (mut pool_o, mut pool_o2, mut pool_e, mut pool_v) = (0.0, 0.0, 0.0, 0.0);
    for (b, &(e, se)) in expected.iter().enumerate() {
        if e < 5.0 {
            pool_o += sum_w[b];
            pool_o2 += sum_w2[b];
            pool_e += e;
            pool_v += se * se;
        } else {
            chi2 += (sum_w[b] - e).powi(2) / variance(sum_w[b], sum_w2[b], e, se);
            dof += 1;
        }
    }
    if pool_e > 0.0 || pool_o > 0.0 {
        let v = variance(pool_o, pool_o2, pool_e, pool_v.sqrt()).max(1.0);
        chi2 += (pool_o - pool_e).powi(2) / v;
        dof += 1;
    }
    gamma_ur(dof as f64 / 2.0, chi2 / 2.0)
}
