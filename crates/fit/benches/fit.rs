//! Speed of single fits and of `--model all` on a 300-point sample, and of one all-orders
//! model evaluation (the unit of cost of `--orders all`).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use stfit_fit::fit::{fit_all, fit_sample};
use stfit_fit::{
    FitOptions, Gamma, Masking, Measurement, Model, ModelKind, ModelSpec, Optimizer, Sample,
    ScatteringOrders,
};

/// The Student-T surface of the benchmarks.
fn truth() -> Model {
    Model::single(ModelKind::StudentT, 0.4, Gamma::Free(2.7), 0.8)
}

/// The Walter grid: theta_i 0, 30, 60, 80; theta_o 106..254 by 2.
fn angles() -> Vec<(f64, f64)> {
    [0.0, 30.0, 60.0, 80.0]
        .iter()
        .flat_map(|&ti| (0..75).map(move |k| (ti, 106.0 + 2.0 * k as f64)))
        .collect()
}

/// A 300-point Walter-like sample (theta_i 0, 30, 60, 80; theta_o 106..254 by 2) of a
/// Student-T surface with 2% deterministic ripple, so the fit does not start at a zero residual.
fn sample() -> Sample {
    let angles = angles();
    let l = truth().predict(&angles).unwrap();
    let points = angles
        .iter()
        .zip(l)
        .enumerate()
        .map(|(j, (&(ti, to), l))| {
            Measurement::in_plane(
                ti,
                to,
                l * (1.0 + 0.02 * ((j % 75) as f64 * 1.7).sin()),
                1.0,
            )
        })
        .collect();
    Sample {
        name: "bench".into(),
        points,
    }
}

fn bench(c: &mut Criterion) {
    let s = sample();
    let spec = |kind, gamma_fixed| ModelSpec::new(kind, gamma_fixed).unwrap();
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
    let angles = angles();
    let all = Model {
        masking: Masking::Correlated,
        orders: ScatteringOrders::All,
        walks: Some(20_000),
        seed: Some(1),
        ..truth()
    };
    let mut group = c.benchmark_group("multiple scattering");
    group.sample_size(10);
    group.bench_function("model at 300 points, 4 x 20000 walks", |b| {
        b.iter(|| all.predict(black_box(&angles)).unwrap())
    });
    // Whole all-orders fits with the surrogate orders >= 2 term (the default).
    let s = sample();
    let opts = FitOptions::with_orders(ScatteringOrders::All);
    for spec in [ModelSpec::student_t(), ModelSpec::ggx()] {
        group.bench_function(
            format!("fit {}, all orders, 300 points, surrogate", spec.label()),
            |b| b.iter(|| fit_sample(black_box(&s), spec, &opts).unwrap()),
        );
    }
    group.finish();
}

/// A general sample (reflection and transmission, light from both sides, out of plane: the
/// default general grid of `stfit synth`, 1,620 points) fitted with free eta.
fn bench_general(c: &mut Criterion) {
    let truth = Model {
        eta: 1.45,
        ..truth()
    };
    let mut sample = stfit_fit::SynthSpec {
        model: truth,
        grid: stfit_fit::Grid::spherical_default(),
        noise: 0.02,
        seed: 1,
        name: "general".into(),
    }
    .sample()
    .unwrap();
    sample.points.retain(|p| p.value > 0.0 || p.weight > 0.0);
    let opts = FitOptions {
        eta: stfit_fit::Parameter::Free,
        ..FitOptions::default()
    };
    c.bench_function(
        "fit student-t free gamma free eta, 1620 general points",
        |b| b.iter(|| fit_sample(black_box(&sample), ModelSpec::student_t(), &opts).unwrap()),
    );
}

/// Reading a file of 200,000 one-row samples (3.1 MB): the merge of samples by name is linear
/// in their number (it had been quadratic: 100,000 took over a minute).
fn bench_load(c: &mut Criterion) {
    let path = std::env::temp_dir().join(format!("stfit-bench-many-{}.csv", std::process::id()));
    let mut text = String::from("sample,theta_i_deg,theta_o_deg,L\n");
    for k in 0..200_000 {
        text += &format!("s{k},0,170,1\n");
    }
    std::fs::write(&path, text).unwrap();
    c.bench_function("load 200,000 one-row samples", |b| {
        b.iter(|| stfit_fit::load_path(black_box(&path)).unwrap())
    });
    std::fs::remove_file(&path).unwrap();
}

criterion_group!(benches, bench, bench_multiple, bench_general, bench_load);
criterion_main!(benches);
