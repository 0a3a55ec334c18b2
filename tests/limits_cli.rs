//! The supported ranges (README, "Limits") as the command line enforces them, and outputs that
//! are never non-finite, never a "± 0" from one walk, and messages that never echo a huge field.

use stfit_test_support::{CaseDir, Cli, Run};

fn stfit(args: &[&str]) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run(args)
}

fn stfit_in(args: &[&str], stdin: &str) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run_with_stdin(args, stdin)
}

/// Noiseless GGX measurements (alpha 0.3, the default grid) written into `dir` as `d.csv`.
fn ggx_data(dir: &CaseDir) -> std::path::PathBuf {
    let data = dir.join("d.csv");
    stfit(&[
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.3",
        "--out",
        data.to_str().unwrap(),
    ])
    .ok();
    data
}

/// Parameters outside their range: exit 2, the flag and the range named, no huge number spelt
/// out in full.
#[test]
fn parameters_outside_their_range_are_usage_errors_naming_the_range() {
    let dir = CaseDir::new("limits-ranges");
    let data = ggx_data(&dir);
    let d = data.to_str().unwrap();
    let surface = |extra: &[&'static str]| {
        let mut a = vec!["albedo", "--theta-i", "30", "--walks", "100"];
        a.extend_from_slice(extra);
        a
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["synth", "--model", "beckmann", "--alpha", "1e-160"],
            "[1e-8, 100]",
        ),
        (
            vec!["synth", "--model", "ggx", "--alpha", "1e156"],
            "[1e-8, 100]",
        ),
        (
            vec![
                "synth",
                "--model",
                "student-t",
                "--alpha",
                "0.3",
                "--gamma",
                "1e25",
            ],
            "1e15",
        ),
        (
            vec![
                "synth", "--model", "ggx", "--alpha", "0.3", "--eta", "1.001",
            ],
            "0.01",
        ),
        (vec![d, "--eta", "0.9"], "[1.05, 3]"),
        (vec![d, "--eta", "3.5"], "[1.05, 3]"),
        (vec![d, "--gamma", "1.5001", "--orders", "all"], "1.501"),
        (
            surface(&[
                "--ndf",
                "student-t",
                "--alpha",
                "0.5",
                "--gamma",
                "1.5001",
                "--eta",
                "1.5",
            ]),
            "1.501",
        ),
        (
            surface(&[
                "--ndf",
                "vmf",
                "--kappa",
                "1e6",
                "--facet",
                "conductor",
                "--walk",
                "null",
            ]),
            "[0.1, 1e4]",
        ),
        (
            surface(&[
                "--ndf",
                "porous",
                "--base",
                "ggx",
                "--alpha",
                "0.5",
                "--porosity",
                "1",
                "--facet",
                "conductor",
                "--walk",
                "null",
            ]),
            "[0, 0.99]",
        ),
        (
            surface(&[
                "--ndf",
                "ggx",
                "--alpha",
                "0.3",
                "--facet",
                "conductor",
                "--n",
                "1e300",
                "--k",
                "1",
            ]),
            "[1e-3, 1e3]",
        ),
        (
            surface(&["--ndf", "ggx", "--alpha", "1e300", "--eta", "1.5"]),
            "[1e-8, 100]",
        ),
        // Walk counts: refused before anything is allocated for them.
        (
            vec![
                "albedo",
                "--theta-i",
                "30",
                "--ndf",
                "ggx",
                "--alpha",
                "0.3",
                "--eta",
                "1.5",
                "--walks",
                "10000000000000",
            ],
            "[1, 1e9]",
        ),
        (
            vec![
                "eval",
                "--ndf",
                "ggx",
                "--alpha",
                "0.3",
                "--eta",
                "1.5",
                "--orders",
                "all",
                "--walks",
                "1000000001",
            ],
            "[1, 1e9]",
        ),
        (
            vec![d, "--orders", "all", "--walks", "18446744073709551615"],
            "[2, 1e9]",
        ),
        (vec![d, "--orders", "all", "--walks", "1"], "at least 2"),
        // The null walk's tentative collisions grow with D's peak.
        (
            surface(&[
                "--ndf", "beckmann", "--alpha", "1e-4", "--eta", "1.5", "--walk", "null",
            ]),
            "1e4",
        ),
    ];
    for (args, range) in cases {
        let err = stfit(&args).fails_with(2).to_string();
        assert!(err.contains(range), "{args:?}: {err}");
        assert!(err.len() < 400, "{args:?}: a long message: {err}");
    }
}

