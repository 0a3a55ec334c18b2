//! Unit costs of the energy tables, one thread: the single-scattering albedo of one cell by
//! quadrature (per NDF, light from outside and inside), the cosine-weighted average of one
//! line, and the random walks of one all-orders cell (orders >= 2, 10^5 walks).
//!
//! Whole tables are timed with the command line (README.md, "Energy tables").

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use stfit_core::Vec3;
use stfit_core::ndf::{Beckmann, Ggx, StudentT};
use stfit_core::walk::{DielectricFacet, Estimator, Microsurface, ScatteringOrders};
use stfit_tables::single::{
    Interface, Quadrature, TableMasking, TableNdf, average, single_scattering,
};

fn bench_cell<N: TableNdf>(c: &mut Criterion, name: &str, ndf: N) {
    let rule = Quadrature::default();
    for (side, eta_rel) in [("outside", 1.5), ("inside", 1.0 / 1.5)] {
        c.bench_function(&format!("tables/e_ss/{name}/{side}"), |b| {
            b.iter(|| {
                single_scattering(
                    black_box(&ndf),
                    Interface::Dielectric { eta_rel },
                    TableMasking::Correlated,
                    black_box(0.5),
                    &rule,
                )
            })
        });
    }
}

fn quadrature(c: &mut Criterion) {
    bench_cell(c, "ggx_0.3", Ggx::new(0.3).unwrap());
    bench_cell(c, "beckmann_0.3", Beckmann::new(0.3).unwrap());
    bench_cell(c, "student-t_0.3_1.6", StudentT::new(0.3, 1.6).unwrap());
    bench_cell(c, "student-t_0.3_4", StudentT::new(0.3, 4.0).unwrap());
    let rule = Quadrature::default();
    let ggx = Ggx::new(0.3).unwrap();
    c.bench_function("tables/e_avg/ggx_0.3/outside", |b| {
        b.iter(|| {
            average(
                black_box(&ggx),
                Interface::Dielectric { eta_rel: 1.5 },
                TableMasking::Correlated,
                &rule,
            )
        })
    });
}

fn walks(c: &mut Criterion) {
    // The walks of one all-orders cell (orders >= 2), GGX alpha 0.3, eta 1.5, mu 0.5, from
    // outside and inside, as `stfit tables --orders all` runs them.
    let ms = Microsurface::new(Ggx::new(0.3).unwrap(), DielectricFacet::new(1.5).unwrap())
        .with_orders(ScatteringOrders::Multiple);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut group = c.benchmark_group("tables");
    group.sample_size(10);
    for (side, z) in [("outside", 0.5), ("inside", -0.5)] {
        let wi = Vec3::new((0.75f64).sqrt(), 0.0, z);
        group.bench_function(format!("ms_walks/ggx_0.3/{side}/1e5"), |b| {
            b.iter(|| pool.install(|| ms.albedo(black_box(wi), 100_000, 1)))
        });
    }
    group.finish();
}

criterion_group!(benches, quadrature, walks);
criterion_main!(benches);
