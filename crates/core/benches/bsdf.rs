//! Speed of the single-scattering rough dielectric per NDF: `eval` (f_cos) and `sample`, at
//! alpha 0.45, gamma 3 (Student-T), eta 1.51, light from air at 60 degrees.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rand::SeedableRng;
use rand_pcg::Pcg64;
use std::hint::black_box;
use stfit_core::Vec3;
use stfit_core::bsdf::{AnalyticBsdf, Bsdf, Masking, RoughDielectric};
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, Ndf, StudentT};

const ALPHA: f64 = 0.45;
const GAMMA: f64 = 3.0;
const ETA: f64 = 1.51;

/// Outgoing directions for `eval`: a fixed spread over both hemispheres (reflection and
/// transmission), so the timing averages over lobes and over cheap zero configurations.
fn outgoing() -> Vec<Vec3> {
    let mut wos = Vec::new();
    for i in 0..16 {
        for j in 0..16 {
            let theta = radians(2.5 + 175.0 * i as f64 / 15.0);
            let phi = radians(360.0 * j as f64 / 16.0 + 1.0);
            wos.push(spherical_direction(theta, phi));
        }
    }
    wos
}

fn bench_ndf<N: Ndf>(c: &mut Criterion, name: &str, ndf: N) {
    let wi = spherical_direction(radians(60.0), 0.0);
    let wos = outgoing();
    for masking in [Masking::Separable, Masking::Correlated] {
        let bsdf = RoughDielectric::new(ndf.clone(), ETA, masking).unwrap();
        let mut group = c.benchmark_group(format!("rough_dielectric/{name}/{masking:?}"));
        group.throughput(Throughput::Elements(wos.len() as u64));
        group.bench_function("eval", |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for &wo in &wos {
                    sum += bsdf.f_cos(black_box(wi), black_box(wo));
                }
                sum
            })
        });
        const N: u64 = 256;
        group.throughput(Throughput::Elements(N));
        let mut rng = Pcg64::seed_from_u64(1);
        group.bench_function("sample", |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for _ in 0..N {
                    if let Some(s) = bsdf.sample(black_box(wi), &mut rng) {
                        sum += s.weight;
                    }
                }
                sum
            })
        });
        group.finish();
    }
}

fn benches(c: &mut Criterion) {
    bench_ndf(c, "beckmann", Beckmann::new(ALPHA).unwrap());
    bench_ndf(c, "ggx", Ggx::new(ALPHA).unwrap());
    bench_ndf(c, "student-t", StudentT::new(ALPHA, GAMMA).unwrap());
    let any: AnyNdf = Ggx::new(ALPHA).unwrap().into();
    bench_ndf(c, "ggx-dyn", any);
}

criterion_group!(benches_group, benches);
criterion_main!(benches_group);