/// A seeded sweep over the supported alpha and gamma ranges (log-uniform, both ends
/// included): synth writes finite values and exits 0 for every model; the closed-form eval
/// gives finite values at every direction pair of a fixed set.
#[test]
fn inside_the_ranges_every_written_value_is_finite() {
    let mut alphas = vec![1e-8, 100.0];
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..6 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let u = (state >> 11) as f64 / (1u64 << 53) as f64;
        alphas.push(10f64.powf(-8.0 + 10.0 * u));
    }
    let pairs = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,-1\n0,0,1,0,0,1\n0.6,0,0.8,-0.6,0,-0.8\n\
                 0.6,0,0.8,0.6,0,-0.8\n0,0.999,0.0447101778,0,-0.2,-0.9797958971\n";
    for &alpha in &alphas {
        let a = format!("{alpha:e}");
        for (model, gamma) in [
            ("beckmann", None),
            ("ggx", None),
            ("student-t", Some("1.5000001")),
            ("student-t", Some("1e15")),
        ] {
            let mut args = vec!["synth", "--model", model, "--alpha", &a];
            if let Some(g) = gamma {
                args.extend(["--gamma", g]);
            }
            let out = stfit(&args);
            for line in out.ok().lines().filter(|l| !l.starts_with('#')).skip(1) {
                let v: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
                assert!(v.is_finite() && v >= 0.0, "{args:?}: {line}");
            }
            let ndf = if model == "student-t" {
                "student-t"
            } else {
                model
            };
            let mut eval = vec!["eval", "--ndf", ndf, "--alpha", &a, "--eta", "1.5"];
            if let Some(g) = gamma {
                eval.extend(["--gamma", g]);
            }
            let out = stfit_in(&eval, pairs);
            for line in out.ok().lines().skip(1) {
                let v: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
                assert!(v.is_finite() && v >= 0.0, "{eval:?}: {line}");
            }
        }
    }
}

/// A scale whose values overflow is refused, nothing written.
#[test]
fn synth_refuses_values_that_overflow() {
    let err = stfit(&[
        "synth", "--model", "beckmann", "--alpha", "0.3", "--scale", "1e308",
    ])
    .fails_with(2)
    .to_string();
    assert!(err.contains("not a representable number"), "{err}");
}

