//! End-to-end tests of `stfit albedo`.

use stfit_test_support::{Cli, Run};

fn stfit(args: &[&str]) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run(args)
}

fn albedo_json(extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "albedo",
        "--json",
        "--walk",
        "heightfield",
        "--walks",
        "40000",
    ];
    args.extend_from_slice(extra);
    let out = stfit(&args);
    assert!(out.code == Some(0), "stfit {args:?} failed: {}", out.stderr);
    // Piped output: no progress bar or other noise on stderr.
    assert!(out.stderr.is_empty(), "{}", out.stderr);
    serde_json::from_str(&out.stdout).expect("one JSON object on stdout")
}

fn num(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("key {key} missing in {v}"))
}

#[test]
fn json_has_the_documented_keys_and_conserves_energy() {
    for (ndf, theta, eta) in [
        ("ggx", "60", "1.51"),
        ("ggx", "150", "1.51"),
        ("ggx", "20", "0.6622516556291391"),
        ("ggx", "120", "0.6622516556291391"),
        ("beckmann", "60", "1.51"),
        ("student-t", "60", "1.51"),
        ("student-t", "135", "0.6622516556291391"),
    ] {
        let mut args = vec![
            "--ndf",
            ndf,
            "--alpha",
            "0.45",
            "--eta",
            eta,
            "--theta-i",
            theta,
        ];
        if ndf == "student-t" {
            args.extend_from_slice(&["--gamma", "1.8"]);
        }
        let v = albedo_json(&args);
        for key in [
            "reflectance",
            "transmittance",
            "reflectance_stderr",
            "transmittance_stderr",
            "mean_bounces",
        ] {
            assert!(num(&v, key).is_finite(), "{key} in {v}");
        }
        let (r, t) = (num(&v, "reflectance"), num(&v, "transmittance"));
        assert!((r + t - 1.0).abs() < 1e-12, "{v}");
        assert!(r > 0.0 && t > 0.0, "{v}");
        assert!(num(&v, "mean_bounces") >= 1.0, "{v}");
    }
}

#[test]
fn single_plus_multiple_is_all_and_same_seed_repeats() {
    let base = [
        "--ndf",
        "ggx",
        "--alpha",
        "0.8",
        "--eta",
        "1.51",
        "--theta-i",
        "45",
    ];
    let run = |s: &str, seed: &str| {
        let mut a = base.to_vec();
        a.extend_from_slice(&["--orders", s, "--seed", seed]);
        albedo_json(&a)
    };
    let all = run("all", "3");
    assert_eq!(all, run("all", "3"));
    let single = run("single", "4");
    let multi = run("multiple", "5");
    assert_eq!(num(&single, "mean_bounces"), 1.0);
    assert!(num(&multi, "mean_bounces") >= 2.0);
    for key in ["reflectance", "transmittance"] {
        let se = |v: &serde_json::Value| num(v, &format!("{key}_stderr"));
        let diff = num(&all, key) - num(&single, key) - num(&multi, key);
        let tol = 4.0 * (se(&all).powi(2) + se(&single).powi(2) + se(&multi).powi(2)).sqrt();
        assert!(diff.abs() <= tol, "{key}: {diff} > {tol}");
    }
}

#[test]
fn null_walk_agrees_with_the_height_field_walk() {
    let run = |walk: &str| {
        let out = stfit(&[
            "albedo",
            "--json",
            "--ndf",
            "ggx",
            "--alpha",
            "0.8",
            "--eta",
            "1.51",
            "--theta-i",
            "50",
            "--walks",
            "40000",
            "--walk",
            walk,
        ]);
        assert!(out.code == Some(0), "{}", out.stderr.clone());
        serde_json::from_str::<serde_json::Value>(&out.stdout).unwrap()
    };
    let (hf, null) = (run("heightfield"), run("null"));
    let se =
        (num(&hf, "reflectance_stderr").powi(2) + num(&null, "reflectance_stderr").powi(2)).sqrt();
    let diff = num(&hf, "reflectance") - num(&null, "reflectance");
    assert!(diff.abs() <= 4.0 * se, "{hf} vs {null}");
}

#[test]
fn text_output_reports_both_fractions() {
    let out = stfit(&[
        "albedo",
        "--ndf",
        "ggx",
        "--alpha",
        "0.3",
        "--eta",
        "1.5",
        "--theta-i",
        "0",
        "--walks",
        "5000",
    ]);
    assert!((out.code == Some(0)));
    let text = out.stdout;
    assert!(
        text.contains("reflectance") && text.contains("transmittance"),
        "{text}"
    );
}

