//! Invalid inputs give typed errors, never panics.

mod common;

use stfit_core::ParamError;
use stfit_fit::fit::{FitError, fit_all, fit_sample};
use stfit_fit::{
    FitOptions, Gamma, Masking, Measurement, Model, ModelKind, ModelSpec, Sample, ScatteringOrders,
};

fn sample(points: Vec<Measurement>) -> Sample {
    Sample {
        name: "test".into(),
        points,
    }
}

fn point(theta_i_deg: f64, theta_o_deg: f64, l: f64) -> Measurement {
    Measurement::in_plane(theta_i_deg, theta_o_deg, l, 1.0)
}

fn spec(kind: ModelKind, gamma_fixed: Option<f64>) -> ModelSpec {
    match gamma_fixed {
        Some(g) if kind != ModelKind::StudentT => {
            // Not constructible: the only way to ask for this is through ModelSpec::new.
            assert!(ModelSpec::new(kind, Some(g)).is_err());
            ModelSpec::new(kind, None).unwrap()
        }
        _ => ModelSpec::new(kind, gamma_fixed).unwrap(),
    }
}

fn good() -> Sample {
    common::synthetic(&common::truth(ModelKind::Ggx, 0.3, 0.0, 1.0), 0.0, 1)
}

#[test]
fn empty_sample_is_too_few_points() {
    let opts = FitOptions::default();
    let e = fit_sample(&sample(vec![]), spec(ModelKind::Ggx, None), &opts).unwrap_err();
    assert!(matches!(e, FitError::TooFewPoints { n: 0, .. }), "{e}");
    assert!(matches!(
        fit_all(&sample(vec![]), &opts),
        Err(FitError::TooFewPoints { .. })
    ));
    // Two points cannot fit alpha and scale with a residual degree of freedom.
    let two = sample(vec![point(0.0, 180.0, 1.0), point(0.0, 170.0, 0.5)]);
    assert!(matches!(
        fit_sample(&two, spec(ModelKind::Ggx, None), &opts),
        Err(FitError::TooFewPoints {
            n: 2,
            needed: 3,
            ..
        })
    ));
}

#[test]
fn all_zero_data_is_rejected() {
    let mut s = good();
    s.points.iter_mut().for_each(|p| p.value = 0.0);
    for kind in [ModelKind::Beckmann, ModelKind::Ggx, ModelKind::StudentT] {
        let e = fit_sample(&s, spec(kind, None), &FitOptions::default()).unwrap_err();
        assert!(matches!(e, FitError::AllZero { .. }), "{e}");
    }
}

#[test]
fn invalid_gamma_is_rejected() {
    let s = good();
    let opts = FitOptions::default();
    for g in [1.5, 1.0, -3.0, f64::NAN, f64::INFINITY] {
        let e = fit_sample(&s, spec(ModelKind::StudentT, Some(g)), &opts).unwrap_err();
        assert!(
            matches!(
                e,
                FitError::InvalidParameter(ParamError::Gamma(_) | ParamError::NonFinite { .. })
            ),
            "gamma {g}: {e}"
        );
    }
    let e = ModelSpec::new(ModelKind::Ggx, Some(3.0)).unwrap_err();
    assert!(matches!(e, FitError::InvalidSpec(_)), "{e}");
}

#[test]
fn invalid_points_and_options_are_rejected() {
    let ggx = spec(ModelKind::Ggx, None);
    let opts = FitOptions::default();
    for bad in [
        point(f64::NAN, 180.0, 1.0),
        point(95.0, 180.0, 1.0),
        point(0.0, 45.0, 1.0),
        point(0.0, 180.0, f64::INFINITY),
        Measurement {
            weight: -1.0,
            ..point(0.0, 180.0, 1.0)
        },
    ] {
        let mut s = good();
        s.points.push(bad);
        let e = fit_sample(&s, ggx, &opts).unwrap_err();
        assert!(
            matches!(e, FitError::InvalidData { index: 300, .. }),
            "{bad:?}: {e}"
        );
    }
    for eta in [1.0, 0.0, -1.5, f64::NAN] {
        let o = FitOptions {
            eta: stfit_fit::Parameter::Fixed(eta),
            ..opts
        };
        let e = fit_sample(&good(), ggx, &o).unwrap_err();
        assert!(matches!(e, FitError::InvalidParameter(_)), "eta {eta}: {e}");
    }
    let all = FitOptions::with_orders(ScatteringOrders::All);
    for bad in [
        FitOptions { walks: 0, ..all },
        // One walk cannot estimate the term's Monte Carlo error; more than 10^9 are refused
        // before anything is allocated for them.
        FitOptions { walks: 1, ..all },
        FitOptions {
            walks: u64::MAX,
            ..all
        },
        // Orders >= 2 only model no measurement.
        FitOptions {
            orders: ScatteringOrders::Multiple,
            ..all
        },
        // The walk's masking is height-correlated by construction.
        FitOptions {
            masking: Masking::Separable,
            ..all
        },
    ] {
        assert!(
            matches!(
                fit_sample(&good(), ggx, &bad),
                Err(FitError::InvalidOption(_))
            ),
            "{bad:?}"
        );
    }
    let model = Model::single(ModelKind::StudentT, 0.3, Gamma::Free(1.2), 1.0);
    assert!(matches!(
        model.predict(&[(0.0, 180.0)]),
        Err(FitError::InvalidParameter(ParamError::Gamma(_)))
    ));
}

/// `predict` refuses angles outside the data format's ranges (naming the point, counted from
/// 1) instead of returning 0 for them.
#[test]
fn predictions_outside_the_angle_ranges_are_refused() {
    let model = Model::single(ModelKind::Ggx, 0.3, Gamma::NotApplicable, 1.0);
    assert!(model.predict(&[(0.0, 180.0), (30.0, 200.0)]).is_ok());
    for bad in [
        (95.0, 180.0),
        (0.0, 20.0),
        (f64::NAN, 180.0),
        (0.0, f64::INFINITY),
    ] {
        let err = model.predict(&[(0.0, 180.0), bad]).unwrap_err();
        assert!(
            matches!(err, FitError::InvalidData { index: 1, .. })
                && err.to_string().contains("point 2 (counting from 1)"),
            "{bad:?}: {err}"
        );
    }
}

#[test]
fn zero_weight_points_are_ignored() {
    let mut s = good();
    // A wild point with zero weight changes nothing.
    s.points.push(Measurement {
        weight: 0.0,
        ..point(0.0, 180.0, 1e6)
    });
    let r = fit_sample(&s, spec(ModelKind::Ggx, None), &FitOptions::default()).unwrap();
    assert_eq!(r.n_points, 300);
    assert!(
        (r.model.alpha - 0.3).abs() < 1e-6 && (r.model.scale - 1.0).abs() < 1e-6,
        "{r:?}"
    );
}
