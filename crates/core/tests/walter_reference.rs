//! Checks the single-scattering rough dielectric against independent Mitsuba 3.9.1 values
//! (`tests/data/walter-btdf-reference.csv` of the project, copied from the shared folder with
//! its provenance in `tests/data/README.md`; separable masking, exact Smith G1).

use stfit_core::Vec3;
use stfit_core::bsdf::{AnalyticBsdf, Masking, RoughDielectric};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx};

fn reference_path() -> std::path::PathBuf {
    stfit_test_support::project_root().join("tests/data/walter-btdf-reference.csv")
}

#[test]
fn rough_dielectric_matches_mitsuba_reference() {
    let path = reference_path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("reference file {} is required: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (c_ndf, c_alpha, c_eta, c_f) = (col("ndf"), col("alpha"), col("eta"), col("f_cos"));
    let c_wi = col("wi_x");
    let c_wo = col("wo_x");
    let (mut n, mut within_1e4, mut worst) = (0usize, 0usize, 0.0f64);
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| f[i].parse::<f64>().unwrap();
        let alpha = num(c_alpha);
        let ndf: AnyNdf = match f[c_ndf] {
            "beckmann" => Beckmann::new(alpha).unwrap().into(),
            "ggx" => Ggx::new(alpha).unwrap().into(),
            other => panic!("unknown ndf {other}"),
        };
        let wi = Vec3::new(num(c_wi), num(c_wi + 1), num(c_wi + 2));
        let wo = Vec3::new(num(c_wo), num(c_wo + 1), num(c_wo + 2));
        let bsdf = RoughDielectric::new(ndf, num(c_eta), Masking::Separable).unwrap();
        let got = bsdf.f_cos(wi, wo);
        let want = num(c_f);
        let err = (got - want).abs();
        let rel = if want.abs() > 0.0 {
            err / want.abs()
        } else {
            0.0
        };
        n += 1;
        if err <= 1e-7 || rel <= 1e-4 {
            within_1e4 += 1;
        }
        if err > 1e-7 {
            worst = worst.max(rel);
            assert!(
                rel <= 1e-3,
                "{line}: got {got}, want {want} (relative error {rel:.2e})"
            );
        }
    }
    assert!(n > 6000, "only {n} reference rows read");
    assert!(
        within_1e4 as f64 >= 0.99 * n as f64,
        "{within_1e4} of {n} rows within 1e-4; worst {worst:.2e}"
    );
}
