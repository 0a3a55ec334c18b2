//! Cost of a whole report (every figure as SVG and PNG, and fits.md) for Walter-sized data:
//! 4 incidence angles x 75 points per sample, four fitted models per sample.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use stfit_core::bsdf::Masking;
use stfit_fit::{Dataset, FitResult, Measurement, ModelKind, ModelParams, Sample};
use stfit_report::{ReportOptions, render_report};

fn sample(name: &str, truth: ModelParams) -> Sample {
    let points = [0.0, 30.0, 60.0, 80.0]
        .iter()
        .flat_map(|&ti| {
            (0..75).map(move |k| {
                let to = 105.82 + (253.89 - 105.82) * k as f64 / 74.0;
                Measurement {
                    theta_i_deg: ti,
                    theta_o_deg: to,
                    l: truth.l_single(ti, to, 1.51, Masking::Separable).unwrap(),
                    weight: 1.0,
                }
            })
        })
        .collect();
    Sample {
        name: name.into(),
        points,
    }
}

fn fit(sample: &Sample, kind: ModelKind, alpha: f64, gamma: Option<f64>, fixed: bool) -> FitResult {
    FitResult {
        sample: sample.name.clone(),
        model: kind,
        alpha,
        gamma,
        gamma_fixed: fixed,
        scale: 1.0,
        rmse_sqrt_l: 0.0,
        n_points: sample.points.len(),
        alpha_stderr: 0.0,
        gamma_stderr: None,
        scale_stderr: 0.0,
        iterations: 0,
    }
}

fn data(n: usize) -> (Dataset, Vec<FitResult>) {
    let samples: Vec<Sample> = (0..n)
        .map(|i| {
            let truth = ModelParams {
                kind: ModelKind::StudentT,
                alpha: 0.2 + 0.1 * i as f64,
                gamma: 2.5,
                scale: 1.0,
            };
            sample(&format!("s{i}"), truth)
        })
        .collect();
    let fits = samples
        .iter()
        .flat_map(|s| {
            [
                fit(s, ModelKind::Beckmann, 0.2, None, false),
                fit(s, ModelKind::Ggx, 0.2, None, false),
                fit(s, ModelKind::StudentT, 0.2, Some(3.0), true),
                fit(s, ModelKind::StudentT, 0.2, Some(2.5), false),
            ]
        })
        .collect();
    (
        Dataset {
            source: PathBuf::from("bench"),
            samples,
        },
        fits,
    )
}

fn bench(c: &mut Criterion) {
    let opts = ReportOptions::default();
    for n in [1, 3] {
        let (d, f) = data(n);
        c.bench_function(&format!("render_report/{n}_samples"), |b| {
            b.iter(|| render_report(black_box(&d), black_box(&f), &opts).unwrap())
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
