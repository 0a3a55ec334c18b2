//! Statistical tests of the BSDF samplers against `pdf` and `eval`: chi-square goodness of
//! fit, weight = eval / pdf, pdf normalisation and directional albedo.

mod bsdf_common;

use bsdf_common::{chi_square_sampler, dir_deg, integrate_sphere};
use rand::SeedableRng;
use rand_pcg::Pcg64;
use stfit_core::Vec3;
use stfit_core::bsdf::{
    Bsdf, Lambertian, Masking, RoughConductor, RoughDielectric, SmoothConductor, SmoothDielectric,
    fresnel_conductor, fresnel_dielectric,
};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, Ndf, StudentT};
use stfit_validate::bonferroni;

/// The NDFs the samplers are tested with: every height-field NDF, Student-T with a moderate
/// and a very heavy tail (gamma 1.6 is below GGX's 2).
fn sampled_ndfs(alpha: f64) -> Vec<AnyNdf> {
    vec![
        Beckmann::new(alpha).unwrap().into(),
        Ggx::new(alpha).unwrap().into(),
        StudentT::new(alpha, 3.0).unwrap().into(),
        StudentT::new(alpha, 1.6).unwrap().into(),
    ]
}

/// Incident directions: polar angles in degrees, above 90 meaning from below.
const WI_DEG: [f64; 5] = [0.0, 35.0, 80.0, 115.0, 180.0];

/// Significance of each chi-square test; Bonferroni-corrected by the number of cases.
const SIGNIFICANCE: f64 = 0.01;

fn rough_dielectric_cases() -> Vec<(RoughDielectric<AnyNdf>, Vec3)> {
    let mut cases = Vec::new();
    for alpha in [0.2, 0.6, 1.3] {
        for ndf in sampled_ndfs(alpha) {
            for eta in [1.5, 1.0 / 1.33] {
                for theta in WI_DEG {
                    let bsdf = RoughDielectric::new(ndf, eta, Masking::Separable).unwrap();
                    cases.push((bsdf, dir_deg(theta)));
                }
            }
        }
    }
    cases
}

fn rough_conductor_cases() -> Vec<(RoughConductor<AnyNdf>, Vec3)> {
    let mut cases = Vec::new();
    for alpha in [0.2, 0.8] {
        for ndf in sampled_ndfs(alpha) {
            for theta in [0.0, 40.0, 80.0, 120.0] {
                let bsdf = RoughConductor::new(ndf, 0.2, 3.6, Masking::Correlated).unwrap();
                cases.push((bsdf, dir_deg(theta)));
            }
        }
    }
    cases
}

/// `wo -> eval(wi, wo)` for quadrature (analytic BSDFs ignore the rng).
fn eval_of<B: Bsdf>(bsdf: &B, wi: Vec3) -> impl Fn(Vec3) -> f64 + Sync + '_ {
    move |wo| bsdf.eval(wi, wo, &mut Pcg64::seed_from_u64(0))
}

/// `wo -> pdf(wi, wo)` for quadrature.
fn pdf_of<B: Bsdf>(bsdf: &B, wi: Vec3) -> impl Fn(Vec3) -> f64 + Sync + '_ {
    move |wo| bsdf.pdf(wi, wo, &mut Pcg64::seed_from_u64(0))
}

/// Latitudes (`wo.z`) where a BSDF's `eval` and `pdf` may jump or be integrably singular,
/// given to the quadratures as cell edges.
trait Cuts {
    fn cos_cuts(&self, wi: Vec3) -> Vec<f64>;
}

impl<N: Ndf> Cuts for RoughDielectric<N> {
    /// The horizon, and the latitude where the facet a refraction needs reaches the horizon:
    /// `n_i wi.z + n_o wo.z = 0`.
    fn cos_cuts(&self, wi: Vec3) -> Vec<f64> {
        let (n_i, n_o) = if wi.z > 0.0 {
            (1.0, self.eta())
        } else {
            (self.eta(), 1.0)
        };
        let cut = -n_i / n_o * wi.z;
        if cut.abs() < 1.0 {
            vec![0.0, cut]
        } else {
            vec![0.0]
        }
    }
}

impl<N: Ndf> Cuts for RoughConductor<N> {
    fn cos_cuts(&self, _wi: Vec3) -> Vec<f64> {
        vec![0.0]
    }
}

