//! Patch-averaged BSDF matrices in the Klems full basis, and their Monte Carlo estimate for
//! layers that need random walks (the pane, the orders >= 2 of a microsurface).
//!
//! Entry `(o, i)` of a block is the BSDF averaged over the pair of patches, weighted by
//! projected solid angle on both sides,
//! `B_oi = integral_i integral_o f cos(theta_i) cos(theta_o) dw_o dw_i / (Lambda_i Lambda_o)`
//! in 1/sr, so that `Lambda_o B_oi` is the fraction of the flux spread uniformly
//! (cosine-weighted) over incident patch `i` that leaves through exiting patch `o`, and `sum_o
//! Lambda_o B_oi` is Radiance's hemispherical total of that patch (`get_extrema` in
//! LBNL-ETA/Radiance src/common/bsdf_m.c, which checkBSDF prints as "Max. Tot. Dir" after taking
//! the maximum over incident patches).
//!
//! Monte Carlo ([`klems_monte_carlo`]): for each incident patch, `n` incident directions drawn
//! cosine-weighted inside the patch on a jittered `sqrt(n) x sqrt(n)` grid in `(cos^2 theta,
//! phi)`, each followed by one random walk through the layer; the exit directions are binned into
//! exiting patches. Every entry is unbiased; its standard error is computed from the same walks
//! and reported. Analytic BSDFs take the deterministic quadrature of [`super::quadrature`]
//! instead.

use rand::RngExt;
use rand_pcg::Pcg64;
use rayon::prelude::*;
use stfit_core::Vec3;

use super::klems::{N_PATCHES, direction_in_patch, patch_of, projected_solid_angle};
use super::layer::Layer;
use super::quadrature::{QuadratureError, QuadratureRule};

/// The four blocks in WINDOW's names: front is the z > 0 side (the rough face).
pub const BLOCK_NAMES: [&str; 4] = [
    "Transmission Front",
    "Reflection Front",
    "Transmission Back",
    "Reflection Back",
];

/// One block: light incident on one side, leaving on one side.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// WINDOW's `WavelengthDataDirection`.
    pub name: &'static str,
    /// BSDF values (1/sr), `values[o * 145 + i]`.
    pub values: Vec<f64>,
    /// Hemispherical total per incident patch, `sum_o Lambda_o B_oi`.
    pub totals: Vec<f64>,
    /// Monte Carlo standard error of each total (0 for a quadrature).
    pub totals_stderr: Vec<f64>,
    /// Largest relative Monte Carlo standard error of the entries holding at least 1% of their
    /// incident patch's flux (0 for a quadrature).
    pub max_rel_stderr_significant: f64,
}

/// How the matrices were computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Monte Carlo with this many random walks per incident patch.
    MonteCarlo { walks_per_patch: u64 },
    /// Deterministic quadrature with its estimated error.
    Quadrature {
        rule: QuadratureRule,
        error: QuadratureError,
    },
    /// Order 1 by quadrature plus orders >= 2 by Monte Carlo.
    Hybrid {
        rule: QuadratureRule,
        error: QuadratureError,
        walks_per_patch: u64,
    },
}

/// The four blocks of a layer.
#[derive(Debug, Clone, PartialEq)]
pub struct KlemsBsdf {
    pub blocks: [Block; 4],
    pub method: Method,
    /// Fraction of the incident flux of the worst patch that left neither side (absorbed, lost
    /// to the safety cap or to failed walks; for a single-scattering interface, the energy of
    /// the orders it does not model).
    pub max_loss: f64,
}

impl KlemsBsdf {
    /// The matrices `blocks` computed by `method`.
    pub fn new(blocks: [Block; 4], method: Method) -> Self {
        let mut max_loss: f64 = 0.0;
        for pair in [[0, 1], [2, 3]] {
            for i in 0..N_PATCHES {
                let out: f64 = pair.iter().map(|&b| blocks[b].totals[i]).sum();
                max_loss = max_loss.max(1.0 - out);
            }
        }
        Self {
            blocks,
            method,
            max_loss,
        }
    }

    /// The block called `name`.
    pub fn block(&self, name: &str) -> Option<&Block> {
        self.blocks.iter().find(|b| b.name == name)
    }

    /// Largest Monte Carlo standard error of any hemispherical total.
    pub fn max_total_stderr(&self) -> f64 {
        self.blocks
            .iter()
            .flat_map(|b| b.totals_stderr.iter().copied())
            .fold(0.0, f64::max)
    }

    /// Largest relative Monte Carlo standard error of a significant entry.
    pub fn max_rel_stderr_significant(&self) -> f64 {
        self.blocks
            .iter()
            .map(|b| b.max_rel_stderr_significant)
            .fold(0.0, f64::max)
    }

    /// The estimated error of the quadrature part, if any.
    pub fn quadrature_error(&self) -> Option<QuadratureError> {
        match self.method {
            Method::MonteCarlo { .. } => None,
            Method::Quadrature { error, .. } | Method::Hybrid { error, .. } => Some(error),
        }
    }
}

/// The flux of one incident patch leaving through each exiting patch, on the incident side
/// (`[0]`) and the other side (`[1]`), as fractions of the patch's incident flux, with standard
/// errors (Monte Carlo; zero for a quadrature).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockSums {
    pub w: [Vec<f64>; 2],
    pub se: [Vec<f64>; 2],
    /// Standard error of the total leaving each side.
    pub total_se: [f64; 2],
}

