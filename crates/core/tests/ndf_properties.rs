//! Properties of the height-field NDFs checked against direct numerical integration:
//! normalisation, projected area, Smith Lambda from the slope distribution, the Student-T
//! limits (GGX at gamma = 2, Beckmann as gamma -> inf), the Gamma superposition of Lambda, and
//! parameter validation.

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, Ndf, StudentT};
use stfit_core::{ParamError, Vec3};
use stfit_validate::integrate_sphere;

const ALPHAS: [f64; 4] = [0.05, 0.3, 1.0, 2.0];
const GAMMAS: [f64; 5] = [1.6, 2.0, 3.0, 10.0, 40.0];

fn ndfs(alpha: f64) -> Vec<AnyNdf> {
    let mut v: Vec<AnyNdf> = vec![
        Beckmann::new(alpha).unwrap().into(),
        Ggx::new(alpha).unwrap().into(),
    ];
    v.extend(
        GAMMAS
            .iter()
            .map(|&g| AnyNdf::from(StudentT::new(alpha, g).unwrap())),
    );
    v
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Trapezoid rule for `integral f(x) dx` over `x in (lo, inf)` with `x = lo + exp(s)`,
/// `s in [s0, s1]` with step `h`: exponentially convergent for the smooth, algebraically or
/// exponentially decaying integrands used here.
fn integrate_to_inf(lo: f64, s0: f64, s1: f64, h: f64, f: impl Fn(f64) -> f64) -> f64 {
    let n = ((s1 - s0) / h).ceil() as usize;
    (0..=n)
        .map(|i| {
            let s = s0 + i as f64 * h;
            let e = s.exp();
            let wgt = if i == 0 || i == n { 0.5 } else { 1.0 };
            wgt * f(lo + e) * e
        })
        .sum::<f64>()
        * h
}

#[test]
fn d_is_normalised_by_projected_area() {
    let mut worst = 0.0f64;
    for &alpha in &ALPHAS {
        for ndf in ndfs(alpha) {
            let i = integrate_sphere(Vec3::z(), |wm| ndf.d(wm) * wm.z.max(0.0), &[]);
            assert!((i - 1.0).abs() < 1e-10, "{ndf:?}: integral {i}");
            worst = worst.max((i - 1.0).abs());
        }
    }
    println!("largest |integral - 1| = {worst:.2e}");
}

#[test]
fn sigma_difference_is_cos_theta() {
    let mut rng = Pcg64::seed_from_u64(7);
    for &alpha in &ALPHAS {
        for ndf in ndfs(alpha) {
            for _ in 0..200 {
                let z: f64 = 2.0 * rng.random::<f64>() - 1.0;
                let w = spherical_direction(z.acos(), std::f64::consts::TAU * rng.random::<f64>());
                let d = ndf.sigma(w) - ndf.sigma(-w);
                assert!((d - w.z).abs() < 1e-13, "{ndf:?} {w:?}: {d} vs {}", w.z);
            }
        }
    }
}

#[test]
fn sigma_equals_quadrature_of_projected_area() {
    let mut worst = 0.0f64;
    for &alpha in &ALPHAS {
        for ndf in ndfs(alpha) {
            for deg in [0.0, 30.0, 60.0, 85.0, 89.9, 90.0, 90.1, 95.0, 120.0, 150.0] {
                let w = spherical_direction(radians(deg), 0.3);
                let sigma = ndf.sigma(w);
                let q = integrate_sphere(
                    Vec3::z(),
                    |wm| w.dot(&wm).max(0.0) * ndf.d(wm),
                    &[w, Vec3::z()],
                );
                if q < 1e-12 {
                    assert!(sigma < 1e-11, "{ndf:?} at {deg}: {sigma} vs {q}");
                    continue;
                }
                let e = rel(sigma, q);
                worst = worst.max(e);
                assert!(
                    e < 1e-8,
                    "{ndf:?} at {deg} deg: sigma {sigma} vs quadrature {q}"
                );
            }
        }
    }
    println!("largest relative error {worst:.2e}");
}

/// `P2(x) = integral P22(x, y) dy` with the slope density `P22 = D(wm) cos^4(theta_m)`.
fn slope_marginal(ndf: &AnyNdf, x: f64) -> f64 {
    let p22 = |y: f64| {
        let wm = Vec3::new(-x, -y, 1.0).normalize();
        let u2 = wm.z * wm.z;
        ndf.d(wm) * u2 * u2
    };
    // The y-extent of P22 scales with 1 + |x|: centre the log-range there.
    let c = (1.0 + x.abs()).ln();
    2.0 * integrate_to_inf(0.0, c - 40.0, c + 40.0, 0.05, p22)
}

#[test]
fn lambda_equals_integral_of_slope_distribution() {
    let mut worst = 0.0f64;
    for &alpha in &[0.3, 1.0] {
        for ndf in ndfs(alpha) {
            for mu_over_alpha in [0.1, 1.0, 3.0] {
                let mu = mu_over_alpha * alpha;
                // Lambda(mu) = (1/mu) integral_mu^inf (x - mu) P2(x) dx.
                let q = integrate_to_inf(mu, -40.0, 150.0, 0.05, |x| {
                    (x - mu) * slope_marginal(&ndf, x)
                }) / mu;
                let w = Vec3::new(1.0, 0.0, mu).normalize();
                let l = ndf.lambda(w);
                let e = rel(l, q);
                worst = worst.max(e);
                assert!(e < 1e-10, "{ndf:?} mu {mu}: Lambda {l} vs integral {q}");
            }
        }
    }
    println!("largest relative error {worst:.2e}");
}

fn directions() -> Vec<Vec3> {
    let mut v: Vec<Vec3> = [
        1e-6,
        1e-3,
        0.1,
        0.5,
        1.0,
        1.3,
        1.5,
        1.57,
        std::f64::consts::FRAC_PI_2 - 1e-4,
        1.6,
        2.0,
        2.8,
    ]
    .iter()
    .map(|&t| spherical_direction(t, 0.4))
    .collect();
    v.push(Vec3::z());
    v
}

#[test]
fn student_t_at_gamma_2_is_ggx() {
    for &alpha in &ALPHAS {
        let st = StudentT::new(alpha, 2.0).unwrap();
        let ggx = Ggx::new(alpha).unwrap();
        for w in directions() {
            if w.z > 0.0 {
                assert!(rel(st.d(w), ggx.d(w)) < 1e-12, "D at {w:?}");
            }
            assert!(
                rel(st.lambda(w), ggx.lambda(w)) < 1e-12 || st.lambda(w) == ggx.lambda(w),
                "Lambda at {w:?}: {} vs {}",
                st.lambda(w),
                ggx.lambda(w)
            );
            assert!(rel(st.sigma(w), ggx.sigma(w)) < 1e-12, "sigma at {w:?}");
        }
    }
}

#[test]
fn student_t_tends_to_beckmann() {
    for &alpha in &ALPHAS {
        let st = StudentT::new(alpha, 1e4).unwrap();
        let b = Beckmann::new(alpha).unwrap();
        let peak = b.d(Vec3::z());
        for i in 0..2000 {
            let wm = spherical_direction(
                (std::f64::consts::FRAC_PI_2 - 1e-4) * i as f64 / 2000.0,
                0.0,
            );
            let (ds, db) = (st.d(wm), b.d(wm));
            // The exact leading-order gap: ln(D_ST / D_B) = (x^2/2 - x) / (g - 1) + O(g^-2),
            // x = tan^2 / alpha^2. It passes 1e-3 at x = 5.6 and reaches about 2.4e-3 on the
            // contour D_B = 1e-3 of its peak, so a 1e-3 bound holds only inside x < 5.5; the
            // test checks the gap against its prediction everywhere above 1e-3 of the peak.
            if db > 1e-3 * peak {
                let x = (1.0 - wm.z * wm.z) / (wm.z * wm.z) / (alpha * alpha);
                let predicted = (0.5 * x * x - x) / (1e4 - 1.0);
                let actual = (ds / db).ln();
                assert!(
                    (actual - predicted).abs() < 1e-6 + 1e-2 * predicted.abs(),
                    "D at {wm:?}: ln ratio {actual} vs predicted {predicted}"
                );
                if x < 5.5 {
                    assert!(rel(ds, db) < 1e-3, "D at {wm:?}: {ds} vs {db}");
                }
            }
        }
        // Lambda wherever masking matters at the 0.1% level (Lambda_B > 1e-3). Further out
        // the tails differ by more than 1e-3 relative (5e-3 at Lambda_B = 1e-6): a property of
        // the distributions, checked to be exact by the Gamma-average test.
        for i in 1..2000 {
            let w = spherical_direction((std::f64::consts::PI - 1e-4) * i as f64 / 2000.0, 0.0);
            let (ls, lb) = (st.lambda(w), b.lambda(w));
            if w.z > 0.0 && lb > 1e-3 {
                assert!(rel(ls, lb) < 1e-3, "Lambda at {w:?}: {ls} vs {lb}");
            }
        }
    }
}

/// `Lambda_ST = E_m[Lambda_B(alpha_m)]` with `m ~ Gamma(g-1)`, `alpha_m = alpha sqrt((g-1)/m)`,
/// by quadrature over `ln m`.
#[test]
fn student_t_lambda_is_gamma_average_of_beckmann() {
    let ln_gamma = statrs::function::gamma::ln_gamma;
    let mut worst = 0.0f64;
    for &alpha in &[0.05, 0.45, 2.0] {
        for &g in &[1.6, 2.0, 3.0, 10.0, 40.0, 1e4] {
            let st = StudentT::new(alpha, g).unwrap();
            for theta in [
                1e-3,
                0.02,
                0.3,
                1.0,
                1.5,
                std::f64::consts::FRAC_PI_2 - 1e-4,
            ] {
                let w = spherical_direction(theta, 0.0);
                // alpha_m from t = ln m directly, so that tiny m do not overflow.
                let lb = |t: f64| {
                    let am = alpha * (g - 1.0).sqrt() * (-0.5 * t).exp();
                    match Beckmann::new(am) {
                        Ok(b) => b.lambda(w),
                        // Beyond the supported roughness: Lambda depends on cot / am only, so
                        // evaluate it at alpha 100 with the cotangent scaled alike.
                        Err(_) => {
                            let cot = w.z / w.x.hypot(w.y) * 100.0 / am;
                            let w2 = Vec3::new(1.0, 0.0, cot).normalize();
                            Beckmann::new(100.0).unwrap().lambda(w2)
                        }
                    }
                };
                // Gamma(g-1) density in t = ln m: exp((g-1) t - e^t - lnGamma(g-1)).
                let h = 0.005;
                // Below t = -1400 the integrand is below exp(-(g - 3/2) 1400): negligible.
                let (t0, t1) = (-1400.0, 12.0 + (g - 1.0).ln());
                let n = ((t1 - t0) / h) as usize;
                let avg: f64 = (0..=n)
                    .map(|i| {
                        let t = t0 + i as f64 * h;
                        let m = t.exp();
                        let p = ((g - 1.0) * t - m - ln_gamma(g - 1.0)).exp();
                        if p == 0.0 { 0.0 } else { p * lb(t) }
                    })
                    .sum::<f64>()
                    * h;
                let l = st.lambda(w);
                if avg < 1e-250 {
                    continue;
                }
                let e = rel(l, avg);
                worst = worst.max(e);
                assert!(e < 1e-9, "alpha {alpha} g {g} theta {theta}: {l} vs {avg}");
            }
        }
    }
    println!("largest relative error {worst:.2e}");
}

#[test]
fn constructors_reject_invalid_parameters() {
    for a in [0.0, -1.0] {
        assert_eq!(Beckmann::new(a), Err(ParamError::Alpha(a)));
        assert_eq!(Ggx::new(a), Err(ParamError::Alpha(a)));
        assert_eq!(StudentT::new(a, 3.0), Err(ParamError::Alpha(a)));
    }
    for a in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(matches!(
            Beckmann::new(a),
            Err(ParamError::NonFinite { name: "alpha", .. })
        ));
        assert!(matches!(
            Ggx::new(a),
            Err(ParamError::NonFinite { name: "alpha", .. })
        ));
        assert!(matches!(
            StudentT::new(a, 3.0),
            Err(ParamError::NonFinite { name: "alpha", .. })
        ));
        assert!(matches!(
            StudentT::new(0.5, a),
            Err(ParamError::NonFinite { name: "gamma", .. })
        ));
    }
    for g in [1.5, 1.0, 0.0, -3.0] {
        assert_eq!(StudentT::new(0.5, g), Err(ParamError::Gamma(g)));
    }
    assert!(StudentT::new(0.5, 1.5 + 1e-9).is_ok());
}
