//! Parallel Monte Carlo estimators over many walks: the BSDF toward many directions at once, and
//! the fractions of incident flux reflected and transmitted.
//!
//! Walks run in fixed chunks of [`CHUNK`] walks, each with its own PCG stream derived from the
//! seed and the chunk index, and chunk sums are added in chunk order. Results are therefore
//! identical for a given seed whatever the number of threads.

use super::engine::{Target, WalkEnd, Walker};
use super::{Facet, Microsurface};
use crate::math::Vec3;
use crate::ndf::Ndf;
use rand_pcg::Pcg64;
use rayon::prelude::*;

/// Walks per chunk: the unit of parallel work and of random-number streams.
pub const CHUNK: u64 = 2048;

/// A Monte Carlo estimate with its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub mean: f64,
    /// Standard error of `mean` (sample standard deviation over `sqrt(n)`); undefined (0)
    /// for fewer than 2 walks: report it through [`defined_stderr`].
    pub stderr: f64,
}

/// Estimates of many quantities from one set of walks, with the per-chunk means they are made
/// of: `batches[c][k]` is the mean of quantity `k` over the walks of chunk `c`, which has
/// [`chunk_walks`]`(walks)[c]` walks. Chunks use independent random numbers, so the batch means
/// are independent and `estimates[k].mean` is their walk-weighted average.
#[derive(Debug, Clone, PartialEq)]
pub struct Batched {
    pub estimates: Vec<Estimate>,
    pub batches: Vec<Vec<f64>>,
}

/// The number of walks of each chunk of a run of `walks` walks: [`CHUNK`] each, the last
/// possibly fewer.
pub fn chunk_walks(walks: u64) -> Vec<u64> {
    (0..walks.div_ceil(CHUNK))
        .map(|c| chunk_len(walks, c))
        .collect()
}

/// A standard error as it may be reported: `None` for fewer than 2 walks, where the sample
/// variance (and so the error) is undefined, never a "± 0".
pub fn defined_stderr(walks: u64, stderr: f64) -> Option<f64> {
    (walks >= 2 && stderr.is_finite()).then_some(stderr)
}

/// One-sided 95% upper bound on the probability that a walk reaches a side of the surface
/// that none of `walks > 0` independent walks reached: the `p` with `(1 - p)^N = 0.05`,
/// `1 - 0.05^(1/N)` (about `3 / N`, the "rule of three"), formed as `-expm1(ln(0.05) / N)`
/// so that it keeps its digits for large `N`. A standard error of 0 would claim a side known
/// to be exactly empty.
pub fn unreached_upper_bound(walks: u64) -> f64 {
    -(0.05f64.ln() / walks as f64).exp_m1()
}

/// How well one side of an albedo estimate is known, as it is reported.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SideError {
    /// The standard error of the estimate.
    Stderr(f64),
    /// No walk reached the side (its estimate is exactly 0): the one-sided 95% upper bound
    /// [`unreached_upper_bound`].
    UpperBound(f64),
    /// A side that walks reached, with fewer than 2 walks: no standard error
    /// ([`defined_stderr`]).
    Undefined,
}

impl SideError {
    /// The error of a side with estimate `value` and standard error `stderr` over `walks`
    /// walks.
    pub fn of(walks: u64, value: f64, stderr: f64) -> Self {
        if walks > 0 && value == 0.0 && stderr == 0.0 {
            return Self::UpperBound(unreached_upper_bound(walks));
        }
        match defined_stderr(walks, stderr) {
            Some(se) => Self::Stderr(se),
            None => Self::Undefined,
        }
    }

    /// The standard error, if there is one.
    pub fn stderr(self) -> Option<f64> {
        match self {
            Self::Stderr(se) => Some(se),
            _ => None,
        }
    }

    /// The upper bound of an unreached side, if this is one.
    pub fn upper_bound(self) -> Option<f64> {
        match self {
            Self::UpperBound(b) => Some(b),
            _ => None,
        }
    }
}

