//! Test cases shared by the walk tests.
#![allow(dead_code)]

use stfit_core::Vec3;
use stfit_core::math::spherical_direction;
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};

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
