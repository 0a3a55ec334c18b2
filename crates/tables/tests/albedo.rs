//! The single-scattering albedo quadrature against independent estimates: the random walk's
//! first order, Student-T at gamma 2 against GGX, the cosine-weighted average against an
//! independent integral of E, and a finer quadrature.

use stfit_core::Vec3;
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT};
use stfit_core::walk::{
    ConductorFacet, DielectricFacet, Estimator, Facet, Microsurface, ScatteringOrders,
};
use stfit_tables::single::{
    Albedo, Interface, Quadrature, TableMasking, TableNdf, average, single_scattering,
};

/// Light direction of cosine `mu` on the given side (`inside`: from the glass, `wi.z < 0`).
fn wi(mu: f64, inside: bool) -> Vec3 {
    let s = (1.0 - mu * mu).sqrt();
    Vec3::new(s, 0.0, if inside { -mu } else { mu })
}

/// The walk's order-1 reflected and transmitted fractions with standard errors.
fn walk_first_order<N: Ndf, F: Facet>(ndf: N, facet: F, w: Vec3, walks: u64) -> [(f64, f64); 2] {
    let a = Microsurface::new(ndf, facet)
        .with_orders(ScatteringOrders::Single)
        .albedo(w, walks, 7);
    [
        (a.reflectance, a.reflectance_stderr),
        (a.transmittance, a.transmittance_stderr),
    ]
}

fn check_against_walk<N: TableNdf + Copy>(name: &str, ndf: N, mu: f64, eta: f64, inside: bool) {
    let rule = Quadrature::default();
    let eta_rel = if inside { 1.0 / eta } else { eta };
    let q = single_scattering(
        &ndf,
        Interface::Dielectric { eta_rel },
        TableMasking::Correlated,
        mu,
        &rule,
    );
    let facet = DielectricFacet::new(eta).unwrap();
    let walk = walk_first_order(ndf, facet, wi(mu, inside), 400_000);
    for ((got, (want, se)), lobe) in [q.reflected, q.transmitted]
        .into_iter()
        .zip(walk)
        .zip(["R", "T"])
    {
        assert!(
            (got - want).abs() <= 4.0 * se + 1e-12,
            "{name} mu {mu} eta {eta} inside {inside} {lobe}: quadrature {got} vs walk {want} +- {se}"
        );
    }
}

#[test]
fn quadrature_equals_the_walks_first_order_within_four_standard_errors() {
    // The walk's first order is the single-scattering BSDF with height-correlated masking
    // (Beta function for transmission), light from either side.
    for (mu, eta, inside) in [
        (0.5, 1.5, false),
        (0.9, 1.5, true),
        (0.15, 1.33, false),
        (0.4, 2.4, true),
    ] {
        check_against_walk("ggx 0.3", Ggx::new(0.3).unwrap(), mu, eta, inside);
        check_against_walk("beckmann 0.6", Beckmann::new(0.6).unwrap(), mu, eta, inside);
        check_against_walk(
            "student-t 0.4 1.8",
            StudentT::new(0.4, 1.8).unwrap(),
            mu,
            eta,
            inside,
        );
        check_against_walk(
            "student-t 0.2 4",
            StudentT::new(0.2, 4.0).unwrap(),
            mu,
            eta,
            inside,
        );
    }
}

#[test]
fn conductor_quadrature_equals_the_walks_first_order() {
    let rule = Quadrature::default();
    for (facet, label) in [
        (ConductorFacet::mirror(), "mirror"),
        (ConductorFacet::fresnel(0.2, 3.5).unwrap(), "gold-like"),
    ] {
        for (alpha, mu) in [(0.2, 0.7), (0.8, 0.3)] {
            let ndf = StudentT::new(alpha, 2.5).unwrap();
            let q = single_scattering(
                &ndf,
                Interface::Conductor(facet),
                TableMasking::Correlated,
                mu,
                &rule,
            );
            assert_eq!(q.transmitted, 0.0);
            let [(r, se), (t, _)] = walk_first_order(ndf, facet, wi(mu, false), 400_000);
            assert_eq!(t, 0.0);
            assert!(
                (q.reflected - r).abs() <= 4.0 * se,
                "{label} alpha {alpha} mu {mu}: {} vs {r} +- {se}",
                q.reflected
            );
        }
    }
}

