//! How noisy the walk's next-event estimate of the orders >= 2 term is: for a few rough
//! dielectrics (Student-T, light from air at 0, 40 and 75 degrees, in-plane directions every 10
//! degrees on both sides), the relative standard error of `eval_many` over `--walks` walks, and
//! the time the walks took. The efficiency of an estimator is `1 / (variance x time)`: compare
//! the product `rel_err^2 x seconds` between builds at equal walks.
//!
//! Run: `cargo run --release -p stfit-core --example walk_variance [-- WALKS]`

use std::time::Instant;
use stfit_core::math::radians;
use stfit_core::ndf::StudentT;
use stfit_core::walk::{DielectricFacet, Estimator, Microsurface};
use stfit_core::{ScatteringOrders, Vec3};

fn main() {
    let walks: u64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().expect("WALKS is a whole number"))
        .unwrap_or(20_000);
    let dir = |deg: f64| {
        let t = radians(deg);
        Vec3::new(t.sin(), 0.0, t.cos())
    };
    // theta from +z in the plane of incidence, 90 (grazing) excluded.
    let wos: Vec<Vec3> = (0..36)
        .map(|k| -175.0 + 10.0 * k as f64)
        .filter(|t: &f64| (t.abs() - 90.0).abs() > 1.0)
        .map(dir)
        .collect();
    println!(
        "alpha  gamma  eta   theta_i  median_rel_err  worst_rel_err  (theta_o)   seconds  err^2*s(median)"
    );
    for (alpha, gamma, eta) in [
        (0.3, 3.0, 1.5),
        (0.05, 10.0, 1.3),
        (1.0, 10.0, 1.7),
        (0.5, 2.2, 1.5),
        (1.0, 1.6, 1.7),
    ] {
        let surface = Microsurface::new(
            StudentT::new(alpha, gamma).expect("in range"),
            DielectricFacet::new(eta).expect("in range"),
        )
        .with_orders(ScatteringOrders::Multiple);
        for ti in [0.0, 40.0, 75.0] {
            let wi = dir(-ti);
            let t0 = Instant::now();
            let e = surface.eval_many(wi, &wos, walks, 7);
            let secs = t0.elapsed().as_secs_f64();
            let peak = e.iter().map(|e| e.mean).fold(0.0, f64::max);
            if peak <= 0.0 {
                println!("{alpha:<6} {gamma:<6} {eta:<5} {ti:<8} (no walk scattered twice)");
                continue;
            }
            // Relative to the value, or to 1e-3 of the peak where the value is smaller.
            let mut rel: Vec<(f64, f64)> = e
                .iter()
                .zip(&wos)
                .map(|(e, wo)| {
                    let theta = wo.x.atan2(wo.z).to_degrees();
                    (e.stderr / e.mean.abs().max(1e-3 * peak), theta)
                })
                .collect();
            rel.sort_by(|a, b| a.0.total_cmp(&b.0));
            let median = rel[rel.len() / 2].0;
            let (worst, at) = rel[rel.len() - 1];
            println!(
                "{alpha:<6} {gamma:<6} {eta:<5} {ti:<8} {median:<15.4} {worst:<14.4} ({at:>6.0})  {secs:<8.3} {:.3e}",
                median * median * secs
            );
        }
    }
}
