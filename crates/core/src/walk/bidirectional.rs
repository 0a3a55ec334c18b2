//! Bidirectional estimation of the height-field walk's BSDF.
//!
//! Next-event estimation from `wi` alone misses paths that it draws rarely but that carry much
//! of `f(wi, wo)`. At normal incidence on glass (alpha 0.3, gamma 3), the orders >= 2 toward
//! the straight-through direction come mostly from light reflected steeply downward by a
//! near-vertical facet, then refracted through a flat one: the walk from `wi` draws the first
//! reflection once in 10^5 walks, and the estimate of that one walk is then 10^5 times the
//! mean. Walked from `wo` (by reciprocity, `f(wi, wo) / n_o^2 = f(wo, wi) / n_i^2`), the same
//! path is drawn often and estimated in small steps. So the estimate adds walks from both ends,
//! each with next-event estimation averaged over its last flight, and weights every path by the
//! balance heuristic of multiple importance sampling (Veach 1997) over the densities with which
//! the two ends choose its directions:
//!
//! ```text
//! w_wi = n_wi p_wi / (n_wi p_wi + n_wo p_wo),   w_wo = 1 - w_wi,
//! ```
//!
//! `p_wi` the product of the facet sampling densities ([`Facet::side_pdf`]) of the path's
//! directions as the walk from `wi` chose them, `p_wo` the same from `wo`, `n` the numbers of
//! walks. The weights leave depths out, so both ends share them whatever depths they drew, and
//! each can average over its last flight; they sum to 1 for every path, which keeps the
//! combination unbiased. The walk's throughput is reciprocal path by path, not only in the
//! mean, which the combination also needs (both are tested here).

use super::engine::{Hit, Target, Walker};
use super::estimate::{
    Batched, Estimate, Sums, chunk_rng, chunk_sums, chunk_walks, direction_seed, merged,
};
use super::{Facet, HeightFieldHit, Microsurface};
use crate::math::Vec3;
use crate::ndf::Ndf;
use rayon::prelude::*;

/// What the direction densities need of a scattering event.
#[derive(Debug, Clone, Copy)]
struct Vertex {
    /// Unit direction back toward where the walker came from.
    wi: Vec3,
    /// The side the walker arrived on.
    inside: bool,
    /// `sigma` seen by the arriving walker.
    sigma: f64,
    order: u32,
}

/// Along one walk, the ratio `p_other / p_this` of the densities with which the opposite end
/// (a walk from the other direction, with next-event estimation at this walk's first event)
/// and this walk choose the directions of the path up to the current event, without the
/// factor that depends on the target.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PathRatio {
    prev: Option<Vertex>,
    ratio: f64,
}

impl PathRatio {
    pub fn new() -> Self {
        Self {
            prev: None,
            ratio: 1.0,
        }
    }

    /// Extends the path to the event `hit`.
    pub fn advance<N: Ndf, F: Facet>(&mut self, s: &Microsurface<N, F>, hit: &Hit) {
        if let Some(p) = self.prev {
            let ndf = s.ndf();
            let facet = s.facet();
            let w = -hit.wi;
            // The walker's direction out of p and its density.
            let this = facet.side_pdf(
                &HeightFieldHit::with_sigma(ndf, p.wi, p.inside, p.sigma),
                w,
                hit.inside,
            );
            // The opposite walk arrives at p along -w (seeing sigma(w_side) = w_side.z + the
            // sigma this flight saw) and leaves toward p.wi; at the first event of this walk it
            // estimates instead of drawing.
            let other = if p.order >= 2 {
                let wz = if hit.inside { -w.z } else { w.z };
                facet.side_pdf(
                    &HeightFieldHit::with_sigma(ndf, w, hit.inside, wz + hit.sigma),
                    p.wi,
                    p.inside,
                )
            } else {
                Some(1.0)
            };
            self.ratio *= other.unwrap_or(0.0) / this.unwrap_or(0.0);
        }
        self.prev = Some(Vertex {
            wi: hit.wi,
            inside: hit.inside,
            sigma: hit.sigma,
            order: hit.order,
        });
    }