/// Fractions of the incident flux leaving on the side of the light (reflectance) and on the
/// other side (transmittance), for the selected scattering orders, with no radiance `1/eta^2`
/// scaling (a non-absorbing dielectric gives `reflectance + transmittance = 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlbedoEstimate {
    pub reflectance: f64,
    pub transmittance: f64,
    pub reflectance_stderr: f64,
    pub transmittance_stderr: f64,
    /// Mean number of scattering events of the walks that left the surface within the selected
    /// orders: the path length; `None` when no walk did (then it is undefined: `--orders
    /// multiple` on a surface so smooth that every walk leaves after one event). Facet albedos
    /// and Fresnel factors enter a walk as its weight, not by ending it, so they scale the flux
    /// and leave this unchanged (a Lambertian reflectance of 0 or 1 gives the same paths).
    pub mean_bounces: Option<f64>,
    /// Fraction of the incident flux dropped by walks that reached the safety cap
    /// ([`MAX_BOUNCES`](super::MAX_BOUNCES) by default).
    pub truncated: f64,
    /// Number of walks.
    pub walks: u64,
}

impl AlbedoEstimate {
    /// The reflectance's standard error, or its upper bound when no walk was reflected.
    pub fn reflectance_error(&self) -> SideError {
        SideError::of(self.walks, self.reflectance, self.reflectance_stderr)
    }

    /// The transmittance's standard error, or its upper bound when no walk was transmitted.
    pub fn transmittance_error(&self) -> SideError {
        SideError::of(self.walks, self.transmittance, self.transmittance_stderr)
    }
}

/// Running mean and sum of squared deviations of a per-walk quantity (Welford, merged with
/// Chan et al.'s formula): no cancellation when the spread is tiny next to the mean.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Sums {
    n: f64,
    pub(crate) mean: f64,
    m2: f64,
}

impl Sums {
    #[inline]
    pub(crate) fn add(&mut self, x: f64) {
        let n = self.n + 1.0;
        self.add_nth(x, n, 1.0 / n);
    }

    /// [`Sums::add`] of the `n`-th value given `inv_n = 1/n`.
    #[inline]
    fn add_nth(&mut self, x: f64, n: f64, inv_n: f64) {
        self.n = n;
        welford(&mut self.mean, &mut self.m2, x, inv_n);
    }

    fn merge(&mut self, o: &Sums) {
        if o.n == 0.0 {
            return;
        }
        let n = self.n + o.n;
        let d = o.mean - self.mean;
        self.mean += d * o.n / n;
        self.m2 += o.m2 + d * d * self.n * o.n / n;
        self.n = n;
    }

    pub(crate) fn estimate(&self) -> Estimate {
        let var = if self.n > 1.0 {
            self.m2 / (self.n - 1.0)
        } else {
            0.0
        };
        Estimate {
            mean: self.mean,
            stderr: (var.max(0.0) / self.n.max(1.0)).sqrt(),
        }
    }
}

/// Welford's step: the `n`-th value `x` (`inv_n = 1/n`) into a running `mean` and sum of
/// squared deviations `m2`.
#[inline(always)]
fn welford(mean: &mut f64, m2: &mut f64, x: f64, inv_n: f64) {
    let d = x - *mean;
    *mean += d * inv_n;
    *m2 += d * (x - *mean);
}

/// [`welford`] with `x = 0`, bit for bit where `m2` is not `-0.0` (a sum of squared deviations
/// that starts at `+0.0` never is): with `d = 0 - mean = -mean`, the step is `mean -= mean
/// inv_n`, `m2 += mean_before * mean_after` (negations are exact; where the product is a zero,
/// its sign cannot change `m2`, which is then not `-0.0`). Four operations instead of six,
/// and no zero to subtract from.
#[inline(always)]
fn welford_zero(mean: &mut f64, m2: &mut f64, inv_n: f64) {
    let before = *mean;
    *mean -= before * inv_n;
    *m2 += before * *mean;
}