impl BlockSums {
    /// No flux anywhere.
    pub fn zero() -> Self {
        Self {
            w: [vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]],
            se: [vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]],
            total_se: [0.0; 2],
        }
    }

    /// Adds an independent estimate of another part of the same flux.
    pub fn add(&mut self, other: &Self) {
        for k in 0..2 {
            for o in 0..N_PATCHES {
                self.w[k][o] += other.w[k][o];
                self.se[k][o] = self.se[k][o].hypot(other.se[k][o]);
            }
            self.total_se[k] = self.total_se[k].hypot(other.total_se[k]);
        }
    }
}

/// The four blocks from the sums of every incident patch, front side first (`sums[side * 145 +
/// i]`).
pub fn blocks_from_sums(sums: &[BlockSums]) -> [Block; 4] {
    // Blocks in BLOCK_NAMES order: (incident side, exit on the other side?).
    let layout = [(0, 1), (0, 0), (1, 1), (1, 0)];
    layout.map(|(side, k)| {
        let mut values = vec![0.0; N_PATCHES * N_PATCHES];
        let (mut totals, mut totals_stderr) = (vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]);
        let mut max_rel: f64 = 0.0;
        for i in 0..N_PATCHES {
            let s = &sums[side * N_PATCHES + i];
            for o in 0..N_PATCHES {
                let p = s.w[k][o];
                values[o * N_PATCHES + i] = p / projected_solid_angle(o);
                if p >= 0.01 {
                    max_rel = max_rel.max(s.se[k][o] / p);
                }
            }
            totals[i] = s.w[k].iter().sum();
            totals_stderr[i] = s.total_se[k];
        }
        Block {
            name: BLOCK_NAMES[if side == 0 { 1 - k } else { 3 - k }],
            values,
            totals,
            totals_stderr,
            max_rel_stderr_significant: max_rel,
        }
    })
}

/// The side of the square grid of stratified walks that stands for `n` walks per patch: the
/// walks actually run are its square, `n` rounded up to a square (at least 1).
pub fn strata_per_side(n: u64) -> u64 {
    (n as f64).sqrt().ceil().max(1.0) as u64
}

/// Monte Carlo estimates of every incident patch's exit fluxes with `n` walks per patch
/// (rounded up to a square, [`strata_per_side`]), deterministic for a given `seed` whatever the
/// number of threads.
pub fn monte_carlo_sums<L: Layer>(layer: &L, n: u64, seed: u64) -> (Vec<BlockSums>, u64) {
    let m = strata_per_side(n);
    let n = m * m;
    let nf = n as f64;
    let jobs: Vec<(usize, usize)> = (0..2)
        .flat_map(|side| (0..N_PATCHES).map(move |i| (side, i)))
        .collect();
    let sums = jobs
        .par_iter()
        .map(|&(side, i)| {
            let mut rng = Pcg64::new(
                (u128::from(seed) << 64) | 0x6b6c_656d_735f_6d74,
                (side * N_PATCHES + i) as u128,
            );
            let mut w = [vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]];
            let mut w2 = [vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]];
            let sign = if side == 0 { 1.0 } else { -1.0 };
            for a in 0..m {
                for b in 0..m {
                    let u1 = (a as f64 + rng.random::<f64>()) / m as f64;
                    let u2 = (b as f64 + rng.random::<f64>()) / m as f64;
                    // Travel direction t (theta from the incident side's normal); wi = -travel.
                    let t = direction_in_patch(i, u1, u2);
                    let wi = Vec3::new(-t.x, -t.y, sign * t.z);
                    let Some((wo, weight)) = layer.scatter(wi, &mut rng) else {
                        continue;
                    };
                    let Some(o) = patch_of(wo.z.abs(), wo.x, wo.y) else {
                        continue;
                    };
                    let k = usize::from((wo.z > 0.0) != (sign > 0.0));
                    w[k][o] += weight;
                    w2[k][o] += weight * weight;
                }
            }
            // Each walk lands in one exiting patch: entry and total variances from the sums.
            let se = |s: f64, s2: f64| ((s2 / nf - (s / nf).powi(2)).max(0.0) / nf).sqrt();
            let total_se = [0, 1].map(|k| se(w[k].iter().sum(), w2[k].iter().sum()));
            let se_entries =
                [0, 1].map(|k| (0..N_PATCHES).map(|o| se(w[k][o], w2[k][o])).collect());
            BlockSums {
                w: [0, 1].map(|k| w[k].iter().map(|v| v / nf).collect()),
                se: se_entries,
                total_se,
            }
        })
        .collect();
    (sums, n)
}

/// The Klems matrices of `layer` by Monte Carlo with `n` walks per incident patch (rounded up
/// to a square).
pub fn klems_monte_carlo<L: Layer>(layer: &L, n: u64, seed: u64) -> KlemsBsdf {
    let (sums, n) = monte_carlo_sums(layer, n, seed);
    KlemsBsdf::new(
        blocks_from_sums(&sums),
        Method::MonteCarlo { walks_per_patch: n },
    )
}
