//! Multiple scattering on a Smith microsurface by the height-field random walk
//! (Heitz et al. 2016, "Multiple-scattering microfacet BSDFs with the Smith model"), for any
//! [`Ndf`](crate::ndf::Ndf) with visible-normal sampling on the whole sphere and any facet BSDF
//! (d'Eon 2023).
//!
//! # The model
//!
//! The microsurface is a random height field whose normals follow the NDF, with uncorrelated
//! heights and slopes (the Smith assumption). A ray at height `h` travelling along `w` (upward
//! in the frame of the surface on its side) leaves the surface without hitting it with
//! probability `G1(w, h) = C1(h)^Lambda(w)`, where `C1` is the height CDF; otherwise the height of
//! its next hit follows by inverting that. At each hit the facet normal is drawn from the
//! distribution of normals visible from the ray, and the facet BSDF scatters the ray. A facet
//! that transmits (a dielectric) sends the ray to the other side of the interface, where it walks
//! on the mirrored surface seen from below (Heitz et al. 2016, section 6).
//!
//! # Heights as depths
//!
//! The walk sees heights only through the height CDF `C1(h)`, so it tracks the *depth*
//! `t = -ln C1(h) >= 0` below the top of the surface on the walker's side. This is the same walk
//! for every continuous height distribution (uniform heights are `h = 2 exp(-t) - 1`, Gaussian
//! heights `h = Phi^-1(exp(-t))`), which is why results do not depend on the choice. Then
//! `G1(w, h) = exp(-t Lambda(w))`: free flights are exponential in `t` with rate `Lambda(w)` (a
//! ray leaves when its flight takes it above `t = 0`; downward, `Lambda <= -1` and it always
//! hits), and crossing to the mirrored surface maps `t` to `-ln(1 - exp(-t))` (the mirrored
//! surface has height CDF `1 - C1(h)`). Depths keep full precision however deep a walk goes,
//! where a height near the bottom of a uniform distribution would round to it.
//!
//! # Full-sphere NDFs
//!
//! [`NullMicrosurface`] runs the same walk for any bounded NDF on the whole sphere
//! ([`SphereNdf`](crate::sphere::SphereNdf): porous blends, von Mises-Fisher lobes, and the
//! height-field NDFs as special cases) by null scattering against a constant majorant.
//!
//! # What is estimated
//!
//! `eval(wi, wo)` returns `f(wi, wo) |wo.z|` with no radiance `1/eta^2` scaling, as every
//! [`Bsdf`](crate::bsdf::Bsdf) in this crate: the walk from `wi` adds, for every flight, the
//! phase function toward `wo` at the facet the flight ends on times the probability of leaving
//! toward `wo` from there (next-event estimation). On the height-field walk the escape is
//! averaged over the depths the flight can reach in closed form; in the bidirectional batch
//! estimates below, so is the whole product, including the probability that the flight hits at
//! all: the same mean, without the heavy tail of steep upward flights, which rarely hit but
//! then see few facets and a large phase function. Walks are never cut at a fixed order; a
//! safety cap of [`MAX_BOUNCES`] scattering events (far above any real path) ends runaway
//! walks, and the estimators report the energy it drops.
//!
//! # Bidirectional estimates
//!
//! Next-event estimation from `wi` alone draws some paths too rarely for the share of
//! `f(wi, wo)` they carry (light reflected steeply downward by a near-vertical facet, then
//! refracted straight through: once in 10^5 walks at normal incidence on alpha 0.3, with an
//! estimate 10^5 times the mean). The batch estimates of a [`Microsurface`] with closed-form
//! facets ([`Estimator`]: `eval_many`, [`eval_pairs`]) therefore also walk from each `wo`
//! toward `wi` (by reciprocity, `f(wi, wo) / n_o^2 = f(wo, wi) / n_i^2`) and weight every path
//! by the balance heuristic over the densities with which the two ends choose its directions.
//! At the hardest directions this cuts the standard error of 20,000 walks from the size of the
//! value to a few percent (`cargo run --release -p stfit-core --example walk_variance`). The
//! walks from `wo` serve one direction each: [`Microsurface::with_walks_from_wo`] sets how
//! many ([`WALKS_FROM_WO`] per walk from `wi` by default, 0 for `wi` alone).

mod bidirectional;
mod cost;
mod engine;
mod estimate;
mod facet;
mod microsurface;
mod null;

pub use cost::{
    LONG_RUN_SECONDS, PILOT_INCIDENCES, PILOT_MAX_WALKS, PILOT_SECONDS, PILOT_SHARE, PILOT_WALKS,
    WalkCost, describe_seconds, long_run_note, pilot_seed,
};
pub use engine::{WalkEnd, WalkSample};
pub use estimate::{
    AlbedoEstimate, Batched, CHUNK, Estimate, Estimator, PairEstimate, SideError, chunk_walks,
    defined_stderr, direction_seed, distinct_incidences, eval_pairs, eval_pairs_batched,
    eval_pairs_walk_count, eval_pairs_with_progress, unreached_upper_bound, walks_from_each_wo,
};
pub use facet::{
    BsdfFacet, ConductorFacet, DielectricFacet, Facet, FacetSample, HeightFieldHit,
    LambertianFacet, VisibleNormals,
};
pub use microsurface::Microsurface;
pub use null::{MAX_NULL_MAJORANT, NullHit, NullMicrosurface};

