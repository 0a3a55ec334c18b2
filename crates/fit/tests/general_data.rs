//! General measurements: any direction pairs, reflection and transmission, light from either
//! side, eta fitted. Synthetic data of known truth are recovered; the Walter geometry written
//! as a general file fits as the in-plane file does; pab-opto files fit back to the truth.

mod common;

use stfit_fit::conventions::{in_plane_to_spherical, wi_from_deg};
use stfit_fit::pabopto::{PabValue, write_pabopto};
use stfit_fit::{
    FitOptions, FitWarning, Gamma, Grid, Loss, Masking, Measurement, Model, ModelKind, ModelSpec,
    Optimizer, Parameter, Sample, ScatteringOrders, SynthSpec, fit_sample, load_paths,
};
use stfit_test_support::CaseDir;

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

fn free_eta() -> FitOptions {
    FitOptions {
        eta: Parameter::Free,
        ..FitOptions::default()
    }
}

/// A general sample of `truth` on the default general grid (light from outside at 0, 30, 60
/// degrees and from inside at 120, 150; outgoing directions over the whole sphere, 1,620
/// points) with multiplicative noise.
fn general_sample(truth: &Model, noise: f64, seed: u64) -> Sample {
    SynthSpec {
        model: *truth,
        grid: Grid::spherical_default(),
        noise,
        seed,
        name: "general".into(),
    }
    .sample()
    .unwrap()
}

fn model(kind: ModelKind, alpha: f64, gamma: Option<f64>, eta: f64, scale: f64) -> Model {
    Model {
        eta,
        ..Model::single(
            kind,
            alpha,
            gamma.map_or(Gamma::NotApplicable, Gamma::Free),
            scale,
        )
    }
}

/// The bands: with free eta, general data (reflection and transmission, both sides,
/// out of plane, 2.5% noise) of every NDF with eta in [1.3, 1.7] give alpha within 3%, gamma
/// within 8%, eta within 0.5% and the scale within 5%.
#[test]
fn general_data_of_every_ndf_are_recovered_with_free_eta() {
    let cases = [
        model(ModelKind::Beckmann, 0.25, None, 1.35, 2.0),
        model(ModelKind::Ggx, 0.4, None, 1.62, 0.7),
        model(ModelKind::StudentT, 0.3, Some(2.6), 1.45, 1.0),
        model(ModelKind::StudentT, 0.5, Some(4.0), 1.7, 3.0),
        model(ModelKind::StudentT, 0.15, Some(1.8), 1.3, 1.0),
    ];
    for (k, truth) in cases.iter().enumerate() {
        let sample = general_sample(truth, 0.025, 40 + k as u64);
        let spec = ModelSpec::new(truth.kind, None).unwrap();
        let r = fit_sample(&sample, spec, &free_eta()).unwrap();
        println!(
            "{:?}: alpha {:.4} gamma {:?} eta {:.4} ± {:?} scale {:.4} rmse {:.4}",
            truth,
            r.model.alpha,
            r.model.gamma,
            r.model.eta,
            r.eta_stderr,
            r.model.scale,
            r.rmse_sqrt_l
        );
        // Eta has a standard error, unless the optimum is pinned on a total-reflection onset
        // or rests on pairs near one (the Student-T case here has the onset of one pair inside
        // the glass and its mirror image at eta 1.448946; of 30 seeds of `synth --grid general
        // --model student-t --alpha 0.3 --gamma 2.6 --eta 1.45 --noise 0.025`, 4 end on it
        // and are not differentiable there, 1 rests on it): then the fit says so and gives
        // none.
        let pinned = r.warnings.iter().any(|w| {
            matches!(w, FitWarning::NotDifferentiable { parameter } if parameter == "eta")
                || matches!(w, FitWarning::TotalReflectionOnset { .. })
        });
        assert!(!r.eta_fixed && (r.eta_stderr.is_some_and(|s| s > 0.0) || pinned));
        assert!(rel(r.model.alpha, truth.alpha) < 0.03, "{truth:?}: {r:?}");
        assert!(rel(r.model.eta, truth.eta) < 0.005, "{truth:?}: {r:?}");
        assert!(rel(r.model.scale, truth.scale) < 0.05, "{truth:?}: {r:?}");
        if let (Some(g), Some(t)) = (r.model.gamma.value(), truth.gamma.value()) {
            assert!(rel(g, t) < 0.08, "{truth:?}: {r:?}");
        }
    }
}

