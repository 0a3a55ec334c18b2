//! End-to-end tests of the `stfit` binary: `stfit synth` output, and the fit command's table,
//! JSON and `--out` on data of known truth.

use std::path::PathBuf;
use std::process::{Command, Output};

use stfit_core::bsdf::Masking;
use stfit_fit::{ModelKind, ModelParams, load_path};

/// A fresh directory for one test under the system temp dir, removed when dropped.
struct CaseDir(PathBuf);

impl CaseDir {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("stfit-cli-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for CaseDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the binary and returns its output, failing the test (with stderr) unless it succeeds.
fn stfit_ok(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_stfit"))
        .args(args)
        .output()
        .expect("the stfit binary runs");
    assert!(
        out.status.success(),
        "stfit {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn p(path: &std::path::Path) -> &str {
    path.to_str().unwrap()
}

#[test]
fn synth_then_load_gives_the_model_values() {
    let dir = CaseDir::new("roundtrip");
    for (model, gamma, kind) in [
        ("student-t", Some("1.8"), ModelKind::StudentT),
        ("beckmann", None, ModelKind::Beckmann),
        ("ggx", None, ModelKind::Ggx),
    ] {
        let file = dir.path(&format!("{model}.csv"));
        let mut args = vec![
            "synth",
            "--model",
            model,
            "--alpha",
            "0.3",
            "--scale",
            "2.5",
            "--theta-i",
            "0,45,75",
            "--theta-o",
            "150:250:0.5",
            "--eta",
            "1.45",
            "--masking",
            "correlated",
            "--sample",
            "ground, fine",
            "--out",
            p(&file),
        ];
        if let Some(g) = gamma {
            args.extend(["--gamma", g]);
        }
        stfit_ok(&args);
        let data = load_path(&file).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(data.samples.len(), 1);
        let sample = &data.samples[0];
        assert_eq!(sample.name, "ground, fine");
        assert_eq!(sample.points.len(), 3 * 201);
        assert_eq!(sample.points[1].theta_o_deg, 150.5);
        assert_eq!(sample.points[201].theta_i_deg, 45.0);
        let truth = ModelParams {
            kind,
            alpha: 0.3,
            gamma: gamma.map_or(f64::NAN, |g| g.parse().unwrap()),
            scale: 2.5,
        };
        let mut positive = 0;
        for m in &sample.points {
            let l = truth
                .l_single(m.theta_i_deg, m.theta_o_deg, 1.45, Masking::Correlated)
                .unwrap();
            assert_eq!(m.l, l, "{model} at ({}, {})", m.theta_i_deg, m.theta_o_deg);
            assert_eq!(m.weight, 1.0);
            positive += usize::from(l > 0.0);
        }
        assert!(
            positive > 300,
            "{model}: the grid sees the transmitted lobe"
        );
    }
}

#[test]
fn synth_is_deterministic_for_a_seed_and_stdout_matches_out() {
    let dir = CaseDir::new("seed");
    let args = |seed: &'static str| {
        vec![
            "synth",
            "--model",
            "student-t",
            "--alpha",
            "0.2",
            "--gamma",
            "3",
            "--noise",
            "0.02",
            "--seed",
            seed,
        ]
    };
    let a = stfit_ok(&args("5")).stdout;
    let b = stfit_ok(&args("5")).stdout;
    let c = stfit_ok(&args("6")).stdout;
    assert_eq!(a, b);
    assert_ne!(a, c);
    let file = dir.path("a.csv");
    let mut with_out = args("5");
    with_out.extend(["--out", p(&file)]);
    assert!(stfit_ok(&with_out).stdout.is_empty());
    assert_eq!(std::fs::read(&file).unwrap(), a);
    let text = String::from_utf8(a).unwrap();
    assert!(
        text.starts_with("# stfit "),
        "records the command: {text:.80}"
    );
    assert!(text.contains("--noise 0.02 --seed 5"));
    assert!(text.contains("\nsample,theta_i_deg,theta_o_deg,L\nsynthetic,0,106,"));
}

#[test]
fn synth_noise_is_relative_with_the_requested_sigma() {
    let dir = CaseDir::new("noise");
    let clean = dir.path("clean.csv");
    let noisy = dir.path("noisy.csv");
    let base = [
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.25",
        "--theta-o",
        "140:220:0.5",
    ];
    let mut a = base.to_vec();
    a.extend(["--out", p(&clean)]);
    stfit_ok(&a);
    let mut b = base.to_vec();
    b.extend(["--noise", "0.05", "--seed", "11", "--out", p(&noisy)]);
    stfit_ok(&b);
    let clean = load_path(&clean).unwrap();
    let noisy = load_path(&noisy).unwrap();
    let rel: Vec<f64> = clean.samples[0]
        .points
        .iter()
        .zip(&noisy.samples[0].points)
        .filter(|(c, _)| c.l > 1e-3)
        .map(|(c, n)| n.l / c.l - 1.0)
        .collect();
    let n = rel.len() as f64;
    assert!(n > 300.0);
    let mean = rel.iter().sum::<f64>() / n;
    let sd = (rel.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    // sd of the sample sd is about sigma / sqrt(2n) < 4%: a 15% band cannot fail by chance.
    assert!((sd / 0.05 - 1.0).abs() < 0.15, "relative sd {sd}");
    assert!(mean.abs() < 4.0 * 0.05 / n.sqrt(), "relative mean {mean}");
}

#[test]
fn synth_append_puts_several_samples_in_one_file() {
    let dir = CaseDir::new("append");
    let file = dir.path("three.csv");
    for (name, alpha) in [("frosted", "0.2"), ("etched", "0.1"), ("ground", "0.4")] {
        stfit_ok(&[
            "synth",
            "--model",
            "ggx",
            "--alpha",
            alpha,
            "--sample",
            name,
            "--theta-i",
            "0",
            "--theta-o",
            "170:190:10",
            "--out",
            p(&file),
            "--append",
        ]);
    }
    let data = load_path(&file).unwrap();
    let names: Vec<_> = data.samples.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["frosted", "etched", "ground"]);
    assert!(data.samples.iter().all(|s| s.points.len() == 3));
    let text = std::fs::read_to_string(&file).unwrap();
    assert_eq!(text.matches("sample,theta_i_deg").count(), 1);

    let other = dir.path("other.csv");
    std::fs::write(&other, "theta_i_deg,theta_o_deg,sqrt_L\n0,180,1\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_stfit"))
        .args(["synth", "--model", "ggx", "--alpha", "0.2"])
        .args(["--out", p(&other), "--append"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("other.csv:1: cannot append"), "{stderr}");
    assert_eq!(
        std::fs::read_to_string(&other).unwrap(),
        "theta_i_deg,theta_o_deg,sqrt_L\n0,180,1\n",
        "a refused append leaves the file alone"
    );
}
