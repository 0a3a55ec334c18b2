//! End-to-end tests of the `stfit` binary: `stfit synth` output, and the fit command's table,
//! JSON and `--out` on data of known truth.

use std::path::PathBuf;
use stfit_test_support::{CaseDir, Cli, Run};

use stfit_fit::{Gamma, Masking, Model, ModelKind, load_path};

fn stfit(args: &[&str]) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run(args)
}

/// Runs the binary and returns its output, failing the test (with stderr) unless it succeeds.
fn stfit_ok(args: &[&str]) -> Run {
    let out = stfit(args);
    assert!(out.code == Some(0), "stfit {args:?} failed: {}", out.stderr);
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
        let file = dir.join(&format!("{model}.csv"));
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
        assert_eq!(sample.points[1].in_plane_angles().unwrap().1, 150.5);
        assert_eq!(sample.points[201].theta_i_deg(), 45.0);
        let truth = Model {
            eta: 1.45,
            masking: Masking::Correlated,
            ..Model::single(
                kind,
                0.3,
                gamma.map_or(Gamma::NotApplicable, |g| Gamma::Fixed(g.parse().unwrap())),
                2.5,
            )
        };
        let mut positive = 0;
        for m in &sample.points {
            let l = truth.predict_points(std::slice::from_ref(m)).unwrap()[0];
            assert_eq!(m.value, l, "{model} at {:?}", m.angles);
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
    let file = dir.join("a.csv");
    let mut with_out = args("5");
    with_out.extend(["--out", p(&file)]);
    assert!(stfit_ok(&with_out).stdout.is_empty());
    // The same file, but for the recorded command, which names the output (data-format.md:
    // pasted into a shell it writes the file again).
    let written = std::fs::read_to_string(&file).unwrap();
    let (command, rest) = written.split_once('\n').unwrap();
    assert!(
        command.ends_with(&format!(" --out {}", p(&file))),
        "{command}"
    );
    assert_eq!(Some(rest), a.split_once('\n').map(|(_, rest)| rest));
    let text = a;
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
    let clean = dir.join("clean.csv");
    let noisy = dir.join("noisy.csv");
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
        .filter(|(c, _)| c.value > 1e-3)
        .map(|(c, n)| n.value / c.value - 1.0)
        .collect();
    let n = rel.len() as f64;
    assert!(n > 300.0);
    let mean = rel.iter().sum::<f64>() / n;
    let sd = (rel.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    // sd of the sample sd is about sigma / sqrt(2n) < 4%: a 15% band cannot fail by chance.
    assert!((sd / 0.05 - 1.0).abs() < 0.15, "relative sd {sd}");
    assert!(mean.abs() < 4.0 * 0.05 / n.sqrt(), "relative mean {mean}");
}

/// `--append` puts several samples in one file with one header, starting from an empty file;
/// a file with another header is refused and left alone.
#[test]
fn synth_append_puts_several_samples_in_one_file() {
    let dir = CaseDir::new("append");
    // An empty file (made by `touch`, say) is appended to as a new one: header first.
    let file = dir.file("three.csv", "");
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

    let other = dir.join("other.csv");
    std::fs::write(&other, "theta_i_deg,theta_o_deg,sqrt_L\n0,180,1\n").unwrap();
    let out = stfit(&[
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.2",
        "--out",
        p(&other),
        "--append",
    ]);
    assert_eq!(out.code, Some(1));
    let stderr = out.stderr.clone();
    assert!(stderr.contains("other.csv:1: cannot append"), "{stderr}");
    assert_eq!(
        std::fs::read_to_string(&other).unwrap(),
        "theta_i_deg,theta_o_deg,sqrt_L\n0,180,1\n",
        "a refused append leaves the file alone"
    );
}

/// Writes a two-sample file of known truth: `st` (Student-T alpha 0.2, gamma 3, scale 1.5) and
/// `gg` (GGX alpha 0.3, scale 0.8), both noiseless on the Walter grid.
fn known_truth(dir: &CaseDir) -> PathBuf {
    let file = dir.join("truth.csv");
    stfit_ok(&[
        "synth",
        "--model",
        "student-t",
        "--alpha",
        "0.2",
        "--gamma",
        "3",
        "--scale",
        "1.5",
        "--sample",
        "st",
        "--out",
        p(&file),
        "--append",
    ]);
    stfit_ok(&[
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.3",
        "--scale",
        "0.8",
        "--sample",
        "gg",
        "--out",
        p(&file),
        "--append",
    ]);
    file
}

fn fits_of(stdout: &str) -> Vec<serde_json::Value> {
    let doc: serde_json::Value = serde_json::from_str(stdout).expect("--json prints JSON");
    let obj = doc.as_object().expect("a JSON object");
    assert_eq!(obj.keys().collect::<Vec<_>>(), ["fits", "version"]);
    assert_eq!(obj["version"], 1);
    obj["fits"].as_array().expect("fits is an array").clone()
}

/// The keys of one fit: those of stfit 0.1 (whose names and meanings stay) and those added
/// since, which record the model and how it was fitted.
const KEYS: [&str; 28] = [
    "alpha",
    "alpha_stderr",
    "data",
    "eta",
    "eta_fixed",
    "eta_stderr",
    "gamma",
    "gamma_fixed",
    "gamma_stderr",
    "iterations",
    "log_floor",
    "loss",
    "masking",
    "measured",
    "model",
    "multiple_term",
    "n_points",
    "optimizer",
    "orders",
    "rmse_sqrt_l",
    "sample",
    "scale",
    "scale_fixed",
    "scale_stderr",
    "seed",
    "stfit_version",
    "walks",
    "warnings",
];

#[test]
fn json_has_every_key_with_its_type_and_recovers_the_truth() {
    let dir = CaseDir::new("json");
    let file = known_truth(&dir);
    let out = stfit_ok(&[p(&file), "--model", "all", "--json"]);
    let fits = fits_of(&out.stdout);
    assert_eq!(fits.len(), 8, "2 samples x 4 models");
    let expected = [
        ("beckmann", false),
        ("ggx", false),
        ("student-t", true),
        ("student-t", false),
    ];
    for (i, fit) in fits.iter().enumerate() {
        let f = fit.as_object().unwrap();
        let mut keys: Vec<_> = f.keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(keys, KEYS);
        let (model, fixed) = expected[i % 4];
        assert_eq!(f["sample"], if i < 4 { "st" } else { "gg" });
        assert_eq!(f["model"], model);
        assert_eq!(f["gamma_fixed"], fixed);
        for key in ["alpha", "scale", "rmse_sqrt_l"] {
            assert!(f[key].as_f64().is_some_and(f64::is_finite), "{key}: {fit}");
        }
        for key in ["alpha_stderr", "scale_stderr", "gamma_stderr"] {
            assert!(f[key].is_null() || f[key].is_f64(), "{key}: {fit}");
        }
        assert_eq!(f["n_points"].as_u64(), Some(300), "{fit}");
        assert!(f["iterations"].is_u64(), "{fit}");
        // The model as fitted: the defaults, the data file and the version.
        assert_eq!(f["eta"], 1.51, "{fit}");
        assert_eq!(f["eta_fixed"], true, "{fit}");
        assert!(f["eta_stderr"].is_null(), "{fit}");
        assert_eq!(f["scale_fixed"], false, "{fit}");
        assert!(f["log_floor"].is_null(), "{fit}");
        assert_eq!(f["masking"], "separable", "{fit}");
        assert_eq!(f["orders"], "single", "{fit}");
        assert_eq!(f["loss"], "sqrt", "{fit}");
        assert_eq!(f["optimizer"], "nelder-mead", "{fit}");
        assert!(f["walks"].is_null() && f["seed"].is_null(), "{fit}");
        assert_eq!(f["data"], p(&file), "{fit}");
        assert_eq!(f["stfit_version"], env!("CARGO_PKG_VERSION"), "{fit}");
        if model == "student-t" {
            assert!(f["gamma"].is_f64(), "{fit}");
        } else {
            assert!(f["gamma"].is_null() && f["gamma_stderr"].is_null(), "{fit}");
        }
        if fixed {
            assert_eq!(f["gamma"].as_f64(), Some(3.0));
            // A fixed parameter has no standard error.
            assert!(f["gamma_stderr"].is_null(), "{fit}");
        }
    }
    // Noiseless data of the model itself: the matching fit recovers the truth and its residual
    // is (numerically) zero, while the wrong family leaves a visible residual. Student-T with
    // free gamma on GGX data finds gamma = 2, where Student-T is GGX.
    let get = |i: usize, k: &str| fits[i][k].as_f64().unwrap();
    for (i, alpha, gamma, scale) in [
        (2, 0.2, Some(3.0), 1.5),
        (3, 0.2, Some(3.0), 1.5),
        (5, 0.3, None, 0.8),
        (7, 0.3, Some(2.0), 0.8),
    ] {
        assert!((get(i, "alpha") / alpha - 1.0).abs() < 1e-6, "{}", fits[i]);
        assert!((get(i, "scale") / scale - 1.0).abs() < 1e-6, "{}", fits[i]);
        if let Some(gamma) = gamma {
            assert!((get(i, "gamma") / gamma - 1.0).abs() < 1e-6, "{}", fits[i]);
        }
        assert!(get(i, "rmse_sqrt_l") < 1e-6, "{}", fits[i]);
    }
    for (wrong, right) in [(0, 3), (1, 3), (4, 5), (6, 5)] {
        assert!(
            get(wrong, "rmse_sqrt_l") > 0.05,
            "{} fits {} too well",
            fits[wrong]["model"],
            fits[right]["sample"]
        );
    }
}

#[test]
fn table_lists_each_sample_and_out_stores_the_json() {
    let dir = CaseDir::new("table");
    let file = known_truth(&dir);
    let json = dir.join("fits.json");
    let out = stfit_ok(&[p(&file), "--out", p(&json)]);
    let table = out.stdout;
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines.len(), 3, "{table}");
    let header: Vec<&str> = lines[0]
        .split("  ")
        .filter(|s| !s.is_empty())
        .map(str::trim)
        .collect();
    assert_eq!(
        header,
        [
            "sample",
            "model",
            "alpha",
            "gamma",
            "scale",
            "rmse sqrt(L)",
            "n"
        ]
    );
    assert!(
        lines[1].starts_with("st ") && lines[1].contains("student-t"),
        "{table}"
    );
    assert!(
        lines[2].starts_with("gg ") && lines[2].contains("student-t"),
        "{table}"
    );
    assert!(
        lines[1].contains(" ± ") && lines[1].ends_with(" 300"),
        "{table}"
    );
    let stored = fits_of(&std::fs::read_to_string(&json).unwrap());
    assert_eq!(stored.len(), 2);
    let printed = fits_of(&stfit_ok(&[p(&file), "--json"]).stdout);
    assert_eq!(stored, printed, "--out stores what --json prints");
    // With --json and --out both, stdout and the file are the same document.
    let json2 = dir.join("fits2.json");
    let both = stfit_ok(&[p(&file), "--json", "--out", p(&json2)]);
    assert_eq!(both.stdout, std::fs::read_to_string(&json2).unwrap());
}

#[test]
fn sample_and_gamma_flags() {
    let dir = CaseDir::new("flags");
    let file = known_truth(&dir);
    let fits = fits_of(&stfit_ok(&[p(&file), "--sample", "gg", "--gamma", "2.5", "--json"]).stdout);
    assert_eq!(fits.len(), 1);
    assert_eq!(fits[0]["sample"], "gg");
    assert_eq!(fits[0]["gamma"].as_f64(), Some(2.5));
    assert_eq!(fits[0]["gamma_fixed"], true);
    let fits = fits_of(
        &stfit_ok(&[
            p(&file),
            "--model",
            "beckmann",
            "--loss",
            "linear",
            "--optimizer",
            "lbfgs",
            "--masking",
            "correlated",
            "--json",
        ])
        .stdout,
    );
    assert_eq!(fits.len(), 2);
    assert!(
        fits.iter()
            .all(|f| f["model"] == "beckmann" && f["gamma"].is_null())
    );
}

/// `--orders all` fits with the random walk: valid JSON, the truth of single-scattering
/// data approximately (multiple scattering is a small correction at alpha 0.3), the same output
/// for the same seed, and other output for another seed.
#[test]
fn multiple_scattering_fits_deterministically_from_the_command_line() {
    let dir = CaseDir::new("multiple");
    let file = known_truth(&dir);
    let run = |seed: &str| {
        stfit_ok(&[
            p(&file),
            "--orders",
            "all",
            "--walks",
            "2000",
            "--seed",
            seed,
            "--model",
            "ggx",
            "--sample",
            "gg",
            "--json",
        ])
        .stdout
    };
    let (a, b, c) = (run("1"), run("1"), run("2"));
    assert_eq!(a, b, "the same seed gives the same fits");
    assert_ne!(a, c, "another seed gives other walks");
    let fits = fits_of(&a);
    assert_eq!(fits.len(), 1);
    let f = fits[0].as_object().unwrap();
    assert_eq!(
        f.keys().collect::<std::collections::BTreeSet<_>>().len(),
        KEYS.len()
    );
    assert_eq!(f["orders"], "all");
    assert_eq!(f["masking"], "correlated");
    assert_eq!(
        (f["walks"].as_u64(), f["seed"].as_u64()),
        (Some(2000), Some(1))
    );
    let alpha = f["alpha"].as_f64().unwrap();
    let se = f["alpha_stderr"].as_f64().unwrap();
    assert!((alpha - 0.3).abs() < 0.03, "alpha {alpha}");
    assert!(se.is_finite() && se > 0.0, "alpha stderr {se}");
}

/// All orders are height-correlated: `--masking separable` with them is a usage error, as is a
/// walk count of zero, and `--orders multiple` (orders >= 2 only) models no measurement.
#[test]
fn all_orders_refuse_separable_masking_and_zero_walks() {
    let dir = CaseDir::new("multiple-usage");
    let file = known_truth(&dir);
    for (extra, needle) in [
        (["--masking", "separable"], "height-correlated"),
        (["--walks", "0"], "--walks"),
        (["--orders", "multiple"], "multiple"),
    ] {
        let mut args = vec![p(&file), "--orders", "all"];
        args.extend(extra);
        let out = stfit(&args);
        let stderr = out.stderr.clone();
        assert_eq!(out.code, Some(2), "{extra:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{extra:?}: nothing fitted");
        assert!(stderr.contains(needle), "{extra:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

/// The help of the commands that model a measurement (fit, report, synth) lists `--orders`
/// single and all only, since they refuse multiple; the commands that evaluate a surface
/// (eval, albedo, tables) list all three.
#[test]
fn orders_help_lists_the_values_each_command_takes() {
    let values = |cmd: &[&str]| {
        let mut args = cmd.to_vec();
        args.push("--help");
        let out = stfit_ok(&args);
        let text = out.stdout.as_str();
        let at = text.find("\n      --orders").expect("an --orders option");
        let block = &text[at..];
        let end = block[1..].find("\n      --").map_or(block.len(), |e| e + 1);
        let listed: Vec<&str> = ["single", "multiple", "all"]
            .into_iter()
            .filter(|v| block[..end].contains(&format!("- {v}:")))
            .collect();
        listed
    };
    for cmd in [&[][..], &["report"], &["synth"]] {
        assert_eq!(values(cmd), ["single", "all"], "{cmd:?}");
    }
    for cmd in [&["eval"][..], &["albedo"], &["tables"]] {
        assert_eq!(values(cmd), ["single", "multiple", "all"], "{cmd:?}");
    }
}
/// `stfit synth --orders all` writes all-orders data (recorded in its comment) that
/// `--orders all` fits back to the truth.
#[test]
fn multiple_scattering_synth_then_fit_recovers_the_truth() {
    let dir = CaseDir::new("multiple-synth");
    let file = dir.join("ms.csv");
    let synth = [
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.6",
        "--orders",
        "all",
        "--walks",
        "20000",
        "--theta-i",
        "0,40",
        "--theta-o",
        "110:250:5",
        "--out",
        p(&file),
    ];
    stfit_ok(&synth);
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(
        text.starts_with("# ") && text.contains("--masking correlated --orders all --walks 20000"),
        "{text}"
    );
    let out = stfit_ok(&[
        p(&file),
        "--model",
        "ggx",
        "--orders",
        "all",
        "--walks",
        "3000",
        "--seed",
        "9",
        "--json",
    ]);
    let fits = fits_of(&out.stdout);
    let alpha = fits[0]["alpha"].as_f64().unwrap();
    let scale = fits[0]["scale"].as_f64().unwrap();
    assert!((alpha / 0.6 - 1.0).abs() < 0.02, "alpha {alpha}");
    assert!((scale - 1.0).abs() < 0.03, "scale {scale}");
    let mut args = synth.to_vec();
    args.extend(["--masking", "separable"]);
    let out = stfit(&args);
    assert_eq!(out.code, Some(2));
    assert!(out.stderr.clone().contains("height-correlated"));
}

/// The published comparison from the command line: Student-T fits frosted and etched glass
/// better than GGX and Beckmann; for ground glass GGX is as good as Student-T.
#[test]
fn walter_measurements_fit_from_the_command_line() {
    let Some(path) =
        stfit_test_support::walter_measurements("walter_measurements_fit_from_the_command_line")
    else {
        return;
    };
    let fits = fits_of(&stfit_ok(&[p(&path), "--model", "all", "--json"]).stdout);
    assert_eq!(fits.len(), 12);
    let rmse = |sample: &str, model: &str, fixed: bool| {
        let f = fits
            .iter()
            .find(|f| f["sample"] == sample && f["model"] == model && f["gamma_fixed"] == fixed)
            .unwrap_or_else(|| panic!("no {model} fit of {sample}"));
        assert_eq!(f["n_points"].as_u64(), Some(300), "{f}");
        f["rmse_sqrt_l"].as_f64().unwrap()
    };
    for sample in ["frosted", "etched"] {
        let st = rmse(sample, "student-t", false);
        let st3 = rmse(sample, "student-t", true);
        let ggx = rmse(sample, "ggx", false);
        let beckmann = rmse(sample, "beckmann", false);
        assert!(
            st <= st3 && st3 < 0.9 * ggx && ggx < beckmann,
            "{sample}: {fits:?}"
        );
    }
    let (st, ggx) = (
        rmse("ground", "student-t", false),
        rmse("ground", "ggx", false),
    );
    assert!((st / ggx - 1.0).abs() < 0.05, "ground: {st} vs {ggx}");
}

fn repo_file(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// The commands of `fits/README.md` rebuild `fits/example.csv` (comment lines aside, which
/// record the version) and its stored fits.
#[test]
fn stored_example_data_and_fits_are_reproduced() {
    let dir = CaseDir::new("example");
    let file = dir.join("example.csv");
    for (alpha, gamma, seed, name) in [
        ("0.2", "3", "1", "frosted"),
        ("0.45", "2.6", "2", "etched"),
        ("0.35", "1.8", "3", "ground"),
    ] {
        stfit_ok(&[
            "synth",
            "--model",
            "student-t",
            "--alpha",
            alpha,
            "--gamma",
            gamma,
            "--noise",
            "0.02",
            "--seed",
            seed,
            "--sample",
            name,
            "--out",
            p(&file),
            "--append",
        ]);
    }
    // Rows agree to rounding: later changes to how the model is evaluated may move the last
    // digits, never more.
    let rows = |path: &std::path::Path| -> Vec<Vec<String>> {
        std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| l.split(',').map(str::to_owned).collect())
            .collect()
    };
    let (made, stored) = (rows(&file), rows(&repo_file("fits/example.csv")));
    assert_eq!(made.len(), stored.len());
    assert_eq!(made[0], stored[0]);
    for (a, b) in made.iter().zip(&stored).skip(1) {
        assert_eq!(a[..3], b[..3]);
        let (x, y): (f64, f64) = (a[3].parse().unwrap(), b[3].parse().unwrap());
        assert!((x - y).abs() <= 1e-12 * y.abs(), "{a:?} vs {b:?}");
    }

    let stored = fits_of(&std::fs::read_to_string(repo_file("fits/example-fits.json")).unwrap());
    let fresh = fits_of(&stfit_ok(&[p(&file), "--model", "all", "--json"]).stdout);
    assert_eq!(stored.len(), 12);
    assert_eq!(fresh.len(), stored.len());
    for (a, b) in fresh.iter().zip(&stored) {
        // The data file is the rebuilt copy here.
        assert_eq!(b["data"], "fits/example.csv");
        for key in KEYS.into_iter().filter(|&k| k != "data") {
            match (a[key].as_f64(), b[key].as_f64()) {
                (Some(x), Some(y)) if key != "iterations" && key != "n_points" => {
                    assert!(
                        (x - y).abs() <= 1e-6 * y.abs().max(1e-3),
                        "{key}: {a} vs {b}"
                    );
                }
                _ => assert_eq!(a[key], b[key], "{key}"),
            }
        }
    }
}

/// The fits of `--model all --orders all` on two samples run in parallel: with
/// `RAYON_NUM_THREADS=1` and `=2` the JSON is byte-identical, and every fit records the
/// default surrogate orders >= 2 term it was searched with.
#[test]
fn fit_json_does_not_depend_on_the_thread_count() {
    let dir = CaseDir::new("threads");
    let file = dir.join("two.csv");
    for (name, alpha, append) in [("a", "0.3", false), ("b", "0.5", true)] {
        let mut args = vec![
            "synth",
            "--model",
            "ggx",
            "--alpha",
            alpha,
            "--noise",
            "0.02",
            "--sample",
            name,
            "--out",
            p(&file),
        ];
        if append {
            args.push("--append");
        }
        stfit_ok(&args);
    }
    let run = |threads: &str| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_stfit"))
            .args([
                p(&file),
                "--model",
                "all",
                "--orders",
                "all",
                "--walks",
                "1000",
                "--json",
            ])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .expect("stfit runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    };
    let one = run("1");
    let text = String::from_utf8_lossy(&one);
    assert_eq!(text.matches("\"sample\"").count(), 8);
    assert_eq!(text.matches("\"multiple_term\": \"surrogate\"").count(), 8);
    assert_eq!(one, run("2"));
}

/// A held scale is reported as given: 0.9 held on the shipped example's frosted sample (largest
/// value 28.389...) had come back as 0.9000000000000001 from its round trip through the fit's
/// units.
#[test]
fn a_held_scale_is_reported_as_given() {
    let example = repo_file("fits/example.csv");
    let out = stfit_ok(&[
        p(&example),
        "--sample",
        "frosted",
        "--model",
        "ggx",
        "--scale",
        "0.9",
        "--json",
    ]);
    let fits = fits_of(&out.stdout);
    assert_eq!(fits[0]["scale"], 0.9);
    assert_eq!(fits[0]["scale_fixed"], true);
}

/// A held scale so large that the model overflows everywhere is named as the likely cause: the
/// message had blamed near-specular directions alone.
#[test]
fn a_held_scale_that_overflows_the_model_is_named() {
    let example = repo_file("fits/example.csv");
    let e = stfit(&[p(&example), "--model", "ggx", "--scale", "1e308"])
        .fails_with(1)
        .to_string();
    assert!(
        e.contains("the held scale 1e308 may make the model overflow"),
        "{e}"
    );
}

/// An option out of its range is named with the option, not called an invalid model (the held
/// scale, the log floor and the walks had read '--scale: invalid model: ...').
#[test]
fn option_errors_name_the_option_not_the_model() {
    let example = repo_file("fits/example.csv");
    for (args, start) in [
        (vec!["--scale", "0"], "error: --scale: a held scale must be"),
        (
            vec!["--loss", "log", "--log-floor", "5"],
            "error: --log-floor: the log floor must be",
        ),
        (
            vec!["--orders", "all", "--walks", "1"],
            "error: --walks: an all-orders fit needs at least 2 walks",
        ),
    ] {
        let mut all = vec![p(&example), "--model", "ggx"];
        all.extend(args);
        let e = stfit(&all).fails_with(2).to_string();
        assert!(e.starts_with(start), "{e}");
    }
}

/// `--out` of a fit names a file: a path ending in `/` is refused with a message that says so
/// (it had said 'Is a directory' for a folder that did not exist).
#[test]
fn out_that_names_a_folder_is_refused_clearly() {
    let dir = CaseDir::new("out-folder");
    let out = format!("{}/missing/", dir.join("x").display());
    let example = repo_file("fits/example.csv");
    let e = stfit(&[p(&example), "--model", "ggx", "--out", &out])
        .fails_with(1)
        .to_string();
    assert!(e.contains("a file is written here, not a folder"), "{e}");
}

/// Data whose largest value is subnormal (below 2.2e-308) are refused with a reason, not fitted
/// to a scale that no model can be multiplied by without underflow (the report then had drawn
/// no model at all).
#[test]
fn subnormal_data_are_refused() {
    let dir = CaseDir::new("subnormal");
    let data = dir.file(
        "sub.csv",
        "sample,theta_i_deg,theta_o_deg,L\na,0,180,1e-320\na,30,170,1e-320\na,30,190,2e-320\n",
    );
    let e = stfit(&[p(&data), "--model", "ggx"])
        .fails_with(1)
        .to_string();
    assert!(e.contains("below the normal range of doubles"), "{e}");
}

/// `--append` to something that is not a regular file is refused at once: with /dev/full,
/// whose reads never end, the header check read it until the process was killed for memory.
#[cfg(unix)]
#[test]
fn synth_append_to_a_device_is_refused() {
    for target in ["/dev/full", "/dev/null"] {
        if !std::path::Path::new(target).exists() {
            continue;
        }
        let out = stfit(&[
            "synth", "--model", "ggx", "--alpha", "0.2", "--out", target, "--append",
        ]);
        assert_eq!(out.code, Some(1), "{target}: {}", out.stderr);
        assert!(
            out.stderr
                .contains(&format!("{target}: cannot append: not a regular file")),
            "{target}: {}",
            out.stderr
        );
    }
    let dir = CaseDir::new("append-folder");
    let out = stfit(&[
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.2",
        "--out",
        p(dir.path()),
        "--append",
    ]);
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    assert!(out.stderr.contains("not a regular file"), "{}", out.stderr);
}

/// An all-orders fit and `synth --orders all` whose random walks take long say so before they
/// start, as `eval`, `albedo`, `export` and `report` do: with 1e9 walks per incidence (the
/// most allowed) the first line on stderr, read while the run goes on and then stopped, is the
/// note, in minutes, hours or days (a fit of one GGX model to the example's frosted sample:
/// at least 4 estimates of the term, the surrogate's 3 nodes and its optimum). With the default
/// walks neither says anything.
#[test]
fn all_orders_fits_and_synth_whose_walks_take_long_say_so_before_they_run() {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fits/example.csv");
    let fit = |walks: &'static str| {
        vec![
            p(&example).to_string(),
            "--sample".into(),
            "frosted".into(),
            "--model".into(),
            "ggx".into(),
            "--orders".into(),
            "all".into(),
            "--walks".into(),
            walks.into(),
        ]
    };
    let synth = |walks: &'static str| {
        [
            "synth", "--model", "ggx", "--alpha", "0.5", "--orders", "all",
        ]
        .map(String::from)
        .into_iter()
        .chain(["--walks".to_string(), walks.to_string()])
        .collect::<Vec<_>>()
    };
    let long_units = |line: &str, shorter: &str| {
        [" min", " h", " days"]
            .iter()
            .any(|unit| line.ends_with(&format!("{unit} ({shorter})\n")))
    };
    let first_line = |args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        Cli::new(env!("CARGO_BIN_EXE_stfit"))
            .first_stderr_line(&args, std::time::Duration::from_secs(120))
            .unwrap_or_else(|| panic!("no line on stderr within 120 s: {args:?}"))
    };
    let line = first_line(fit("1000000000"));
    assert!(
        line.starts_with(
            "note: the random walks of the all-orders fits (at least 4 estimates of the orders \
             >= 2 term, 1000000000 walks per incident direction each) will take about "
        ) && long_units(&line, "fewer --walks make it shorter"),
        "{line}"
    );
    let line = first_line(synth("1000000000"));
    assert!(
        line.starts_with(
            "note: the random walks of the orders >= 2 term (1000000000 walks per incident \
             direction) will take about "
        ) && long_units(&line, "fewer --walks make it shorter"),
        "{line}"
    );
    for args in [fit("20000"), synth("20000")] {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let run = stfit_ok(&args);
        assert!(!run.stderr.contains("note:"), "{args:?}: {}", run.stderr);
    }
}
