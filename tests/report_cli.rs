//! End-to-end tests of `stfit report`: every file written, sizes and text of the figures,
//! stored fits against fitting first, the flags, bad input, and the Walter data from the
//! shared folder (never copied into the project).

use std::path::{Path, PathBuf};
use stfit_test_support::{CaseDir, Cli, Run};

fn stfit(args: &[&str]) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run(args)
}

/// Runs the binary, failing the test (with stderr) unless it succeeds without warnings.
fn stfit_ok(args: &[&str]) -> Run {
    let out = stfit(args);
    let stderr = out.stderr.clone();
    assert!(out.code == Some(0), "stfit {args:?} failed: {stderr}");
    assert!(
        !stderr.contains("warning"),
        "stfit {args:?} warned: {stderr}"
    );
    out
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fits/example.csv")
}

/// The files of a report of `samples`, sorted.
fn expected_files(samples: &[&str]) -> Vec<String> {
    let mut names = vec!["fits.md".to_string()];
    for fig in ["overview", "ndf"] {
        names.push(format!("{fig}.svg"));
        names.push(format!("{fig}.png"));
    }
    for s in samples {
        for kind in ["fits", "residuals"] {
            names.push(format!("{s}-{kind}.svg"));
            names.push(format!("{s}-{kind}.png"));
        }
    }
    names.sort();
    names
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).unwrap()
}

fn png_size(path: &Path) -> (u32, u32) {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let reader = png::Decoder::new(file).read_info().unwrap();
    (reader.info().width, reader.info().height)
}

/// Rows of the fits.md table of one sample: `(model, rmse cell)`.
fn table_rows<'a>(md: &'a str, sample: &str) -> Vec<(&'a str, &'a str)> {
    md.lines()
        .filter_map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (cells.len() > 9 && cells[1] == sample).then(|| (cells[2], cells[8]))
        })
        .collect()
}

#[test]
fn report_fits_first_and_from_stored_fits_gives_the_same_files() {
    let dir = CaseDir::new("stored");
    let (fitted, stored, json) = (
        dir.join("fitted"),
        dir.join("stored"),
        dir.join("fits.json"),
    );
    let out = stfit_ok(&["report", p(&example()), "--out", p(&fitted)]);
    let samples = ["frosted", "etched", "ground"];
    let expected = expected_files(&samples);
    assert_eq!(files_in(&fitted), expected);
    // stdout lists every file written.
    let stdout = out.stdout;
    assert_eq!(stdout.lines().count(), expected.len());

    stfit_ok(&[p(&example()), "--model", "all", "--out", p(&json)]);
    stfit_ok(&[
        "report",
        p(&example()),
        "--fits",
        p(&json),
        "--out",
        p(&stored),
    ]);
    assert_eq!(files_in(&stored), expected);
    for name in &expected {
        assert!(
            std::fs::read(fitted.join(name)).unwrap() == std::fs::read(stored.join(name)).unwrap(),
            "{name} differs between fitting first and stored fits"
        );
    }

    for s in samples {
        assert_eq!(
            png_size(&fitted.join(format!("{s}-fits.png"))),
            (1600, 1200)
        );
        assert_eq!(
            png_size(&fitted.join(format!("{s}-residuals.png"))),
            (1600, 1200)
        );
        let svg = read(&fitted, &format!("{s}-fits.svg"));
        for needle in [
            "Beckmann",
            "GGX",
            "Student-T, γ fixed",
            "Student-T, γ free",
            "γ = 3 (fixed)",
            "α = ",
            "scale = ",
            "rmse √L = ",
            "measured",
            "model",
            "θi = 0°",
            "θi = 80°",
        ] {
            assert!(svg.contains(needle), "{s}-fits.svg lacks `{needle}`");
        }
        // The example data are Student-T made: Student-T with free gamma fits best.
        let md = read(&fitted, "fits.md");
        let rows = table_rows(&md, s);
        assert_eq!(rows.len(), 4, "{s}");
        assert!(rows[3].1.starts_with("**"), "{s}: {rows:?}");
    }
    assert_eq!(
        png_size(&fitted.join("overview.png")),
        (1800, 100 + 3 * 400)
    );
    assert_eq!(png_size(&fitted.join("ndf.png")), (3 * 640, 100 + 560));
    // The shipped example report is what the code draws now (fits/README.md's command).
    let shipped = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fits/report");
    for name in &expected {
        assert!(
            std::fs::read(fitted.join(name)).unwrap() == std::fs::read(shipped.join(name)).unwrap(),
            "fits/report/{name} differs from what `stfit report` draws now; regenerate it"
        );
    }
}

