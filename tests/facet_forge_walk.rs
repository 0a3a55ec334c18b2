//! Checks the multiple-scattering random walk of `stfit albedo` and `stfit eval` against
//! independent values from NVlabs facet-forge, the seed paper's published C++ code
//! (`tests/data/facet-forge-walk-reference.csv`; provenance in `tests/data/README.md`).
//!
//! Each reference value is recomputed with stfit at a fixed seed and with far fewer walks; the
//! difference, in units of the combined standard error, must stay within a two-sided bound
//! Bonferroni-corrected over all rows (family-wise level 1e-3).

use std::collections::BTreeMap;

use stfit_core::ndf::special::erfcx;
use stfit_test_support::Cli;

const REFERENCE: &str = "tests/data/facet-forge-walk-reference.csv";
const SEED: &str = "20230806";
/// Walks of `stfit albedo` per configuration and orders.
const ALBEDO_WALKS: &str = "500000";
/// Walks of `stfit eval` per incident direction (plus a quarter as many from each `wo`).
const EVAL_WALKS: &str = "100000";
/// Family-wise probability of a false failure.
const FAMILY_LEVEL: f64 = 1e-3;

/// One row of the reference file.
struct Row {
    ndf: String,
    alpha: String,
    gamma: String,
    eta: String,
    theta_i: String,
    wi: [f64; 3],
    wo: Option<[f64; 3]>,
    quantity: String,
    value: f64,
    stderr: f64,
}

fn read_reference() -> Vec<Row> {
    let path = stfit_test_support::project_root().join(REFERENCE);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("reference file {} is required: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("{REFERENCE}: no column {name}"))
    };
    let (c_ndf, c_alpha, c_gamma, c_eta, c_ti) = (
        col("ndf"),
        col("alpha"),
        col("gamma"),
        col("eta"),
        col("theta_i_deg"),
    );
    let (c_wi, c_wo, c_q, c_v, c_se, c_walks) = (
        col("wi_x"),
        col("wo_x"),
        col("quantity"),
        col("value"),
        col("stderr"),
        col("walks"),
    );
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let num = |i: usize| -> f64 {
                f[i].parse()
                    .unwrap_or_else(|e| panic!("{REFERENCE}: {line}: column {i}: {e}"))
            };
            let walks = num(c_walks);
            assert!(walks >= 1e6, "{line}: the reference needs many walks");
            Row {
                ndf: f[c_ndf].to_string(),
                alpha: f[c_alpha].to_string(),
                gamma: f[c_gamma].to_string(),
                eta: f[c_eta].to_string(),
                theta_i: f[c_ti].to_string(),
                wi: [num(c_wi), num(c_wi + 1), num(c_wi + 2)],
                wo: (!f[c_wo].is_empty()).then(|| [num(c_wo), num(c_wo + 1), num(c_wo + 2)]),
                quantity: f[c_q].to_string(),
                value: num(c_v),
                stderr: num(c_se),
            }
        })
        .collect()
}

fn surface(row: &Row) -> Vec<String> {
    let mut s = vec![
        "--ndf".into(),
        row.ndf.clone(),
        "--alpha".into(),
        row.alpha.clone(),
        "--eta".into(),
        row.eta.clone(),
    ];
    if !row.gamma.is_empty() {
        s.extend(["--gamma".into(), row.gamma.clone()]);
    }
    s
}

fn stfit(args: &[String], stdin: &str) -> String {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = Cli::new(env!("CARGO_BIN_EXE_stfit")).run_with_stdin(&args, stdin);
    out.ok().to_string()
}