    /// The whole ratio for next-event estimation toward `t` from the current event.
    pub fn toward<N: Ndf, F: Facet>(&self, s: &Microsurface<N, F>, t: &Target) -> f64 {
        let cur = self.prev.expect("advanced to an event");
        if cur.order < 2 {
            return self.ratio;
        }
        // The opposite walk arrives along -wo, seeing sigma(wo_side) = |wo.z| (1 + Lambda(wo)).
        let sigma = t.wo.z.abs() * (1.0 + t.lambda);
        let other = s.facet().side_pdf(
            &HeightFieldHit::with_sigma(s.ndf(), t.wo, t.inside, sigma),
            cur.wi,
            cur.inside,
        );
        self.ratio * other.unwrap_or(0.0)
    }
}

/// The ratio `eval(wi, wo) / eval(wo, wi)` of a walk with relative index `eta` below the
/// interface: `n_o^2 |wo.z| / (n_i^2 |wi.z|)`, by `f(wi, wo) / n_o^2 = f(wo, wi) / n_i^2` and
/// `eval = f |wo.z|`.
pub(crate) fn reciprocity(eta: f64, wi: Vec3, wo: Vec3) -> f64 {
    let n2 = |w: Vec3| if w.z < 0.0 { eta * eta } else { 1.0 };
    n2(wo) * wo.z.abs() / (n2(wi) * wi.z.abs())
}

/// Whether the surface's facets give their sampling densities in closed form, which the
/// bidirectional estimate needs.
pub(crate) fn supported<N: Ndf, F: Facet>(s: &Microsurface<N, F>) -> bool {
    let z = Vec3::z();
    s.facet()
        .side_pdf(&HeightFieldHit::new(s.ndf(), z, false), z, false)
        .is_some()
}

/// One walk from `start` with next-event estimation toward `targets`, each path weighted by
/// the balance heuristic against the walks from the other end, `kappa` times as many: adds
/// the weighted estimates to `acc`, and returns whether it may have added any (whether an
/// event of a selected order estimated).
fn weighted_walk<N: Ndf, F: Facet, R: rand::Rng + ?Sized>(
    s: &Microsurface<N, F>,
    start: &super::engine::Start,
    targets: &[Option<Target>],
    kappa: f64,
    rng: &mut R,
    acc: &mut [f64],
) -> bool {
    let orders = s.orders();
    let mut path = PathRatio::new();
    let mut added = false;
    s.walk::<true, _>(start, rng, |hit, rng| {
        path.advance(s, hit);
        if !orders.includes(hit.order) {
            return;
        }
        added = true;
        let reach = hit.reach();
        for (a, t) in acc.iter_mut().zip(targets) {
            let Some(t) = t else { continue };
            let p = Walker::phase(s, hit, t.wo, false, rng);
            if p > 0.0 {
                let weight = 1.0 / (1.0 + kappa * path.toward(s, t));
                let c = hit.weight * p * t.escape(&reach) * weight;
                // A weight of 0 on an infinite ratio, and nothing else, can give a NaN.
                if c.is_finite() {
                    *a += c;
                }
            }
        }
    });
    added
}

/// Distinguishes the random numbers of the walks from `wo` from those of walks from `wi`.
const FROM_WO: u64 = 0x5bd1_e995_27d4_eb2f;