#[test]
fn bad_arguments_are_errors() {
    let ok = [
        "--ndf",
        "ggx",
        "--alpha",
        "0.5",
        "--eta",
        "1.5",
        "--theta-i",
        "30",
    ];
    let cases: &[(&[&str], &str)] = &[
        (&["--alpha", "0"], "alpha"),
        (&["--alpha", "-1"], "alpha"),
        (&["--alpha", "nan"], "alpha"),
        (&["--eta", "1"], "eta"),
        (&["--eta", "-2"], "eta"),
        (&["--theta-i", "90"], "theta"),
        (&["--theta-i", "181"], "theta"),
        (&["--gamma", "3"], "gamma"),
        (&["--ndf", "student-t"], "gamma"),
        (&["--ndf", "student-t", "--gamma", "1.5"], "gamma"),
        (&["--orders", "double"], "orders"),
        (&["--walk", "volume"], "walk"),
        (
            &["--walk", "null", "--ndf", "student-t", "--gamma", "1.8"],
            "majorant",
        ),
        (&["--walks", "0"], "walks"),
    ];
    for (over, word) in cases {
        // The valid arguments, with those named in `over` replaced.
        let mut args = vec!["albedo"];
        for pair in ok.chunks(2) {
            if !over.contains(&pair[0]) {
                args.extend_from_slice(pair);
            }
        }
        args.extend_from_slice(over);
        let out = stfit(&args);
        assert!(out.code != Some(0), "{args:?} succeeded");
        let err = out.stderr.clone();
        assert!(err.contains(word), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}

/// Runs `stfit eval` with `args` on CSV `input`; returns the appended columns of each row.
fn eval_rows(args: &[&str], input: &str) -> Vec<Vec<f64>> {
    let mut all = vec!["eval"];
    all.extend_from_slice(args);
    let out = Cli::new(env!("CARGO_BIN_EXE_stfit")).run_with_stdin(&all, input);
    assert!(out.code == Some(0), "{}", out.stderr);
    let text = out.stdout;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[6], "f_cos");
    lines
        .map(|l| l.split(',').skip(6).map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn eval_scattering_orders_add_up() {
    // Light from air at 40 degrees; transmitted and reflected directions.
    let input = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n\
        -0.6427876096865393,0,0.766044443118978,0.3,0,-0.9539392014169457\n\
        -0.6427876096865393,0,0.766044443118978,0.5,0.2,0.8426149773176359\n";
    let base = ["--ndf", "ggx", "--alpha", "0.7", "--eta", "1.51"];
    let run = |extra: &[&str]| {
        let mut a = base.to_vec();
        a.extend_from_slice(extra);
        eval_rows(&a, input)
    };
    let single = run(&["--masking", "correlated"]);
    let multi = run(&["--orders", "multiple", "--walks", "40000"]);
    let all = run(&["--orders", "all", "--walks", "40000", "--seed", "9"]);
    for k in 0..2 {
        assert_eq!(single[k].len(), 1);
        assert_eq!(all[k].len(), 2, "f_cos and f_cos_stderr");
        let se = (multi[k][1].powi(2) + all[k][1].powi(2)).sqrt();
        let diff = all[k][0] - single[k][0] - multi[k][0];
        assert!(diff.abs() <= 4.0 * se, "row {k}: {diff} (se {se})");
        assert!(multi[k][0] > 0.0);
    }
}

/// `stfit albedo --json` with exactly `args`.
fn albedo_json_with(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["albedo", "--json"];
    all.extend_from_slice(args);
    let out = stfit(&all);
    assert!(out.code == Some(0), "stfit {all:?} failed: {}", out.stderr);
    serde_json::from_str(&out.stdout).expect("one JSON object on stdout")
}

#[test]
fn full_sphere_ndfs_with_lossless_facets_reflect_everything() {
    // Furnace: non-absorbing facets in the half-space reflect all the flux; nothing can leave
    // below an unbounded half-space.
    let cases: &[&[&str]] = &[
        &["--ndf", "vmf", "--kappa", "4", "--facet", "conductor"],
        &[
            "--ndf",
            "porous",
            "--base",
            "ggx",
            "--alpha",
            "0.6",
            "--porosity",
            "0.4",
            "--facet",
            "lambertian",
            "--reflectance",
            "1",
        ],
        &[
            "--ndf",
            "porous",
            "--base",
            "student-t",
            "--alpha",
            "0.5",
            "--gamma",
            "3",
            "--porosity",
            "0.5",
            "--facet",
            "conductor",
        ],
    ];
    for case in cases {
        let mut args = vec!["--walk", "null", "--theta-i", "50", "--walks", "20000"];
        args.extend_from_slice(case);
        let v = albedo_json_with(&args);
        let (r, se) = (num(&v, "reflectance"), num(&v, "reflectance_stderr"));
        assert!(
            (r + num(&v, "truncated") - 1.0).abs() <= 4.0 * se + 1e-12,
            "{case:?}: {v}"
        );
        assert_eq!(num(&v, "transmittance"), 0.0, "{case:?}");
        assert!(num(&v, "mean_bounces") > 1.0, "{case:?}: {v}");
    }
    // An absorbing facet loses flux.
    let v = albedo_json_with(&[
        "--walk",
        "null",
        "--theta-i",
        "50",
        "--walks",
        "20000",
        "--ndf",
        "vmf",
        "--kappa",
        "4",
        "--facet",
        "lambertian",
        "--reflectance",
        "0.5",
    ]);
    let r = num(&v, "reflectance");
    assert!(r > 0.2 && r < 0.5, "{v}");
}

#[test]
fn porous_without_pores_is_the_height_field() {
    // Porosity 0 on the null walk against the height-field walk, conductor facets.
    let common = [
        "--alpha",
        "0.6",
        "--facet",
        "conductor",
        "--n",
        "1.5",
        "--k",
        "3",
        "--theta-i",
        "60",
        "--walks",
        "40000",
    ];
    let mut null = vec![
        "--walk",
        "null",
        "--ndf",
        "porous",
        "--base",
        "ggx",
        "--porosity",
        "0",
    ];
    null.extend_from_slice(&common);
    let mut hf = vec!["--walk", "heightfield", "--ndf", "ggx", "--seed", "2"];
    hf.extend_from_slice(&common);
    let (a, b) = (albedo_json_with(&null), albedo_json_with(&hf));
    let se = num(&a, "reflectance_stderr").hypot(num(&b, "reflectance_stderr"));
    let diff = num(&a, "reflectance") - num(&b, "reflectance");
    assert!(se > 0.0 && diff.abs() <= 4.0 * se, "{a} vs {b}");
}

#[test]
fn bad_full_sphere_arguments_are_usage_errors() {
    let vmf = [
        "--ndf",
        "vmf",
        "--kappa",
        "4",
        "--facet",
        "conductor",
        "--walk",
        "null",
    ];
    let cases: &[(&[&str], &str)] = &[
        (
            &["--ndf", "vmf", "--facet", "conductor", "--walk", "null"],
            "kappa",
        ),
        (&["--kappa", "0"], "kappa"),
        (&["--kappa", "nan"], "kappa"),
        (&["--walk", "heightfield"], "walk null"),
        (&["--facet", "dielectric"], "dielectric"),
        (&["--alpha", "0.5"], "alpha"),
        (&["--eta", "1.5"], "eta"),
        (&["--n", "1.5"], "--k"),
        (&["--reflectance", "0.5"], "reflectance"),
        (
            &["--ndf", "porous", "--alpha", "0.5", "--porosity", "0.2"],
            "base",
        ),
        (
            &["--ndf", "porous", "--base", "ggx", "--porosity", "0.2"],
            "alpha",
        ),
        (
            &["--ndf", "porous", "--base", "ggx", "--alpha", "0.5"],
            "porosity",
        ),
        (
            &[
                "--ndf",
                "porous",
                "--base",
                "ggx",
                "--alpha",
                "0.5",
                "--porosity",
                "1.5",
            ],
            "porosity",
        ),
        (
            &[
                "--ndf",
                "porous",
                "--base",
                "ggx",
                "--alpha",
                "0.5",
                "--porosity",
                "0.2",
                "--kappa",
                "3",
            ],
            "kappa",
        ),
        (
            &[
                "--ndf",
                "porous",
                "--base",
                "student-t",
                "--alpha",
                "0.5",
                "--porosity",
                "0.2",
            ],
            "gamma",
        ),
        (&["--facet", "lambertian"], "reflectance"),
        (
            &["--facet", "lambertian", "--reflectance", "1.5"],
            "reflectance",
        ),
        (&["--facet", "conductor", "--n", "-1", "--k", "0"], "n"),
        (&["--ndf", "ggx", "--alpha", "0.5", "--base", "ggx"], "base"),
        (
            &["--ndf", "ggx", "--porosity", "0.3", "--alpha", "0.5"],
            "porosity",
        ),
    ];
    for (over, word) in cases {
        // The valid vMF arguments, with the options named in `over` replaced.
        let mut args = vec!["albedo", "--theta-i", "30", "--walks", "100"];
        let mut k = 0;
        while k < vmf.len() {
            // A new --ndf drops the vMF's --kappa too.
            let replaced =
                over.contains(&vmf[k]) || (over.contains(&"--ndf") && vmf[k] == "--kappa");
            if !replaced {
                args.extend_from_slice(&vmf[k..k + 2]);
            }
            k += 2;
        }
        args.extend_from_slice(over);
        let out = stfit(&args);
        assert_eq!(out.code, Some(2), "{args:?}");
        let err = out.stderr.clone();
        assert!(err.contains(word), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}

/// Where no walk leaves within the orders (orders >= 2 of a near-specular surface: every walk
/// leaves after one event), the path length is undefined: null in JSON and a dash in the text,
/// not a mean of 0 events.
#[test]
fn mean_bounces_is_undefined_when_no_walk_left_within_the_orders() {
    let args = [
        "--ndf",
        "ggx",
        "--alpha",
        "1e-8",
        "--eta",
        "1.5",
        "--theta-i",
        "30",
        "--orders",
        "multiple",
    ];
    let v = albedo_json(&args);
    assert_eq!(num(&v, "reflectance") + num(&v, "transmittance"), 0.0);
    assert!(v["mean_bounces"].is_null(), "{v}");
    let mut text_args = vec!["albedo", "--walks", "1000"];
    text_args.extend_from_slice(&args);
    let out = stfit(&text_args);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert!(
        out.stdout
            .contains("mean bounces   - (no walk left within the orders)"),
        "{}",
        out.stdout
    );
    // With every order, each walk counts.
    let all = albedo_json(&args[..8]);
    assert!(num(&all, "mean_bounces") >= 1.0, "{all}");
}

/// A side that no walk reached (here both: orders >= 2 of a near-specular surface) reports
/// no standard error but the one-sided 95% upper bound `1 - 0.05^(1/N)`, in JSON
/// (`*_upper_bound`, the stderr null) and in the text; it used to report a standard error of
/// 0. A side that walks reached has a standard error and a null bound.
#[test]
fn unreached_side_reports_a_95_percent_upper_bound() {
    let base = [
        "--ndf",
        "ggx",
        "--alpha",
        "1e-8",
        "--eta",
        "1.5",
        "--theta-i",
        "30",
    ];
    let mut args = base.to_vec();
    args.extend_from_slice(&["--orders", "multiple"]);
    let v = albedo_json(&args);
    let bound = 1.0 - 0.05f64.powf(1.0 / 40000.0);
    for side in ["reflectance", "transmittance"] {
        assert_eq!(num(&v, side), 0.0, "{v}");
        assert!(v[format!("{side}_stderr")].is_null(), "{v}");
        let b = num(&v, &format!("{side}_upper_bound"));
        assert!(
            (b / bound - 1.0).abs() < 1e-9,
            "{side}: {b} against {bound}"
        );
    }
    let mut text_args = vec!["albedo", "--walks", "1000"];
    text_args.extend_from_slice(&args);
    let out = stfit(&text_args);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    for side in ["reflectance   ", "transmittance "] {
        assert!(
            out.stdout
                .contains(&format!("{side} 0.000000 (no walk; below 2.991e-3 at 95%)")),
            "{}",
            out.stdout
        );
    }
    assert!(!out.stdout.contains("+-"), "{}", out.stdout);
    // Every order: both sides reached, standard errors and no bounds.
    let v = albedo_json(&base);
    for side in ["reflectance", "transmittance"] {
        assert!(num(&v, &format!("{side}_stderr")) > 0.0, "{v}");
        assert!(v[format!("{side}_upper_bound")].is_null(), "{v}");
    }
}
