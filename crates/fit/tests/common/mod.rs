//! Helpers shared by the fitting tests: synthetic samples from known models, and the Walter
//! 2007 measurements read from the shared folder.

#![allow(dead_code)]

use std::path::PathBuf;

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use stfit_core::bsdf::Masking;
use stfit_fit::{Measurement, ModelParams, Sample};

/// Incidence angles of the synthetic grid (degrees).
pub const THETA_I: [f64; 4] = [0.0, 30.0, 60.0, 80.0];

/// A synthetic sample of `params` on the grid `theta_i in THETA_I`, `theta_o = 106, 108, ...,
/// 254`, with multiplicative noise `L (1 + noise e)`, `e` uniform with unit variance
/// (`[-sqrt 3, sqrt 3]`), from a fixed seed.
pub fn synthetic(params: &ModelParams, noise: f64, seed: u64) -> Sample {
    let mut rng = Pcg64::seed_from_u64(seed);
    let mut points = Vec::new();
    for ti in THETA_I {
        for k in 0..75 {
            let to = 106.0 + 2.0 * k as f64;
            let l = params
                .l_single(ti, to, 1.51, Masking::Separable)
                .expect("valid test parameters");
            let e = (2.0 * rng.random::<f64>() - 1.0) * 3f64.sqrt();
            points.push(Measurement {
                theta_i_deg: ti,
                theta_o_deg: to,
                l: l * (1.0 + noise * e),
                weight: 1.0,
            });
        }
    }
    Sample {
        name: format!("synthetic-{}", params.kind.name()),
        points,
    }
}

/// The shared folder: `$STFIT_SHARED`, else `../shared` beside the repository root.
pub fn shared_dir() -> PathBuf {
    match std::env::var_os("STFIT_SHARED") {
        Some(p) => PathBuf::from(p),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"),
    }
}

/// The Walter 2007 samples (frosted, etched, ground) from `measurements.csv` (columns
/// `sample,theta_i_deg,theta_o_deg,sqrt_L`). Panics with a clear message if the file is
/// missing: the tests that use it must not pass silently without it.
pub fn walter_samples() -> Vec<Sample> {
    let path = shared_dir().join("data/walter2007/measurements.csv");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "cannot read the Walter 2007 data at {} ({e}); set STFIT_SHARED to the shared folder",
            path.display()
        )
    });
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(
        header,
        ["sample", "theta_i_deg", "theta_o_deg", "sqrt_L"],
        "unexpected columns in {}",
        path.display()
    );
    let mut samples: Vec<Sample> = Vec::new();
    for line in lines.filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| -> f64 { f[i].trim().parse().expect("a number") };
        let m = Measurement {
            theta_i_deg: num(1),
            theta_o_deg: num(2),
            l: num(3) * num(3),
            weight: 1.0,
        };
        match samples.iter_mut().find(|s| s.name == f[0]) {
            Some(s) => s.points.push(m),
            None => samples.push(Sample {
                name: f[0].to_string(),
                points: vec![m],
            }),
        }
    }
    samples
}
