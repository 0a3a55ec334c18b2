//! Chi-square goodness of fit of every visible-normal sampler against its density
//! `D_w(wm) = max(0, w.wm) D(wm) / sigma(w)`, on the whole sphere of incident directions.

use rand::SeedableRng;
use rand_pcg::Pcg64;
use rayon::prelude::*;
use stfit_core::Vec3;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, Ndf, StudentT};
use stfit_validate::{SphereBins, bonferroni, chi_square};

const ALPHAS: [f64; 4] = [0.05, 0.3, 1.0, 2.0];
const GAMMAS: [f64; 5] = [1.6, 2.0, 3.0, 10.0, 40.0];
const THETAS_DEG: [f64; 6] = [0.0, 30.0, 60.0, 85.0, 100.0, 150.0];
const SAMPLES: usize = 100_000;

fn all_ndfs() -> Vec<AnyNdf> {
    let mut v = Vec::new();
    for &a in &ALPHAS {
        v.push(Beckmann::new(a).unwrap().into());
        v.push(Ggx::new(a).unwrap().into());
        for &g in &GAMMAS {
            v.push(StudentT::new(a, g).unwrap().into());
        }
    }
    v
}

struct Case {
    ndf: AnyNdf,
    theta_deg: f64,
    w: Vec3,
    seed: u64,
    /// The per-case significance level (Bonferroni over the test's cases).
    significance: f64,
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for (i, ndf) in all_ndfs().into_iter().enumerate() {
        for (j, &t) in THETAS_DEG.iter().enumerate() {
            // A non-zero azimuth exercises the rotation to the frame of w.
            let w = spherical_direction(radians(t), 0.7);
            if t > 90.0 && ndf.sigma(w) <= 1e-4 {
                continue;
            }
            out.push(Case {
                ndf,
                theta_deg: t,
                w,
                seed: 1000 * i as u64 + j as u64,
                significance: 0.0,
            });
        }
    }
    let significance = bonferroni(0.01, out.len());
    for c in &mut out {
        c.significance = significance;
    }
    out
}

/// The chi-square test of one case's sampler against `D_w`, after checking that every sample
/// is a unit normal on the visible side: its p-value, or what failed.
fn check_case(c: &Case) -> Result<f64, String> {
    let mut rng = Pcg64::seed_from_u64(c.seed);
    let samples: Vec<Vec3> = (0..SAMPLES)
        .map(|_| c.ndf.sample_visible(c.w, &mut rng))
        .collect();
    for wm in &samples {
        let ok = (wm.norm() - 1.0).abs() < 1e-12 && wm.z > 0.0 && wm.dot(&c.w) > 0.0;
        if !ok {
            return Err(format!(
                "{:?} theta {}: invalid sample {wm:?}",
                c.ndf, c.theta_deg
            ));
        }
    }
    let sigma = c.ndf.sigma(c.w);
    let (ndf, w) = (c.ndf, c.w);
    let density = move |wm: Vec3| {
        let cos = w.dot(&wm);
        if cos > 0.0 {
            cos * ndf.d(wm) / sigma
        } else {
            0.0
        }
    };
    let bins = SphereBins::equal_mass(Vec3::z(), 24, 24, density);
    let r = chi_square(&bins, &samples, density, &[w, Vec3::z()]);
    if r.passes(c.significance) {
        Ok(r.p_value)
    } else {
        Err(format!("{:?} theta {}: {r}", c.ndf, c.theta_deg))
    }
}

