//! Test cases shared by the walk tests.
#![allow(dead_code)]

use stfit_core::Vec3;
use stfit_core::math::spherical_direction;
use stfit_core::ndf::{AnyNdf, Ggx};

/// The NDFs under test at the given roughnesses.
pub fn ndfs(alphas: &[f64]) -> Vec<AnyNdf> {
    let mut out = Vec::new();
    for &a in alphas {
        out.push(Ggx::new(a).unwrap().into());
    }
    out
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