#[test]
fn sample_and_scale_flags_select_what_is_drawn() {
    let dir = CaseDir::new("flags");
    let (json, out) = (dir.join("fits.json"), dir.join("out"));
    stfit_ok(&[p(&example()), "--model", "all", "--out", p(&json)]);
    stfit_ok(&[
        "report",
        p(&example()),
        "--fits",
        p(&json),
        "--sample",
        "etched",
        "--y-axis",
        "linear",
        "--out",
        p(&out),
    ]);
    assert_eq!(files_in(&out), expected_files(&["etched"]));
    let md = read(&out, "fits.md");
    assert_eq!(table_rows(&md, "etched").len(), 4);
    assert!(table_rows(&md, "frosted").is_empty());
    assert!(md.contains("Figures of in-plane data plot L."));
    assert!(read(&out, "etched-residuals.svg").contains("L measured − L model"));
    assert!(!read(&out, "etched-fits.svg").contains("√L<"));
}

#[test]
fn bad_input_fails_with_a_message() {
    let dir = CaseDir::new("bad");
    let bad_json = dir.join("bad.json");
    std::fs::write(&bad_json, "{\"fits\": [{\"sample\": 3}]}").unwrap();
    let fit = r#"{"sample": "frosted", "model": "ggx", "alpha": 0.2, "gamma": null,
        "gamma_fixed": false, "scale": 1.0, "eta": 1.51, "masking": "separable",
        "orders": "single", "walks": null, "seed": null, "loss": "sqrt",
        "optimizer": "nelder-mead", "rmse_sqrt_l": 0.1, "n_points": 12, "alpha_stderr": 0.01,
        "gamma_stderr": null, "scale_stderr": 0.01, "iterations": 3, "data": "x.csv",
        "stfit_version": "0.2.0"}"#;
    let foreign = dir.file(
        "foreign.json",
        format!("{{\"version\": 1, \"fits\": [{fit}]}}"),
    );
    let old = dir.file("old.json", format!("{{\"fits\": [{fit}]}}"));
    let newer = dir.file(
        "newer.json",
        format!("{{\"version\": 9, \"fits\": [{fit}]}}"),
    );
    let invalid = dir.file(
        "invalid.json",
        format!(
            "{{\"version\": 1, \"fits\": [{}]}}",
            // Orders all with separable masking: not a model stfit makes.
            fit.replace("\"orders\": \"single\"", "\"orders\": \"all\"")
        ),
    );
    let out_dir = dir.join("out");
    let (missing, none) = (dir.join("missing.csv"), dir.join("none.json"));
    let ex = example();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["report", p(&missing)], "missing.csv"),
        (vec!["report", p(&ex), "--fits", p(&none)], "none.json"),
        (vec!["report", p(&ex), "--fits", p(&bad_json)], "bad.json"),
        (vec!["report", p(&ex), "--fits", p(&foreign)], "12 points"),
        (
            vec!["report", p(&ex), "--fits", p(&old)],
            "no format version",
        ),
        (vec!["report", p(&ex), "--fits", p(&newer)], "version 9"),
        (vec!["export", p(&invalid), "--to", "pbrt-v4"], "correlated"),
        (
            vec!["report", p(&ex), "--fits", p(&foreign), "--sample", "nope"],
            "nope",
        ),
    ];
    for (args, needle) in cases {
        let mut args = args;
        args.extend(["--out", p(&out_dir)]);
        let out = stfit(&args);
        let stderr = out.stderr.clone();
        assert_eq!(out.code, Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(needle),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    let out = stfit(&["report", p(&ex), "--y-axis", "log"]);
    assert_eq!(out.code, Some(2));
    let out = stfit(&["report", p(&ex), "--scale", "linear"]);
    assert_eq!(out.code, Some(2));
    assert!(out.stderr.contains("--y-axis"), "{}", out.stderr);
    let out = stfit(&["report", p(&ex), "--eta", "1"]);
    assert_eq!(out.code, Some(2));
}

#[test]
fn report_of_the_walter_measurements() {
    let Some(data) = stfit_test_support::walter_measurements("report_of_the_walter_measurements")
    else {
        return;
    };
    let dir = CaseDir::new("walter");
    let out = dir.join("report");
    stfit_ok(&["report", p(&data), "--out", p(&out)]);
    assert_eq!(
        files_in(&out),
        expected_files(&["frosted", "etched", "ground"])
    );
    // The published finding: Student-T fits frosted and etched glass better than Beckmann or
    // GGX (the best rmse of each sample is bold in fits.md).
    let md = read(&out, "fits.md");
    for s in ["frosted", "etched"] {
        let rows = table_rows(&md, s);
        let best: Vec<_> = rows.iter().filter(|r| r.1.starts_with("**")).collect();
        assert_eq!(best.len(), 1, "{s}: {rows:?}");
        assert!(best[0].0.starts_with("Student-T"), "{s}: {rows:?}");
    }
}

/// A fits file without fits, or without a fit of the selected sample, is refused (exit 1)
/// instead of drawing a report without models.
#[test]
fn stored_fits_must_hold_a_fit_to_draw() {
    let dir = CaseDir::new("report-no-fits");
    let empty = dir.file("empty.json", r#"{"version": 1, "fits": []}"#);
    let out = dir.join("out");
    let e = stfit(&[
        "report",
        p(&example()),
        "--fits",
        p(&empty),
        "--out",
        p(&out),
    ])
    .fails_with(1)
    .to_string();
    assert!(e.contains("the file holds no fits"), "{e}");
    assert!(!out.exists());
}

/// A report fits the four models of `--model all`: saying `--model all` is accepted, any other
/// model (the fit command's default, student-t, included) is refused with status 2.
#[test]
fn model_flag_of_a_report_must_be_all() {
    let dir = CaseDir::new("report-model-flag");
    let out = dir.join("report");
    stfit_ok(&[
        "report",
        p(&example()),
        "--model",
        "all",
        "--sample",
        "frosted",
        "--out",
        p(&out),
    ]);
    for model in ["student-t", "ggx"] {
        let run = stfit(&["report", p(&example()), "--model", model, "--out", p(&out)]);
        assert_eq!(run.code, Some(2), "--model {model}: {}", run.stderr);
        assert!(run.stderr.contains("--model all"), "{}", run.stderr);
    }
}

/// A report that reruns long random walks says so before it starts, as `export` does: the
/// example's GGX fit of `frosted`, hand-edited to all orders with 1e9 walks per incidence,
/// announces more than a minute and a half (80 min on a loaded 2-core machine), read from
/// stderr while the report runs, which the test then stops. The same fit with 200 walks says
/// nothing.
#[test]
fn a_report_whose_walks_take_long_says_so_before_it_runs() {
    let dir = CaseDir::new("report-long-run");
    let example_fits = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fits/example-fits.json");
    let mut file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example_fits).unwrap()).unwrap();
    let all_orders = |walks: u64| {
        let mut fit = file["fits"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["sample"] == "frosted" && f["model"] == "ggx")
            .unwrap()
            .clone();
        fit["orders"] = "all".into();
        fit["masking"] = "correlated".into();
        fit["walks"] = walks.into();
        fit["seed"] = 1.into();
        fit
    };
    let (long, quick) = (all_orders(1_000_000_000), all_orders(200));
    file["fits"] = serde_json::json!([long]);
    let long = dir.file("long.json", file.to_string());
    file["fits"] = serde_json::json!([quick]);
    let quick = dir.file("quick.json", file.to_string());
    let out = dir.join("out");
    let report = |fits: &Path| {
        vec![
            "report".to_string(),
            p(&example()).to_string(),
            "--sample".into(),
            "frosted".into(),
            "--fits".into(),
            p(fits).to_string(),
            "--out".into(),
            p(&out).to_string(),
        ]
    };
    // Without a note the report would run its walks silently for far longer than two minutes.
    let args = report(&long);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let line = Cli::new(env!("CARGO_BIN_EXE_stfit"))
        .first_stderr_line(&args, std::time::Duration::from_secs(120))
        .expect("no line on stderr within 120 s");
    assert!(
        line.starts_with(
            "note: the all-orders fits' own random walks, which give the orders >= 2 of the \
             curves and of the model at the measured points, will take about "
        ) && [" min", " h", " days"]
            .iter()
            .any(|unit| line.ends_with(&format!(
                "{unit} (fits with fewer --walks make it shorter)\n"
            ))),
        "{line}"
    );
    let args = report(&quick);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let quick = stfit(&args);
    assert_eq!(quick.code, Some(0), "{}", quick.stderr);
    assert!(!quick.stderr.contains("note:"), "{}", quick.stderr);
    assert!(out.join("frosted-fits.png").exists());
}