/// `(value, stderr)` of stfit for every row, in order.
fn recompute(rows: &[Row]) -> Vec<(f64, f64)> {
    let mut got = vec![(f64::NAN, f64::NAN); rows.len()];
    // Albedo rows: one run per configuration and orders.
    let mut albedo: BTreeMap<(Vec<String>, String, String), Vec<usize>> = BTreeMap::new();
    // Eval rows: one run per configuration and orders, all pairs on stdin.
    let mut eval: BTreeMap<(Vec<String>, String), Vec<usize>> = BTreeMap::new();
    for (i, row) in rows.iter().enumerate() {
        let (what, orders) = row
            .quantity
            .rsplit_once('_')
            .unwrap_or_else(|| panic!("bad quantity {}", row.quantity));
        match what {
            "reflectance" | "transmittance" => albedo
                .entry((surface(row), row.theta_i.clone(), orders.to_string()))
                .or_default()
                .push(i),
            "f_cos" => eval
                .entry((surface(row), orders.to_string()))
                .or_default()
                .push(i),
            other => panic!("unknown quantity {other}"),
        }
    }
    for ((surf, theta_i, orders), idx) in &albedo {
        let mut args = vec!["albedo".to_string()];
        args.extend(surf.iter().cloned());
        args.extend(
            [
                "--theta-i",
                theta_i,
                "--orders",
                orders,
                "--walks",
                ALBEDO_WALKS,
                "--seed",
                SEED,
                "--json",
            ]
            .map(String::from),
        );
        let json: serde_json::Value = serde_json::from_str(&stfit(&args, "")).unwrap();
        for &i in idx {
            let key = rows[i].quantity.rsplit_once('_').unwrap().0;
            let v = json[key].as_f64().unwrap();
            let se = json[format!("{key}_stderr")].as_f64().unwrap();
            got[i] = (v, se);
        }
    }
    for ((surf, orders), idx) in &eval {
        let mut args = vec!["eval".to_string()];
        args.extend(surf.iter().cloned());
        args.extend(["--orders", orders, "--walks", EVAL_WALKS, "--seed", SEED].map(String::from));
        let mut input = String::from("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n");
        for &i in idx {
            let (wi, wo) = (rows[i].wi, rows[i].wo.unwrap());
            input += &format!(
                "{},{},{},{},{},{}\n",
                wi[0], wi[1], wi[2], wo[0], wo[1], wo[2]
            );
        }
        let out = stfit(&args, &input);
        let lines: Vec<&str> = out.lines().skip(1).collect();
        assert_eq!(lines.len(), idx.len(), "{out}");
        for (&i, line) in idx.iter().zip(lines) {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            got[i] = (v[6], v[7]);
        }
    }
    got
}

/// The two-sided bound `z` with `P(|N(0,1)| > z) = p`, by bisection on `erfc`.
fn two_sided_bound(p: f64) -> f64 {
    let tail = |z: f64| {
        let x = z / std::f64::consts::SQRT_2;
        erfcx(x) * (-x * x).exp()
    };
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tail(mid) > p { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

#[test]
fn walk_matches_facet_forge() {
    let rows = read_reference();
    assert!(rows.len() >= 50, "{} rows", rows.len());
    let got = recompute(&rows);
    let bound = two_sided_bound(FAMILY_LEVEL / rows.len() as f64);
    let mut report = String::new();
    let mut worst = 0.0f64;
    for (row, &(v, se)) in rows.iter().zip(&got) {
        let combined = se.hypot(row.stderr);
        assert!(combined > 0.0, "{}: zero standard error", row.quantity);
        let z = (v - row.value) / combined;
        worst = worst.max(z.abs());
        report += &format!(
            "{} alpha {} gamma {} eta {} theta_i {} wo {:?} {}: stfit {v:.6e} +- {se:.2e}, \
             facet-forge {:.6e} +- {:.2e}, z {z:+.2}\n",
            row.ndf,
            row.alpha,
            row.gamma,
            row.eta,
            row.theta_i,
            row.wo,
            row.quantity,
            row.value,
            row.stderr
        );
    }
    assert!(
        worst <= bound,
        "largest |z| {worst:.2} exceeds the Bonferroni bound {bound:.2}:\n{report}"
    );
    // A sign of standard errors that are too large: every |z| small.
    let rms = (got
        .iter()
        .zip(&rows)
        .map(|(&(v, se), r)| ((v - r.value) / se.hypot(r.stderr)).powi(2))
        .sum::<f64>()
        / rows.len() as f64)
        .sqrt();
    assert!(rms > 0.3, "rms z {rms:.2} is implausibly small:\n{report}");
}
