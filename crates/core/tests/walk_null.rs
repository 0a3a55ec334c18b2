//! The null-scattering walk: it reproduces the height-field walk for height-field NDFs, and
//! conserves energy on full-sphere NDFs (von Mises-Fisher lobes, porous blends).

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::PI;
use stfit_core::Vec3;
use stfit_core::bsdf::Bsdf;
use stfit_core::math::spherical_direction;
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT};
use stfit_core::sphere::{HeightField, Porous, SphereNdf, VonMisesFisher};
use stfit_core::walk::Estimator;
use stfit_core::walk::{
    ConductorFacet, DielectricFacet, Facet, LambertianFacet, Microsurface, NullMicrosurface,
    ScatteringOrders,
};

mod walk_cases;
use walk_cases::directions;

/// Asserts that two estimates agree within 4 combined standard errors.
fn assert_close(a: (f64, f64), b: (f64, f64), what: &str) {
    let se = (a.1 * a.1 + b.1 * b.1).sqrt();
    assert!(
        (a.0 - b.0).abs() <= 4.0 * se + 1e-12,
        "{what}: {} +- {} vs {} +- {}",
        a.0,
        a.1,
        b.0,
        b.1
    );
}

/// [`assert_close`] for two BSDF estimates where both are resolved (standard error at most 10%
/// of the mean); returns whether they were compared. The null walk's next-event estimate is
/// heavy-tailed toward directions that single scattering cannot reach (its mean converges
/// slowly, from below, and its standard error understates the gap), while the height-field
/// walk's estimate is bidirectional: such pairs test the null walk's variance, not its mean.
fn assert_close_where_resolved(a: (f64, f64), b: (f64, f64), what: &str) -> bool {
    let resolved = |x: (f64, f64)| x.1 <= 0.1 * x.0.abs();
    if !(resolved(a) && resolved(b)) {
        return false;
    }
    assert_close(a, b, what);
    true
}

#[test]
fn null_walk_reproduces_the_height_field_walk() {
    let (mut compared, mut nonzero) = (0, 0);
    for alpha in [0.5, 1.0] {
        let ndf = Ggx::new(alpha).unwrap();
        for eta in [1.51, 1.0 / 1.51] {
            let facet = DielectricFacet::new(eta).unwrap();
            for orders in [ScatteringOrders::Single, ScatteringOrders::All] {
                let hf = Microsurface::new(ndf, facet).with_orders(orders);
                let null = NullMicrosurface::new(HeightField(ndf), facet)
                    .unwrap()
                    .with_orders(orders);
                for theta in [0.6, PI - 1.0] {
                    let wi = spherical_direction(theta, 0.0);
                    let what = format!("alpha {alpha} eta {eta} {orders:?} theta {theta}");
                    let a = hf.albedo(wi, 20_000, 1);
                    let b = null.albedo(wi, 20_000, 2);
                    let r = |x: &stfit_core::walk::AlbedoEstimate| {
                        (x.reflectance, x.reflectance_stderr)
                    };
                    let t = |x: &stfit_core::walk::AlbedoEstimate| {
                        (x.transmittance, x.transmittance_stderr)
                    };
                    assert_close(r(&a), r(&b), &format!("{what} R"));
                    assert_close(t(&a), t(&b), &format!("{what} T"));
                    let wos = directions();
                    let ea = hf.eval_many(wi, &wos, 10_000, 3);
                    let eb = null.eval_many(wi, &wos, 10_000, 4);
                    for ((wo, x), y) in wos.iter().zip(&ea).zip(&eb) {
                        nonzero += usize::from(x.mean > 0.0);
                        compared += usize::from(assert_close_where_resolved(
                            (x.mean, x.stderr),
                            (y.mean, y.stderr),
                            &format!("{what} wo {wo:?}"),
                        ));
                    }
                }
            }
        }
    }
    assert!(
        compared > 100 && compared * 10 >= nonzero * 7,
        "only {compared} of {nonzero} nonzero pairs compared"
    );
}

