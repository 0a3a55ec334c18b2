//! Fitting with all scattering orders (`ScatteringOrders::All`): deterministic for a seed (common
//! random numbers), recovers the truth of data made with multiple scattering, where the
//! single-scattering fit of the same data is biased.

use stfit_fit::fit::fit_sample;
use stfit_fit::{
    FitOptions, FitResult, Gamma, Masking, Measurement, Model, ModelKind, ModelSpec, Sample,
    ScatteringOrders,
};

/// A coarse grid: incidence 0, 30, 60 degrees, transmission 110 to 250 degrees in steps of 5.
fn angles() -> Vec<(f64, f64)> {
    [0.0, 30.0, 60.0]
        .into_iter()
        .flat_map(|ti| (0..29).map(move |k| (ti, 110.0 + 5.0 * k as f64)))
        .collect()
}

/// Noise-free all-orders data of `truth` from `walks` walks per incidence (seed 1000,
/// independent of the fits' seeds).
fn multiple_scattering_sample(truth: &Model, walks: u64) -> Sample {
    let angles = angles();
    let all = Model {
        masking: Masking::Correlated,
        orders: ScatteringOrders::All,
        walks: Some(walks),
        seed: Some(1000),
        ..*truth
    };
    let l = all.predict(&angles).expect("valid parameters");
    Sample {
        name: "multiple".into(),
        points: angles
            .iter()
            .zip(l)
            .map(|(&(ti, to), l)| Measurement::in_plane(ti, to, l, 1.0))
            .collect(),
    }
}

fn multiple(walks: u64, seed: u64) -> FitOptions {
    FitOptions {
        walks,
        seed,
        ..FitOptions::with_orders(ScatteringOrders::All)
    }
}

fn spec(kind: ModelKind) -> ModelSpec {
    ModelSpec::new(kind, None).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn show(label: &str, r: &FitResult) {
    println!(
        "{label}: alpha {:.5} +- {:.2e}, gamma {:?} +- {:?}, scale {:.5} +- {:.2e}, rmse {:.3e}, \
         iterations {}",
        r.model.alpha,
        r.alpha_stderr.unwrap_or(f64::NAN),
        r.model.gamma,
        r.gamma_stderr,
        r.model.scale,
        r.scale_stderr.unwrap_or(f64::NAN),
        r.rmse_sqrt_l,
        r.iterations
    );
}

#[test]
fn multiple_scattering_fit_is_deterministic_for_a_seed() {
    let truth = Model::single(ModelKind::Ggx, 0.5, Gamma::NotApplicable, 1.0);
    let sample = multiple_scattering_sample(&truth, 2000);
    let a = fit_sample(&sample, spec(ModelKind::Ggx), &multiple(1000, 3)).unwrap();
    let b = fit_sample(&sample, spec(ModelKind::Ggx), &multiple(1000, 3)).unwrap();
    let c = fit_sample(&sample, spec(ModelKind::Ggx), &multiple(1000, 4)).unwrap();
    show("seed 3", &a);
    show("seed 4", &c);
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
    assert_ne!(
        a.model.alpha, c.model.alpha,
        "another seed gives other walks"
    );
}

#[test]
fn multiple_scattering_fit_recovers_multiple_scattering_data() {
    let truth = Model::single(ModelKind::StudentT, 0.6, Gamma::Free(2.5), 1.0);
    let truth_gamma = 2.5;
    let sample = multiple_scattering_sample(&truth, 40_000);
    let ms = fit_sample(&sample, spec(ModelKind::StudentT), &multiple(5000, 1)).unwrap();
    let ss = fit_sample(&sample, spec(ModelKind::StudentT), &FitOptions::default()).unwrap();
    show("multiple", &ms);
    show("single", &ss);
    let (ms_gamma, ss_gamma) = (
        ms.model.gamma.value().unwrap(),
        ss.model.gamma.value().unwrap(),
    );
    // The bands.
    assert!(
        rel(ms.model.alpha, truth.alpha) < 0.02,
        "alpha {}",
        ms.model.alpha
    );
    assert!(rel(ms_gamma, truth_gamma) < 0.10, "gamma {ms_gamma}");
    assert!(
        rel(ms.model.scale, truth.scale) < 0.03,
        "scale {}",
        ms.model.scale
    );
    // Single scattering explains the multiply scattered light with a heavier tail (lower gamma)
    // and a larger scale: off the truth by several of its own standard errors, and fitting
    // the data ten times worse.
    let gamma_bias = truth_gamma - ss_gamma;
    assert!(
        gamma_bias > 0.03 * truth_gamma && gamma_bias > 3.0 * ss.gamma_stderr.unwrap(),
        "single-scattering gamma {ss_gamma}"
    );
    assert!(
        ss.model.scale - truth.scale > 3.0 * ss.scale_stderr.unwrap(),
        "single-scattering scale {}",
        ss.model.scale
    );
    assert!(ms.rmse_sqrt_l < ss.rmse_sqrt_l / 5.0);
}
