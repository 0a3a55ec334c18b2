//! End-to-end tests of general measurements through the binary: `stfit synth --grid general`
//! and `--pabopto`, fits of general and pab-opto data with free eta, the report of a general
//! sample, and the errors of malformed general and pab-opto files.

use std::path::Path;

use stfit_test_support::{CaseDir, Cli, Run};

fn stfit(args: &[&str]) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run(args)
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The only fit of a `--json` output.
fn only_fit(json: &str) -> serde_json::Value {
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    let fits = v["fits"].as_array().unwrap();
    assert_eq!(fits.len(), 1, "{json}");
    fits[0].clone()
}

fn rel(a: &serde_json::Value, truth: f64) -> f64 {
    (a.as_f64().unwrap() - truth).abs() / truth
}

/// `synth --grid general` writes a general file (reflection and transmission, light from both
/// sides, out of plane) that the fit command reads and fits back with free eta, reporting eta
/// with its standard error, what was measured and the options as fitted.
#[test]
fn general_files_fit_back_with_free_eta() {
    let dir = CaseDir::new("general-fit");
    let file = dir.join("general.csv");
    stfit(&[
        "synth",
        "--grid",
        "general",
        "--model",
        "student-t",
        "--alpha",
        "0.25",
        "--gamma",
        "2.5",
        "--eta",
        "1.62",
        "--scale",
        "2",
        "--noise",
        "0.02",
        "--seed",
        "4",
        "--out",
        p(&file),
    ])
    .ok();
    let text = std::fs::read_to_string(&file).unwrap();
    let header = text.lines().find(|l| !l.starts_with('#')).unwrap();
    assert_eq!(
        header,
        "sample,theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf"
    );
    let json = stfit(&[p(&file), "--eta", "free", "--json"])
        .ok()
        .to_owned();
    let fit = only_fit(&json);
    assert!(rel(&fit["alpha"], 0.25) < 0.03, "{fit}");
    assert!(rel(&fit["gamma"], 2.5) < 0.08, "{fit}");
    assert!(rel(&fit["eta"], 1.62) < 0.005, "{fit}");
    assert!(rel(&fit["scale"], 2.0) < 0.05, "{fit}");
    assert_eq!(fit["eta_fixed"], false);
    assert!(fit["eta_stderr"].as_f64().is_some_and(|s| s > 0.0), "{fit}");
    assert_eq!(fit["measured"], "bsdf");
    assert_eq!(fit["n_points"], 1620);
    // The table shows the eta column and names the rmse's quantity.
    let table = stfit(&[p(&file), "--eta", "free"]).ok().to_owned();
    let head = table.lines().next().unwrap();
    assert!(
        head.contains(" eta ") && head.contains("rmse sqrt(BSDF)"),
        "{table}"
    );
    // Held scale and log loss are recorded as fitted.
    let json = stfit(&[
        p(&file),
        "--eta",
        "free",
        "--scale",
        "2",
        "--loss",
        "log",
        "--json",
    ])
    .ok()
    .to_owned();
    let fit = only_fit(&json);
    assert_eq!(
        (&fit["scale"], &fit["scale_fixed"]),
        (&2.0.into(), &true.into())
    );
    assert!(fit["scale_stderr"].is_null());
    assert_eq!(fit["loss"], "log");
    assert_eq!(fit["log_floor"], 1e-3);
    assert!(rel(&fit["eta"], 1.62) < 0.005, "{fit}");
}

