//! Throughput of visible-normal sampling and Smith Lambda for each NDF (alpha 0.45, gamma 3,
//! incident theta 60 degrees, one thread). One call per iteration: M/s = 1000 / (ns/iter).
//! The `build` rows time the construction of a [`TabulatedStudentT`]; the `below` rows time
//! Student-T's sampler from below the horizon, where it thins a proposal by the visibility gap.

use criterion::{Criterion, criterion_group, criterion_main};
use rand::SeedableRng;
use rand_pcg::Pcg64;
use std::hint::black_box;
use stfit_core::Vec3;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT, TabulatedStudentT};

fn bench_ndf<N: Ndf>(c: &mut Criterion, name: &str, ndf: N) {
    let w: Vec3 = spherical_direction(radians(60.0), 0.3);
    let mut rng = Pcg64::seed_from_u64(1);
    c.bench_function(&format!("{name}/sample_visible"), |b| {
        b.iter(|| ndf.sample_visible(black_box(w), &mut rng))
    });
    c.bench_function(&format!("{name}/lambda"), |b| {
        b.iter(|| ndf.lambda(black_box(w)))
    });
}

/// Visible normals drawn from `theta_deg` (below the horizon).
fn bench_below<N: Ndf>(c: &mut Criterion, name: &str, ndf: N, theta_deg: f64) {
    let w: Vec3 = spherical_direction(radians(theta_deg), 0.3);
    let mut rng = Pcg64::seed_from_u64(1);
    c.bench_function(&format!("{name}/sample_visible_below_{theta_deg}"), |b| {
        b.iter(|| ndf.sample_visible(black_box(w), &mut rng))
    });
}

fn ndfs(c: &mut Criterion) {
    bench_ndf(c, "beckmann", Beckmann::new(0.45).unwrap());
    bench_ndf(c, "ggx", Ggx::new(0.45).unwrap());
    bench_ndf(c, "student_t", StudentT::new(0.45, 3.0).unwrap());
    // A non-integer gamma: the incomplete-beta continued fraction does not terminate.
    bench_ndf(c, "student_t_g2.8", StudentT::new(0.45, 2.8).unwrap());
    // Above `QUADRATURE_GAMMA`: Lambda by the Gauss rule of the superposition.
    bench_ndf(c, "student_t_g1e6", StudentT::new(0.45, 1e6).unwrap());
    // Lambda's fractions interpolated, for batches; and what building the table costs.
    let st = StudentT::new(0.45, 2.8).unwrap();
    bench_ndf(c, "tabulated_student_t_g2.8", TabulatedStudentT::new(st));
    // Far below the horizon: the gap's proposal (large shapes) and the thinned Gamma one.
    bench_below(
        c,
        "student_t_a0.001_g1e8",
        StudentT::new(0.001, 1e8).unwrap(),
        179.0,
    );
    bench_below(
        c,
        "student_t_a0.3_g10",
        StudentT::new(0.3, 10.0).unwrap(),
        150.0,
    );
    for gamma in [2.8, 100.0] {
        let st = StudentT::new(0.45, gamma).unwrap();
        c.bench_function(&format!("tabulated_student_t_g{gamma}/build"), |b| {
            b.iter(|| TabulatedStudentT::new(black_box(st)))
        });
    }
}

criterion_group!(benches, ndfs);
criterion_main!(benches);
