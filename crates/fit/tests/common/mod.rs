//! Helpers shared by the fitting tests: synthetic samples from known models, and the Walter
//! 2007 measurements read from the shared folder.

#![allow(dead_code)]

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use stfit_fit::{Gamma, Measurement, Model, ModelKind, Sample};

/// Incidence angles of the synthetic grid (degrees).
pub const THETA_I: [f64; 4] = [0.0, 30.0, 60.0, 80.0];

/// The single-scattering model of `kind` (eta 1.51, separable masking), `gamma` used only by
/// Student-T.
pub fn truth(kind: ModelKind, alpha: f64, gamma: f64, scale: f64) -> Model {
    let gamma = if kind == ModelKind::StudentT {
        Gamma::Free(gamma)
    } else {
        Gamma::NotApplicable
    };
    Model::single(kind, alpha, gamma, scale)
}

/// The Walter grid: `theta_i in THETA_I`, `theta_o = 106, 108, ..., 254`.
pub fn grid() -> Vec<(f64, f64)> {
    THETA_I
        .iter()
        .flat_map(|&ti| (0..75).map(move |k| (ti, 106.0 + 2.0 * k as f64)))
        .collect()
}

/// A synthetic sample of `model` on [`grid`], with multiplicative noise `L (1 + noise e)`, `e`
/// uniform with unit variance (`[-sqrt 3, sqrt 3]`), from a fixed seed.
pub fn synthetic(model: &Model, noise: f64, seed: u64) -> Sample {
    let mut rng = Pcg64::seed_from_u64(seed);
    let angles = grid();
    let l = model.predict(&angles).expect("valid test parameters");
    let points = angles
        .iter()
        .zip(l)
        .map(|(&(ti, to), l)| {
            let e = (2.0 * rng.random::<f64>() - 1.0) * 3f64.sqrt();
            Measurement::in_plane(ti, to, l * (1.0 + noise * e), 1.0)
        })
        .collect();
    Sample {
        name: format!("synthetic-{}", model.kind.name()),
        points,
    }
}

/// The Walter 2007 samples (frosted, etched, ground) from the shared folder, or `None` (with one
/// line saying `test` did not run) when it is absent; under `CI=true` its absence fails.
pub fn walter_samples(test: &str) -> Option<Vec<Sample>> {
    let path = stfit_test_support::walter_measurements(test)?;
    Some(
        stfit_fit::load_path(&path)
            .expect("the Walter data load")
            .samples,
    )
}