impl Cuts for Lambertian {
    fn cos_cuts(&self, _wi: Vec3) -> Vec<f64> {
        vec![0.0]
    }
}

/// Runs the chi-square test of `bsdf.sample` against `bsdf.pdf` for every case and fails with
/// the list of rejected cases.
fn assert_sampler_matches_pdf<B: Bsdf + Cuts + std::fmt::Debug>(cases: &[(B, Vec3)], n: usize) {
    let level = bonferroni(SIGNIFICANCE, cases.len());
    let mut failures = Vec::new();
    for (k, (bsdf, wi)) in cases.iter().enumerate() {
        let mut rng = Pcg64::seed_from_u64(0x5eed_0000 + k as u64);
        let wi = *wi;
        let test = chi_square_sampler(
            || bsdf.sample(wi, &mut rng).map(|s| s.wo),
            pdf_of(bsdf, wi),
            n,
            (32, 64),
            &bsdf.cos_cuts(wi),
        );
        if !test.passes(level) {
            failures.push(format!("{bsdf:?}, wi {wi:?}: {test}"));
        }
    }
    assert!(failures.is_empty(), "rejected:\n{}", failures.join("\n"));
}

#[test]
fn rough_dielectric_sampling_matches_pdf() {
    assert_sampler_matches_pdf(&rough_dielectric_cases(), 100_000);
}

#[test]
fn rough_conductor_sampling_matches_pdf() {
    assert_sampler_matches_pdf(&rough_conductor_cases(), 200_000);
}

#[test]
fn lambertian_sampling_matches_pdf() {
    let bsdf = Lambertian::new(0.7).unwrap();
    assert_sampler_matches_pdf(&[(bsdf, dir_deg(35.0)), (bsdf, dir_deg(160.0))], 200_000);
}

/// The chi-square test has power: a sampler at roughness 0.2 is rejected against the pdf at
/// roughness 0.22, and a dielectric sampler against the pdf of a slightly different index.
#[test]
fn chi_square_rejects_a_wrong_pdf() {
    let ggx = |a| AnyNdf::from(Ggx::new(a).unwrap());
    let wi = dir_deg(30.0);
    let mismatched = [
        (
            RoughDielectric::new(ggx(0.2), 1.5, Masking::Separable).unwrap(),
            RoughDielectric::new(ggx(0.22), 1.5, Masking::Separable).unwrap(),
        ),
        (
            RoughDielectric::new(ggx(0.6), 1.5, Masking::Separable).unwrap(),
            RoughDielectric::new(ggx(0.6), 1.55, Masking::Separable).unwrap(),
        ),
    ];
    for (k, (sampler, density)) in mismatched.iter().enumerate() {
        let mut rng = Pcg64::seed_from_u64(77 + k as u64);
        let test = chi_square_sampler(
            || sampler.sample(wi, &mut rng).map(|s| s.wo),
            pdf_of(density, wi),
            200_000,
            (32, 64),
            &density.cos_cuts(wi),
        );
        assert!(test.p_value < 1e-6, "{k}: not rejected: {test}");
    }
}