/// Samples whose names map to one file name are all reported: `a b` and `a_b` (the space
/// becomes `_`) and `A_B` (the same name where file names ignore case), the example's three
/// samples renamed. The later samples' figures get `-2` and `-3`, and fits.md links each
/// sample's figures under its own name, which each figure's title gives.
#[test]
fn samples_that_map_to_one_file_name_are_all_reported() {
    let dir = CaseDir::new("same-file-name");
    let names = ["a b", "a_b", "A_B"];
    let csv: String = std::fs::read_to_string(example())
        .unwrap()
        .lines()
        .map(|l| {
            let l = l
                .replacen("frosted,", "a b,", 1)
                .replacen("etched,", "a_b,", 1)
                .replacen("ground,", "A_B,", 1);
            format!("{l}\n")
        })
        .collect();
    let data = dir.file("collide.csv", csv);
    let out = dir.join("out");
    stfit_ok(&["report", p(&data), "--out", p(&out)]);
    let stems = ["a_b", "a_b-2", "A_B-3"];
    assert_eq!(files_in(&out), expected_files(&stems));
    let md = read(&out, "fits.md");
    for (sample, stem) in names.iter().zip(stems) {
        let line =
            format!("- {sample}: [fits]({stem}-fits.png), [residuals]({stem}-residuals.png)");
        assert!(md.lines().any(|l| l == line), "{line} not in {md}");
        assert_eq!(table_rows(&md, sample).len(), 4, "{sample}");
        assert!(
            read(&out, &format!("{stem}-fits.svg"))
                .contains(&format!("{sample}: measured transmission")),
            "{stem}-fits.svg"
        );
    }
}