/// Compares both walks on a dielectric of the given NDF, light from both sides.
fn compare_walks<N: Ndf + std::fmt::Debug + 'static>(ndf: N)
where
    HeightField<N>: SphereNdf,
{
    let facet = DielectricFacet::new(1.51).unwrap();
    let hf = Microsurface::new(ndf.clone(), facet);
    let null = NullMicrosurface::new(HeightField(ndf.clone()), facet).unwrap();
    for theta in [0.6, PI - 1.0] {
        let wi = spherical_direction(theta, 0.0);
        let what = format!("{ndf:?} theta {theta}");
        let (a, b) = (hf.albedo(wi, 20_000, 1), null.albedo(wi, 20_000, 2));
        assert_close(
            (a.reflectance, a.reflectance_stderr),
            (b.reflectance, b.reflectance_stderr),
            &format!("{what} R"),
        );
        let wos = directions();
        let ea = hf.eval_many(wi, &wos, 10_000, 3);
        let eb = null.eval_many(wi, &wos, 10_000, 4);
        let (mut compared, mut nonzero) = (0, 0);
        for ((wo, x), y) in wos.iter().zip(&ea).zip(&eb) {
            nonzero += usize::from(x.mean > 0.0);
            compared += usize::from(assert_close_where_resolved(
                (x.mean, x.stderr),
                (y.mean, y.stderr),
                &format!("{what} wo {wo:?}"),
            ));
        }
        assert!(
            compared * 10 >= nonzero * 7,
            "{what}: only {compared} of {nonzero} nonzero pairs compared"
        );
    }
}

#[test]
fn null_walk_reproduces_the_height_field_walk_for_every_family() {
    compare_walks(Beckmann::new(0.8).unwrap());
    compare_walks(StudentT::new(0.8, 3.0).unwrap());
    compare_walks(StudentT::new(0.8, 10.0).unwrap());
}

#[test]
fn null_walk_reproduces_opaque_height_field_facets() {
    let ndf = Ggx::new(0.7).unwrap();
    let wi = spherical_direction(1.0, 0.0);
    let wos: Vec<Vec3> = directions().into_iter().filter(|w| w.z > 0.0).collect();
    let hf = Microsurface::new(ndf, LambertianFacet::new(0.8).unwrap());
    let null = NullMicrosurface::new(HeightField(ndf), LambertianFacet::new(0.8).unwrap()).unwrap();
    let (a, b) = (hf.albedo(wi, 20_000, 5), null.albedo(wi, 20_000, 6));
    assert_close(
        (a.reflectance, a.reflectance_stderr),
        (b.reflectance, b.reflectance_stderr),
        "lambertian R",
    );
    let (ea, eb) = (
        hf.eval_many(wi, &wos, 20_000, 7),
        null.eval_many(wi, &wos, 20_000, 8),
    );
    for ((wo, x), y) in wos.iter().zip(&ea).zip(&eb) {
        assert_close(
            (x.mean, x.stderr),
            (y.mean, y.stderr),
            &format!("lambertian wo {wo:?}"),
        );
    }
    let hf = Microsurface::new(ndf, ConductorFacet::mirror());
    let null = NullMicrosurface::new(HeightField(ndf), ConductorFacet::mirror()).unwrap();
    let (ea, eb) = (
        hf.eval_many(wi, &wos, 20_000, 7),
        null.eval_many(wi, &wos, 20_000, 8),
    );
    for ((wo, x), y) in wos.iter().zip(&ea).zip(&eb) {
        assert_close(
            (x.mean, x.stderr),
            (y.mean, y.stderr),
            &format!("mirror wo {wo:?}"),
        );
    }
}

/// `integral eval(wi, wo) dwo` over the upper hemisphere with `wo` drawn cosine-weighted.
fn hemisphere_integral<B: Bsdf>(bsdf: &B, wi: Vec3, n: usize) -> (f64, f64) {
    let mut rng = Pcg64::seed_from_u64(12);
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let u: f64 = rng.random();
        let r = u.sqrt();
        let phi = 2.0 * PI * rng.random::<f64>();
        let wo = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u).sqrt());
        let x = bsdf.eval(wi, wo, &mut rng) / (wo.z / PI);
        s1 += x;
        s2 += x * x;
    }
    let mean = s1 / n as f64;
    (mean, ((s2 / n as f64 - mean * mean) / n as f64).sqrt())
}

fn assert_full_sphere_furnace<S: SphereNdf, F: Facet>(ms: &NullMicrosurface<S, F>, what: &str) {
    for theta in [0.0, 1.2] {
        let wi = spherical_direction(theta, 0.4);
        let a = ms.albedo(wi, 20_000, 9);
        assert!(
            (a.reflectance - 1.0).abs() < 1e-12 && a.transmittance == 0.0 && a.truncated == 0.0,
            "{what} theta {theta}: {a:?}"
        );
        assert!(a.mean_bounces.is_some_and(|b| b >= 1.0));
        let (mean, se) = hemisphere_integral(ms, wi, 20_000);
        eprintln!("NULL FURNACE {what} theta {theta}: {mean:.4} +- {se:.4}");
        assert!(
            (mean - 1.0).abs() <= 4.0 * se && se < 0.02,
            "{what} theta {theta}: integral of eval {mean} +- {se}"
        );
    }
}