/// The [`Sums`] of many quantities that advance together, one value of each per walk, stored
/// by field (every mean, then every `m2`) so that a walk's update of all of them is vector
/// arithmetic.
///
/// A walk that added nothing to any quantity (most walks, toward most targets) is only
/// recorded: the zeros of a run of such walks are added to each quantity in turn before the
/// next walk that added something (and at the end), [`LANES`] quantities at a time, whose
/// running sums stay in registers through the run. Each quantity sees the same updates in the
/// same order as walk by walk, so the sums are the same bit for bit.
struct ManySums {
    n: f64,
    mean: Vec<f64>,
    m2: Vec<f64>,
    /// `1/n` of each walk of the current run of walks that added nothing, in order.
    zero_walks: Vec<f64>,
}

/// Quantities whose sums advance together through a run of zero walks
/// ([`ManySums::add_zero_walks`]): 8 keeps 16 sums and their temporaries in vector registers.
const LANES: usize = 8;

impl ManySums {
    fn new(k: usize) -> Self {
        Self {
            n: 0.0,
            mean: vec![0.0; k],
            m2: vec![0.0; k],
            zero_walks: Vec::with_capacity(CHUNK as usize),
        }
    }

    /// Adds the `n`-th walk's values `acc` (one per quantity) and sets them back to 0, ready
    /// for the next walk. One division per walk, not per quantity.
    #[inline]
    fn add_and_clear(&mut self, n: f64, acc: &mut [f64]) {
        self.add_zero_walks();
        self.n = n;
        let inv_n = 1.0 / n;
        for ((mean, m2), a) in self.mean.iter_mut().zip(&mut self.m2).zip(acc) {
            welford(mean, m2, *a, inv_n);
            *a = 0.0;
        }
    }

    /// Adds the `n`-th walk with the value 0 for every quantity (recorded, added by
    /// [`ManySums::add_zero_walks`]).
    #[inline]
    fn add_zeros(&mut self, n: f64) {
        self.n = n;
        self.zero_walks.push(1.0 / n);
    }

    /// Adds the recorded walks that added nothing: their value 0 to every quantity, walk by
    /// walk, [`LANES`] quantities at a time.
    fn add_zero_walks(&mut self) {
        if self.zero_walks.is_empty() {
            return;
        }
        let mut means = self.mean.chunks_exact_mut(LANES);
        let mut m2s = self.m2.chunks_exact_mut(LANES);
        for (mean, m2) in (&mut means).zip(&mut m2s) {
            let mut lane_mean: [f64; LANES] = std::array::from_fn(|l| mean[l]);
            let mut lane_m2: [f64; LANES] = std::array::from_fn(|l| m2[l]);
            for &inv_n in &self.zero_walks {
                for (mean, m2) in lane_mean.iter_mut().zip(&mut lane_m2) {
                    welford_zero(mean, m2, inv_n);
                }
            }
            mean.copy_from_slice(&lane_mean);
            m2.copy_from_slice(&lane_m2);
        }
        let rest = means.into_remainder().iter_mut().zip(m2s.into_remainder());
        for (mean, m2) in rest {
            for &inv_n in &self.zero_walks {
                welford_zero(mean, m2, inv_n);
            }
        }
        self.zero_walks.clear();
    }

    /// The sums of each quantity.
    fn into_sums(mut self) -> Vec<Sums> {
        self.add_zero_walks();
        let n = self.n;
        self.mean
            .into_iter()
            .zip(self.m2)
            .map(|(mean, m2)| Sums { n, mean, m2 })
            .collect()
    }
}

/// The random-number stream of one chunk.
pub(crate) fn chunk_rng(seed: u64, chunk: u64) -> Pcg64 {
    Pcg64::new(
        (u128::from(seed) << 64) | 0xa02b_db6f_7e5c_3c1d,
        u128::from(chunk),
    )
}

/// Number of walks in chunk `c` of a run of `walks`.
fn chunk_len(walks: u64, c: u64) -> u64 {
    CHUNK.min(walks - c * CHUNK)
}