/// A stored fit whose record is not one a fit writes (fits-format.md) but whose model can be
/// evaluated is named and not drawn, as a model out of its range is: `report --fits` had drawn
/// it and printed its numbers in `fits.md` (`0.3000 ± -1.0`, an rmse of `-1.000`, `± 0` for a
/// standard error, an eta no glass of a fit has), where `export` refuses the same file.
#[test]
fn stored_fits_outside_the_format_are_named_not_drawn() {
    let dir = CaseDir::new("report-invalid-record");
    let fits = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fits/example-fits.json");
    let text = std::fs::read_to_string(&fits).unwrap();
    // The first fit is frosted's Beckmann fit.
    for (from, to, named) in [
        (
            "\"alpha_stderr\": 0.",
            "\"alpha_stderr\": -0.",
            "alpha_stderr",
        ),
        ("\"rmse_sqrt_l\": 0.", "\"rmse_sqrt_l\": -0.", "rmse_sqrt_l"),
        (
            "\"scale_stderr\": 0.037816213187896595",
            "\"scale_stderr\": 0",
            "scale_stderr",
        ),
        ("\"eta\": 1.51", "\"eta\": 1.01", "eta"),
        ("\"log_floor\": null", "\"log_floor\": 0.01", "log_floor"),
    ] {
        assert!(text.contains(from), "{from}");
        let edited = dir.file("fits.json", text.replacen(from, to, 1));
        let out = dir.join("report");
        let run = stfit(&[
            "report",
            p(&example()),
            "--sample",
            "frosted",
            "--fits",
            p(&edited),
            "--out",
            p(&out),
        ]);
        assert_eq!(run.code, Some(0), "{to}: {}", run.stderr);
        let warning = run
            .stderr
            .lines()
            .find(|l| l.contains("is not valid"))
            .unwrap_or_else(|| panic!("{to}: no warning: {}", run.stderr));
        assert!(
            warning.starts_with("warning: sample 'frosted', beckmann") && warning.contains(named),
            "{to}: {warning}"
        );
        let md = read(&out, "fits.md");
        assert!(md.contains("## Not drawn"), "{to}: {md}");
        assert_eq!(table_rows(&md, "frosted").len(), 3, "{to}: {md}");
        assert!(!md.contains("± -") && !md.contains("± 0 "), "{to}: {md}");
    }
}

/// Valid data whose values come near the largest double are drawn: the models between the
/// measured points exceed it (GGX's peak of a general grid whose largest value is 1.3e308),
/// and the fits' curves had overflowed, every fit being "not drawn"; the rmse recomputed from
/// squared residuals of the square roots (each near 1e154) had overflowed to inf, warning that
/// the fits came from other data.
#[test]
fn data_near_the_largest_double_are_drawn() {
    let dir = CaseDir::new("report-huge");
    let data = dir.join("huge.csv");
    for (grid, y_axis) in [
        ("general", "sqrt"),
        ("general", "linear"),
        ("in-plane", "sqrt"),
    ] {
        stfit_ok(&[
            "synth",
            "--grid",
            grid,
            "--model",
            "ggx",
            "--alpha",
            "0.3",
            "--theta-o",
            if grid == "general" {
                "5:175:10"
            } else {
                "106:254:4"
            },
            "--scale",
            "1e307",
            "--noise",
            "0.01",
            "--out",
            p(&data),
        ]);
        let out = dir.join(&format!("{grid}-{y_axis}"));
        let run = stfit_ok(&["report", p(&data), "--y-axis", y_axis, "--out", p(&out)]);
        assert!(
            !run.stderr.contains("warning"),
            "{grid}, {y_axis}: {}",
            run.stderr
        );
        let md = read(&out, "fits.md");
        assert!(!md.contains("not drawn"), "{md}");
        assert_eq!(table_rows(&md, "synthetic").len(), 4, "{md}");
    }
}