#[test]
fn full_sphere_ndfs_pass_the_furnace() {
    for kappa in [1.0, 8.0] {
        let vmf = VonMisesFisher::new(kappa).unwrap();
        let ms = NullMicrosurface::new(vmf, ConductorFacet::mirror()).unwrap();
        assert_full_sphere_furnace(&ms, &format!("vMF {kappa} mirror"));
        let ms = NullMicrosurface::new(vmf, LambertianFacet::new(1.0).unwrap()).unwrap();
        assert_full_sphere_furnace(&ms, &format!("vMF {kappa} lambertian"));
    }
    let porous = Porous::new(HeightField(Ggx::new(0.5).unwrap()), 0.3).unwrap();
    let ms = NullMicrosurface::new(porous, ConductorFacet::mirror()).unwrap();
    assert_full_sphere_furnace(&ms, "porous GGX 0.5 P 0.3 mirror");
}

#[test]
fn porosity_changes_the_result_and_zero_porosity_is_the_height_field() {
    let ggx = Ggx::new(0.5).unwrap();
    let wi = spherical_direction(0.8, 0.0);
    let wo = spherical_direction(0.8, PI);
    let eval = |p: f64| {
        let porous = Porous::new(HeightField(ggx), p).unwrap();
        NullMicrosurface::new(porous, ConductorFacet::mirror())
            .unwrap()
            .eval_many(wi, &[wo], 40_000, 10)[0]
    };
    let hf = Microsurface::new(ggx, ConductorFacet::mirror()).eval_many(wi, &[wo], 40_000, 11)[0];
    let (p0, p5) = (eval(0.0), eval(0.5));
    assert_close((p0.mean, p0.stderr), (hf.mean, hf.stderr), "porosity 0");
    // Uniformly oriented facets scatter light away from the specular peak.
    assert!(
        p5.mean + 4.0 * p5.stderr < p0.mean,
        "porosity 0.5 peak {} +- {} vs {} +- {}",
        p5.mean,
        p5.stderr,
        p0.mean,
        p0.stderr
    );
}

#[test]
fn unbounded_ndfs_are_rejected() {
    let st = StudentT::new(0.5, 1.8).unwrap();
    assert!(NullMicrosurface::new(HeightField(st), ConductorFacet::mirror()).is_err());
    let st = StudentT::new(0.5, 3.0).unwrap();
    assert!(NullMicrosurface::new(HeightField(st), ConductorFacet::mirror()).is_ok());
}

/// Reciprocity of the null walk's `eval`: `f(a, b) / n_b^2 = f(b, a) / n_a^2` (the index is
/// `eta` below the surface, 1 above; `eval = f |wo.z|`) within 4 standard errors, for the
/// direction pairs on `a`'s side (and across, for transmitting facets). Pairs whose estimate
/// rests on a handful of walks (relative error above 10%) are skipped, as in `walk_single.rs`.
fn assert_reciprocal<S: SphereNdf + std::fmt::Debug, F: Facet + std::fmt::Debug>(
    ms: &NullMicrosurface<S, F>,
    eta: f64,
    dirs: &[Vec3],
    walks: u64,
) {
    let index = |w: Vec3| if w.z < 0.0 { eta } else { 1.0 };
    let est: Vec<_> = dirs
        .iter()
        .enumerate()
        .map(|(i, &a)| ms.eval_many(a, dirs, walks, 31 + i as u64))
        .collect();
    let (mut compared, mut total) = (0, 0);
    for i in 0..dirs.len() {
        for j in i + 1..dirs.len() {
            let (a, b) = (dirs[i], dirs[j]);
            let (ab, ba) = (est[i][j], est[j][i]);
            if ab.mean == 0.0 && ba.mean == 0.0 {
                continue;
            }
            total += 1;
            let resolved = |e: &stfit_core::walk::Estimate| e.stderr <= 0.1 * e.mean;
            if !(resolved(&ab) && resolved(&ba)) {
                continue;
            }
            compared += 1;
            let sa = 1.0 / (b.z.abs() * index(b).powi(2));
            let sb = 1.0 / (a.z.abs() * index(a).powi(2));
            let (x, y) = (ab.mean * sa, ba.mean * sb);
            let se = (ab.stderr * sa).hypot(ba.stderr * sb);
            assert!(
                (x - y).abs() <= 4.0 * se + 1e-12 * x.abs(),
                "{ms:?}: {a:?} <-> {b:?}: {x} vs {y} (se {se})"
            );
        }
    }
    assert!(
        total > 0 && compared * 10 >= total * 6,
        "{ms:?}: only {compared} of {total} nonzero pairs compared"
    );
}

/// A few directions in general position (not in one plane), both hemispheres.
fn reciprocity_directions() -> Vec<Vec3> {
    [
        (0.4, 0.3),
        (1.0, 2.0),
        (1.3, -1.2),
        (PI - 0.5, 0.8),
        (PI - 1.1, -2.5),
    ]
    .iter()
    .map(|&(t, p)| spherical_direction(t, p))
    .collect()
}