/// A stored fit outside the supported ranges (a hand-edited file): `report` names it in a
/// warning and in fits.md, draws the other fits and exits 0; `export` refuses it (exit 1),
/// naming the fit and the range.
#[test]
fn stored_fits_outside_the_ranges_are_named_by_report_and_refused_by_export() {
    let dir = CaseDir::new("limits-stored");
    let data = dir.join("d.csv");
    let fits = dir.join("fits.json");
    stfit(&[
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.3",
        "--sample",
        "s",
        "--out",
        data.to_str().unwrap(),
    ])
    .ok();
    stfit(&[
        data.to_str().unwrap(),
        "--model",
        "all",
        "--out",
        fits.to_str().unwrap(),
    ])
    .ok();
    let text = std::fs::read_to_string(&fits).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let ggx = v["fits"]
        .as_array()
        .unwrap()
        .iter()
        .position(|f| f["model"] == "ggx")
        .unwrap();
    v["fits"][ggx]["alpha"] = serde_json::json!(1e-160);
    std::fs::write(&fits, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let out = dir.join("report");
    let run = stfit(&[
        "report",
        data.to_str().unwrap(),
        "--fits",
        fits.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    run.ok();
    let warning = run
        .stderr
        .lines()
        .find(|l| l.contains("cannot be evaluated"))
        .unwrap_or_else(|| panic!("no warning: {}", run.stderr));
    assert!(
        warning.starts_with("warning: sample 's', ggx")
            && warning.contains("[1e-8, 100]")
            && warning.contains("not drawn"),
        "{warning}"
    );
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    let md = std::fs::read_to_string(out.join("fits.md")).unwrap();
    assert!(
        md.contains("## Not drawn") && md.contains("sample 's', ggx"),
        "{md}"
    );
    let rows = md.lines().filter(|l| l.starts_with("| s |")).count();
    assert_eq!(rows, 3, "{md}");
    let svg = std::fs::read_to_string(out.join("s-fits.svg")).unwrap();
    assert!(svg.contains("Beckmann") && svg.contains("Student-T"));

    let err = stfit(&["export", fits.to_str().unwrap(), "--to", "pbrt-v4"])
        .fails_with(1)
        .to_string();
    assert!(
        err.contains("sample 's', ggx") && err.contains("[1e-8, 100]"),
        "{err}"
    );
}

/// One walk has no sample variance: the standard error is empty (eval) or null (albedo JSON),
/// not 0.
#[test]
fn a_single_walk_has_no_standard_error() {
    let pairs = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,-1\n";
    let args = [
        "eval", "--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5", "--orders", "all",
    ];
    let one = stfit_in(&[&args[..], &["--walks", "1"]].concat(), pairs);
    let row = one.ok().lines().nth(1).unwrap().to_string();
    assert!(row.ends_with(','), "{row}");
    let two = stfit_in(&[&args[..], &["--walks", "2"]].concat(), pairs);
    assert!(!two.ok().lines().nth(1).unwrap().ends_with(','));
    // A few walks from wi give a few from each wo too, never one: a non-zero estimate
    // carries a non-zero standard error.
    let oblique = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0.6,0,-0.8\n";
    for walks in ["2", "3", "5"] {
        let run = stfit_in(
            &[
                "eval", "--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5", "--orders", "multiple",
                "--walks", walks,
            ],
            oblique,
        );
        let row = run.ok().lines().nth(1).unwrap().to_string();
        let fields: Vec<f64> = row.split(',').map(|f| f.parse().unwrap()).collect();
        let (value, stderr) = (fields[6], fields[7]);
        assert!(value == 0.0 || stderr > 0.0, "walks {walks}: {row}");
    }
    let json = stfit(&[
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
        "1",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(json.ok()).unwrap();
    assert!(
        v["reflectance_stderr"].is_null() && v["transmittance_stderr"].is_null(),
        "{v}"
    );
    let text = stfit(&[
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
        "1",
    ]);
    assert!(!text.ok().contains("+-"), "{}", text.stdout);
}

/// A fit on a search bound is flagged in the JSON, the table and on stderr, with null
/// standard errors.
#[test]
fn a_flagged_fit_is_marked_everywhere() {
    let dir = CaseDir::new("limits-flagged");
    let data = dir.join("rough.csv");
    stfit(&[
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "60",
        "--out",
        data.to_str().unwrap(),
    ])
    .ok();
    let json = stfit(&[data.to_str().unwrap(), "--model", "ggx", "--json"]);
    let v: serde_json::Value = serde_json::from_str(json.ok()).unwrap();
    let f = &v["fits"][0];
    assert_eq!(f["warnings"][0]["kind"], "at-bound", "{f}");
    assert_eq!(f["warnings"][0]["parameter"], "alpha", "{f}");
    assert!(
        f["alpha_stderr"].is_null() && f["scale_stderr"].is_null(),
        "{f}"
    );
    assert!(
        json.stderr
            .contains("warning: sample 'synthetic', ggx: alpha ended on the search bound 20")
    );
    let table = stfit(&[data.to_str().unwrap(), "--model", "ggx"]);
    let lines: Vec<&str> = table.ok().lines().collect();
    assert!(
        lines[0].ends_with("warnings") && lines[1].ends_with("at-bound(alpha)"),
        "{lines:?}"
    );
    assert!(!lines[1].contains('±'), "{lines:?}");
}

/// Sample names of any length and content: errors shorten them, tables keep one line per row.
#[test]
fn huge_and_odd_names_are_shortened_and_escaped() {
    let dir = CaseDir::new("limits-names");
    let name = "é".repeat(5000);
    let data = dir.join("big.csv");
    stfit(&[
        "synth",
        "--model",
        "ggx",
        "--alpha",
        "0.3",
        "--sample",
        &name,
        "--out",
        data.to_str().unwrap(),
    ])
    .ok();
    let err = stfit(&[data.to_str().unwrap(), "--sample", "nope"])
        .fails_with(1)
        .to_string();
    assert!(
        err.contains("(5002 characters)") && err.chars().count() < 300,
        "{err}"
    );
    let odd = dir.file(
        "odd.csv",
        "sample,theta_i_deg,theta_o_deg,L\n\"a\nb\tc\",0,180,1\n\"a\nb\tc\",0,170,0.5\n\"a\nb\tc\",30,170,0.7\n\"a\nb\tc\",30,160,0.2\n",
    );
    let table = stfit(&[odd.to_str().unwrap(), "--model", "ggx"]);
    assert_eq!(table.ok().lines().count(), 2, "{}", table.stdout);
    assert!(table.stdout.contains("a\\nb\\tc"));
}

/// Runs that take a moment are not announced: the pilot that estimates the cost of the walks
/// prints nothing (a note comes only above `LONG_RUN_SECONDS`, see `walk::WalkCost`), and the
/// estimates are those of the seed, pilot or not.
#[test]
fn short_walk_runs_print_no_cost_note() {
    let args = [
        "albedo",
        "--ndf",
        "student-t",
        "--alpha",
        "0.5",
        "--gamma",
        "1.6",
        "--eta",
        "1.5",
        "--theta-i",
        "30",
        "--walks",
        "5000",
        "--json",
    ];
    let a = stfit(&args);
    let b = stfit(&args);
    assert_eq!(a.ok(), b.ok());
    assert!(a.stderr.is_empty(), "{}", a.stderr);
    let pairs = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,-1\n0.6,0,0.8,0,0,-1\n";
    let e = stfit_in(
        &[
            "eval", "--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5", "--orders", "all", "--walks",
            "2000",
        ],
        pairs,
    );
    e.ok();
    assert!(e.stderr.is_empty(), "{}", e.stderr);
}

/// Fit options that do not apply to the chosen orders or loss are refused (exit 2, the flag
/// named) rather than silently ignored, in the fit command and in `stfit report`; the report's
/// help does not list the --model and --gamma it refuses.
#[test]
fn fit_options_that_do_not_apply_are_refused() {
    let dir = CaseDir::new("limits-inapplicable");
    let data = ggx_data(&dir);
    let d = data.to_str().unwrap();
    let out = dir.join("report");
    let o = out.to_str().unwrap();
    let cases: [(Vec<&str>, &str); 6] = [
        (
            vec![d, "--walks", "5000"],
            "--walks applies to --orders all",
        ),
        (vec![d, "--seed", "3"], "--seed applies to --orders all"),
        (
            vec![d, "--multiple-term", "exact"],
            "--multiple-term applies",
        ),
        (
            vec![d, "--log-floor", "0.01"],
            "--log-floor applies to --loss log",
        ),
        (
            vec!["report", d, "--out", o, "--seed", "2"],
            "--seed applies",
        ),
        (
            vec![
                "report",
                d,
                "--out",
                o,
                "--log-floor",
                "0.1",
                "--loss",
                "sqrt",
            ],
            "--log-floor applies",
        ),
    ];
    for (args, needle) in cases {
        let err = stfit(&args).fails_with(2).to_string();
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    assert!(
        !out.exists(),
        "nothing is written when an option is refused"
    );
    // Where they apply they are accepted.
    stfit(&[d, "--loss", "log", "--log-floor", "0.01", "--model", "ggx"]).ok();
    let help = stfit(&["report", "--help"]).ok().to_string();
    assert!(help.contains("--eta") && !help.contains("--model") && !help.contains("--gamma"));
}

/// Fits the data cannot determine are flagged, never reported with meaningless standard
/// errors: a scale held 300 decades from the data's, and 20,000 copies of one measurement
/// (one informative direction pair).
#[test]
fn undetermined_fits_are_flagged_singular() {
    let dir = CaseDir::new("limits-undetermined");
    let data = ggx_data(&dir);
    let run = stfit(&[
        data.to_str().unwrap(),
        "--model",
        "ggx",
        "--scale",
        "1e-300",
        "--json",
    ]);
    let json = run.ok().to_string();
    assert!(
        json.contains("singular") || json.contains("Singular"),
        "{json}"
    );
    assert!(!json.contains("e147") && !json.contains("e+1"), "{json}");
    let mut copies = String::from("theta_i_deg,theta_o_deg,L\n");
    for _ in 0..20_000 {
        copies.push_str("10,190,0.5\n");
    }
    let one = dir.file("copies.csv", copies);
    let run = stfit(&[one.to_str().unwrap(), "--model", "ggx"]);
    let table = run.ok().to_string();
    assert!(table.contains("few-points"), "{table}");
    assert!(run.stderr.contains("only 1 informative"), "{}", run.stderr);
}

/// Out-of-range values are named in the range that applies (a fit's eta in [1.05, 3]), and
/// empty or huge numbers in messages are short.
#[test]
fn messages_name_the_range_that_applies_and_stay_short() {
    let err = stfit(&["x.csv", "--eta", "1e300"])
        .fails_with(2)
        .to_string();
    assert!(err.contains("[1.05, 3]") && err.contains("1e300"), "{err}");
    let err = stfit(&["x.csv", "--scale=-1e-300"])
        .fails_with(2)
        .to_string();
    assert!(err.contains("-1e-300") && err.len() < 200, "{err}");
    let synth = ["synth", "--model", "ggx", "--alpha", "0.3"];
    let err = stfit(&[&synth[..], &["--noise=-1e-300"]].concat())
        .fails_with(2)
        .to_string();
    assert!(err.contains("-1e-300") && err.len() < 200, "{err}");
    let err = stfit(&[&synth[..], &["--noise", "1e308"]].concat())
        .fails_with(2)
        .to_string();
    assert!(err.contains("1e308") && err.len() < 200, "{err}");
    for list in ["", "10,,20", "0:10:"] {
        let err = stfit(&[&synth[..], &["--theta-i", list]].concat())
            .fails_with(2)
            .to_string();
        assert!(err.contains("empty"), "{list}: {err}");
    }
}

/// Walk flags where nothing walks are refused (exit 2): `eval` in closed form, `synth` without
/// `--orders all`; a data file given twice (directly, through its folder or as one pipe) is
/// refused rather than counted twice; `synth` writes tiny values in exponent form, never 300 digits.
#[test]
fn walk_flags_without_walks_and_files_given_twice_are_refused() {
    let pair = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,-1\n";
    let ggx = ["eval", "--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5"];
    for flag in ["--walks", "--seed"] {
        let err = stfit_in(&[&ggx[..], &[flag, "100"]].concat(), pair)
            .fails_with(2)
            .to_string();
        assert!(err.contains(flag) && err.contains("closed form"), "{err}");
    }
    stfit_in(
        &[&ggx[..], &["--orders", "all", "--walks", "100"]].concat(),
        pair,
    )
    .ok();
    let err = stfit(&["synth", "--model", "ggx", "--alpha", "0.3", "--walks", "10"])
        .fails_with(2)
        .to_string();
    assert!(err.contains("--walks applies to --orders all"), "{err}");

    let dir = CaseDir::new("limits-twice");
    let data = ggx_data(&dir);
    let via_folder = dir.path().join(".").join("d.csv");
    for twice in [
        [data.to_str().unwrap(), via_folder.to_str().unwrap()],
        [dir.path().to_str().unwrap(), data.to_str().unwrap()],
    ] {
        let err = stfit(&twice).fails_with(1).to_string();
        assert!(err.contains("given twice"), "{err}");
    }
    // One pipe named twice: the second read had found it drained and called the file empty.
    #[cfg(unix)]
    {
        let text = std::fs::read_to_string(&data).unwrap();
        let err = stfit_in(&["/dev/stdin", "/dev/stdin"], &text)
            .fails_with(1)
            .to_string();
        assert!(err.contains("given twice"), "{err}");
    }

    let tiny = stfit(&[
        "synth",
        "--model",
        "beckmann",
        "--alpha",
        "0.035",
        "--theta-i",
        "0",
        "--theta-o",
        "164",
    ]);
    let row = tiny.ok().lines().last().unwrap().to_string();
    assert!(row.len() < 60 && row.contains("e-"), "{row}");
}