/// The bidirectional estimate of `f(wi, wo) |wo.z|` for every `wo` in `wos` (module
/// documentation): `walks` walks from `wi` toward every `wo`, and from each `wo` toward `wi`
/// `fraction` as many (at least two per chunk), seeded by `seed` and `wo`.
///
/// The walks from `wo` follow the chunks of those from `wi`: chunk `c` has `fraction` times
/// the walks of chunk `c` from `wi`, and its own random numbers. Batch `c` of the result is
/// the sum of the two chunks' estimates, and the estimate is the walk-weighted mean of the
/// batches (weights of the chunks from `wi`), so the batches are independent and
/// [`Batched`]'s relations hold.
pub(crate) fn eval_many<N: Ndf, F: Facet>(
    s: &Microsurface<N, F>,
    wi: Vec3,
    wos: &[Vec3],
    walks: u64,
    fraction: f64,
    seed: u64,
) -> Batched {
    let k = wos.len();
    let targets: Vec<Option<Target>> = wos.iter().map(|&wo| s.target(wo)).collect();
    let from_wi = (wi.z != 0.0).then(|| s.start(wi));
    // The ratio of walks from wo to walks from wi the weights assume.
    let kappa = fraction;
    let forward = chunk_sums(walks, seed, k, |rng, acc| match &from_wi {
        Some(start) => weighted_walk(s, start, &targets, kappa, rng, acc),
        None => false,
    });
    let lens = chunk_walks(walks);
    let toward_wi = [s.target(wi)];
    let eta = s.facet().relative_index();
    // The walks from each wo: per target, the scale from eval(wo, wi) to eval(wi, wo) and the
    // sums of its chunks (none where it has no walks), every (target, chunk) in parallel.
    let jobs: Vec<(usize, usize)> = match toward_wi[0] {
        Some(_) => targets
            .iter()
            .enumerate()
            .filter(|(_, t)| t.is_some())
            .flat_map(|(j, _)| (0..lens.len()).map(move |c| (j, c)))
            .collect(),
        None => Vec::new(),
    };
    let starts: Vec<Option<(super::engine::Start, u64)>> = targets
        .iter()
        .map(|t| t.map(|t| (s.start(t.wo), direction_seed(seed ^ FROM_WO, t.wo))))
        .collect();
    let sums: Vec<Sums> = jobs
        .par_iter()
        .map(|&(j, c)| {
            let (start, seed) = starts[j].expect("a job per valid target");
            chunk_like(lens[c], fraction, seed, c, |rng, acc| {
                weighted_walk(s, &start, &toward_wi, 1.0 / kappa, rng, acc);
            })
        })
        .collect();
    let mut reverse: Vec<(f64, Vec<Sums>)> = targets
        .iter()
        .map(|t| match t {
            Some(t) if toward_wi[0].is_some() => (reciprocity(eta, wi, t.wo), Vec::new()),
            _ => (0.0, Vec::new()),
        })
        .collect();
    for (&(j, _), sum) in jobs.iter().zip(sums) {
        reverse[j].1.push(sum);
    }
    let total = walks as f64;
    let estimates = merged(&forward, k)
        .iter()
        .zip(&reverse)
        .map(|(f, (c, sums))| {
            let f = f.estimate();
            // The walk-weighted mean of the chunks from wo, and its standard error.
            let (mut mean, mut var) = (0.0, 0.0);
            for (sum, &n) in sums.iter().zip(&lens) {
                let (w, e) = (n as f64 / total, sum.estimate());
                mean += w * e.mean;
                var += (w * e.stderr).powi(2);
            }
            Estimate {
                mean: f.mean + c * mean,
                stderr: f.stderr.hypot(c * var.sqrt()),
            }
        })
        .collect();
    let batches = forward
        .iter()
        .enumerate()
        .map(|(chunk, sums)| {
            sums.iter()
                .zip(&reverse)
                .map(|(f, (c, r))| f.mean + r.get(chunk).map_or(0.0, |r| c * r.mean))
                .collect()
        })
        .collect();
    Batched { estimates, batches }
}

