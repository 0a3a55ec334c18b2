//! Deterministic identities of the BSDFs: reciprocity, Student-T at gamma = 2 is GGX, Fresnel
//! limits, parameter validation.

use nalgebra::Complex;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use stfit_core::Vec3;
use stfit_core::bsdf::{
    AnalyticBsdf, Bsdf, Lambertian, Masking, RoughConductor, RoughDielectric, SmoothConductor,
    SmoothDielectric, fresnel_conductor, fresnel_dielectric,
};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};

fn uniform_sphere(rng: &mut Pcg64) -> Vec3 {
    let z = 2.0 * rng.random::<f64>() - 1.0;
    let phi = 2.0 * std::f64::consts::PI * rng.random::<f64>();
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

fn ndfs(alpha: f64) -> Vec<AnyNdf> {
    vec![
        Beckmann::new(alpha).unwrap().into(),
        Ggx::new(alpha).unwrap().into(),
        StudentT::new(alpha, 1.6).unwrap().into(),
        StudentT::new(alpha, 3.0).unwrap().into(),
        StudentT::new(alpha, 12.0).unwrap().into(),
    ]
}

fn assert_close(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-300,
        "{what}: {a} vs {b} (relative {:.2e})",
        (a - b).abs() / a.abs().max(b.abs())
    );
}

/// `f(wi, wo) / n_o^2 = f(wo, wi) / n_i^2` for transmission and `f(wi, wo) = f(wo, wi)` for
/// reflection, with `f = eval / |wo.z|`, for every NDF and both masking models.
#[test]
fn rough_dielectric_is_reciprocal() {
    let mut rng = Pcg64::seed_from_u64(2);
    let mut nonzero = [0usize; 2];
    for alpha in [0.1, 0.5, 1.5] {
        for ndf in ndfs(alpha) {
            for eta in [1.5, 1.0 / 1.33] {
                for masking in [Masking::Separable, Masking::Correlated] {
                    let bsdf = RoughDielectric::new(ndf, eta, masking).unwrap();
                    let index = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta };
                    for _ in 0..2000 {
                        let (wi, wo) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
                        let f_io = bsdf.eval(wi, wo, &mut rng) / wo.z.abs();
                        let f_oi = bsdf.eval(wo, wi, &mut rng) / wi.z.abs();
                        let (n_i, n_o) = (index(wi), index(wo));
                        let what = format!("{bsdf:?} {wi:?} {wo:?}");
                        // 1 - F near total internal reflection limits the agreement.
                        assert_close(f_io / (n_o * n_o), f_oi / (n_i * n_i), 1e-7, &what);
                        if f_io > 0.0 {
                            nonzero[usize::from(wi.z * wo.z < 0.0)] += 1;
                        }
                    }
                }
            }
        }
    }
    // Both lobes were exercised.
    assert!(nonzero[0] > 10_000 && nonzero[1] > 10_000, "{nonzero:?}");
}

/// `f_cos_with_terms` from the per-direction Smith terms is `f_cos` itself, bit for bit, for
/// every NDF, both maskings and pairs on every side.
#[test]
fn rough_dielectric_with_precomputed_terms_is_f_cos() {
    let mut rng = Pcg64::seed_from_u64(5);
    for ndf in ndfs(0.4) {
        for masking in [Masking::Separable, Masking::Correlated] {
            let bsdf = RoughDielectric::new(ndf, 1.5, masking).unwrap();
            for _ in 0..500 {
                let (wi, wo) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
                let terms = (bsdf.smith_term(wi), bsdf.smith_term(wo));
                let cached = bsdf.f_cos_with_terms(wi, wo, terms.0, terms.1);
                assert_eq!(
                    cached.to_bits(),
                    bsdf.f_cos(wi, wo).to_bits(),
                    "{wi:?} {wo:?}"
                );
            }
        }
    }
}

