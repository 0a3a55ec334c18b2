//! Fits recover the parameters of synthetic data generated from known models: exactly from
//! noise-free data, within tolerance bands from noisy data.

mod common;

use common::truth as params;
use stfit_fit::fit::fit_sample;
use stfit_fit::{FitOptions, FitResult, Gamma, Model, ModelKind, ModelSpec};

fn spec(kind: ModelKind) -> ModelSpec {
    ModelSpec::new(kind, None).unwrap()
}

fn gamma_of(m: &Model) -> f64 {
    m.gamma.value().unwrap_or(f64::NAN)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn fit(truth: &Model, noise: f64, seed: u64) -> FitResult {
    let sample = common::synthetic(truth, noise, seed);
    let r = fit_sample(&sample, spec(truth.kind), &FitOptions::default()).unwrap();
    println!(
        "{:?} truth alpha {} gamma {:?} scale {} noise {noise}: fit alpha {:.6} (+-{:.2e}) gamma {:?} \
         (+-{:?}) scale {:.6} (+-{:.2e}) rmse {:.3e} iters {}",
        truth.kind,
        truth.alpha,
        truth.gamma,
        truth.scale,
        r.model.alpha,
        r.alpha_stderr.unwrap_or(f64::NAN),
        r.model.gamma,
        r.gamma_stderr,
        r.model.scale,
        r.scale_stderr.unwrap_or(f64::NAN),
        r.rmse_sqrt_l,
        r.iterations
    );
    r
}

/// The cases: every model, alpha across [0.1, 0.8], gamma across [1.7, 8].
fn cases() -> Vec<Model> {
    use ModelKind::*;
    vec![
        params(Beckmann, 0.1, 0.0, 1.0),
        params(Beckmann, 0.35, 0.0, 20.0),
        params(Beckmann, 0.8, 0.0, 0.3),
        params(Ggx, 0.1, 0.0, 2.0),
        params(Ggx, 0.4, 0.0, 1.0),
        params(Ggx, 0.8, 0.0, 50.0),
        params(StudentT, 0.1, 1.7, 1.0),
        params(StudentT, 0.3, 3.0, 5.0),
        params(StudentT, 0.5, 1.75, 0.5),
        params(StudentT, 0.2, 8.0, 1.0),
        params(StudentT, 0.8, 4.0, 3.0),
    ]
}

#[test]
fn exact_data_is_recovered() {
    for truth in cases() {
        let r = fit(&truth, 0.0, 1);
        assert_eq!(r.model.kind, truth.kind);
        assert!(
            rel(r.model.alpha, truth.alpha) < 1e-4,
            "{truth:?}: alpha {}",
            r.model.alpha
        );
        assert!(
            rel(r.model.scale, truth.scale) < 1e-4,
            "{truth:?}: scale {}",
            r.model.scale
        );
        if truth.kind == ModelKind::StudentT {
            let g = r.model.gamma.value().unwrap();
            assert!(rel(g, gamma_of(&truth)) < 1e-4, "{truth:?}: gamma {g}");
        } else {
            assert_eq!(r.model.gamma, Gamma::NotApplicable);
        }
        assert!(
            r.rmse_sqrt_l < 1e-6 * truth.scale.sqrt(),
            "{truth:?}: {}",
            r.rmse_sqrt_l
        );
    }
}

#[test]
fn noisy_data_is_recovered_within_tolerance() {
    for (k, truth) in cases().into_iter().enumerate() {
        for (noise, seed) in [(0.01, 10 + k as u64), (0.03, 100 + k as u64)] {
            let r = fit(&truth, noise, seed);
            assert!(
                rel(r.model.alpha, truth.alpha) < 0.02,
                "{truth:?} noise {noise}: alpha {}",
                r.model.alpha
            );
            assert!(
                rel(r.model.scale, truth.scale) < 0.03,
                "{truth:?} noise {noise}: scale {}",
                r.model.scale
            );
            if truth.kind == ModelKind::StudentT {
                let g = r.model.gamma.value().unwrap();
                assert!(
                    rel(g, gamma_of(&truth)) < 0.10,
                    "{truth:?} noise {noise}: gamma {g}"
                );
            }
        }
    }
}

#[test]
fn fixed_gamma_fits_alpha_and_scale_only() {
    let truth = params(ModelKind::StudentT, 0.25, 3.0, 2.0);
    let sample = common::synthetic(&truth, 0.0, 3);
    let spec = ModelSpec::student_t_fixed(3.0);
    let r = fit_sample(&sample, spec, &FitOptions::default()).unwrap();
    assert_eq!(r.model.gamma, Gamma::Fixed(3.0));
    // A fixed parameter has no standard error.
    assert_eq!(r.gamma_stderr, None);
    assert!(
        rel(r.model.alpha, 0.25) < 1e-4 && rel(r.model.scale, 2.0) < 1e-4,
        "{r:?}"
    );
}

/// How noise enters the replications of [`calibration`].
#[derive(Debug, Clone, Copy)]
enum Noise {
    /// `sqrt(L) + sd z`: equal noise in every residual of the sqrt loss.
    AdditiveSqrt(f64),
    /// `L (1 + sd z)`: noise proportional to the signal, unequal across residuals.
    Multiplicative(f64),
}

/// Ratio of the empirical standard deviation of the estimates of `(alpha, gamma, scale)` over
/// `reps` noisy replications of `truth` to the mean reported standard error.
fn calibration(truth: Model, noise: Noise, reps: usize, seed: u64) -> [f64; 3] {
    use rand::{RngExt, SeedableRng};
    let clean = common::synthetic(&truth, 0.0, 0);
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let mut est: Vec<[f64; 3]> = Vec::new();
    let mut se: Vec<[f64; 3]> = Vec::new();
    for _ in 0..reps {
        let mut sample = clean.clone();
        for p in &mut sample.points {
            // Box-Muller normal deviate.
            let (u1, u2): (f64, f64) = (rng.random(), rng.random());
            let z = (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
            p.value = match noise {
                Noise::AdditiveSqrt(sd) => {
                    let y = p.value.sqrt() + sd * z;
                    y * y.abs()
                }
                Noise::Multiplicative(sd) => p.value * (1.0 + sd * z),
            };
        }
        let r = fit_sample(&sample, spec(truth.kind), &FitOptions::default()).unwrap();
        est.push([
            r.model.alpha,
            r.model.gamma.value().unwrap_or(0.0),
            r.model.scale,
        ]);
        se.push([
            r.alpha_stderr.unwrap(),
            r.gamma_stderr.unwrap_or(0.0),
            r.scale_stderr.unwrap(),
        ]);
    }
    let mut ratios = [f64::NAN; 3];
    for (k, name) in ["alpha", "gamma", "scale"].iter().enumerate() {
        let mean = est.iter().map(|e| e[k]).sum::<f64>() / reps as f64;
        let sd =
            (est.iter().map(|e| (e[k] - mean).powi(2)).sum::<f64>() / (reps - 1) as f64).sqrt();
        let se_mean = se.iter().map(|s| s[k]).sum::<f64>() / reps as f64;
        ratios[k] = sd / se_mean;
        println!(
            "{:?} {noise:?} {name}: empirical sd {sd:.3e}, mean reported stderr {se_mean:.3e}, \
             ratio {:.3}",
            truth.kind, ratios[k]
        );
    }
    ratios
}

/// With 200 replications the sample sd is within about +-15% of the truth (3 sigma), so a
/// calibrated standard error gives a ratio in 0.8..1.25.
const CALIBRATED: std::ops::Range<f64> = 0.8..1.25;

/// The reported (sandwich) standard errors match the actual scatter of the estimates under
/// additive, homoscedastic noise on `sqrt(L)` (what the classical formula assumes).
#[test]
fn standard_errors_match_the_scatter_under_additive_noise() {
    let truth = params(ModelKind::StudentT, 0.3, 2.5, 2.0);
    let ratios = calibration(truth, Noise::AdditiveSqrt(0.01), 200, 42);
    for (k, r) in ratios.iter().enumerate() {
        assert!(CALIBRATED.contains(r), "parameter {k}: sd / stderr {r}");
    }
}

/// The standard errors stay calibrated under multiplicative noise, where the residuals of the
/// sqrt loss have unequal variances (the classical `sigma^2 (J^T J)^-1` is off there).
#[test]
fn standard_errors_match_the_scatter_under_multiplicative_noise() {
    let truth = params(ModelKind::StudentT, 0.3, 2.5, 2.0);
    let ratios = calibration(truth, Noise::Multiplicative(0.05), 200, 43);
    for (k, r) in ratios.iter().enumerate() {
        assert!(CALIBRATED.contains(r), "parameter {k}: sd / stderr {r}");
    }
}

/// Student-T fitted to Beckmann data: gamma runs to large values (Student-T tends to Beckmann as
/// gamma grows) and the fit is as good as Beckmann's own, without numerical trouble.
#[test]
fn student_t_on_beckmann_data_goes_to_large_gamma() {
    let truth = params(ModelKind::Beckmann, 0.3, 0.0, 1.0);
    let sample = common::synthetic(&truth, 0.0, 5);
    let st = fit_sample(&sample, spec(ModelKind::StudentT), &FitOptions::default()).unwrap();
    let g = st.model.gamma.value().unwrap();
    println!("student-t on beckmann data: {st:?}");
    assert!(g > 30.0, "gamma {g}");
    assert!(rel(st.model.alpha, 0.3) < 0.02, "alpha {}", st.model.alpha);
    assert!(st.rmse_sqrt_l < 2e-3, "rmse {}", st.rmse_sqrt_l);
}
