//! White furnace tests: a microsurface of non-absorbing facets reflects and transmits all the
//! light it receives, both as counted by sampled walks and as integrated from `eval`.

use rand::{Rng, RngExt, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::PI;
use stfit_core::Vec3;
use stfit_core::bsdf::{Bsdf, fresnel_dielectric};
use stfit_core::math::spherical_direction;
use stfit_core::ndf::{AnyNdf, Ggx, Ndf};
use stfit_core::walk::Estimator;
use stfit_core::walk::{
    BsdfFacet, ConductorFacet, DielectricFacet, Facet, LambertianFacet, Microsurface,
};

mod walk_cases;
use walk_cases::ndfs;

/// Incidence angles: from air and from inside.
const THETAS: [f64; 2] = [0.9, PI - 0.6];

/// Asserts that every walk leaves the surface with its full weight.
fn assert_sampled_furnace<N: Ndf, F: Facet>(ms: &Microsurface<N, F>, wi: Vec3, what: &str) {
    let a = ms.albedo(wi, 20_000, 1);
    let total = a.reflectance + a.transmittance;
    assert!((total - 1.0).abs() < 1e-12, "{what}: R + T = {total}");
    assert_eq!(a.truncated, 0.0, "{what}");
    assert!(
        a.mean_bounces.is_some_and(|b| b >= 1.0 && b.is_finite()),
        "{what}"
    );
}

/// Estimates `integral eval(wi, wo) dwo` over the sphere, drawing `wo` from the mixture
/// `q = (1 - u) p + u / (4 pi)` of a sampler `draw` of known density `p` and the uniform sphere.
fn eval_integral<N: Ndf, F: Facet>(
    ms: &Microsurface<N, F>,
    wi: Vec3,
    draw: impl Fn(&mut Pcg64) -> Option<Vec3>,
    p: impl Fn(Vec3) -> f64,
    u: f64,
    n: usize,
) -> (f64, f64) {
    integral(|wo, rng| ms.eval(wi, wo, rng), draw, p, u, n)
}

/// Estimates `integral f(wo) dwo` for a stochastic `f` as [`eval_integral`] does.
fn integral(
    f: impl Fn(Vec3, &mut Pcg64) -> f64,
    draw: impl Fn(&mut Pcg64) -> Option<Vec3>,
    p: impl Fn(Vec3) -> f64,
    u: f64,
    n: usize,
) -> (f64, f64) {
    let mut rng = Pcg64::seed_from_u64(2024);
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let wo = if rng.random::<f64>() < u {
            uniform_sphere(&mut rng)
        } else {
            match draw(&mut rng) {
                Some(wo) => wo,
                None => uniform_sphere(&mut rng),
            }
        };
        let q = (1.0 - u) * p(wo) + u / (4.0 * PI);
        let x = f(wo, &mut rng) / q;
        s1 += x;
        s2 += x * x;
    }
    let mean = s1 / n as f64;
    (mean, ((s2 / n as f64 - mean * mean) / n as f64).sqrt())
}

fn uniform_sphere<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    let z = 1.0 - 2.0 * rng.random::<f64>();
    spherical_direction(z.acos(), 2.0 * PI * rng.random::<f64>())
}

/// The first-scattering direction density of a smooth dielectric microsurface lit from `wi`
/// (reflection and refraction at one visible facet, whichever side the light leaves on),
/// written independently of the library's phase functions.
fn first_bounce_density<N: Ndf>(ndf: &N, eta: f64, wi: Vec3, wo: Vec3) -> f64 {
    let inside = wi.z < 0.0;
    let s = if inside { -1.0 } else { 1.0 };
    let wi_side = wi * s;
    let sigma = ndf.sigma(wi_side);
    let outward = |v: Vec3| {
        let h = v.normalize();
        if h.z < 0.0 { -h } else { h }
    };
    let mut total = 0.0;
    // Reflection.
    let h = outward(wi + wo);
    if wi_side.dot(&h) > 0.0 && s * wo.dot(&h) > 0.0 {
        total += fresnel_dielectric(wi.dot(&h), eta) * ndf.d(h) / (4.0 * sigma);
    }
    // Refraction into the other medium.
    let (n_i, n_t) = if inside { (eta, 1.0) } else { (1.0, eta) };
    let h = outward(-(wi * n_i + wo * n_t));
    let (hi, ho) = (wi.dot(&h), wo.dot(&h));
    if s * hi > 0.0 && s * ho < 0.0 {
        let d_vis = s * hi * ndf.d(h) / sigma;
        let denom = n_i * hi + n_t * ho;
        total +=
            (1.0 - fresnel_dielectric(hi, eta)) * d_vis * ho.abs() * n_t * n_t / (denom * denom);
    }
    total
}