/// The Monte Carlo estimators of a random walk over many walks, behind one object-safe trait,
/// so that a surface chosen at run time (a command line, a Python call) is one
/// `Box<dyn Estimator>` (see [`crate::surface`]). Both walks implement it. Every estimate is
/// parallel (rayon) and identical for a given seed whatever the number of threads: walks run
/// in chunks of [`CHUNK`], each with its own random-number stream, summed in chunk order.
///
/// ```
/// use stfit_core::Vec3;
/// use stfit_core::ndf::Ggx;
/// use stfit_core::walk::{DielectricFacet, Estimator, Microsurface};
///
/// let glass = Microsurface::new(Ggx::new(0.5)?, DielectricFacet::new(1.5)?);
/// let albedo = glass.albedo(Vec3::new(0.0, 0.0, 1.0), 20_000, 7);
/// // A lossless dielectric conserves energy: every walk leaves on one side or the other.
/// assert!((albedo.reflectance + albedo.transmittance - 1.0).abs() < 1e-12);
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
pub trait Estimator: Sync {
    /// Estimates `f(wi, wo) |wo.z|` for every `wo` in `wos` from one set of `walks` walks from
    /// `wi`, with next-event estimation toward every `wo` at every hit.
    fn eval_many(&self, wi: Vec3, wos: &[Vec3], walks: u64, seed: u64) -> Vec<Estimate> {
        self.eval_many_batched(wi, wos, walks, seed).estimates
    }

    /// [`Estimator::eval_many`] with the means of each chunk of [`CHUNK`] walks it is made of
    /// (the same walks and the same estimates): independent batches, from which the Monte
    /// Carlo error of anything computed from the estimates can be propagated.
    fn eval_many_batched(&self, wi: Vec3, wos: &[Vec3], walks: u64, seed: u64) -> Batched;

    /// Fractions of the flux arriving from `wi` that leave on each side, from `walks` walks,
    /// calling `progress(n)` after each chunk of `n` walks (from any thread).
    fn albedo_with_progress(
        &self,
        wi: Vec3,
        walks: u64,
        seed: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> AlbedoEstimate;

    /// Walks from each `wo` per walk from `wi` that [`Estimator::eval_many_batched`] adds
    /// (bidirectional estimates, see the [module documentation](super)); 0 where it walks
    /// from `wi` alone.
    fn walks_from_wo(&self) -> f64 {
        0.0
    }

    /// [`Estimator::albedo_with_progress`] without progress reports.
    fn albedo(&self, wi: Vec3, walks: u64, seed: u64) -> AlbedoEstimate {
        self.albedo_with_progress(wi, walks, seed, &|_| {})
    }
}

/// Implements [`Estimator`] for a walker type through the generic estimators of this module.
macro_rules! estimators {
    ($ty:ident < $($g:ident : $b:path),* >) => {
        impl<$($g: $b),*> $crate::walk::Estimator for $ty<$($g),*> {
            fn eval_many_batched(
                &self,
                wi: Vec3,
                wos: &[Vec3],
                walks: u64,
                seed: u64,
            ) -> $crate::walk::Batched {
                $crate::walk::estimate::eval_many(self, wi, wos, walks, seed)
            }

            fn albedo_with_progress(
                &self,
                wi: Vec3,
                walks: u64,
                seed: u64,
                progress: &(dyn Fn(u64) + Sync),
            ) -> AlbedoEstimate {
                $crate::walk::estimate::albedo(self, wi, walks, seed, progress)
            }
        }
    };
}
pub(crate) use estimators;

/// The height-field walk estimates `eval_many` bidirectionally where its facets allow
/// (see "Bidirectional estimates" in the [module documentation](super)), else from `wi`
/// alone.
impl<N: Ndf, F: Facet> Estimator for Microsurface<N, F> {
    fn eval_many_batched(&self, wi: Vec3, wos: &[Vec3], walks: u64, seed: u64) -> Batched {
        let fraction = Estimator::walks_from_wo(self);
        if fraction > 0.0 {
            super::bidirectional::eval_many(self, wi, wos, walks, fraction, seed)
        } else {
            eval_many(self, wi, wos, walks, seed)
        }
    }

