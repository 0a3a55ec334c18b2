//! Speed of single fits and of `--model all` on a 300-point sample, and of one
//! multiple-scattering model evaluation (the unit of cost of `--scattering multiple`).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use stfit_core::bsdf::Masking;
use stfit_fit::fit::{fit_all, fit_sample};
use stfit_fit::{FitOptions, Measurement, ModelKind, ModelParams, ModelSpec, Optimizer, Sample};

/// A 300-point Walter-like sample (theta_i 0, 30, 60, 80; theta_o 106..254 by 2) of a
/// Student-T surface with 2% deterministic ripple, so the fit does not start at a zero residual.
fn sample() -> Sample {
    let truth = ModelParams {
        kind: ModelKind::StudentT,
        alpha: 0.4,
        gamma: 2.7,
        scale: 0.8,
    };
    let mut points = Vec::new();
    for ti in [0.0, 30.0, 60.0, 80.0] {
        for k in 0..75 {
            let to = 106.0 + 2.0 * k as f64;
            let l = truth.l_single(ti, to, 1.51, Masking::Separable).unwrap();
            points.push(Measurement {
                theta_i_deg: ti,
                theta_o_deg: to,
                l: l * (1.0 + 0.02 * (k as f64 * 1.7).sin()),
                weight: 1.0,
            });
        }
    }
    Sample {
        name: "bench".into(),
        points,
    }
}

fn bench(c: &mut Criterion) {
    let s = sample();
    let spec = |kind, gamma_fixed| ModelSpec { kind, gamma_fixed };
    let nm = FitOptions::default();
    let lbfgs = FitOptions {
        optimizer: Optimizer::Lbfgs,
        ..nm
    };
    c.bench_function("fit student-t free gamma, 300 points, nelder-mead", |b| {
        b.iter(|| fit_sample(black_box(&s), spec(ModelKind::StudentT, None), &nm).unwrap())
    });
    c.bench_function("fit student-t free gamma, 300 points, l-bfgs", |b| {
        b.iter(|| fit_sample(black_box(&s), spec(ModelKind::StudentT, None), &lbfgs).unwrap())
    });
    c.bench_function("fit ggx, 300 points, nelder-mead", |b| {
        b.iter(|| fit_sample(black_box(&s), spec(ModelKind::Ggx, None), &nm).unwrap())
    });
    c.bench_function("fit all four models, 300 points", |b| {
        b.iter(|| fit_all(black_box(&s), &nm).unwrap())
    });
}

/// One evaluation of the all-orders model on the 300-point grid: 4 incidence angles, 20000 walks
/// each (the `--walks` default), as the multiple-scattering objective does per evaluation.
fn bench_multiple(c: &mut Criterion) {
    let angles: Vec<(f64, f64)> = sample()
        .points
        .iter()
        .map(|p| (p.theta_i_deg, p.theta_o_deg))
        .collect();
    let params = ModelParams {
        kind: ModelKind::StudentT,
        alpha: 0.4,
        gamma: 2.7,
        scale: 0.8,
    };
    let mut group = c.benchmark_group("multiple scattering");
    group.sample_size(10);
    group.bench_function("model at 300 points, 4 x 20000 walks", |b| {
        b.iter(|| {
            params
                .l_multiple_batch(black_box(&angles), 1.51, 20_000, 1)
                .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench, bench_multiple);
criterion_main!(benches);