/// Whether the eval integral is a meaningful test: Student-T below gamma = 2 has a D that grows
/// without bound toward grazing facets, so the next-event estimate of eval near such half
/// vectors has infinite variance and standard errors mean nothing there. Those surfaces are
/// checked by the sampled furnace (and the first-order test checks their eval).
fn eval_has_finite_variance(ndf: &AnyNdf) -> bool {
    !matches!(ndf.gamma(), Some(g) if g < 2.0)
}

#[test]
fn dielectric_furnace_every_ndf_roughness_side_and_index() {
    for ndf in ndfs(&[0.1, 0.5, 1.0, 2.0]) {
        for eta in [1.51, 1.0 / 1.51] {
            let facet = DielectricFacet::new(eta).unwrap();
            let ms = Microsurface::new(ndf, facet);
            for theta in THETAS {
                let wi = spherical_direction(theta, 0.0);
                let what = format!("{ndf:?} eta {eta} theta {theta}");
                assert_sampled_furnace(&ms, wi, &what);
                if !eval_has_finite_variance(&ndf) {
                    continue;
                }
                let wi_side = if wi.z < 0.0 { -wi } else { wi };
                let draw = |rng: &mut Pcg64| {
                    let m = ndf.sample_visible(wi_side, rng);
                    facet.scatter(wi, m, rng).map(|s| s.wo)
                };
                let p = |wo| first_bounce_density(&ndf, eta, wi, wo);
                let (mean, se) = eval_integral(&ms, wi, draw, p, 0.3, 100_000);
                eprintln!("FURNACE {what}: {mean:.4} +- {se:.4}");
                assert!(
                    (mean - 1.0).abs() <= 4.0 * se && se < 0.02,
                    "{what}: integral of eval {mean} +- {se}"
                );
            }
        }
    }
}

#[test]
fn mirror_furnace() {
    for ndf in ndfs(&[0.1, 0.5, 1.0, 2.0]) {
        let ms = Microsurface::new(ndf, ConductorFacet::mirror());
        let wi = spherical_direction(1.0, 0.0);
        let what = format!("mirror {ndf:?}");
        assert_sampled_furnace(&ms, wi, &what);
        let a = ms.albedo(wi, 1000, 3);
        assert_eq!(a.reflectance, 1.0, "{what}");
        if !eval_has_finite_variance(&ndf) {
            continue;
        }
        let draw = |rng: &mut Pcg64| {
            let m = ndf.sample_visible(wi, rng);
            Some(m * (2.0 * wi.dot(&m)) - wi)
        };
        let p = |wo: Vec3| {
            let h = (wi + wo).normalize();
            if wi.dot(&h) > 0.0 {
                ndf.d(h) / (4.0 * ndf.sigma(wi))
            } else {
                0.0
            }
        };
        let (mean, se) = eval_integral(&ms, wi, draw, p, 0.3, 100_000);
        eprintln!("FURNACE {what}: {mean:.4} +- {se:.4}");
        assert!(
            (mean - 1.0).abs() <= 4.0 * se && se < 0.02,
            "{what}: integral of eval {mean} +- {se}"
        );
    }
}

/// Cosine-weighted directions on the upper hemisphere.
fn cosine_upper(rng: &mut Pcg64) -> Option<Vec3> {
    let u: f64 = rng.random();
    let r = u.sqrt();
    let phi = 2.0 * PI * rng.random::<f64>();
    Some(Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u).sqrt()))
}

#[test]
fn lambertian_facets_with_albedo_one_conserve_energy() {
    for alpha in [0.3, 1.0, 2.0] {
        let ndf = Ggx::new(alpha).unwrap();
        let ms = Microsurface::new(ndf, LambertianFacet::new(1.0).unwrap());
        for theta in [0.0, 1.2] {
            let wi = spherical_direction(theta, 0.5);
            let what = format!("lambertian alpha {alpha} theta {theta}");
            assert_sampled_furnace(&ms, wi, &what);
            assert_eq!(ms.albedo(wi, 1000, 3).reflectance, 1.0, "{what}");
            let p = |wo: Vec3| wo.z.max(0.0) / PI;
            let (mean, se) = eval_integral(&ms, wi, cosine_upper, p, 0.2, 20_000);
            eprintln!("FURNACE {what}: {mean:.4} +- {se:.4}");
            assert!(
                (mean - 1.0).abs() <= 4.0 * se && se < 0.02,
                "{what}: integral of eval {mean} +- {se}"
            );
        }
    }
    // A grey Lambertian surface reflects less than its facets' albedo would alone.
    let ms = Microsurface::new(Ggx::new(1.0).unwrap(), LambertianFacet::new(0.5).unwrap());
    let a = ms.albedo(Vec3::z(), 20_000, 4);
    assert!(a.reflectance < 0.5 && a.reflectance > 0.3, "{a:?}");
}