/// `synth --pabopto` writes one pab-opto file per incident direction and side; the folder
/// fits back to the truth in both value forms, and the report of a general sample draws its
/// plane-of-incidence and polar figures.
#[test]
fn pabopto_folders_fit_back_and_report() {
    let dir = CaseDir::new("general-pabopto");
    for form in ["dsf", "bsdf"] {
        let out = dir.join(form);
        let listing = stfit(&[
            "synth",
            "--grid",
            "general",
            "--model",
            "ggx",
            "--alpha",
            "0.3",
            "--eta",
            "1.4",
            "--noise",
            "0.02",
            "--pabopto",
            form,
            "--out",
            p(&out),
        ])
        .ok()
        .to_owned();
        // 5 incident directions, reflection and transmission each.
        assert_eq!(listing.lines().count(), 10, "{listing}");
        let first = std::fs::read_to_string(out.join("synthetic_0_0_R.txt")).unwrap();
        assert!(
            first.contains(&format!("#format: theta phi {}", form.to_uppercase())),
            "{first}"
        );
        let fit = only_fit(stfit(&[p(&out), "--model", "ggx", "--eta", "free", "--json"]).ok());
        assert!(rel(&fit["alpha"], 0.3) < 0.03, "{form}: {fit}");
        assert!(rel(&fit["eta"], 1.4) < 0.005, "{form}: {fit}");
        assert_eq!(fit["data"], p(&out));
    }
    let report = dir.join("report");
    let files = stfit(&[
        "report",
        p(&dir.join("dsf")),
        "--eta",
        "free",
        "--out",
        p(&report),
    ])
    .ok()
    .to_owned();
    for name in [
        "synthetic-plane.svg",
        "synthetic-plane.png",
        "synthetic-polar.svg",
        "synthetic-polar.png",
        "ndf.svg",
        "fits.md",
    ] {
        assert!(files.contains(name), "{name} not in {files}");
        assert!(report.join(name).is_file(), "{name}");
    }
    assert!(!files.contains("overview"), "{files}");
}

/// Malformed general and pab-opto files fail with exit 1 and a message naming file, line and
/// column; a pab-opto file is told from a CSV by its contents.
#[test]
fn malformed_general_and_pabopto_files_name_file_and_line() {
    let dir = CaseDir::new("general-bad");
    let cases: [(&str, &str, &str); 11] = [
        (
            "theta90.csv",
            "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf\n0,0,170,0,1\n0,0,90,0,1\n",
            "theta90.csv:3: column 'theta_o_deg': 90 is out of range",
        ),
        (
            "phi.csv",
            "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf\n0,x,170,0,1\n",
            "phi.csv:2: column 'phi_i_deg': 'x' is not a number",
        ),
        (
            "mixed.csv",
            "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,L\n0,0,170,0,1\n",
            "mixed.csv:1: column 'L': a general file",
        ),
        (
            "noformat.txt",
            "#sample_name \"s\"\n#intheta 0\n#inphi 0\n10 0 1\n",
            "noformat.txt:1: column '#format:': missing",
        ),
        (
            "fields.txt",
            "#format: theta phi BSDF\n#intheta 0\n#inphi 0\n10 0 1\n20 0\n",
            "fields.txt:5:",
        ),
        (
            "sides.txt",
            "#format: theta phi BSDF\n#intheta 0\n#inphi 0\n10 0 1\n170 0 1\n",
            "sides.txt:5:",
        ),
        (
            "twice.txt",
            "#format: theta phi BSDF\n#intheta 30\n#inphi 0\n#intheta 60\n10 0 1\n",
            "twice.txt:4: column '#intheta': given again; line 2 gave it already",
        ),
        (
            "conflict.txt",
            "#format: theta phi BSDF\n#intheta 60\n#inphi 0\n#incident_angle 30 0\n10 0 1\n",
            "conflict.txt:4: column '#incident_angle': disagrees with '#intheta 60' on line 2",
        ),
        (
            "unnamed.txt",
            "#sample_name \"\"\n#format: theta phi BSDF\n#intheta 0\n#inphi 0\n10 0 1\n",
            "unnamed.txt:1: column '#sample_name': empty sample name",
        ),
        (
            "xyz.txt",
            "#format: theta phi BSDF\n#intheta 0\n#inphi 0\n#colorimetry: CIE-XYZ\n\
             10 0 -5 1 1\n",
            "xyz.txt:5: column 'X': -5 is negative",
        ),
        (
            "grazing.txt",
            "#format: theta phi DSF\n#intheta 30\n#inphi 0\n150 0 1\n90.0000000001 0 1e300\n",
            "grazing.txt:5: column 'value': 1e300 is too large",
        ),
    ];
    for (name, text, needle) in cases {
        let file = dir.file(name, text);
        let stderr = stfit(&[p(&file)]).fails_with(1).to_owned();
        assert!(stderr.contains(needle), "{name}: {stderr}");
    }
}