/// Largest number of walks of one estimate (per incident direction, per table cell): 10^9
/// walks take minutes to hours, and the run's per-chunk results stay small.
pub const MAX_WALKS: u64 = 1_000_000_000;

/// Validates a number of walks of one estimate: in `[1, MAX_WALKS]`. (With one walk the
/// estimate has no standard error: see [`defined_stderr`].)
pub fn check_walks(walks: u64) -> Result<u64, crate::ParamError> {
    if (1..=MAX_WALKS).contains(&walks) {
        Ok(walks)
    } else {
        Err(crate::ParamError::OutOfRange {
            name: "walks",
            value: walks as f64,
            expected: "in [1, 1e9]",
        })
    }
}

/// Walks from each direction `wo` per walk from `wi` in the batch estimates of a
/// [`Microsurface`] ([`Estimator`]; see [`Microsurface::with_walks_from_wo`]).
pub const WALKS_FROM_WO: f64 = 0.25;

/// Validates a number of walks from each `wo` per walk from `wi`
/// ([`Microsurface::with_walks_from_wo`]): in `[0, 16]`.
pub fn check_walks_from_wo(fraction: f64) -> Result<f64, crate::ParamError> {
    if (0.0..=16.0).contains(&fraction) {
        Ok(fraction)
    } else {
        Err(crate::ParamError::OutOfRange {
            name: "walks_from_wo",
            value: fraction,
            expected: "in [0, 16]",
        })
    }
}

use crate::bsdf::Masking;
use serde::{Deserialize, Serialize};

/// Separable masking asked of a model with orders >= 2 (see
/// [`ScatteringOrders::check_masking`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaskingError {
    pub orders: ScatteringOrders,
}

impl std::fmt::Display for MaskingError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "orders {} come from the random walk, whose masking is height-correlated by \
             construction: masking must be correlated",
            self.orders.name()
        )
    }
}

impl std::error::Error for MaskingError {}

/// Default number of walks of the Monte Carlo estimates of `eval`: walks per distinct
/// incident direction.
pub const DEFAULT_EVAL_WALKS: u64 = 100_000;

/// Default number of walks of an albedo estimate.
pub const DEFAULT_ALBEDO_WALKS: u64 = 1_000_000;

/// Safety cap on the number of scattering events in one walk. No physical path comes near it
/// (mean path lengths are a few events); a walk that reaches it is dropped and counted.
pub const MAX_BOUNCES: u32 = 1_000_000;

/// Which scattering orders a model includes, the one vocabulary of every command and type:
/// `single` is order 1 (paths that scatter exactly once: the single-scattering BSDF with
/// height-correlated masking), `multiple` is orders >= 2 only, `all` is the full BSDF (every
/// order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScatteringOrders {
    /// Order 1: paths that scatter exactly once.
    Single,
    /// Orders >= 2: paths that scatter two or more times.
    Multiple,
    /// Every order: the full BSDF.
    #[default]
    All,
}

impl std::str::FromStr for ScatteringOrders {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "single" => Ok(Self::Single),
            "multiple" => Ok(Self::Multiple),
            "all" => Ok(Self::All),
            _ => Err(format!(
                "unknown orders '{s}' (expected single, multiple or all)"
            )),
        }
    }
}

impl ScatteringOrders {
    /// The name used on the command line and in files: `single`, `multiple` or `all`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Single => "single",
            Self::Multiple => "multiple",
            Self::All => "all",
        }
    }

    /// The masking of a model with these orders unless told otherwise: separable for single
    /// scattering (Walter et al. 2007, what the published fits used), height-correlated
    /// otherwise (the random walk's, by construction).
    pub fn default_masking(self) -> Masking {
        match self {
            Self::Single => Masking::Separable,
            Self::Multiple | Self::All => Masking::Correlated,
        }
    }

    /// `masking`, if a model with these orders can have it: orders >= 2 come from the random
    /// walk, whose masking is height-correlated by construction, so `multiple` and `all` take
    /// only [`Masking::Correlated`]. The one place this rule is enforced.
    pub fn check_masking(self, masking: Masking) -> Result<Masking, MaskingError> {
        match (self, masking) {
            (Self::Multiple | Self::All, Masking::Separable) => Err(MaskingError { orders: self }),
            _ => Ok(masking),
        }
    }

    /// The masking given, or [`ScatteringOrders::default_masking`], checked by
    /// [`ScatteringOrders::check_masking`].
    pub fn masking(self, given: Option<Masking>) -> Result<Masking, MaskingError> {
        self.check_masking(given.unwrap_or(self.default_masking()))
    }

    /// Whether a path with `order` scattering events is included.
    #[inline]
    pub fn includes(self, order: u32) -> bool {
        match self {
            Self::Single => order == 1,
            Self::Multiple => order >= 2,
            Self::All => order >= 1,
        }
    }

    /// The highest order that can contribute: walks stop there.
    #[inline]
    pub fn last_order(self) -> u32 {
        match self {
            Self::Single => 1,
            Self::Multiple | Self::All => u32::MAX,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Walk counts are refused outside `[1, MAX_WALKS]`, before any run allocates for them.
    #[test]
    fn walk_counts_outside_the_range_are_refused() {
        for walks in [1, 20_000, MAX_WALKS] {
            assert_eq!(check_walks(walks), Ok(walks));
        }
        for walks in [0, MAX_WALKS + 1, u64::MAX] {
            assert!(check_walks(walks).is_err(), "{walks}");
        }
    }
}