/// Every sample's weight equals `eval / pdf` and its pdf equals `pdf(wi, wo)`.
fn assert_weight_is_eval_over_pdf<B: Bsdf + std::fmt::Debug>(cases: &[(B, Vec3)]) {
    let mut rng = Pcg64::seed_from_u64(3);
    for (bsdf, wi) in cases {
        let wi = *wi;
        for _ in 0..2000 {
            let Some(s) = bsdf.sample(wi, &mut rng) else {
                continue;
            };
            assert!(!s.delta);
            let pdf = bsdf.pdf(wi, s.wo, &mut rng);
            let f = bsdf.eval(wi, s.wo, &mut rng);
            let close =
                |a: f64, b: f64, rel: f64| (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-300;
            assert!(close(s.pdf, pdf, 1e-12), "{bsdf:?} {wi:?} {s:?}: pdf {pdf}");
            assert!(
                close(s.weight, f / pdf, 1e-9),
                "{bsdf:?} {wi:?} {s:?}: eval/pdf {}",
                f / pdf
            );
        }
    }
}

#[test]
fn weight_is_eval_over_pdf() {
    let mut dielectric = rough_dielectric_cases();
    let ggx = AnyNdf::from(Ggx::new(0.5).unwrap());
    for theta in [20.0, 88.0, 100.0] {
        let wi = dir_deg(theta);
        dielectric.push((
            RoughDielectric::new(ggx, 1.5, Masking::Correlated).unwrap(),
            wi,
        ));
    }
    assert_weight_is_eval_over_pdf(&dielectric);
    assert_weight_is_eval_over_pdf(&rough_conductor_cases());
    let lambert = Lambertian::new(0.3).unwrap();
    assert_weight_is_eval_over_pdf(&[(lambert, dir_deg(10.0)), (lambert, dir_deg(135.0))]);
}

/// Fraction of `n` draws for which `sample` returns a direction, with its standard error.
fn success_fraction<B: Bsdf>(bsdf: &B, wi: Vec3, n: usize, seed: u64) -> (f64, f64) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let hits = (0..n)
        .filter(|_| bsdf.sample(wi, &mut rng).is_some())
        .count();
    let p = hits as f64 / n as f64;
    (p, (p * (1.0 - p) / n as f64).sqrt().max(1.0 / n as f64))
}

/// The pdf integrates over the sphere to the probability that `sample` returns a direction.
#[test]
fn pdf_integrates_to_sampling_probability() {
    let check = |name: String, integral: f64, (p, se): (f64, f64)| {
        assert!(
            (integral - p).abs() <= 5.0 * se + 2e-3,
            "{name}: integral {integral}, sampled fraction {p} +- {se}"
        );
    };
    for (k, (bsdf, wi)) in rough_dielectric_cases().iter().enumerate() {
        let integral = integrate_sphere(pdf_of(bsdf, *wi), &bsdf.cos_cuts(*wi));
        check(
            format!("{bsdf:?} {wi:?}"),
            integral,
            success_fraction(bsdf, *wi, 100_000, k as u64),
        );
    }
    for (k, (bsdf, wi)) in rough_conductor_cases().iter().enumerate() {
        let integral = integrate_sphere(pdf_of(bsdf, *wi), &bsdf.cos_cuts(*wi));
        check(
            format!("{bsdf:?} {wi:?}"),
            integral,
            success_fraction(bsdf, *wi, 100_000, 100 + k as u64),
        );
    }
    let lambert = Lambertian::new(0.5).unwrap();
    let integral = integrate_sphere(pdf_of(&lambert, dir_deg(40.0)), &[0.0]);
    assert!(
        (integral - 1.0).abs() < 1e-4,
        "Lambertian pdf integral {integral}"
    );
}

/// Mean and standard error of the sample weight over `n` draws (zero for failed draws): an
/// estimate of the directional albedo `integral eval dwo`.
fn mean_weight<B: Bsdf>(bsdf: &B, wi: Vec3, n: usize) -> (f64, f64) {
    let mut rng = Pcg64::seed_from_u64(11);
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let w = bsdf.sample(wi, &mut rng).map_or(0.0, |s| s.weight);
        s1 += w;
        s2 += w * w;
    }
    let m = s1 / n as f64;
    (m, ((s2 / n as f64 - m * m).max(0.0) / n as f64).sqrt())
}

/// Directional albedo `integral eval dwo` is at most 1, and the quadrature agrees with the mean
/// sample weight.
fn assert_albedo_at_most_one<B: Bsdf + Cuts + std::fmt::Debug>(bsdf: &B, wi: Vec3) {
    let albedo = integrate_sphere(eval_of(bsdf, wi), &bsdf.cos_cuts(wi));
    assert!(albedo <= 1.0 + 1e-3, "{bsdf:?} {wi:?}: albedo {albedo}");
    let (m, se) = mean_weight(bsdf, wi, 100_000);
    assert!(
        (albedo - m).abs() <= 5.0 * se + 2e-3,
        "{bsdf:?} {wi:?}: quadrature {albedo}, sampled {m} +- {se}"
    );
}

