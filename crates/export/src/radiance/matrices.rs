//! Patch-averaged BSDF matrices in the Klems full basis, by Monte Carlo quadrature.
//!
//! Entry `(o, i)` of a block is the BSDF averaged over the pair of patches, weighted by
//! projected solid angle on both sides,
//! `B_oi = integral_i integral_o f cos(theta_i) cos(theta_o) dw_o dw_i / (Lambda_i Lambda_o)`
//! in 1/sr, so that `sum_o Lambda_o B_oi` is the flux fraction leaving through the block for
//! light spread uniformly (cosine-weighted) over incident patch `i`: Radiance's hemispherical
//! total of that patch (`get_extrema` in LBNL-ETA/Radiance src/common/bsdf_m.c, which
//! checkBSDF prints as "Max. Tot. Dir" after taking the maximum over incident patches).
//!
//! Quadrature: for each incident patch, `n` incident directions drawn cosine-weighted inside
//! the patch on a jittered `sqrt(n) x sqrt(n)` grid in `(cos^2 theta, phi)`, each scattered
//! once by the layer; the exit directions are binned into exiting patches. The estimate of
//! every entry is unbiased (no discretisation error beyond the basis itself); its standard
//! error is computed from the same draws and reported.

use rand::RngExt;
use rand_pcg::Pcg64;
use rayon::prelude::*;
use stfit_core::Vec3;

use super::klems::{N_PATCHES, direction_in_patch, patch_of, projected_solid_angle};
use super::layer::Layer;

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
    /// Standard error of each total.
    pub totals_stderr: Vec<f64>,
    /// Largest relative standard error of the entries holding at least 1% of their incident
    /// patch's flux.
    pub max_rel_stderr_significant: f64,
}

/// The four blocks of a layer.
#[derive(Debug, Clone, PartialEq)]
pub struct KlemsBsdf {
    pub blocks: [Block; 4],
    /// Incident directions per patch.
    pub samples_per_patch: u64,
    /// Fraction of the incident flux of the worst patch that left neither side (absorbed, lost
    /// to the safety cap or to failed draws).
    pub max_loss: f64,
}

impl KlemsBsdf {
    /// The block called `name`.
    pub fn block(&self, name: &str) -> Option<&Block> {
        self.blocks.iter().find(|b| b.name == name)
    }

    /// Largest standard error of any hemispherical total.
    pub fn max_total_stderr(&self) -> f64 {
        self.blocks
            .iter()
            .flat_map(|b| b.totals_stderr.iter().copied())
            .fold(0.0, f64::max)
    }
}

/// Sums of one incident patch: `[exit on incident side, exit on the other side]` per exiting
/// patch, weights and squared weights.
struct PatchSums {
    w: [Vec<f64>; 2],
    w2: [Vec<f64>; 2],
}

/// Estimates the Klems matrices of `layer` with `n` incident directions per patch (rounded up
/// to a square), deterministic for a given `seed` whatever the number of threads.
pub fn klems_bsdf<L: Layer>(layer: &L, n: u64, seed: u64) -> KlemsBsdf {
    let m = (n as f64).sqrt().ceil().max(1.0) as u64;
    let n = m * m;
    let jobs: Vec<(usize, usize)> = (0..2)
        .flat_map(|side| (0..N_PATCHES).map(move |i| (side, i)))
        .collect();
    let sums: Vec<PatchSums> = jobs
        .par_iter()
        .map(|&(side, i)| {
            let mut rng = Pcg64::new(
                (u128::from(seed) << 64) | 0x6b6c_656d_735f_6d74,
                (side * N_PATCHES + i) as u128,
            );
            let mut s = PatchSums {
                w: [vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]],
                w2: [vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]],
            };
            let sign = if side == 0 { 1.0 } else { -1.0 };
            for a in 0..m {
                for b in 0..m {
                    let u1 = (a as f64 + rng.random::<f64>()) / m as f64;
                    let u2 = (b as f64 + rng.random::<f64>()) / m as f64;
                    // Travel direction t (theta from the incident side's normal); wi = -travel.
                    let t = direction_in_patch(i, u1, u2);
                    let wi = Vec3::new(-t.x, -t.y, sign * t.z);
                    let Some((wo, w)) = layer.scatter(wi, &mut rng) else {
                        continue;
                    };
                    let same = (wo.z > 0.0) == (sign > 0.0);
                    let Some(o) = patch_of(wo.z.abs(), wo.x, wo.y) else {
                        continue;
                    };
                    let k = usize::from(!same);
                    s.w[k][o] += w;
                    s.w2[k][o] += w * w;
                }
            }
            s
        })
        .collect();
    let nf = n as f64;
    let mut max_loss: f64 = 0.0;
    // Blocks in BLOCK_NAMES order: (incident side, exit on the other side?).
    let layout = [(0, 1), (0, 0), (1, 1), (1, 0)];
    let blocks = layout.map(|(side, k)| {
        let mut values = vec![0.0; N_PATCHES * N_PATCHES];
        let (mut totals, mut totals_stderr) = (vec![0.0; N_PATCHES], vec![0.0; N_PATCHES]);
        let mut max_rel: f64 = 0.0;
        for i in 0..N_PATCHES {
            let s = &sums[side * N_PATCHES + i];
            let (mut t, mut t2) = (0.0, 0.0);
            for o in 0..N_PATCHES {
                let p = s.w[k][o] / nf;
                values[o * N_PATCHES + i] = p / projected_solid_angle(o);
                t += s.w[k][o];
                t2 += s.w2[k][o];
                if p >= 0.01 {
                    let se = ((s.w2[k][o] / nf - p * p).max(0.0) / nf).sqrt();
                    max_rel = max_rel.max(se / p);
                }
            }
            totals[i] = t / nf;
            // Each draw lands in one exiting patch: the total's variance from its sums.
            totals_stderr[i] = ((t2 / nf - totals[i] * totals[i]).max(0.0) / nf).sqrt();
        }
        Block {
            name: BLOCK_NAMES[if side == 0 { 1 - k } else { 3 - k }],
            values,
            totals,
            totals_stderr,
            max_rel_stderr_significant: max_rel,
        }
    });
    for side in 0..2 {
        for i in 0..N_PATCHES {
            let s = &sums[side * N_PATCHES + i];
            let out: f64 = s.w.iter().flat_map(|v| v.iter()).sum::<f64>() / nf;
            max_loss = max_loss.max(1.0 - out);
        }
    }
    KlemsBsdf {
        blocks,
        samples_per_patch: n,
        max_loss,
    }
}
