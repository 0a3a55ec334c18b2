//! Instruction counts per call, for `valgrind --tool=callgrind`: runs one of the main benchmark
//! rows of `ndf.rs` and `walk.rs` (same configurations: alpha 0.45, gamma 3, eta 1.51, 60
//! degrees, one thread, `Pcg64` seeded with 1) a given number of times and nothing else.
//! Instructions per call are the difference of the totals of two runs with different counts,
//! divided by the difference of the counts, so start-up cancels:
//!
//! ```sh
//! cargo bench -p stfit-core --bench calls --no-run
//! B=$(ls -t target/release/deps/calls-* | grep -v '\.d$' | head -1)
//! for n in 100000 200000; do
//!   valgrind --tool=callgrind --callgrind-out-file=/dev/null $B walk/ggx/sample $n 2>&1 | grep Collected
//! done
//! ```
//!
//! `walk/NDF/eval_many` runs one `eval_many` of N walks toward the 64 directions of the batch
//! row (threads from `RAYON_NUM_THREADS`). Without a row name (as under `cargo bench`) it
//! lists the rows and exits.

use rand::SeedableRng;
use rand_pcg::Pcg64;
use std::hint::black_box;
use stfit_core::Vec3;
use stfit_core::bsdf::Bsdf;
use stfit_core::math::{radians, spherical_direction};
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT, TabulatedStudentT};
use stfit_core::walk::{DielectricFacet, Estimator, Microsurface};

/// Runs row `op` of NDF `ndf` `n` times; false if `op` is not one of its rows.
fn run_ndf<N: Ndf>(ndf: N, op: &str, n: u64) -> bool {
    let mut rng = Pcg64::seed_from_u64(1);
    let w: Vec3 = spherical_direction(radians(60.0), 0.3);
    let t = radians(60.0);
    let wi = Vec3::new(-t.sin(), 0.0, t.cos());
    let wos: Vec<Vec3> = (0..16)
        .map(|k| {
            let z = -0.95 + 1.9 * (k as f64 + 0.5) / 16.0;
            spherical_direction(z.acos(), 0.7 * k as f64)
        })
        .collect();
    match op {
        "sample_visible" => (0..n).for_each(|_| {
            black_box(ndf.sample_visible(black_box(w), &mut rng));
        }),
        "lambda" => (0..n).for_each(|_| {
            black_box(ndf.lambda(black_box(w)));
        }),
        "walk_eval_many" => {
            // The batch row of walk.rs: 64 outgoing directions, N walks, threads from
            // RAYON_NUM_THREADS.
            let ms = Microsurface::new(ndf, DielectricFacet::new(1.51).unwrap());
            let wos: Vec<Vec3> = (0..64)
                .map(|k| spherical_direction(radians(100.0 + k as f64), 0.0))
                .collect();
            black_box(ms.eval_many(wi, &wos, n, 1));
        }
        "walk_sample" | "walk_eval" => {
            let ms = Microsurface::new(ndf, DielectricFacet::new(1.51).unwrap());
            if op == "walk_sample" {
                (0..n).for_each(|_| {
                    black_box(ms.sample_walk(black_box(wi), &mut rng));
                });
            } else {
                (0..n).for_each(|k| {
                    black_box(ms.eval(black_box(wi), wos[(k + 1) as usize % 16], &mut rng));
                });
            }
        }
        _ => return false,
    }
    true
}

const ROWS: [&str; 16] = [
    "beckmann/sample_visible",
    "beckmann/lambda",
    "ggx/sample_visible",
    "ggx/lambda",
    "student_t/sample_visible",
    "student_t/lambda",
    "student_t_g2.8/sample_visible",
    "student_t_g2.8/lambda",
    "tabulated_student_t_g2.8/lambda",
    "walk/beckmann/sample",
    "walk/beckmann/eval",
    "walk/ggx/sample",
    "walk/ggx/eval",
    "walk/ggx/eval_many",
    "walk/student-t/sample",
    "walk/student-t/eval",
];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(row), Some(n)) = (
        args.first(),
        args.get(1).and_then(|n| n.parse::<u64>().ok()),
    ) else {
        println!("usage: calls ROW N, ROW one of: {}", ROWS.join(" "));
        return;
    };
    let parts: Vec<&str> = row.split('/').collect();
    let (name, op) = match parts.as_slice() {
        ["walk", name, op] => (*name, format!("walk_{op}")),
        [name, op] => (*name, op.to_string()),
        _ => ("", String::new()),
    };
    let ok = match name {
        "beckmann" => run_ndf(Beckmann::new(0.45).unwrap(), &op, n),
        "ggx" => run_ndf(Ggx::new(0.45).unwrap(), &op, n),
        "student_t" | "student-t" => run_ndf(StudentT::new(0.45, 3.0).unwrap(), &op, n),
        "student_t_g2.8" => run_ndf(StudentT::new(0.45, 2.8).unwrap(), &op, n),
        "tabulated_student_t_g2.8" => run_ndf(
            TabulatedStudentT::new(StudentT::new(0.45, 2.8).unwrap()),
            &op,
            n,
        ),
        _ => false,
    };
    if !ok {
        eprintln!("unknown row {row}; rows: {}", ROWS.join(" "));
        std::process::exit(2);
    }
}