/// Grazing specular reflection is `F G D(h) / (4 |wi.z|)` for directions that are unit vectors
/// to their rounding: the norms' last bits must not tilt the ratio of `wi.h` and `wo.h`, both
/// about `|wi.z|` there (it came out 0.29 at `|z| = 1e-8`, on either side of the surface).
#[test]
fn grazing_specular_reflection_ignores_the_rounding_of_the_norms() {
    let (x, z) = (1.0 - f64::EPSILON / 2.0, 1e-8);
    for side in [1.0, -1.0] {
        // Each within 1.2e-16 of unit length; h is z but for that rounding.
        let (wi, wo) = (Vec3::new(-x, 0.0, side * z), Vec3::new(1.0, 0.0, side * z));
        for ndf in ndfs(0.3) {
            let d = stfit_core::ndf::Ndf::d(&ndf, Vec3::z());
            let lambda =
                |w: Vec3| stfit_core::ndf::Ndf::lambda(&ndf, Vec3::new(w.x, w.y, w.z.abs()));
            let (li, lo) = (lambda(wi), lambda(wo));
            for masking in [Masking::Separable, Masking::Correlated] {
                let g = match masking {
                    Masking::Separable => 1.0 / ((1.0 + li) * (1.0 + lo)),
                    Masking::Correlated => 1.0 / (1.0 + li + lo),
                };
                let glass = RoughDielectric::new(ndf, 1.5, masking).unwrap();
                let f = fresnel_dielectric(side * z, 1.5);
                let what = format!("{glass:?} {wi:?} {wo:?}");
                assert_close(glass.f_cos(wi, wo), f * g * d / (4.0 * z), 1e-6, &what);
                if side > 0.0 {
                    let metal = RoughConductor::new(ndf, 0.2, 3.6, masking).unwrap();
                    let f = fresnel_conductor(z, Complex::new(0.2, 3.6));
                    let what = format!("{metal:?} {wi:?} {wo:?}");
                    assert_close(metal.f_cos(wi, wo), f * g * d / (4.0 * z), 1e-6, &what);
                }
            }
        }
    }
}

/// Transmission whose refracted direction leaves the facet at grazing, just short of total
/// internal reflection, is reciprocal: from the side that can reflect totally, Fresnel must
/// not decide by the rounding of `wi.h` (it gave 0 one way and the full value the other).
/// Light from the air onto an index of 0.01 (critical angle 0.57 degrees) and onto 1/1.5.
#[test]
fn transmission_at_the_critical_angle_is_reciprocal() {
    for (eta, alpha) in [(0.01, 1e-8), (0.01, 0.3), (1.0 / 1.5, 0.3)] {
        // wi 1e-9 inside the critical angle of the macro-normal facet; wo grazing below.
        let s = eta * (1.0 - 1e-9);
        let wi = Vec3::new(-s, 0.0, ((1.0 - s) * (1.0 + s)).sqrt());
        let wo = Vec3::new((1.0f64 - 1e-16).sqrt(), 0.0, -1e-8);
        for ndf in ndfs(alpha) {
            for masking in [Masking::Separable, Masking::Correlated] {
                let glass = RoughDielectric::new(ndf, eta, masking).unwrap();
                let f_io = glass.f_cos(wi, wo) / wo.z.abs() / (eta * eta);
                let f_oi = glass.f_cos(wo, wi) / wi.z.abs();
                let what = format!("{glass:?} {wi:?} {wo:?}");
                assert!(f_oi > 0.0, "{what}");
                assert_close(f_io, f_oi, 1e-6, &what);
            }
        }
    }
}

#[test]
fn reflection_bsdfs_are_symmetric() {
    let mut rng = Pcg64::seed_from_u64(4);
    let lambert = Lambertian::new(0.6).unwrap();
    for alpha in [0.1, 0.7] {
        for ndf in ndfs(alpha) {
            for masking in [Masking::Separable, Masking::Correlated] {
                let bsdf = RoughConductor::new(ndf, 0.2, 3.6, masking).unwrap();
                for _ in 0..2000 {
                    let (wi, wo) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
                    let what = format!("{bsdf:?} {wi:?} {wo:?}");
                    let f_io = bsdf.eval(wi, wo, &mut rng) / wo.z.abs();
                    let f_oi = bsdf.eval(wo, wi, &mut rng) / wi.z.abs();
                    assert_close(f_io, f_oi, 1e-9, &what);
                    let l_io = lambert.eval(wi, wo, &mut rng) / wo.z.abs();
                    let l_oi = lambert.eval(wo, wi, &mut rng) / wi.z.abs();
                    assert_close(l_io, l_oi, 1e-12, &what);
                }
            }
        }
    }
}

/// Student-T with gamma = 2 is GGX: same eval and pdf for both BSDFs, all sides, both masking
/// models.
#[test]
fn student_t_at_gamma_two_is_ggx() {
    let mut rng = Pcg64::seed_from_u64(6);
    for alpha in [0.05, 0.4, 1.2] {
        let st = StudentT::new(alpha, 2.0).unwrap();
        let ggx = Ggx::new(alpha).unwrap();
        for masking in [Masking::Separable, Masking::Correlated] {
            let d_st = RoughDielectric::new(st, 1.5, masking).unwrap();
            let d_ggx = RoughDielectric::new(ggx, 1.5, masking).unwrap();
            let c_st = RoughConductor::new(st, 0.2, 3.6, masking).unwrap();
            let c_ggx = RoughConductor::new(ggx, 0.2, 3.6, masking).unwrap();
            for _ in 0..3000 {
                let (wi, wo) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
                let what = format!("alpha {alpha} {masking:?} {wi:?} {wo:?}");
                let mut r = rng.clone();
                assert_close(
                    d_st.eval(wi, wo, &mut r),
                    d_ggx.eval(wi, wo, &mut r),
                    1e-8,
                    &what,
                );
                assert_close(
                    d_st.pdf(wi, wo, &mut r),
                    d_ggx.pdf(wi, wo, &mut r),
                    1e-8,
                    &what,
                );
                assert_close(
                    c_st.eval(wi, wo, &mut r),
                    c_ggx.eval(wi, wo, &mut r),
                    1e-8,
                    &what,
                );
                assert_close(
                    c_st.pdf(wi, wo, &mut r),
                    c_ggx.pdf(wi, wo, &mut r),
                    1e-8,
                    &what,
                );
            }
        }
    }
}