#[test]
fn student_t_at_gamma_2_equals_ggx() {
    let rule = Quadrature::default();
    for alpha in [1e-4, 0.05, 0.5, 2.0] {
        let (st, ggx) = (StudentT::new(alpha, 2.0).unwrap(), Ggx::new(alpha).unwrap());
        for (mu, eta_rel) in [(1e-4, 1.5), (0.3, 1.0 / 1.5), (0.8, 2.4), (1.0, 1.0 / 1.1)] {
            for masking in [TableMasking::Correlated, TableMasking::ReflectionForm] {
                let i = Interface::Dielectric { eta_rel };
                let a = single_scattering(&st, i, masking, mu, &rule);
                let b = single_scattering(&ggx, i, masking, mu, &rule);
                assert!(
                    (a.reflected - b.reflected).abs() < 1e-9
                        && (a.transmitted - b.transmitted).abs() < 1e-9,
                    "alpha {alpha} mu {mu} eta_rel {eta_rel} {masking:?}: {a:?} vs {b:?}"
                );
            }
        }
        let i = Interface::Dielectric { eta_rel: 1.0 / 1.5 };
        let (a, b) = (
            average(&st, i, TableMasking::Correlated, &rule),
            average(&ggx, i, TableMasking::Correlated, &rule),
        );
        assert!((a.total() - b.total()).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

/// `2 integral_0^1 E(mu) mu dmu = integral_0^1 4 v^3 E(v^2) dv` by the composite midpoint rule
/// in `v` on `n` and `2 n` equal cells, Richardson-extrapolated (the rule's error falls like
/// `n^-2`; `mu = v^2` tames the power-law behaviour of E at grazing incidence for heavy tails):
/// an estimate independent of the cuts and nodes of `average`, and its own error estimate.
fn midpoint_average<N: TableNdf>(ndf: &N, i: Interface, n: usize) -> (f64, f64) {
    let rule = Quadrature::default();
    let mid = |n: usize| {
        (0..n)
            .map(|k| {
                let v = (k as f64 + 0.5) / n as f64;
                let e = single_scattering(ndf, i, TableMasking::Correlated, v * v, &rule).total();
                4.0 * v * v * v * e
            })
            .sum::<f64>()
            / n as f64
    };
    let (coarse, fine) = (mid(n), mid(2 * n));
    (fine + (fine - coarse) / 3.0, (fine - coarse).abs() / 3.0)
}

#[test]
fn the_average_equals_the_integral_of_e() {
    let rule = Quadrature::default();
    for eta_rel in [1.5, 1.0 / 1.5] {
        let i = Interface::Dielectric { eta_rel };
        let ggx = Ggx::new(0.4).unwrap();
        let st = StudentT::new(0.25, 1.7).unwrap();
        for (name, avg, (mid, err)) in [
            (
                "ggx 0.4",
                average(&ggx, i, TableMasking::Correlated, &rule),
                midpoint_average(&ggx, i, 150),
            ),
            (
                "student-t 0.25 1.7",
                average(&st, i, TableMasking::Correlated, &rule),
                midpoint_average(&st, i, 150),
            ),
        ] {
            println!(
                "{name} eta_rel {eta_rel}: {:e} (midpoint error {err:e})",
                avg.total() - mid
            );
            assert!(
                (avg.total() - mid).abs() < 1e-6 + err,
                "{name} eta_rel {eta_rel}: average {} vs midpoint {mid} +- {err}",
                avg.total()
            );
        }
    }
}

#[test]
fn the_default_rule_is_within_2e_6_of_a_finer_one() {
    // Hard cells: grazing, near-specular, heavy tails, extreme indices, light in the glass
    // at the critical angle.
    let fine = Quadrature::new(32, 32, 1e-11);
    let rule = Quadrature::default();
    let cases: [(f64, f64, f64); 6] = [
        (1e-8, 1e-4, 1.5),
        (0.0044, 1e-4, 1.0 / 1.009),
        (0.3, 0.6, 0.8),
        (1.0, 0.0667, 1.0 / 99.5),
        (0.6, 0.5, 99.5),
        (0.05, 1.0, 1.0 / 1.5),
    ];
    for (alpha, mu, eta_rel) in cases {
        let i = Interface::Dielectric { eta_rel };
        let pairs: [(Albedo, Albedo, &str); 3] = [
            (
                single_scattering(
                    &Ggx::new(alpha).unwrap(),
                    i,
                    TableMasking::Correlated,
                    mu,
                    &rule,
                ),
                single_scattering(
                    &Ggx::new(alpha).unwrap(),
                    i,
                    TableMasking::Correlated,
                    mu,
                    &fine,
                ),
                "ggx",
            ),
            (
                single_scattering(
                    &Beckmann::new(alpha).unwrap(),
                    i,
                    TableMasking::Correlated,
                    mu,
                    &rule,
                ),
                single_scattering(
                    &Beckmann::new(alpha).unwrap(),
                    i,
                    TableMasking::Correlated,
                    mu,
                    &fine,
                ),
                "beckmann",
            ),
            (
                single_scattering(
                    &StudentT::new(alpha, 1.6).unwrap(),
                    i,
                    TableMasking::Correlated,
                    mu,
                    &rule,
                ),
                single_scattering(
                    &StudentT::new(alpha, 1.6).unwrap(),
                    i,
                    TableMasking::Correlated,
                    mu,
                    &fine,
                ),
                "student-t 1.6",
            ),
        ];
        for (a, b, name) in pairs {
            let d = (a.reflected - b.reflected)
                .abs()
                .max((a.transmitted - b.transmitted).abs());
            assert!(
                d < 2e-6,
                "{name} alpha {alpha} mu {mu} eta_rel {eta_rel}: {a:?} vs {b:?}"
            );
        }
    }
}

#[test]
fn near_specular_surfaces_conserve_energy_in_single_scattering() {
    // A smooth dielectric reflects F and transmits 1 - F: E = 1 from either side, with the
    // Fresnel split (up to the masking loss, 1e-9 at alpha 1e-6).
    let rule = Quadrature::default();
    let ndf = Ggx::new(1e-6).unwrap();
    for (mu, eta_rel) in [(0.3, 1.5), (0.9, 1.0 / 1.5), (0.5, 1.0 / 1.5)] {
        let a = single_scattering(
            &ndf,
            Interface::Dielectric { eta_rel },
            TableMasking::Correlated,
            mu,
            &rule,
        );
        let f = stfit_core::bsdf::fresnel_dielectric(mu, eta_rel);
        assert!(
            (a.total() - 1.0).abs() < 1e-7,
            "mu {mu} eta_rel {eta_rel}: {a:?}"
        );
        assert!(
            (a.reflected - f).abs() < 1e-6,
            "mu {mu} eta_rel {eta_rel}: {a:?} vs F {f}"
        );
    }
}

#[test]
fn single_scattering_albedos_never_exceed_one() {
    // E <= 1 exactly (G <= G1(wi)); at near-specular Beckmann cells the quadrature's rounding
    // had given 1 + 9e-16 (alpha 1e-8, mu 1e-4, eta 100, both sides), so 1 - E < 0.
    let rule = Quadrature::default();
    for alpha in [1e-8, 1e-6, 1e-3] {
        let ndf = Beckmann::new(alpha).unwrap();
        for eta_rel in [100.0, 50.0, 1.0 / 50.0, 1.0 / 100.0] {
            let interface = Interface::Dielectric { eta_rel };
            for masking in [TableMasking::Correlated, TableMasking::Separable] {
                for mu in [1e-4, 1e-3, 0.5, 1.0] {
                    let a = single_scattering(&ndf, interface, masking, mu, &rule);
                    assert!(
                        a.total() <= 1.0 && a.total() > 0.9,
                        "alpha {alpha} eta_rel {eta_rel} {masking:?} mu {mu}: {a:?}"
                    );
                }
                let avg = average(&ndf, interface, masking, &rule);
                assert!(
                    avg.total() <= 1.0,
                    "alpha {alpha} eta_rel {eta_rel}: {avg:?}"
                );
            }
        }
    }
}

#[test]
fn ggx_mirror_at_alpha_1_reflects_one_minus_ln_2_at_normal_incidence() {
    // At alpha = 1, D = 1/pi; at normal incidence Lambda_i = 0 and the reflection of a facet
    // at theta leaves at 2 theta with 1 + Lambda_o = (1 + 1/cos 2theta) / 2, so
    // E = integral_0^1 u / (1 + u) du = 1 - ln 2 (u = cos 2theta).
    let e = single_scattering(
        &Ggx::new(1.0).unwrap(),
        Interface::Conductor(ConductorFacet::mirror()),
        TableMasking::Correlated,
        1.0,
        &Quadrature::default(),
    );
    assert!(
        (e.total() - (1.0 - std::f64::consts::LN_2)).abs() < 1e-12,
        "{e:?}"
    );
}
