//! Property tests: no NaN or infinity from `eval`, `sample` or `pdf` of any BSDF, for random
//! and special directions (exactly normal, exactly opposite, exactly grazing) and parameters
//! anywhere in their valid ranges.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use rand::SeedableRng;
use rand_pcg::Pcg64;
use stfit_core::Vec3;
use stfit_core::bsdf::{
    AnalyticBsdf, Bsdf, Lambertian, Masking, RoughConductor, RoughDielectric, SmoothConductor,
    SmoothDielectric,
};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};

fn config() -> Config {
    Config {
        cases: 3000,
        rng_seed: RngSeed::Fixed(0x5f17),
        failure_persistence: None,
        ..Config::default()
    }
}

/// A unit direction: uniform on the sphere, or one of the special ones: the poles, exactly on
/// the horizon, or within 1e-12 of it.
fn direction() -> impl Strategy<Value = Vec3> {
    let uniform = (-1.0f64..=1.0, 0.0f64..std::f64::consts::TAU).prop_map(|(z, phi)| {
        let s = (1.0 - z * z).sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), z)
    });
    let horizon = (
        0.0f64..std::f64::consts::TAU,
        prop_oneof![Just(0.0f64), Just(1e-12), Just(-1e-12)],
    )
        .prop_map(|(phi, z)| {
            let s = (1.0 - z * z).sqrt();
            Vec3::new(s * phi.cos(), s * phi.sin(), z)
        });
    prop_oneof![
        4 => uniform,
        1 => Just(Vec3::z()),
        1 => Just(-Vec3::z()),
        2 => horizon,
    ]
}

/// A pair `(wi, wo)`, with `wo` sometimes exactly `-wi`, `wi`, or the mirror of `wi`.
fn direction_pair() -> impl Strategy<Value = (Vec3, Vec3)> {
    (direction(), direction(), 0u8..5).prop_map(|(wi, wo, kind)| match kind {
        0 => (wi, -wi),
        1 => (wi, wi),
        2 => (wi, Vec3::new(-wi.x, -wi.y, wi.z)),
        _ => (wi, wo),
    })
}

#[derive(Debug, Clone, Copy)]
enum NdfKind {
    Beckmann,
    Ggx,
    StudentT(f64),
}

fn ndf_kind() -> impl Strategy<Value = NdfKind> {
    prop_oneof![
        Just(NdfKind::Beckmann),
        Just(NdfKind::Ggx),
        (1.5f64..40.0)
            .prop_filter("gamma > 3/2", |g| *g > 1.5)
            .prop_map(NdfKind::StudentT),
        Just(NdfKind::StudentT(1.5 + 1e-9)),
    ]
}

fn ndf(kind: NdfKind, alpha: f64) -> AnyNdf {
    match kind {
        NdfKind::Beckmann => Beckmann::new(alpha).unwrap().into(),
        NdfKind::Ggx => Ggx::new(alpha).unwrap().into(),
        NdfKind::StudentT(g) => StudentT::new(alpha, g).unwrap().into(),
    }
}

fn alpha() -> impl Strategy<Value = f64> {
    prop_oneof![1e-3f64..3.0, Just(1e-3), Just(3.0)]
}

fn eta() -> impl Strategy<Value = f64> {
    prop_oneof![
        0.2f64..5.0,
        Just(1.0 + 0.005),
        Just(1.0 - 0.005),
        Just(1.5),
        Just(1.0 / 1.5),
    ]
    .prop_filter("|eta - 1| >= 0.005", |e| (e - 1.0).abs() >= 0.005)
}

fn masking() -> impl Strategy<Value = Masking> {
    prop_oneof![Just(Masking::Separable), Just(Masking::Correlated)]
}

/// Asserts that `eval`, `pdf` and (if `sample`) a few draws are finite and in range.
fn check<B: Bsdf + std::fmt::Debug>(
    bsdf: &B,
    wi: Vec3,
    wo: Vec3,
    sample: bool,
    seed: u64,
) -> Result<(), TestCaseError> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let f = bsdf.eval(wi, wo, &mut rng);
    let p = bsdf.pdf(wi, wo, &mut rng);
    prop_assert!(
        f.is_finite() && f >= 0.0,
        "eval {f}: {bsdf:?} {wi:?} {wo:?}"
    );
    prop_assert!(p.is_finite() && p >= 0.0, "pdf {p}: {bsdf:?} {wi:?} {wo:?}");
    if sample {
        for _ in 0..8 {
            if let Some(s) = bsdf.sample(wi, &mut rng) {
                prop_assert!(
                    s.wo.iter().all(|x| x.is_finite()) && (s.wo.norm() - 1.0).abs() < 1e-9,
                    "{s:?}: {bsdf:?} {wi:?}"
                );
                prop_assert!(
                    s.weight.is_finite() && s.weight >= 0.0,
                    "{s:?}: {bsdf:?} {wi:?}"
                );
                prop_assert!(s.pdf.is_finite() && s.pdf > 0.0, "{s:?}: {bsdf:?} {wi:?}");
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn rough_dielectric_is_finite(
        (wi, wo) in direction_pair(),
        kind in ndf_kind(),
        alpha in alpha(),
        eta in eta(),
        masking in masking(),
        seed in any::<u64>(),
    ) {
        let bsdf = RoughDielectric::new(ndf(kind, alpha), eta, masking).unwrap();
        check(&bsdf, wi, wo, true, seed)?;
        prop_assert!(bsdf.f_cos(wi, wo).is_finite());
    }

    #[test]
    fn rough_conductor_is_finite(
        (wi, wo) in direction_pair(),
        kind in ndf_kind(),
        alpha in alpha(),
        n in 0.01f64..5.0,
        k in prop_oneof![Just(0.0), 0.0f64..10.0],
        masking in masking(),
        seed in any::<u64>(),
    ) {
        let bsdf = RoughConductor::new(ndf(kind, alpha), n, k, masking).unwrap();
        check(&bsdf, wi, wo, true, seed)?;
    }

    #[test]
    fn facet_bsdfs_are_finite(
        (wi, wo) in direction_pair(),
        eta in eta(),
        n in 0.01f64..5.0,
        k in prop_oneof![Just(0.0), 0.0f64..10.0],
        r in 0.0f64..=1.0,
        seed in any::<u64>(),
    ) {
        check(&SmoothDielectric::new(eta).unwrap(), wi, wo, true, seed)?;
        check(&SmoothConductor::new(n, k).unwrap(), wi, wo, true, seed)?;
        check(&Lambertian::new(r).unwrap(), wi, wo, true, seed)?;
    }
}