#[test]
fn directional_albedo_is_at_most_one() {
    let ggx = |a| AnyNdf::from(Ggx::new(a).unwrap());
    for alpha in [0.2, 0.6, 1.3] {
        for eta in [1.5, 1.0 / 1.5] {
            for masking in [Masking::Separable, Masking::Correlated] {
                for theta in [0.0, 45.0, 85.0, 95.0, 135.0] {
                    let bsdf = RoughDielectric::new(ggx(alpha), eta, masking).unwrap();
                    assert_albedo_at_most_one(&bsdf, dir_deg(theta));
                }
            }
        }
    }
    for alpha in [0.2, 1.0] {
        for theta in [10.0, 80.0, 170.0] {
            let bsdf = RoughConductor::new(ggx(alpha), 0.2, 3.6, Masking::Separable).unwrap();
            assert_albedo_at_most_one(&bsdf, dir_deg(theta));
        }
    }
    let lambert = Lambertian::new(0.8).unwrap();
    let albedo = integrate_sphere(eval_of(&lambert, dir_deg(60.0)), &[0.0]);
    assert!((albedo - 0.8).abs() < 1e-4, "Lambertian albedo {albedo}");
}

/// Smooth dielectric: reflection is chosen with probability F, each delta lobe has weight 1
/// (its mass over its probability), the directions are the mirror and the refracted ones, and
/// `eval` and `pdf` contain no delta.
#[test]
fn smooth_dielectric_samples_its_delta_lobes() {
    let n = 100_000;
    for eta in [1.5, 1.0 / 1.5] {
        let bsdf = SmoothDielectric::new(eta).unwrap();
        for theta in [0.0, 40.0, 70.0, 120.0, 170.0] {
            let wi = dir_deg(theta);
            let f = fresnel_dielectric(wi.z, eta);
            let (n_i, n_t) = if wi.z > 0.0 { (1.0, eta) } else { (eta, 1.0) };
            let mut rng = Pcg64::seed_from_u64(21);
            let mut reflected = 0usize;
            for _ in 0..n {
                let s = bsdf
                    .sample(wi, &mut rng)
                    .expect("a smooth dielectric always scatters");
                assert!(s.delta && s.weight == 1.0);
                assert!((s.wo.norm() - 1.0).abs() < 1e-12);
                assert_eq!(bsdf.eval(wi, s.wo, &mut rng), 0.0);
                assert_eq!(bsdf.pdf(wi, s.wo, &mut rng), 0.0);
                if s.wo.z * wi.z > 0.0 {
                    reflected += 1;
                    assert_eq!(s.pdf, f);
                    assert!((s.wo - Vec3::new(-wi.x, -wi.y, wi.z)).norm() < 1e-15);
                } else {
                    assert_eq!(s.pdf, 1.0 - f);
                    // Snell's law, in the plane of incidence.
                    let sin_i = (1.0 - wi.z * wi.z).sqrt();
                    let sin_t = (1.0 - s.wo.z * s.wo.z).sqrt();
                    assert!((n_i * sin_i - n_t * sin_t).abs() < 1e-12, "{wi:?} {s:?}");
                    assert!(wi.cross(&s.wo).dot(&Vec3::z()).abs() < 1e-12);
                }
            }
            let se = (f * (1.0 - f) / n as f64).sqrt();
            let p = reflected as f64 / n as f64;
            assert!(
                (p - f).abs() <= 5.0 * se + 1e-12,
                "{wi:?}: reflected {p}, F {f}"
            );
        }
    }
}

/// Smooth conductor: always the mirror direction with probability 1 and weight F.
#[test]
fn smooth_conductor_samples_its_delta_lobe() {
    let bsdf = SmoothConductor::new(0.2, 3.6).unwrap();
    let mut rng = Pcg64::seed_from_u64(1);
    for theta in [0.0, 40.0, 89.0, 150.0] {
        let wi = dir_deg(theta);
        let s = bsdf.sample(wi, &mut rng).unwrap();
        assert!(s.delta && s.pdf == 1.0);
        assert_eq!(s.wo, Vec3::new(-wi.x, -wi.y, wi.z));
        let f = fresnel_conductor(wi.z, bsdf.eta());
        assert_eq!(s.weight, f);
        assert!(f > 0.0 && f <= 1.0);
        assert_eq!(bsdf.eval(wi, s.wo, &mut rng), 0.0);
        assert_eq!(bsdf.pdf(wi, s.wo, &mut rng), 0.0);
    }
}
