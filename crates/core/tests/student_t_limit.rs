//! Student-T tends to Beckmann as gamma grows, over the whole supported range of gamma up to
//! its top (1e15): D, Lambda and sigma within a relative `C (1 + x^2) / gamma` of Beckmann's
//! (the first-order gap of the two families, `x = tan^2 / alpha^2` or `cot^2 / alpha^2`), and
//! the visible-normal sampler passes a chi-square test against Beckmann's visible density.

use rand::SeedableRng;
use rand_pcg::Pcg64;
use stfit_core::Vec3;
use stfit_core::error::GAMMA_MAX;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{Beckmann, Ndf, StudentT};
use stfit_validate::{SphereBins, bonferroni, chi_square};

const ALPHAS: [f64; 4] = [0.05, 0.3, 1.0, 3.0];

/// gamma from 1e4 (where the first-order gap dominates) to the top of the range, a third of a
/// decade apart, with both sides of the
/// switch to the Beckmann limit.
fn gammas() -> Vec<f64> {
    let mut g: Vec<f64> = (12..=45).map(|k| 10f64.powf(f64::from(k) / 3.0)).collect();
    g.extend([
        StudentT::BECKMANN_LIMIT * 0.999,
        StudentT::BECKMANN_LIMIT * 1.001,
        GAMMA_MAX,
    ]);
    g
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// D at normals with `x = tan^2/alpha^2` up to 30 (D down to e^-30 of its peak).
#[test]
fn d_tends_to_beckmann_up_to_the_top_of_the_range() {
    let mut worst = 0.0f64;
    for &alpha in &ALPHAS {
        let b = Beckmann::new(alpha).unwrap();
        for g in gammas() {
            let st = StudentT::new(alpha, g).unwrap();
            for k in 0..=30 {
                let x = f64::from(k);
                let tan = alpha * x.sqrt();
                let wm = Vec3::new(tan, 0.0, 1.0).normalize();
                let e = rel(st.d(wm), b.d(wm));
                let bound = (1.0 + x * x) / g + 1e-13;
                worst = worst.max(e / bound);
                assert!(
                    e <= bound,
                    "alpha {alpha} gamma {g:e} x {x}: {e:e} > {bound:e}"
                );
            }
        }
    }
    println!("largest error / bound: {worst:.3}");
}

/// Lambda and sigma at directions with `a = cot / alpha` in [0.05, 4] on both sides of the
/// horizon.
#[test]
fn lambda_and_sigma_tend_to_beckmann_up_to_the_top_of_the_range() {
    let mut worst = 0.0f64;
    for &alpha in &ALPHAS {
        let b = Beckmann::new(alpha).unwrap();
        for g in gammas() {
            let st = StudentT::new(alpha, g).unwrap();
            for k in 1..=80 {
                let a = 0.05 * f64::from(k);
                let cot = a * alpha;
                let w = Vec3::new(1.0, 0.0, cot).normalize();
                let bound = 10.0 * (1.0 + a.powi(4)) / g + 1e-11;
                let e = rel(st.lambda(w), b.lambda(w));
                worst = worst.max(e / bound);
                assert!(
                    e <= bound,
                    "Lambda alpha {alpha} gamma {g:e} a {a}: {e:e} > {bound:e}"
                );
                for w in [w, -w] {
                    let e = rel(st.sigma(w), b.sigma(w));
                    worst = worst.max(e / bound);
                    assert!(e <= bound, "sigma alpha {alpha} gamma {g:e} w {w:?}: {e:e}");
                }
            }
        }
    }
    println!("largest error / bound: {worst:.3}");
}

/// Visible normals of Student-T at large gamma, tested against Beckmann's visible density.
#[test]
fn sampling_tends_to_beckmann_up_to_the_top_of_the_range() {
    let gammas = [1e4, 1e8, 1e11, 1e13, GAMMA_MAX];
    let thetas = [0.0, 45.0, 80.0, 120.0];
    let alphas = [0.1, 1.0];
    let significance = bonferroni(0.01, gammas.len() * thetas.len() * alphas.len());
    for (i, &alpha) in alphas.iter().enumerate() {
        let b = Beckmann::new(alpha).unwrap();
        for (j, &g) in gammas.iter().enumerate() {
            let st = StudentT::new(alpha, g).unwrap();
            for (l, &t) in thetas.iter().enumerate() {
                let w = spherical_direction(radians(t), 0.4);
                let sigma = b.sigma(w);
                let density = move |wm: Vec3| {
                    let c = w.dot(&wm);
                    if c > 0.0 { c * b.d(wm) / sigma } else { 0.0 }
                };
                let mut rng = Pcg64::seed_from_u64((100 * i + 10 * j + l) as u64);
                let samples: Vec<Vec3> = (0..50_000)
                    .map(|_| st.sample_visible(w, &mut rng))
                    .collect();
                let bins = SphereBins::equal_mass(Vec3::z(), 16, 16, density);
                let r = chi_square(&bins, &samples, density, &[w, Vec3::z()]);
                assert!(
                    r.passes(significance),
                    "alpha {alpha} gamma {g:e} theta {t}: {r}"
                );
            }
        }
    }
}