/// Height-correlated masking masks less than separable masking in reflection (both directions
/// see the same heights) and more in transmission (a point high enough to be seen from above
/// is harder to see from below); the two agree for normal incidence and exit (Lambda = 0).
#[test]
fn correlated_masking_bounds_separable() {
    let mut rng = Pcg64::seed_from_u64(8);
    for ndf in ndfs(0.6) {
        let sep = RoughDielectric::new(ndf, 1.5, Masking::Separable).unwrap();
        let cor = RoughDielectric::new(ndf, 1.5, Masking::Correlated).unwrap();
        for _ in 0..3000 {
            let (wi, wo) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
            let (s, c) = (sep.eval(wi, wo, &mut rng), cor.eval(wi, wo, &mut rng));
            if wi.z * wo.z > 0.0 {
                assert!(c >= s * (1.0 - 1e-12), "{ndf:?} {wi:?} {wo:?}: {c} < {s}");
            } else {
                assert!(c <= s * (1.0 + 1e-12), "{ndf:?} {wi:?} {wo:?}: {c} > {s}");
            }
        }
        let (up, down) = (Vec3::z(), -Vec3::z());
        for (wi, wo) in [(up, up), (up, down), (down, up), (down, down)] {
            let what = format!("{ndf:?} {wi:?} {wo:?}");
            assert_close(sep.f_cos(wi, wo), cor.f_cos(wi, wo), 1e-12, &what);
        }
    }
}

#[test]
fn conductor_fresnel_limits() {
    // A real index reduces to the dielectric formula, including total internal reflection.
    for eta in [1.5, 1.0 / 1.5, 3.0] {
        for k in 0..=100 {
            let c = k as f64 / 100.0;
            let what = format!("eta {eta} cos {c}");
            let (fc, fd) = (
                fresnel_conductor(c, Complex::new(eta, 0.0)),
                fresnel_dielectric(c, eta),
            );
            assert!((fc - fd).abs() < 1e-13, "{what}: {fc} vs {fd}");
        }
    }
    for (n, k) in [(0.2, 3.6), (1.5, 0.5), (2.9, 3.0), (0.05, 0.0)] {
        let eta = Complex::new(n, k);
        let normal = ((n - 1.0) * (n - 1.0) + k * k) / ((n + 1.0) * (n + 1.0) + k * k);
        assert_close(
            fresnel_conductor(1.0, eta),
            normal,
            1e-13,
            "normal incidence",
        );
        assert_eq!(fresnel_conductor(0.0, eta), 1.0);
        for j in 0..=200 {
            let f = fresnel_conductor(j as f64 / 200.0, eta);
            assert!(
                (0.0..=1.0).contains(&f),
                "{eta} cos {}: {f}",
                j as f64 / 200.0
            );
            assert_eq!(f, fresnel_conductor(-(j as f64) / 200.0, eta));
        }
    }
}

#[test]
fn invalid_parameters_are_rejected() {
    let ggx = Ggx::new(0.3).unwrap();
    for eta in [0.0, -1.5, 1.0, f64::NAN, f64::INFINITY] {
        assert!(
            RoughDielectric::new(ggx, eta, Masking::Separable).is_err(),
            "{eta}"
        );
        assert!(SmoothDielectric::new(eta).is_err(), "{eta}");
    }
    for (n, k) in [
        (0.0, 1.0),
        (-1.0, 1.0),
        (1.0, -0.1),
        (f64::NAN, 1.0),
        (1.0, f64::INFINITY),
    ] {
        assert!(SmoothConductor::new(n, k).is_err(), "{n} {k}");
        assert!(
            RoughConductor::new(ggx, n, k, Masking::Separable).is_err(),
            "{n} {k}"
        );
    }
    for r in [-0.1, 1.1, f64::NAN] {
        assert!(Lambertian::new(r).is_err(), "{r}");
    }
    assert!(Lambertian::new(0.0).is_ok() && Lambertian::new(1.0).is_ok());
}