#[test]
fn null_walk_eval_is_reciprocal() {
    let dirs = reciprocity_directions();
    let up: Vec<Vec3> = dirs.iter().copied().filter(|w| w.z > 0.0).collect();
    let vmf = VonMisesFisher::new(3.0).unwrap();
    let porous = Porous::new(HeightField(Beckmann::new(0.5).unwrap()), 0.3).unwrap();
    let conductor = ConductorFacet::fresnel(1.3, 2.2).unwrap();
    let lambert = LambertianFacet::new(0.8).unwrap();
    assert_reciprocal(
        &NullMicrosurface::new(vmf, conductor).unwrap(),
        1.0,
        &up,
        20_000,
    );
    assert_reciprocal(
        &NullMicrosurface::new(vmf, lambert).unwrap(),
        1.0,
        &up,
        20_000,
    );
    assert_reciprocal(
        &NullMicrosurface::new(porous, conductor).unwrap(),
        1.0,
        &up,
        20_000,
    );
    assert_reciprocal(
        &NullMicrosurface::new(porous, lambert).unwrap(),
        1.0,
        &up,
        20_000,
    );
    // Light and view on both sides of a rough dielectric: transmission carries eta^2.
    for eta in [1.51, 1.0 / 1.51] {
        let ms = NullMicrosurface::new(
            HeightField(Ggx::new(0.6).unwrap()),
            DielectricFacet::new(eta).unwrap(),
        )
        .unwrap();
        assert_reciprocal(&ms, eta, &dirs, 30_000);
    }
}

/// Chi-square p-value of `n` exits sampled by the null walk against its `eval`, by
/// [`walk_cases::sample_eval_p_value`].
fn sample_eval_p_value<S: SphereNdf, F: Facet>(
    ms: &NullMicrosurface<S, F>,
    wi: Vec3,
    n: u64,
) -> f64 {
    // Enough walks that the heavy-tailed next-event estimate of rare multiple-scattering paths
    // is resolved in the sparse bins (at 6000 walks it is visibly too low there).
    walk_cases::sample_eval_p_value(
        |rng| ms.sample_walk(wi, rng),
        |nodes| ms.eval_many(wi, nodes, 20_000, 77),
        n,
    )
}

#[test]
fn null_walk_samples_follow_its_eval() {
    let wi = spherical_direction(0.9, 0.0);
    let vmf = VonMisesFisher::new(3.0).unwrap();
    let porous = Porous::new(HeightField(Ggx::new(0.5).unwrap()), 0.3).unwrap();
    let ggx = Ggx::new(0.6).unwrap();
    let p = [
        sample_eval_p_value(
            &NullMicrosurface::new(vmf, ConductorFacet::fresnel(1.3, 2.2).unwrap()).unwrap(),
            wi,
            40_000,
        ),
        sample_eval_p_value(
            &NullMicrosurface::new(porous, LambertianFacet::new(0.8).unwrap()).unwrap(),
            wi,
            40_000,
        ),
        sample_eval_p_value(
            &NullMicrosurface::new(HeightField(ggx), DielectricFacet::new(1.51).unwrap()).unwrap(),
            wi,
            40_000,
        ),
    ];
    eprintln!("CHI2 p = {p:?}");
    let threshold = stfit_validate::bonferroni(1e-3, p.len());
    assert!(p.iter().all(|&x| x > threshold), "p = {p:?}");
}

#[test]
fn null_walk_reproduces_conductor_facets_lit_from_inside() {
    // The mirrored surface below the interface: light from below, conductor facets.
    let ndf = Ggx::new(0.7).unwrap();
    let facet = ConductorFacet::fresnel(1.3, 2.2).unwrap();
    let wi = spherical_direction(PI - 0.8, 0.0);
    let wos: Vec<Vec3> = directions().into_iter().filter(|w| w.z < 0.0).collect();
    let hf = Microsurface::new(ndf, facet);
    let null = NullMicrosurface::new(HeightField(ndf), facet).unwrap();
    let (a, b) = (hf.albedo(wi, 20_000, 5), null.albedo(wi, 20_000, 6));
    assert_close(
        (a.reflectance, a.reflectance_stderr),
        (b.reflectance, b.reflectance_stderr),
        "conductor from inside R",
    );
    assert_eq!(b.transmittance, 0.0);
    let (ea, eb) = (
        hf.eval_many(wi, &wos, 20_000, 7),
        null.eval_many(wi, &wos, 20_000, 8),
    );
    for ((wo, x), y) in wos.iter().zip(&ea).zip(&eb) {
        assert_close(
            (x.mean, x.stderr),
            (y.mean, y.stderr),
            &format!("conductor from inside wo {wo:?}"),
        );
    }
}