    fn walks_from_wo(&self) -> f64 {
        if super::bidirectional::supported(self) {
            Microsurface::walks_from_wo(self)
        } else {
            0.0
        }
    }

    fn albedo_with_progress(
        &self,
        wi: Vec3,
        walks: u64,
        seed: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> AlbedoEstimate {
        albedo(self, wi, walks, seed, progress)
    }
}

/// A seed for the walks from one incident direction: `seed` mixed with the bits of `wi`
/// (SplitMix64's finaliser), so that every direction has its own random numbers, fixed by the
/// direction itself whatever the order in which directions come.
pub fn direction_seed(seed: u64, wi: Vec3) -> u64 {
    let mut z = seed;
    for c in [wi.x, wi.y, wi.z] {
        // `+ 0.0` maps -0.0 to 0.0: the same direction has one seed.
        z = splitmix(z ^ (c + 0.0).to_bits());
    }
    z
}

/// SplitMix64's output function of a 64-bit state.
fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Estimates `f(wi, wo) |wo.z|` for every pair `(wi, wo)`: pairs that share `wi` (bit for bit)
/// share one set of `walks` walks seeded by [`direction_seed`]`(seed, wi)`, so each estimate
/// depends on its direction pair and the seed, not on the order or grouping of the pairs.
/// Groups are found by hashing, in time linear in the number of pairs.
pub fn eval_pairs(
    estimator: &dyn Estimator,
    pairs: &[(Vec3, Vec3)],
    walks: u64,
    seed: u64,
) -> Vec<Estimate> {
    eval_pairs_with_progress(estimator, pairs, walks, seed, &|_| {})
}

/// [`eval_pairs`], calling `progress(walks)` after the walks of each incident direction.
pub fn eval_pairs_with_progress(
    estimator: &dyn Estimator,
    pairs: &[(Vec3, Vec3)],
    walks: u64,
    seed: u64,
    progress: &dyn Fn(u64),
) -> Vec<Estimate> {
    let mut out = vec![
        Estimate {
            mean: 0.0,
            stderr: 0.0
        };
        pairs.len()
    ];
    let from_wo = walks_from_each_wo(estimator, walks);
    for_each_incidence(estimator, pairs, walks, seed, |_, members, b| {
        for (&k, e) in members.iter().zip(b.estimates) {
            out[k] = e;
        }
        progress(walks + from_wo * members.len() as u64);
    });
    out
}

/// The walks that [`Estimator::eval_many_batched`] with `walks` walks from `wi` runs from
/// each `wo`: [`Estimator::walks_from_wo`] times as many per chunk, at least two per chunk.
pub fn walks_from_each_wo(estimator: &dyn Estimator, walks: u64) -> u64 {
    let fraction = estimator.walks_from_wo();
    if fraction == 0.0 {
        return 0;
    }
    chunk_walks(walks)
        .iter()
        .map(|&n| walks_like(n, fraction))
        .sum()
}

/// Every walk [`eval_pairs`] runs for `pairs` with `walks` walks per incident direction: those
/// from each distinct incidence ([`distinct_incidences`]) and, for a bidirectional estimator,
/// those from each pair's `wo` ([`walks_from_each_wo`]); saturating at `u64::MAX`.
pub fn eval_pairs_walk_count(estimator: &dyn Estimator, pairs: &[(Vec3, Vec3)], walks: u64) -> u64 {
    walks
        .saturating_mul(distinct_incidences(pairs).len() as u64)
        .saturating_add(walks_from_each_wo(estimator, walks).saturating_mul(pairs.len() as u64))
}

/// The walks from a `wo` that match a chunk of `len` walks from `wi`: `fraction` times as
/// many, rounded, and at least two, so that every chunk's variance (and the estimate's
/// standard error) is defined.
pub(crate) fn walks_like(len: u64, fraction: f64) -> u64 {
    ((len as f64 * fraction).round() as u64).max(2)
}

/// The distinct incident directions of `pairs` (bit for bit, `-0.0` as `0.0`), in order of
/// first appearance: the walks [`eval_pairs`] runs are `walks` per direction.
pub fn distinct_incidences(pairs: &[(Vec3, Vec3)]) -> Vec<Vec3> {
    incidence_groups(pairs)
        .into_iter()
        .map(|(wi, _)| wi)
        .collect()
}

/// The pairs grouped by incident direction, in order of first appearance, by hashing.
pub(crate) fn incidence_groups(pairs: &[(Vec3, Vec3)]) -> Vec<(Vec3, Vec<usize>)> {
    let key = |w: &Vec3| [w.x + 0.0, w.y + 0.0, w.z + 0.0].map(f64::to_bits);
    let mut groups: Vec<(Vec3, Vec<usize>)> = Vec::new();
    let mut index: std::collections::HashMap<[u64; 3], usize> = std::collections::HashMap::new();
    for (k, (wi, _)) in pairs.iter().enumerate() {
        let g = *index.entry(key(wi)).or_insert_with(|| {
            groups.push((*wi, Vec::new()));
            groups.len() - 1
        });
        groups[g].1.push(k);
    }
    groups
}

/// The estimate of one pair by [`eval_pairs_batched`]: the estimate, the index of the group of
/// pairs that share its `wi` (and its walks; groups are numbered in order of first appearance),
/// and its per-chunk means ([`Batched`]). Estimates of one group are correlated (the same
/// walks), estimates of different groups independent.
#[derive(Debug, Clone, PartialEq)]
pub struct PairEstimate {
    pub estimate: Estimate,
    pub group: usize,
    pub batch_means: Vec<f64>,
}

/// [`eval_pairs`] with each estimate's walk group and per-chunk means: the same walks and the
/// same estimates.
pub fn eval_pairs_batched(
    estimator: &dyn Estimator,
    pairs: &[(Vec3, Vec3)],
    walks: u64,
    seed: u64,
) -> Vec<PairEstimate> {
    let mut out = vec![None; pairs.len()];
    for_each_incidence(estimator, pairs, walks, seed, |g, members, b| {
        for (i, (&k, e)) in members.iter().zip(b.estimates).enumerate() {
            out[k] = Some(PairEstimate {
                estimate: e,
                group: g,
                batch_means: b.batches.iter().map(|c| c[i]).collect(),
            });
        }
    });
    out.into_iter()
        .map(|p| p.expect("every pair is in a group"))
        .collect()
}

/// Runs the walks of each incident direction of `pairs` (seeded by [`direction_seed`]) and
/// hands `visit` the group's index, the indices of its pairs and their estimates, group by
/// group in order of first appearance. The one walk loop of [`eval_pairs`] and
/// [`eval_pairs_batched`]; only the batched form keeps each pair's chunk means.
fn for_each_incidence(
    estimator: &dyn Estimator,
    pairs: &[(Vec3, Vec3)],
    walks: u64,
    seed: u64,
    mut visit: impl FnMut(usize, &[usize], Batched),
) {
    for (g, (wi, members)) in incidence_groups(pairs).iter().enumerate() {
        let wos: Vec<Vec3> = members.iter().map(|&k| pairs[k].1).collect();
        visit(
            g,
            members,
            estimator.eval_many_batched(*wi, &wos, walks, direction_seed(seed, *wi)),
        );
    }
}

/// Runs `walks` walks in chunks of [`CHUNK`] (in parallel, each chunk with its own stream from
/// `seed`), `walk(rng, acc)` adding one walk's contributions to `k` quantities to `acc` (all 0
/// when it is called) and returning whether it may have added any, and returns the running
/// sums of every chunk, in chunk order.
pub(crate) fn chunk_sums<Wk>(walks: u64, seed: u64, k: usize, walk: Wk) -> Vec<Vec<Sums>>
where
    Wk: Fn(&mut Pcg64, &mut [f64]) -> bool + Sync,
{
    (0..walks.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut rng = chunk_rng(seed, c);
            let mut sums = ManySums::new(k);
            let mut acc = vec![0.0f64; k];
            for i in 0..chunk_len(walks, c) {
                let n = (i + 1) as f64;
                if walk(&mut rng, &mut acc) {
                    sums.add_and_clear(n, &mut acc);
                } else {
                    sums.add_zeros(n);
                }
            }
            sums.into_sums()
        })
        .collect()
}

/// The sums of all chunks merged, per quantity.
pub(crate) fn merged(chunks: &[Vec<Sums>], k: usize) -> Vec<Sums> {
    let mut total = vec![Sums::default(); k];
    for sums in chunks {
        for (t, s) in total.iter_mut().zip(sums) {
            t.merge(s);
        }
    }
    total
}

/// Estimates `f(wi, wo) |wo.z|` for every `wo` in `wos` from one set of `walks` walks from
/// `wi`, with next-event estimation toward every `wo` at every hit, the escape averaged over
/// the depths of the flight's hits ([`super::engine::Start::at_hits`]). Parallel (rayon) and
/// deterministic for a given `seed`.
pub(crate) fn eval_many<W: Walker>(
    w: &W,
    wi: Vec3,
    wos: &[Vec3],
    walks: u64,
    seed: u64,
) -> Batched {
    let targets: Vec<Option<Target>> = wos.iter().map(|&wo| w.target(wo)).collect();
    let k = wos.len();
    let start = (wi.z != 0.0).then(|| w.start(wi).at_hits(true));
    let chunks = chunk_sums(walks, seed, k, |rng, acc| {
        let Some(start) = &start else { return false };
        let mut added = false;
        w.walk::<true, _>(start, rng, |hit, rng| {
            if !w.orders().includes(hit.order) {
                return;
            }
            added = true;
            let reach = hit.reach();
            for (a, t) in acc.iter_mut().zip(&targets) {
                let Some(t) = t else { continue };
                let p = w.phase(hit, t.wo, false, rng);
                if p > 0.0 {
                    *a += hit.weight * p * t.escape(&reach);
                }
            }
        });
        added
    });
    Batched {
        estimates: merged(&chunks, k).iter().map(Sums::estimate).collect(),
        batches: chunks
            .iter()
            .map(|sums| sums.iter().map(|s| s.mean).collect())
            .collect(),
    }
}

/// Fractions of the flux arriving from `wi` that leave on each side, from `walks` walks, calling
/// `progress(n)` after each chunk of `n` walks.
pub(crate) fn albedo<W: Walker>(
    w: &W,
    wi: Vec3,
    walks: u64,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> AlbedoEstimate {
    #[derive(Default)]
    struct Acc {
        r: Sums,
        t: Sums,
        bounces: u64,
        escaped: u64,
        truncated: f64,
    }
    let light_inside = wi.z < 0.0;
    let start = (wi.z != 0.0).then(|| w.start(wi));
    let n_chunks = walks.div_ceil(CHUNK);
    let chunks: Vec<Acc> = (0..n_chunks)
        .into_par_iter()
        .map(|c| {
            let mut rng = chunk_rng(seed, c);
            let mut acc = Acc::default();
            let n = chunk_len(walks, c);
            for _ in 0..n {
                let (mut r, mut t) = (0.0, 0.0);
                let end = match &start {
                    Some(start) => w.walk::<false, _>(start, &mut rng, |_, _| {}),
                    None => WalkEnd::Absorbed,
                };
                match end {
                    WalkEnd::Escaped(s) if w.orders().includes(s.order) => {
                        if (s.wo.z < 0.0) == light_inside {
                            r = s.weight;
                        } else {
                            t = s.weight;
                        }
                        acc.bounces += u64::from(s.order);
                        acc.escaped += 1;
                    }
                    WalkEnd::Truncated { weight } => acc.truncated += weight,
                    _ => {}
                }
                acc.r.add(r);
                acc.t.add(t);
            }
            progress(n);
            acc
        })
        .collect();
    let mut total = Acc::default();
    for a in &chunks {
        total.r.merge(&a.r);
        total.t.merge(&a.t);
        total.bounces += a.bounces;
        total.escaped += a.escaped;
        total.truncated += a.truncated;
    }
    let (r, t) = (total.r.estimate(), total.t.estimate());
    AlbedoEstimate {
        reflectance: r.mean,
        transmittance: t.mean,
        reflectance_stderr: r.stderr,
        transmittance_stderr: t.stderr,
        mean_bounces: (total.escaped > 0).then(|| total.bounces as f64 / total.escaped as f64),
        truncated: if walks > 0 {
            total.truncated / walks as f64
        } else {
            0.0
        },
        walks,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Welford's step with a zero value in its short form gives the general step's bits,
    /// for means of both signs (zeros included), tiny and huge values, and `n` from 1 on.
    #[test]
    fn zero_step_is_the_general_step_bit_for_bit() {
        use rand::{RngExt, SeedableRng};
        let mut rng = Pcg64::seed_from_u64(5);
        let special = [0.0, -0.0, 1e-310, -1e-310, 1e300, -1e300, 1.0, -1.0];
        for i in 0..200_000 {
            let mean = if i < special.len() * 8 {
                special[i % special.len()]
            } else {
                let e: f64 = rng.random::<f64>() * 40.0 - 20.0;
                (rng.random::<f64>() - 0.3) * 10f64.powf(e)
            };
            let m2 = if i % 8 == 0 {
                0.0
            } else {
                rng.random::<f64>() * 10.0
            };
            let n = 1.0 + (i % 3000) as f64;
            let inv_n = 1.0 / n;
            let (mut m_a, mut s_a) = (mean, m2);
            welford(&mut m_a, &mut s_a, 0.0, inv_n);
            let (mut m_b, mut s_b) = (mean, m2);
            welford_zero(&mut m_b, &mut s_b, inv_n);
            assert_eq!(
                (m_a.to_bits(), s_a.to_bits()),
                (m_b.to_bits(), s_b.to_bits()),
                "mean {mean:e}, m2 {m2:e}, n {n}"
            );
        }
    }

    fn estimate(reflectance: f64, transmittance: f64, walks: u64) -> AlbedoEstimate {
        AlbedoEstimate {
            reflectance,
            transmittance,
            reflectance_stderr: 0.0,
            transmittance_stderr: if transmittance > 0.0 { 0.01 } else { 0.0 },
            mean_bounces: Some(1.0),
            truncated: 0.0,
            walks,
        }
    }

    /// A side no walk reached has the one-sided 95% bound `1 - 0.05^(1/N)` (`(1 - p)^N = 0.05`
    /// holds for it; about 3/N for large N, and 0.95 for one walk), not a standard error of 0;
    /// a reached side keeps its standard error, which is undefined for one walk.
    #[test]
    fn unreached_side_reports_an_upper_bound_not_a_zero_stderr() {
        for n in [1u64, 2, 10, 40_000, 1_000_000_000] {
            let b = unreached_upper_bound(n);
            let coverage = (n as f64 * (-b).ln_1p()).exp();
            assert!(
                (coverage - 0.05).abs() < 1e-13,
                "N {n}: {b} gives {coverage}"
            );
        }
        assert!((unreached_upper_bound(1) - 0.95).abs() < 1e-15);
        assert!(
            (unreached_upper_bound(1_000_000_000) * 1e9 / 0.05f64.ln().abs() - 1.0).abs() < 1e-8
        );
        let a = estimate(0.0, 1.0, 40_000);
        let bound = SideError::UpperBound(unreached_upper_bound(40_000));
        assert_eq!(a.reflectance_error(), bound);
        assert_eq!(a.reflectance_error().stderr(), None);
        assert_eq!(a.transmittance_error(), SideError::Stderr(0.01));
        assert_eq!(a.transmittance_error().upper_bound(), None);
        let one = estimate(0.0, 1.0, 1);
        assert_eq!(
            one.reflectance_error(),
            SideError::UpperBound(unreached_upper_bound(1))
        );
        assert_eq!(one.transmittance_error(), SideError::Undefined);
    }
}