/// Runs [`check_case`] on every case in parallel and fails with the list of failures.
fn check_cases(cases: &[Case]) {
    let results: Vec<Result<f64, String>> = cases.par_iter().map(check_case).collect();
    let min_p = results
        .iter()
        .filter_map(|r| r.as_ref().ok())
        .fold(1.0f64, |a, &b| a.min(b));
    println!("{} cases, smallest p-value {min_p:.3e}", cases.len());
    let failures: Vec<&str> = results
        .iter()
        .filter_map(|r| r.as_ref().err().map(|s| s.as_str()))
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases fail:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn visible_normal_samplers_match_d_visible() {
    check_cases(&cases());
}

/// Far below the horizon at large shapes the visibility gap is tiny (about `1 / (2 a^2)`), and
/// the sampler proposes from `Gamma(g - 5/2)` instead of thinning part 1 by the gap (which
/// took 1e8 draws per normal at gamma 1e8): its samples follow `D_w` there too.
#[test]
fn student_t_far_below_the_horizon_at_large_shapes_matches_d_visible() {
    let mut cases = Vec::new();
    for (k, &(alpha, gamma, theta)) in [
        (0.3, 1e3, 120.0),
        (0.3, 1e4, 150.0),
        (1.0, 1e6, 160.0),
        (2.0, 5e7, 175.0),
        (0.05, 1e4, 95.0),
    ]
    .iter()
    .enumerate()
    {
        let ndf: AnyNdf = StudentT::new(alpha, gamma).unwrap().into();
        let w = spherical_direction(radians(theta), 0.7);
        assert!(ndf.sigma(w) > 1e-200, "{ndf:?} theta {theta}");
        cases.push(Case {
            ndf,
            theta_deg: theta,
            w,
            seed: 77 + k as u64,
            significance: 0.0,
        });
    }
    let significance = bonferroni(0.01, cases.len());
    for c in &mut cases {
        c.significance = significance;
    }
    check_cases(&cases);
}

/// Extreme parameters and directions: samples stay finite unit vectors on the visible side.
#[test]
fn samplers_are_robust_at_extremes() {
    let ndfs: Vec<AnyNdf> = vec![
        Beckmann::new(1e-4).unwrap().into(),
        Beckmann::new(50.0).unwrap().into(),
        Ggx::new(1e-4).unwrap().into(),
        Ggx::new(50.0).unwrap().into(),
        StudentT::new(0.3, 1.5 + 1e-6).unwrap().into(),
        StudentT::new(1e-4, 1.7).unwrap().into(),
        StudentT::new(50.0, 3.0).unwrap().into(),
        StudentT::new(0.3, 1e4).unwrap().into(),
    ];
    // Just above and just below the horizon, and just short of straight down.
    use std::f64::consts::{FRAC_PI_2, PI};
    let mut dirs: Vec<Vec3> = [
        0.0,
        1e-9,
        0.5,
        FRAC_PI_2 - 1e-4,
        FRAC_PI_2 + 1e-4,
        1.6,
        2.5,
        PI - 1e-4,
    ]
    .iter()
    .map(|&t| spherical_direction(t, 2.0))
    .collect();
    dirs.push(Vec3::new(1.0, 0.0, 0.0));
    let mut rng = Pcg64::seed_from_u64(99);
    for ndf in &ndfs {
        for &w in &dirs {
            let sigma = ndf.sigma(w);
            for _ in 0..2000 {
                let wm = ndf.sample_visible(w, &mut rng);
                assert!(
                    wm.iter().all(|c| c.is_finite()) && (wm.norm() - 1.0).abs() < 1e-12,
                    "{ndf:?} w {w:?}: {wm:?}"
                );
                assert!(wm.z > 0.0, "{ndf:?} w {w:?}: {wm:?}");
                if sigma > 1e-12 {
                    assert!(wm.dot(&w) > 0.0, "{ndf:?} w {w:?}: {wm:?}");
                }
            }
        }
    }
    // Nothing is visible from straight below: a defined fallback, no panic.
    let z = Vec3::z();
    for ndf in &ndfs {
        assert_eq!(ndf.sigma(-z), 0.0);
        assert_eq!(ndf.sample_visible(-z, &mut rng), z);
    }
}

/// The two-uniform samplers of GGX and Beckmann (`sample_visible_from`, pbrt's
/// `Sample_wm(w, u)`): uniform `u` gives exactly the visible-normal density, for directions
/// above and below the horizon.
#[test]
fn two_uniform_samplers_match_d_visible() {
    use rand::RngExt;
    let mut cases: Vec<(AnyNdf, f64)> = Vec::new();
    for &a in &[0.05, 0.3, 1.0, 2.0] {
        for &t in &THETAS_DEG {
            cases.push((Beckmann::new(a).unwrap().into(), t));
            cases.push((Ggx::new(a).unwrap().into(), t));
        }
    }
    cases.retain(|(ndf, t)| *t < 90.0 || ndf.sigma(spherical_direction(radians(*t), 0.7)) > 1e-4);
    let significance = bonferroni(0.01, cases.len());
    let failures: Vec<String> = cases
        .par_iter()
        .enumerate()
        .filter_map(|(k, &(ndf, t))| {
            let w = spherical_direction(radians(t), 0.7);
            let mut rng = Pcg64::seed_from_u64(5000 + k as u64);
            let samples: Vec<Vec3> = (0..SAMPLES)
                .map(|_| {
                    let u = [rng.random::<f64>(), rng.random::<f64>()];
                    match ndf {
                        AnyNdf::Beckmann(b) => b.sample_visible_from(w, u),
                        AnyNdf::Ggx(g) => g.sample_visible_from(w, u),
                        AnyNdf::StudentT(_) => unreachable!("only Beckmann and GGX cases"),
                    }
                })
                .collect();
            let density = move |wm: Vec3| ndf.d_visible(w, wm);
            let bins = SphereBins::equal_mass(Vec3::z(), 24, 24, density);
            let r = chi_square(&bins, &samples, density, &[w, Vec3::z()]);
            (!r.passes(significance)).then(|| format!("{ndf:?} theta {t}: {r}"))
        })
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