/// With eta free, the cost jumps in eta where a transmitted point's refraction half vector
/// turns horizontal (Student-T with gamma < 2 has `D` unbounded there), and the optimum of
/// exact data can lie in a piece between two jumps that no starting index falls in: these
/// in-plane data of eta 1.4 (`synth --model student-t --alpha 0.5 --gamma 1.6 --eta 1.4`)
/// have a jump at 1.407, and the local search from the starting index 1.45 ended at eta
/// 1.4465, alpha 0.481 with both optimisers before the fit scanned the pieces. Each optimiser
/// now recovers the truth.
#[test]
fn exact_data_are_recovered_across_the_jumps_of_the_cost_in_eta() {
    let truth = model(ModelKind::StudentT, 0.5, Some(1.6), 1.4, 1.0);
    let sample = SynthSpec {
        model: truth,
        grid: Grid::in_plane_default(),
        noise: 0.0,
        seed: 1,
        name: "jumps".into(),
    }
    .sample()
    .unwrap();
    for optimizer in [Optimizer::NelderMead, Optimizer::Lbfgs] {
        let opts = FitOptions {
            optimizer,
            ..free_eta()
        };
        let r = fit_sample(&sample, ModelSpec::student_t(), &opts).unwrap();
        assert!(rel(r.model.eta, 1.4) < 1e-6, "{optimizer:?}: {r:?}");
        assert!(rel(r.model.alpha, 0.5) < 1e-5, "{optimizer:?}: {r:?}");
        assert!(
            rel(r.model.gamma.value().unwrap(), 1.6) < 1e-5,
            "{optimizer:?}: {r:?}"
        );
        assert!(r.rmse_sqrt_l < 1e-6, "{optimizer:?}: {r:?}");
    }
}

/// A piece beside the optimum's is searched even when alpha and gamma held at the optimum's do
/// not fit it better: on exact general data of Student-T 0.2, 1.8, eta 1.5 (`synth --model
/// student-t --alpha 0.2 --gamma 1.8 --eta 1.5 --grid general`), L-BFGS stopped across the
/// jump at 1.5098, at eta 1.5134, gamma 1.904, where the scan of the other pieces at that
/// gamma found nothing better; both optimisers now recover the truth.
#[test]
fn exact_data_are_recovered_from_across_a_jump_near_the_optimum() {
    let truth = model(ModelKind::StudentT, 0.2, Some(1.8), 1.5, 1.0);
    let sample = general_sample(&truth, 0.0, 1);
    for optimizer in [Optimizer::NelderMead, Optimizer::Lbfgs] {
        let opts = FitOptions {
            optimizer,
            ..free_eta()
        };
        let r = fit_sample(&sample, ModelSpec::student_t(), &opts).unwrap();
        assert!(rel(r.model.eta, 1.5) < 1e-6, "{optimizer:?}: {r:?}");
        assert!(rel(r.model.alpha, 0.2) < 1e-5, "{optimizer:?}: {r:?}");
        assert!(
            rel(r.model.gamma.value().unwrap(), 1.8) < 1e-5,
            "{optimizer:?}: {r:?}"
        );
    }
}

/// Exact data are recovered exactly, under every loss, and with the scale held at its value.
/// (Not at eta 1.5: the pair inside the glass at 150 and 125 degrees, azimuths 0 and 160,
/// turns totally reflected at 1.50063, and its unbounded slope there outweighs every other
/// point's information on eta, so fits there can carry `total-reflection-onset`.)
#[test]
fn exact_general_data_are_recovered_under_every_loss_and_with_a_fixed_scale() {
    let truth = model(ModelKind::StudentT, 0.35, Some(3.0), 1.52, 1.0);
    let sample = general_sample(&truth, 0.0, 1);
    for loss in [Loss::Sqrt, Loss::Linear, Loss::Log] {
        for scale in [Parameter::Free, Parameter::Fixed(1.0)] {
            let opts = FitOptions {
                loss,
                scale,
                ..free_eta()
            };
            let r = fit_sample(&sample, ModelSpec::student_t(), &opts).unwrap();
            let what = format!("{loss:?} {scale:?}");
            assert!(rel(r.model.alpha, 0.35) < 1e-5, "{what}: {r:?}");
            assert!(
                rel(r.model.gamma.value().unwrap(), 3.0) < 1e-4,
                "{what}: {r:?}"
            );
            assert!(rel(r.model.eta, 1.52) < 1e-6, "{what}: {r:?}");
            assert!(rel(r.model.scale, 1.0) < 1e-5, "{what}: {r:?}");
            assert!(r.warnings.is_empty(), "{what}: {r:?}");
            assert_eq!(r.scale_fixed, scale == Parameter::Fixed(1.0));
            assert_eq!(r.scale_stderr.is_none(), r.scale_fixed);
            assert_eq!(r.log_floor.is_some(), loss == Loss::Log);
        }
    }
}

