//! Measures the error of the default albedo quadrature: at 672 cells per NDF spanning Cycles'
//! 16^3 glass grid (6 ior nodes, 7 cosines, 8 roughnesses, light from both sides), the largest
//! difference of `R_ss` or `T_ss` from the same quadrature with 4x the azimuth nodes and a
//! 1e-11 tilt tolerance, and the cost per cell. The figures quoted in `single.rs` and
//! `tables-format.md` come from
//!
//! ```text
//! cargo run --release -p stfit-tables --example quadrature_accuracy -- ggx beckmann 1.6 4
//! ```
//!
//! (an argument that is a number is a Student-T gamma).

use std::time::Instant;
use stfit_core::ndf::{Beckmann, Ggx, StudentT};
use stfit_tables::grid::{cycles_ior, cycles_mu, cycles_roughness};
use stfit_tables::single::{
    Albedo, Interface, Quadrature, TableMasking, TableNdf, single_scattering,
};

/// `(alpha, mu, eta_rel)` of the cells: a subset of Cycles' nodes, both sides.
fn cells() -> Vec<(f64, f64, f64)> {
    let (alpha, mu, ior) = (cycles_roughness(16), cycles_mu(16), cycles_ior(16));
    let mut out = Vec::new();
    for z in [1, 3, 5, 8, 11, 15] {
        let eta = ior.values[z];
        for y in [0, 1, 3, 6, 9, 12, 15] {
            for x in [0, 1, 2, 4, 7, 10, 13, 15] {
                for eta_rel in [eta, 1.0 / eta] {
                    out.push((alpha.values[x], mu.values[y], eta_rel));
                }
            }
        }
    }
    out
}

fn albedo<N: TableNdf>(ndf: &N, mu: f64, eta_rel: f64, rule: &Quadrature) -> Albedo {
    let i = Interface::Dielectric { eta_rel };
    single_scattering(ndf, i, TableMasking::Correlated, mu, rule)
}

fn study<N: TableNdf>(name: &str, make: impl Fn(f64) -> Result<N, stfit_core::ParamError>) {
    let (rule, fine) = (Quadrature::default(), Quadrature::new(64, 16, 1e-11));
    let cells = cells();
    let (mut worst, mut at) = (0.0f64, (0.0, 0.0, 0.0));
    let mut seconds = 0.0;
    for &(alpha, mu, eta_rel) in &cells {
        let ndf = match make(alpha) {
            Ok(n) => n,
            Err(e) => {
                eprintln!("{name}: {e}");
                return;
            }
        };
        let t = Instant::now();
        let a = albedo(&ndf, mu, eta_rel, &rule);
        seconds += t.elapsed().as_secs_f64();
        let b = albedo(&ndf, mu, eta_rel, &fine);
        let d = (a.reflected - b.reflected)
            .abs()
            .max((a.transmitted - b.transmitted).abs());
        if d > worst {
            (worst, at) = (d, (alpha, mu, eta_rel));
        }
    }
    println!(
        "{name}: {} cells, {:.3} ms per cell, largest difference {worst:.2e} at \
         (alpha, mu, eta_rel) = {at:?}",
        cells.len(),
        1e3 * seconds / cells.len() as f64
    );
}

fn main() {
    for arg in std::env::args().skip(1) {
        match arg.as_str() {
            "ggx" => study("ggx", Ggx::new),
            "beckmann" => study("beckmann", Beckmann::new),
            g => match g.parse::<f64>() {
                Ok(gamma) => study(&format!("student-t gamma {gamma}"), |a| {
                    StudentT::new(a, gamma)
                }),
                Err(_) => eprintln!("'{g}': expected ggx, beckmann or a Student-T gamma"),
            },
        }
    }
}