/// Invalid values of the general fit options are usage errors (exit 2) naming the flag.
#[test]
fn invalid_general_fit_options_are_usage_errors() {
    let dir = CaseDir::new("general-flags");
    let file = dir.file(
        "g.csv",
        "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf\n0,0,170,0,1\n0,0,160,0,1\n",
    );
    for (args, needle) in [
        (vec!["--eta", "fre"], "--eta: invalid value 'fre'"),
        (vec!["--eta", "1"], "--eta"),
        (vec!["--scale", "-1"], "--scale"),
        (vec!["--scale", "sqrt"], "--y-axis"),
        (vec!["--loss", "log", "--log-floor", "0"], "--log-floor"),
        (vec!["--loss", "log", "--log-floor", "nan"], "--log-floor"),
        // The floor is a fraction of the largest value: 1e308 of it overflowed.
        (vec!["--loss", "log", "--log-floor", "1e308"], "[1e-12, 1]"),
        (vec!["--loss", "log", "--log-floor", "1e-13"], "[1e-12, 1]"),
        // A subnormal scale has too few digits to come back as given.
        (vec!["--scale", "1e-320"], "2.2e-308"),
        (vec!["--loss", "cubic"], "--loss"),
    ] {
        let mut all = vec![p(&file)];
        all.extend(&args);
        let stderr = stfit(&all).fails_with(2).to_owned();
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
}

/// Extreme but valid angles and a long sample name give pab-opto file names a file system
/// takes: angles in the shortest form that reads back (`1e-300`, not 300 digits), at most 100
/// characters of the name. The files read back to the same angles, and a file that cannot be
/// written is named in the error (exit 1), not its folder.
#[test]
fn pabopto_file_names_stay_short_and_a_failed_file_is_named() {
    let dir = CaseDir::new("pabopto-names");
    let out = dir.join("tiny");
    let long = "g".repeat(300);
    let grid = [
        "synth",
        "--grid",
        "general",
        "--model",
        "ggx",
        "--alpha",
        "0.3",
        "--theta-o",
        "40,140",
        "--phi-o",
        "0",
        "--pabopto",
        "bsdf",
    ];
    let mut args = grid.to_vec();
    args.extend([
        "--theta-i",
        "1e-300,179.99999999999997",
        "--phi-i",
        "1e-300,-1.7976931348623157e308",
        "--sample",
        &long,
        "--out",
        p(&out),
    ]);
    let listing = stfit(&args).ok().to_owned();
    assert_eq!(listing.lines().count(), 8, "{listing}");
    let stem = "g".repeat(100);
    for name in [
        format!("{stem}_1e-300_1e-300_R.txt"),
        format!("{stem}_179.99999999999997_-1.7976931348623157e308_T.txt"),
    ] {
        assert!(out.join(&name).is_file(), "{name} not in {listing}");
    }
    for line in listing.lines() {
        let name = Path::new(line).file_name().unwrap().len();
        assert!(name <= 160, "{name} bytes: {line}");
    }
    let csv = stfit(&[p(&out), "--model", "ggx", "--json"])
        .ok()
        .to_owned();
    assert!(csv.contains("\"fits\""), "{csv}");

    // A folder where a file should go: the error names that file.
    let blocked = dir.join("blocked");
    std::fs::create_dir_all(blocked.join("synthetic_30_0_T.txt")).unwrap();
    let mut args = grid.to_vec();
    args.extend(["--theta-i", "30", "--out", p(&blocked)]);
    let stderr = stfit(&args).fails_with(1).to_owned();
    let file = blocked.join("synthetic_30_0_T.txt");
    assert!(
        stderr.contains(&format!("{}: cannot write", p(&file))),
        "{stderr}"
    );
}