#[test]
fn any_bsdf_as_facet_passes_the_furnace() {
    // A microsurface wrapped as a plain Bsdf (sampling with its pdf walk) behaves as itself.
    let inner = Microsurface::new(Ggx::new(0.3).unwrap(), LambertianFacet::new(1.0).unwrap());
    let ms = Microsurface::new(Ggx::new(0.5).unwrap(), BsdfFacet(inner));
    let wi = spherical_direction(0.7, 0.0);
    assert_sampled_furnace(&ms, wi, "BsdfFacet");
    let p = |wo: Vec3| wo.z.max(0.0) / PI;
    let (mean, se) = eval_integral(&ms, wi, cosine_upper, p, 0.2, 20_000);
    eprintln!("FURNACE BsdfFacet: {mean:.4} +- {se:.4}");
    assert!(
        (mean - 1.0).abs() <= 4.0 * se && se < 0.02,
        "integral of eval {mean} +- {se}"
    );
}

#[test]
fn biscale_dielectric_passes_the_furnace() {
    let inner = Microsurface::new(Ggx::new(0.3).unwrap(), DielectricFacet::new(1.51).unwrap());
    let ndf = Ggx::new(0.6).unwrap();
    let ms = Microsurface::new(ndf, inner);
    for theta in THETAS {
        let wi = spherical_direction(theta, 0.0);
        let what = format!("bi-scale theta {theta}");
        assert_sampled_furnace(&ms, wi, &what);
        // Single-scale roughness sqrt(0.6^2 + 0.3^2) approximates the lobe for sampling.
        let approx = Ggx::new(0.67).unwrap();
        let facet = DielectricFacet::new(1.51).unwrap();
        let wi_side = if wi.z < 0.0 { -wi } else { wi };
        let draw = |rng: &mut Pcg64| {
            let m = approx.sample_visible(wi_side, rng);
            facet.scatter(wi, m, rng).map(|s| s.wo)
        };
        let p = |wo| first_bounce_density(&approx, 1.51, wi, wo);
        let (mean, se) = eval_integral(&ms, wi, draw, p, 0.3, 100_000);
        eprintln!("FURNACE {what}: {mean:.4} +- {se:.4}");
        assert!(
            (mean - 1.0).abs() <= 4.0 * se && se < 0.02,
            "{what}: integral of eval {mean} +- {se}"
        );
    }
}

#[test]
fn pdf_is_the_density_of_sampled_directions_for_grey_lambertian_facets() {
    // Sample weights are 0.6 per bounce, so eval integrates to the albedo but the density of
    // the directions `sample` returns integrates to 1.
    let ms = Microsurface::new(Ggx::new(1.0).unwrap(), LambertianFacet::new(0.6).unwrap());
    let wi = spherical_direction(0.8, 0.0);
    let cos = |wo: Vec3| wo.z.max(0.0) / PI;
    let (pdf, se) = integral(
        |wo, rng| ms.pdf(wi, wo, rng),
        cosine_upper,
        cos,
        0.2,
        20_000,
    );
    eprintln!("FURNACE grey lambertian pdf: {pdf:.4} +- {se:.4}");
    assert!(
        (pdf - 1.0).abs() <= 4.0 * se && se < 0.02,
        "pdf integral {pdf} +- {se}"
    );
    let a = ms.albedo(wi, 20_000, 9);
    let (ev, se) = eval_integral(&ms, wi, cosine_upper, cos, 0.2, 20_000);
    let tol = 4.0 * (se * se + a.reflectance_stderr.powi(2)).sqrt();
    assert!((ev - a.reflectance).abs() <= tol, "eval {ev}, albedo {a:?}");
    assert!(a.reflectance < 0.6 && a.transmittance == 0.0, "{a:?}");
    // Bsdf::sample reports the pdf estimate and the path weight.
    let mut rng = Pcg64::seed_from_u64(3);
    let mut positive = 0;
    for _ in 0..1000 {
        let s = ms
            .sample(wi, &mut rng)
            .expect("every walk leaves a Lambertian surface");
        assert!(!s.delta && s.wo.z > 0.0 && s.pdf >= 0.0);
        assert!(s.weight <= 0.6 + 1e-15 && s.weight > 0.0);
        positive += usize::from(s.pdf > 0.0);
    }
    // One-normal estimates of a Lambertian facet's phase are 0 when the drawn facet faces away
    // from wo; most are positive.
    assert!(positive > 800, "{positive} positive pdf estimates of 1000");
}

