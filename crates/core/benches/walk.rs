//! Speed of the height-field random walk: `sample` and `eval` of a rough dielectric
//! microsurface per NDF (light from air at 60 degrees, alpha 0.45, gamma 3, eta 1.51, one
//! thread), the 1 -> 2 thread speed-up of batch evaluation, and walks per second of the
//! null-scattering walk against the height-field walk per roughness (`walk_null_vs_hf`).

use criterion::{Criterion, criterion_group, criterion_main};
use rand::SeedableRng;
use rand_pcg::Pcg64;
use std::hint::black_box;
use stfit_core::Vec3;
use stfit_core::bsdf::Bsdf;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT};
use stfit_core::sphere::{HeightField, SphereNdf};
use stfit_core::walk::Estimator;
use stfit_core::walk::{DielectricFacet, Microsurface, NullMicrosurface};

fn wi() -> Vec3 {
    let t = radians(60.0);
    Vec3::new(-t.sin(), 0.0, t.cos())
}

/// Outgoing directions for `eval`: a spread over both hemispheres.
fn wos() -> Vec<Vec3> {
    (0..16)
        .map(|k| {
            let z = -0.95 + 1.9 * (k as f64 + 0.5) / 16.0;
            spherical_direction(z.acos(), 0.7 * k as f64)
        })
        .collect()
}

/// The null-scattering walk on the same surface, for comparison.
fn bench_null<N: Ndf + 'static>(c: &mut Criterion, name: &str, ndf: N)
where
    HeightField<N>: SphereNdf,
{
    let ms = NullMicrosurface::new(HeightField(ndf), DielectricFacet::new(1.51).unwrap()).unwrap();
    let wi = wi();
    let mut rng = Pcg64::seed_from_u64(1);
    c.bench_function(&format!("walk/{name}/null_sample"), |b| {
        b.iter(|| black_box(ms.sample_walk(black_box(wi), &mut rng)))
    });
    let wos = wos();
    let mut k = 0;
    c.bench_function(&format!("walk/{name}/null_eval"), |b| {
        b.iter(|| {
            k = (k + 1) % wos.len();
            black_box(ms.eval(black_box(wi), wos[k], &mut rng))
        })
    });
}

fn bench_ndf<N: Ndf>(c: &mut Criterion, name: &str, ndf: N) {
    let ms = Microsurface::new(ndf, DielectricFacet::new(1.51).unwrap());
    let wi = wi();
    let mut rng = Pcg64::seed_from_u64(1);
    c.bench_function(&format!("walk/{name}/sample"), |b| {
        b.iter(|| black_box(ms.sample_walk(black_box(wi), &mut rng)))
    });
    c.bench_function(&format!("walk/{name}/sample_with_pdf"), |b| {
        b.iter(|| black_box(ms.sample(black_box(wi), &mut rng)))
    });
    let wos = wos();
    let mut k = 0;
    c.bench_function(&format!("walk/{name}/eval"), |b| {
        b.iter(|| {
            k = (k + 1) % wos.len();
            black_box(ms.eval(black_box(wi), wos[k], &mut rng))
        })
    });
}

fn per_ndf(c: &mut Criterion) {
    bench_ndf(c, "beckmann", Beckmann::new(0.45).unwrap());
    bench_ndf(c, "ggx", Ggx::new(0.45).unwrap());
    bench_ndf(c, "student-t", StudentT::new(0.45, 3.0).unwrap());
    bench_null(c, "ggx", Ggx::new(0.45).unwrap());
}

fn batch(c: &mut Criterion) {
    let ms = Microsurface::new(Ggx::new(0.45).unwrap(), DielectricFacet::new(1.51).unwrap());
    let wi = wi();
    let wos: Vec<Vec3> = (0..64)
        .map(|k| spherical_direction(radians(100.0 + k as f64), 0.0))
        .collect();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        c.bench_function(
            &format!("walk/ggx/eval_many_64x20000/{threads}threads"),
            |b| b.iter(|| pool.install(|| black_box(ms.eval_many(wi, &wos, 20_000, 1)))),
        );
    }
}

/// Walks per second of the null-scattering walk against the height-field walk on the same
/// surface (dielectric facets, eta 1.51, light from air at 60 degrees): one `sample_walk` each.
fn null_vs_hf_at<N: Ndf + 'static>(c: &mut Criterion, name: &str, ndf: N)
where
    HeightField<N>: SphereNdf,
{
    let facet = DielectricFacet::new(1.51).unwrap();
    let hf = Microsurface::new(ndf.clone(), facet);
    let null = NullMicrosurface::new(HeightField(ndf), facet).unwrap();
    let wi = wi();
    let mut group = c.benchmark_group(format!("walk_null_vs_hf/{name}"));
    let mut rng = Pcg64::seed_from_u64(1);
    group.bench_function("null", |b| {
        b.iter(|| black_box(null.sample_walk(black_box(wi), &mut rng)))
    });
    group.bench_function("heightfield", |b| {
        b.iter(|| black_box(hf.sample_walk(black_box(wi), &mut rng)))
    });
    group.finish();
}

fn null_vs_hf(c: &mut Criterion) {
    for alpha in [0.2, 0.4, 0.8, 1.5] {
        null_vs_hf_at(c, &format!("alpha_{alpha}"), Ggx::new(alpha).unwrap());
    }
    null_vs_hf_at(c, "beckmann_alpha_0.4", Beckmann::new(0.4).unwrap());
}

criterion_group!(benches, per_ndf, batch, null_vs_hf);
criterion_main!(benches);
