//! Cost of a whole report (every figure as SVG and PNG, and fits.md) for Walter-sized data:
//! 4 incidence angles x 75 points per sample, four fitted models per sample.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use stfit_fit::{
    Dataset, FitResult, Gamma, Loss, Measurement, Model, ModelKind, Optimizer, Sample,
};
use stfit_report::{ReportOptions, render_report};

fn sample(name: &str, truth: Model) -> Sample {
    let angles: Vec<(f64, f64)> = [0.0, 30.0, 60.0, 80.0]
        .iter()
        .flat_map(|&ti| (0..75).map(move |k| (ti, 105.82 + (253.89 - 105.82) * k as f64 / 74.0)))
        .collect();
    let l = truth.predict(&angles).unwrap();
    let points = angles
        .iter()
        .zip(l)
        .map(|(&(theta_i_deg, theta_o_deg), l)| {
            Measurement::in_plane(theta_i_deg, theta_o_deg, l, 1.0)
        })
        .collect();
    Sample {
        name: name.into(),
        points,
    }
}

fn fit(sample: &Sample, kind: ModelKind, alpha: f64, gamma: Gamma) -> FitResult {
    FitResult {
        sample: sample.name.clone(),
        model: Model::single(kind, alpha, gamma, 1.0),
        loss: Loss::Sqrt,
        optimizer: Optimizer::NelderMead,
        multiple_term: None,
        rmse_sqrt_l: 0.0,
        n_points: sample.points.len(),
        alpha_stderr: None,
        gamma_stderr: None,
        scale_stderr: None,
        iterations: 0,
        data: None,
        warnings: Vec::new(),
        stfit_version: "bench".into(),
        eta_fixed: true,
        scale_fixed: false,
        log_floor: None,
        eta_stderr: None,
        measured: sample.measured(),
    }
}

fn data(n: usize) -> (Dataset, Vec<FitResult>) {
    let samples: Vec<Sample> = (0..n)
        .map(|i| {
            let truth = Model::single(
                ModelKind::StudentT,
                0.2 + 0.1 * i as f64,
                Gamma::Free(2.5),
                1.0,
            );
            sample(&format!("s{i}"), truth)
        })
        .collect();
    let fits = samples
        .iter()
        .flat_map(|s| {
            [
                fit(s, ModelKind::Beckmann, 0.2, Gamma::NotApplicable),
                fit(s, ModelKind::Ggx, 0.2, Gamma::NotApplicable),
                fit(s, ModelKind::StudentT, 0.2, Gamma::Fixed(3.0)),
                fit(s, ModelKind::StudentT, 0.2, Gamma::Free(2.5)),
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