/// The Walter geometry written as a general file (spherical angles, the BSDF
/// `k L` with `k = eta^2 / cos(theta_i)`) gives the same fit as the in-plane file: exactly the
/// truth for exact data, and the same optimum for noisy or real data when the weights carry
/// the change of units (`1/k`: the sqrt loss's residuals grow by `sqrt(k)`).
#[test]
fn the_walter_geometry_as_a_general_file_gives_the_same_fit() {
    let eta = 1.51;
    let convert = |in_plane: &Sample, weighted: bool| Sample {
        name: in_plane.name.clone(),
        points: in_plane
            .points
            .iter()
            .map(|p| {
                let (ti, to) = p.in_plane_angles().unwrap();
                let (i, o) = in_plane_to_spherical(ti, to);
                let k = eta * eta / wi_from_deg(ti).z;
                let w = if weighted { p.weight / k } else { p.weight };
                Measurement::spherical(i, o, k * p.value, w)
            })
            .collect(),
    };
    // Exact data, unit weights: both forms give the truth.
    let truth = common::truth(ModelKind::StudentT, 0.3, 2.4, 1.3);
    let exact = common::synthetic(&truth, 0.0, 1);
    for sample in [exact.clone(), convert(&exact, false)] {
        let r = fit_sample(&sample, ModelSpec::student_t(), &FitOptions::default()).unwrap();
        assert!(
            rel(r.model.alpha, 0.3) < 1e-6 && rel(r.model.scale, 1.3) < 1e-6,
            "{r:?}"
        );
        assert!(rel(r.model.gamma.value().unwrap(), 2.4) < 1e-5, "{r:?}");
    }
    let mut samples = vec![common::synthetic(&truth, 0.02, 9)];
    samples.extend(
        common::walter_samples("the_walter_geometry_as_a_general_file_gives_the_same_fit")
            .unwrap_or_default(),
    );
    for in_plane in samples {
        let general = convert(&in_plane, true);
        for spec in stfit_fit::all_models() {
            let a = fit_sample(&in_plane, spec, &FitOptions::default()).unwrap();
            let b = fit_sample(&general, spec, &FitOptions::default()).unwrap();
            let what = format!(
                "{} {}: alpha {} vs {}, scale {} vs {}, rmse {} vs {}",
                in_plane.name,
                spec.label(),
                a.model.alpha,
                b.model.alpha,
                a.model.scale,
                b.model.scale,
                a.rmse_sqrt_l,
                b.rmse_sqrt_l
            );
            assert!(rel(a.model.alpha, b.model.alpha) < 1e-7, "{what}");
            assert!(rel(a.model.scale, b.model.scale) < 1e-6, "{what}");
            if let (Some(x), Some(y)) = (a.model.gamma.value(), b.model.gamma.value()) {
                assert!(rel(x, y) < 1e-6, "{what}");
            }
        }
    }
}

/// pab-opto files written from the model, both sides, reflection and transmission, in DSF and
/// BSDF form, read back as a folder and fit back to the truth, eta included.
#[test]
fn pabopto_files_fit_back_to_the_truth() {
    let truth = model(ModelKind::Ggx, 0.45, None, 1.4, 1.0);
    let sample = general_sample(&truth, 0.0, 1);
    for form in [PabValue::Dsf, PabValue::Bsdf] {
        let dir = CaseDir::new(&format!("pab-{}", form.name()));
        let paths = write_pabopto(dir.path(), &sample, form, Some("test")).unwrap();
        // Five incident directions, each with its reflection and transmission file.
        assert_eq!(paths.len(), 10);
        let data = load_paths(&[dir.path().to_path_buf()]).unwrap();
        assert_eq!(data.samples.len(), 1);
        let back = &data.samples[0];
        assert_eq!(back.points.len(), sample.points.len());
        let r = fit_sample(back, ModelSpec::ggx(), &free_eta()).unwrap();
        assert!(rel(r.model.alpha, 0.45) < 1e-6, "{form:?}: {r:?}");
        assert!(rel(r.model.eta, 1.4) < 1e-6, "{form:?}: {r:?}");
        assert!(rel(r.model.scale, 1.0) < 1e-6, "{form:?}: {r:?}");
    }
}

/// All orders on general data: the all-orders model of a rough Student-T fits back to its
/// truth with eta free (light from both sides).
#[test]
fn all_orders_general_data_fit_back_with_free_eta() {
    let truth = Model {
        masking: Masking::Correlated,
        orders: ScatteringOrders::All,
        walks: Some(2000),
        seed: Some(3),
        ..model(ModelKind::StudentT, 0.6, Some(2.5), 1.5, 1.0)
    };
    let grid = Grid::Spherical {
        theta_i_deg: vec![20.0, 140.0],
        phi_i_deg: vec![0.0],
        theta_o_deg: (0..9).map(|k| 15.0 + 20.0 * k as f64).collect(),
        phi_o_deg: vec![0.0, 90.0, 180.0],
    };
    let sample = SynthSpec {
        model: truth,
        grid,
        noise: 0.0,
        seed: 3,
        name: "all".into(),
    }
    .sample()
    .unwrap();
    let opts = FitOptions {
        walks: 2000,
        seed: 3,
        ..FitOptions {
            eta: Parameter::Free,
            ..FitOptions::with_orders(ScatteringOrders::All)
        }
    };
    let r = fit_sample(&sample, ModelSpec::student_t(), &opts).unwrap();
    println!("{r:?}");
    assert!(rel(r.model.alpha, 0.6) < 0.02, "{r:?}");
    assert!(rel(r.model.eta, 1.5) < 0.005, "{r:?}");
    assert!(rel(r.model.gamma.value().unwrap(), 2.5) < 0.05, "{r:?}");
}