#[test]
fn pdf_equals_eval_for_a_dielectric() {
    // Unit sample weights: the two estimators coincide draw for draw.
    let ms = Microsurface::new(Ggx::new(0.4).unwrap(), DielectricFacet::new(1.51).unwrap());
    let wi = spherical_direction(0.5, 0.0);
    for wo in [spherical_direction(2.8, 0.1), spherical_direction(0.6, 3.0)] {
        let e = ms.eval(wi, wo, &mut Pcg64::seed_from_u64(8));
        let p = ms.pdf(wi, wo, &mut Pcg64::seed_from_u64(8));
        assert!(e > 0.0 && e == p, "{e} vs {p}");
    }
}

#[test]
fn flux_dropped_at_the_safety_cap_is_counted() {
    let ndf = Ggx::new(1.0).unwrap();
    let ms = Microsurface::new(ndf, DielectricFacet::new(1.51).unwrap());
    let wi = spherical_direction(1.2, 0.0);
    assert!(ms.with_max_bounces(0).is_err());
    let full = ms.albedo(wi, 20_000, 6);
    assert_eq!(full.truncated, 0.0);
    for cap in [1, 2, 3] {
        let capped = ms.with_max_bounces(cap).unwrap().albedo(wi, 20_000, 6);
        let total = capped.reflectance + capped.transmittance + capped.truncated;
        assert!((total - 1.0).abs() < 1e-12, "cap {cap}: {capped:?}");
        assert!(capped.truncated > 0.0, "cap {cap}: {capped:?}");
    }
    // With a cap of one event, the multiply scattered flux is dropped (weights are 1, so the
    // dropped fraction is a binomial proportion).
    let capped = ms.with_max_bounces(1).unwrap().albedo(wi, 20_000, 6);
    let multiple = ms
        .with_orders(stfit_core::walk::ScatteringOrders::Multiple)
        .albedo(wi, 20_000, 7);
    let dropped = multiple.reflectance + multiple.transmittance;
    let t = capped.truncated;
    let se = (t * (1.0 - t) / 20_000.0 + dropped * (1.0 - dropped) / 20_000.0).sqrt();
    assert!((t - dropped).abs() <= 4.0 * se, "{capped:?} {multiple:?}");
}

#[test]
fn fresnel_conductor_first_order_and_energy() {
    use stfit_core::bsdf::{Masking, RoughConductor};
    use stfit_core::walk::ScatteringOrders;
    let (n, k) = (0.2, 3.6);
    assert!(ConductorFacet::fresnel(-1.0, 1.0).is_err());
    assert!(ConductorFacet::fresnel(1.0, f64::NAN).is_err());
    let ndf = Ggx::new(0.5).unwrap();
    let facet = ConductorFacet::fresnel(n, k).unwrap();
    let single = Microsurface::new(ndf, facet).with_orders(ScatteringOrders::Single);
    let analytic = RoughConductor::new(ndf, n, k, Masking::Correlated).unwrap();
    let mut rng = Pcg64::seed_from_u64(1);
    let wi = spherical_direction(0.9, 0.0);
    let wos: Vec<Vec3> = [(0.2, 2.0), (0.9, 3.1), (1.3, 0.5), (0.6, 4.0)]
        .iter()
        .map(|&(t, p)| spherical_direction(t, p))
        .collect();
    for (wo, e) in wos.iter().zip(single.eval_many(wi, &wos, 20_000, 2)) {
        let want = analytic.eval(wi, *wo, &mut rng);
        assert!(want > 0.0);
        assert!(
            (e.mean - want).abs() <= 4.0 * e.stderr + 1e-12,
            "wo {wo:?}: walk {} +- {}, analytic {want}",
            e.mean,
            e.stderr
        );
    }
    // All orders: the sampled albedo equals the integral of eval, and is below 1.
    let ms = Microsurface::new(ndf, facet);
    let a = ms.albedo(wi, 40_000, 3);
    let p = |wo: Vec3| wo.z.max(0.0) / PI;
    let (ev, se) = eval_integral(&ms, wi, cosine_upper, p, 0.2, 40_000);
    let tol = 4.0 * (se * se + a.reflectance_stderr.powi(2)).sqrt();
    assert!(
        (ev - a.reflectance).abs() <= tol,
        "eval {ev} +- {se}, albedo {a:?}"
    );
    assert!(a.reflectance < 0.99 && a.reflectance > 0.8, "{a:?}");
}