/// One quantity's sums over chunk `chunk` of walks from `wo`: `fraction` times the `len` walks
/// of the matching chunk from `wi`, at least two (`walks_like`; [`super::walks_from_each_wo`]
/// counts them), with the chunk's own stream from `seed`.
fn chunk_like<Wk>(len: u64, fraction: f64, seed: u64, chunk: usize, walk: Wk) -> Sums
where
    Wk: Fn(&mut rand_pcg::Pcg64, &mut [f64]),
{
    let walks = super::estimate::walks_like(len, fraction);
    let mut rng = chunk_rng(seed, chunk as u64);
    let mut sums = Sums::default();
    let mut acc = [0.0];
    for _ in 0..walks {
        acc[0] = 0.0;
        walk(&mut rng, &mut acc);
        sums.add(acc[0]);
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ndf::StudentT;
    use crate::walk::DielectricFacet;
    use crate::walk::engine::{Flight, WalkEnd, mirrored_depth};
    use rand::SeedableRng;
    use rand_pcg::Pcg64;

    /// The real events of a walk from `wi` (not the one placed on the flight that left).
    fn record<N: Ndf>(s: &Microsurface<N, DielectricFacet>, wi: Vec3, rng: &mut Pcg64) -> Vec<Hit> {
        let mut hits = vec![];
        let end = s.walk::<true, _>(&s.start(wi), rng, |hit, _| hits.push(*hit));
        if let WalkEnd::Escaped(e) = end {
            hits.retain(|h| h.order <= e.order);
        }
        hits
    }

    /// The event of the opposite walk at a vertex, reached along `-w` (macro frame) on side
    /// `inside` from depth `from`, at depth `depth`.
    fn reverse_hit<N: Ndf>(
        ndf: &N,
        w: Vec3,
        inside: bool,
        from: f64,
        depth: f64,
        order: u32,
    ) -> Hit {
        let u = if inside { w } else { -w };
        let lambda = ndf.lambda(u);
        let flight = if u.z > 0.0 {
            Flight::Up { from, lambda }
        } else {
            Flight::Down {
                from,
                rate: -lambda,
            }
        };
        Hit {
            wi: w,
            inside,
            sigma: u.z * lambda,
            sigma_nee: u.z * lambda,
            depth,
            flight,
            weight: 1.0,
            order,
        }
    }

    fn depth_on(h: &Hit, inside: bool) -> f64 {
        if h.inside == inside {
            h.depth
        } else {
            mirrored_depth(h.depth)
        }
    }

    /// The events of the walk from `wo` that retraces the path `hits` (from `wi`) backward.
    fn retrace<N: Ndf>(s: &Microsurface<N, DielectricFacet>, hits: &[Hit], wo: Vec3) -> Vec<Hit> {
        let k = hits.len();
        let inside = wo.z < 0.0;
        let mut out = vec![reverse_hit(
            s.ndf(),
            wo,
            inside,
            0.0,
            depth_on(&hits[k - 1], inside),
            1,
        )];
        for j in (0..k - 1).rev() {
            let next = &hits[j + 1];
            out.push(reverse_hit(
                s.ndf(),
                -next.wi,
                next.inside,
                next.depth,
                depth_on(&hits[j], next.inside),
                (k - j) as u32,
            ));
        }
        out
    }

    /// `p_reverse / p_forward` of a recorded path toward `wo`, depths included: flight densities
    /// `rate exp(-rate |dt|)` (reverse rates differ by 1), visible-normal direction densities,
    /// and the Jacobian `1 / (exp(t) - 1)` of the mirrored depth where the two walks arrive at
    /// an event from different sides.
    fn full_ratio<N: Ndf>(s: &Microsurface<N, DielectricFacet>, hits: &[Hit], t: &Target) -> f64 {
        let mut q = PathRatio::new();
        let mut ratio = 1.0;
        for (i, h) in hits.iter().enumerate() {
            q.advance(s, h);
            let (from, rate, back) = match h.flight {
                Flight::Up { from, lambda } => (from, lambda, 1.0 + lambda),
                Flight::Down { from, rate } => (from, rate, rate - 1.0),
                Flight::Sampled => unreachable!(),
            };
            if i == 0 {
                ratio /= rate * (-rate * h.depth).exp();
            } else {
                ratio *= back / rate * (h.depth - from).exp();
                if hits[i - 1].inside != h.inside {
                    ratio /= hits[i - 1].depth.exp_m1();
                }
            }
        }
        let last = hits.last().unwrap();
        let rate = 1.0 + t.lambda;
        ratio *= rate * (-rate * depth_on(last, t.inside)).exp();
        if t.inside != last.inside {
            ratio /= last.depth.exp_m1();
        }
        ratio * q.toward(s, t)
    }

    fn surface() -> Microsurface<StudentT, DielectricFacet> {
        Microsurface::new(
            StudentT::new(0.6, 2.5).unwrap(),
            DielectricFacet::new(1.5).unwrap(),
        )
    }

    fn targets() -> [Vec3; 2] {
        [
            Vec3::new(-0.3, 0.2, 0.93).normalize(),
            Vec3::new(0.2, -0.4, -0.89).normalize(),
        ]
    }

    /// The two strategies' direction-density ratios of one path are reciprocal, `q_forward
    /// q_reverse = 1`, so the balance-heuristic weights of a path sum to 1 whichever end drew
    /// it: the combination is unbiased.
    #[test]
    fn direction_ratios_of_both_ends_are_reciprocal() {
        let s = surface();
        let mut rng = Pcg64::seed_from_u64(3);
        let wi = Vec3::new(0.5, 0.1, 0.86).normalize();
        let ti = s.target(wi).unwrap();
        let mut checked = 0;
        for _ in 0..2000 {
            let hits = record(&s, wi, &mut rng);
            if hits.len() < 2 {
                continue;
            }
            for wo in targets() {
                let t = s.target(wo).unwrap();
                let mut f = PathRatio::new();
                hits.iter().for_each(|h| f.advance(&s, h));
                let mut r = PathRatio::new();
                retrace(&s, &hits, wo).iter().for_each(|h| r.advance(&s, h));
                let (qf, qr) = (f.toward(&s, &t), r.toward(&s, &ti));
                if qf > 0.0 && qr > 0.0 && qf.is_finite() && qr.is_finite() {
                    assert!(
                        (qf * qr - 1.0).abs() < 1e-9,
                        "order {}: {qf} * {qr}",
                        hits.len()
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 50, "{checked}");
    }

    /// Path by path, the throughput from `wi` is [`reciprocity`] times that from `wo`: the
    /// ratio of the two ends' next-event estimates (depths drawn, not averaged) equals the
    /// ratio of their path densities. The combination needs this pointwise, not only in the
    /// mean.
    #[test]
    fn path_throughputs_are_reciprocal() {
        let s = surface();
        let mut rng = Pcg64::seed_from_u64(4);
        let wi = Vec3::new(0.5, 0.1, 0.86).normalize();
        let ti = s.target(wi).unwrap();
        let mut checked = 0;
        for _ in 0..2000 {
            let hits = record(&s, wi, &mut rng);
            if hits.is_empty() {
                continue;
            }
            for wo in targets() {
                let t = s.target(wo).unwrap();
                let back = retrace(&s, &hits, wo);
                // Next-event estimates at the depths drawn: the true sigma, no averaging.
                let sampled = |h: &Hit| Hit {
                    sigma_nee: h.sigma,
                    ..*h
                };
                let (last, first) = (sampled(hits.last().unwrap()), *back.last().unwrap());
                let xf = Walker::phase(&s, &last, wo, false, &mut rng)
                    * (-depth_on(&last, t.inside) * t.lambda).exp();
                let xr = Walker::phase(&s, &first, wi, false, &mut rng)
                    * (-depth_on(&first, ti.inside) * ti.lambda).exp();
                let q = full_ratio(&s, &hits, &t);
                if xf > 0.0 && xr > 0.0 && q.is_finite() && q > 0.0 {
                    let ratio = xf / (reciprocity(1.5, wi, wo) * xr);
                    assert!(
                        (ratio / q - 1.0).abs() < 1e-8,
                        "order {}: {ratio} vs {q}",
                        hits.len()
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 200, "{checked}");
    }
}
