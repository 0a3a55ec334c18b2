//! `stfit export`: end-to-end runs of the command, its outputs and its errors.

use stfit_fit::FitsFile;
use stfit_test_support::{CaseDir, Cli, project_root};

fn cli() -> Cli {
    Cli::new(env!("CARGO_BIN_EXE_stfit"))
}

fn example_fits() -> String {
    project_root()
        .join("fits/example-fits.json")
        .display()
        .to_string()
}

/// The text of the shipped example fits.
fn example_text() -> String {
    std::fs::read_to_string(example_fits()).unwrap()
}

/// The shipped example fits, parsed.
fn example_file() -> FitsFile {
    FitsFile::from_json("example", &example_text()).unwrap()
}

/// A pbrt-v4 export of one GGX fit prints one named material, `ground_ggx`, whose roughness is
/// alpha^2 of the stored fit (pbrt's default remapping), to 1e-6.
#[test]
fn pbrt_export_of_a_ggx_fit_prints_roughness_alpha_squared() {
    let fits = FitsFile::read(&project_root().join("fits/example-fits.json")).unwrap();
    let alpha = fits
        .fits
        .iter()
        .find(|f| f.sample == "ground" && f.model.kind.name() == "ggx")
        .unwrap()
        .model
        .alpha;
    let run = cli().run(&[
        "export",
        &example_fits(),
        "--to",
        "pbrt-v4",
        "--sample",
        "ground",
        "--model",
        "ggx",
    ]);
    let text = run.ok();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), 1, "{text}");
    assert!(
        lines[0].starts_with("MakeNamedMaterial \"ground_ggx\" \"string type\" [ \"dielectric\" ]"),
        "{}",
        lines[0]
    );
    let r: f64 = lines[0]
        .split("\"float roughness\" [ ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((r.sqrt() - alpha).abs() < 1e-6, "{}", lines[0]);
}

/// A Radiance export writes a WINDOW XML file with the four Klems blocks of 145 x 145 values:
/// the pane by random walks, the single-scattering interface by the deterministic quadrature.
#[test]
fn radiance_export_writes_four_klems_blocks() {
    let dir = CaseDir::new("export-radiance");
    for (layer, walks, method) in [
        (
            "pane",
            &["--walks", "64"][..],
            "Monte Carlo: 64 cosine-weighted",
        ),
        ("interface", &[], "deterministic quadrature"),
    ] {
        let path = dir.join(&format!("{layer}.xml"));
        let fits = example_fits();
        let args = [
            &[
                "export",
                fits.as_str(),
                "--to",
                "radiance",
                "--sample",
                "etched",
                "--model",
                "student-t",
                "--layer",
                layer,
                "--out",
                path.to_str().unwrap(),
            ][..],
            walks,
        ]
        .concat();
        cli().run(&args).ok();
        let xml = std::fs::read_to_string(&path).unwrap();
        for b in [
            "Transmission Front",
            "Transmission Back",
            "Reflection Front",
            "Reflection Back",
        ] {
            assert!(xml.contains(&format!(
                "<WavelengthDataDirection>{b}</WavelengthDataDirection>"
            )));
        }
        let rows = xml.lines().filter(|l| l.split(", ").count() == 145).count();
        assert_eq!(rows, 4 * 145, "{layer}");
        assert!(xml.contains("is not applied"), "{layer}");
        assert!(xml.contains(method), "{layer}");
    }
}

/// With an existing folder as `--out`, every selected fit gets its own file named
/// SAMPLE_MODEL-TARGET.EXT, listed on stdout; V-Ray writes a .vrscene.
#[test]
fn export_to_a_folder_writes_one_file_per_fit() {
    let dir = CaseDir::new("export-folder");
    let run = cli().run(&[
        "export",
        &example_fits(),
        "--to",
        "vray",
        "--sample",
        "frosted",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let listed: Vec<&str> = run.ok().lines().collect();
    assert_eq!(listed.len(), 4, "{listed:?}");
    for name in [
        "frosted_beckmann-vray.vrscene",
        "frosted_ggx-vray.vrscene",
        "frosted_student_t-vray.vrscene",
        "frosted_student_t_gamma_fixed-vray.vrscene",
    ] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(text.contains("BRDFVRayMtl"), "{name}");
    }
}

/// Invalid command-line values exit with 2, bad data with 1, naming the file and the fit.
#[test]
fn bad_values_and_bad_files_are_refused_with_the_right_exit_code() {
    let fits = example_fits();
    let dir = CaseDir::new("export-errors");
    let one_file = dir.join("x.xml");
    let usage: [&[&str]; 6] = [
        &["--to", "radiance", "--absorption", "1.5"],
        &["--to", "mitsuba3", "--layer", "interface"],
        &["--to", "radiance", "--walks", "0"],
        &["--to", "radiance", "--walks", "10000000000000"],
        &["--to", "radiance", "--out", one_file.to_str().unwrap()],
        &["--to", "pbrt-v4", "--samples", "10"],
    ];
    for extra in usage {
        let args = [&["export", fits.as_str()], extra].concat();
        let err = cli().run(&args).fails_with(2).to_string();
        assert!(err.starts_with("error"), "{args:?}: {err}");
    }
    let err = cli()
        .run(&["export", &fits, "--to", "pbrt-v4", "--samples", "10"])
        .fails_with(2)
        .to_string();
    assert!(err.contains("--walks"), "{err}");
    let unversioned = dir.file(
        "old.json",
        r#"{"fits": [{"sample": "s", "model": "ggx", "alpha": 0.3, "scale": 1.0}]}"#,
    );
    let err = cli()
        .run(&["export", unversioned.to_str().unwrap(), "--to", "pbrt-v4"])
        .fails_with(1)
        .to_string();
    assert!(err.contains("old.json") && err.contains("version"), "{err}");
    let bad = edited_fits(
        &dir,
        "bad.json",
        "\"alpha\": 0.21829845077431576",
        "\"alpha\": -1.0",
    );
    let err = cli()
        .run(&["export", bad.to_str().unwrap(), "--to", "pbrt-v4"])
        .fails_with(1)
        .to_string();
    assert!(
        err.contains("bad.json") && err.contains("fit 0") && err.contains("alpha"),
        "{err}"
    );
    let err = cli()
        .run(&["export", &fits, "--to", "pbrt-v4", "--sample", "nothing"])
        .fails_with(1)
        .to_string();
    assert!(err.contains("no fit matches"), "{err}");
}

/// A pane needs random walks, which a Student-T shape below 1.501 would make endless (a
/// single-scattering fit may have one): the pane export of such a fit is refused as bad data,
/// naming the file and the walk's range, instead of running without end.
#[test]
fn a_pane_of_a_gamma_below_the_walk_range_is_refused() {
    let dir = CaseDir::new("export-pane-gamma");
    let mut file = example_file();
    file.fits
        .retain(|f| f.sample == "ground" && f.model.kind.name() == "student-t");
    file.fits.truncate(1);
    file.fits[0].model.gamma = stfit_fit::Gamma::Free(1.5000001);
    let path = dir.file("g.json", file.to_json());
    let err = cli()
        .run(&[
            "export",
            path.to_str().unwrap(),
            "--to",
            "radiance",
            "--walks",
            "2",
        ])
        .fails_with(1)
        .to_string();
    assert!(
        err.contains("g.json") && err.contains("gamma >= 1.501"),
        "{err}"
    );
}

/// The example fits with the first fit's `from` replaced by `to` (once), written into `dir`.
fn edited_fits(dir: &CaseDir, name: &str, from: &str, to: &str) -> std::path::PathBuf {
    let text = example_text();
    assert!(text.contains(from), "{from}");
    dir.file(name, text.replacen(from, to, 1))
}

/// Stored numbers outside their documented ranges (an eta that is no glass of a fit, a
/// negative rmse or standard error) are refused as bad data, naming the file, the fit and the
/// key; a leading byte order mark is read.
#[test]
fn stored_numbers_outside_their_ranges_are_refused_and_a_bom_is_read() {
    let dir = CaseDir::new("export-ranges");
    for (from, to, key) in [
        ("\"eta\": 1.51", "\"eta\": 10.0", "eta"),
        ("\"eta\": 1.51", "\"eta\": 0.5", "eta"),
        ("\"rmse_sqrt_l\": 0.", "\"rmse_sqrt_l\": -0.", "rmse_sqrt_l"),
        (
            "\"alpha_stderr\": 0.",
            "\"alpha_stderr\": -0.",
            "alpha_stderr",
        ),
    ] {
        let path = edited_fits(&dir, "bad.json", from, to);
        let err = cli()
            .run(&["export", path.to_str().unwrap(), "--to", "pbrt-v4"])
            .fails_with(1)
            .to_string();
        assert!(
            err.contains("bad.json: fit 0 (sample 'frosted', beckmann)") && err.contains(key),
            "{to}: {err}"
        );
    }
    let path = edited_fits(&dir, "bom.json", "{", "\u{feff}{");
    let text = cli()
        .run(&[
            "export",
            path.to_str().unwrap(),
            "--to",
            "pbrt-v4",
            "--sample",
            "ground",
            "--model",
            "ggx",
        ])
        .ok()
        .to_string();
    assert!(text.contains("Material"), "{text}");
}

/// Samples `a b` and `a_b` would both write `a_b_ggx-pbrt-v4.pbrt`: refused with exit 1 naming
/// both fits, and nothing is written.
#[test]
fn fits_that_would_share_a_file_name_are_refused() {
    let dir = CaseDir::new("export-collide");
    let mut file = example_file();
    file.fits.retain(|f| f.model.kind.name() == "ggx");
    file.fits.truncate(2);
    file.fits[0].sample = "a b".into();
    file.fits[1].sample = "a_b".into();
    let path = dir.file("collide.json", file.to_json());
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let err = cli()
        .run(&[
            "export",
            path.to_str().unwrap(),
            "--to",
            "pbrt-v4",
            "--out",
            out.to_str().unwrap(),
        ])
        .fails_with(1)
        .to_string();
    assert!(
        err.contains("collide.json")
            && err.contains("sample 'a b', ggx")
            && err.contains("sample 'a_b', ggx"),
        "{err}"
    );
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 0);
}

/// Radiance's flags are refused with another target even at their default values; `--out
/// DIR/` creates the folder; an exact mapping prints no sensitivity of its rounding-level rmse.
#[test]
fn radiance_flags_where_they_do_not_apply_are_refused_and_out_folders_are_made() {
    let fits = example_fits();
    for extra in [
        &["--to", "mitsuba3", "--layer", "pane"][..],
        &["--to", "pbrt-v4", "--seed", "1"],
        &["--to", "mitsuba3", "--absorption", "0"],
    ] {
        let args = [
            &[
                "export",
                fits.as_str(),
                "--sample",
                "frosted",
                "--model",
                "ggx",
            ],
            extra,
        ]
        .concat();
        let err = cli().run(&args).fails_with(2).to_string();
        assert!(err.contains("--"), "{args:?}: {err}");
    }
    // The walks of a Radiance interface are those of an all-orders fit's orders >= 2: refused
    // for single-scattering fits, accepted for an all-orders one.
    let dir = CaseDir::new("export-new-folder");
    let interface = |fits: &str, extra: &[&str]| {
        cli().run(
            &[
                &["export", fits, "--to", "radiance", "--layer", "interface"][..],
                extra,
            ]
            .concat(),
        )
    };
    let single = dir.join("single.xml");
    for flag in ["--walks", "--seed"] {
        let err = interface(
            &fits,
            &[
                "--sample",
                "frosted",
                "--model",
                "ggx",
                flag,
                "64",
                "--out",
                single.to_str().unwrap(),
            ],
        )
        .fails_with(2)
        .to_string();
        assert!(err.contains(&format!("{flag} applies")), "{err}");
    }
    // With no fit selected, the selection is what is wrong (exit 1), not the walk flags.
    let err = interface(&fits, &["--sample", "no such sample", "--walks", "64"])
        .fails_with(1)
        .to_string();
    assert!(err.contains("no fit matches"), "{err}");
    let all = dir.join("all-orders.json");
    let data = project_root().join("fits/example.csv");
    cli()
        .run(&[
            data.to_str().unwrap(),
            "--sample",
            "frosted",
            "--model",
            "ggx",
            "--orders",
            "all",
            "--walks",
            "200",
            "--out",
            all.to_str().unwrap(),
        ])
        .ok();
    let all_xml = dir.join("all.xml");
    interface(
        all.to_str().unwrap(),
        &[
            "--walks",
            "8",
            "--seed",
            "3",
            "--out",
            all_xml.to_str().unwrap(),
        ],
    )
    .ok();
    let folder = format!("{}/made/", dir.path().display());
    let run = cli().run(&[
        "export", &fits, "--to", "mitsuba3", "--sample", "frosted", "--out", &folder,
    ]);
    assert!(run.ok().lines().count() >= 4, "{}", run.stdout);
    let py = std::fs::read_to_string(dir.join("made").join("frosted_ggx-mitsuba3.py")).unwrap();
    assert!(
        py.contains("exact to rounding") && !py.contains("e-17"),
        "{py}"
    );
}

/// A very long sample name is cut in file names (to 100 characters), so export to a folder
/// writes files every file system accepts.
#[test]
fn long_sample_names_give_short_file_names() {
    let dir = CaseDir::new("export-long-name");
    let long = "x".repeat(5000);
    let fits = edited_fits(&dir, "long.json", "\"frosted\"", &format!("\"{long}\""));
    let folder = format!("{}/out/", dir.path().display());
    let run = cli().run(&[
        "export",
        fits.to_str().unwrap(),
        "--to",
        "mitsuba3",
        "--out",
        &folder,
    ]);
    let listing = run.ok().to_string();
    assert!(listing.lines().count() >= 8, "{listing}");
    for path in listing.lines() {
        let name = std::path::Path::new(path)
            .file_name()
            .unwrap()
            .to_string_lossy()
            .len();
        assert!(name < 150, "{path}");
    }
}

/// The shipped example exports of one sample (`fits/export/frosted_*`, every target but
/// Radiance, whose walks make it slow; one sample keeps the test short) are what the current
/// code writes from the shipped fits, byte for byte: a change of an export is regenerated with
/// the command in `fits/export/README.md`.
#[test]
fn shipped_example_exports_are_current() {
    let dir = CaseDir::new("export-examples");
    let out = format!("{}/", dir.path().display());
    let fits = example_fits();
    let mut compared = 0;
    for target in [
        "mitsuba3",
        "pbrt-v4",
        "cycles",
        "appleseed",
        "openpbr",
        "vray",
    ] {
        let listing = cli()
            .run(&[
                "export", &fits, "--to", target, "--sample", "frosted", "--out", &out,
            ])
            .ok()
            .to_string();
        for path in listing.lines() {
            let path = std::path::Path::new(path);
            let name = path.file_name().unwrap();
            let shipped = project_root().join("fits/export").join(name);
            let shipped =
                std::fs::read(&shipped).unwrap_or_else(|e| panic!("{}: {e}", shipped.display()));
            assert!(
                std::fs::read(path).unwrap() == shipped,
                "fits/export/{} differs from what `stfit export` writes now; regenerate it \
                 (fits/export/README.md)",
                name.to_string_lossy()
            );
            compared += 1;
        }
    }
    assert_eq!(compared, 28);
}

/// The shipped Radiance example panes (`fits/export/*_student_t-radiance.xml`) are what the
/// current code writes from the shipped fits, apart from what depends on the number of walks:
/// an export with 4 walks per patch (the full 65,536 take 24 s a sample) gives the same lines
/// outside the `ScatteringData` blocks and the two comments that report the walks' Monte Carlo
/// error and totals (the source fit, its scale, the model, the angle basis, the layout).
#[test]
fn shipped_radiance_examples_are_current_but_for_their_walks() {
    let dir = CaseDir::new("export-radiance-examples");
    let fits = example_fits();
    let walk_free = |text: &str| -> Vec<String> {
        let mut inside = false;
        let mut kept = Vec::new();
        for line in text.lines() {
            let trimmed = line.trim();
            if trimmed == "<ScatteringData>" {
                inside = true;
            } else if trimmed == "</ScatteringData>" {
                inside = false;
            } else if !inside
                && !trimmed.starts_with("<!-- Patch averages by Monte Carlo")
                && !trimmed.starts_with("<!-- Hemispherical totals")
            {
                kept.push(line.to_string());
            }
        }
        kept
    };
    for sample in ["frosted", "etched", "ground"] {
        let name = format!("{sample}_student_t-radiance.xml");
        let out = dir.join(&name);
        cli()
            .run(&[
                "export",
                &fits,
                "--to",
                "radiance",
                "--sample",
                sample,
                "--model",
                "student-t",
                "--walks",
                "4",
                "--out",
                out.to_str().unwrap(),
            ])
            .ok();
        let shipped = std::fs::read_to_string(project_root().join("fits/export").join(&name))
            .unwrap_or_else(|e| panic!("fits/export/{name}: {e}"));
        let now = std::fs::read_to_string(&out).unwrap();
        let (shipped, now) = (walk_free(&shipped), walk_free(&now));
        assert!(shipped.len() > 100, "{name}: {} lines kept", shipped.len());
        assert!(
            shipped == now,
            "fits/export/{name} differs from what `stfit export` writes now outside its walks; \
             regenerate it (fits/export/README.md)"
        );
    }
}

/// One walk per Klems patch cannot estimate the standard errors a Radiance pane file states:
/// refused (exit 2); two are rounded up to a square (4) and the file says so.
#[test]
fn radiance_needs_two_walks_per_patch() {
    let dir = CaseDir::new("radiance-one-walk");
    let (fits, out) = (example_fits(), dir.join("pane.xml"));
    let run = |walks: &str| {
        cli().run(&[
            "export",
            fits.as_str(),
            "--sample",
            "frosted",
            "--model",
            "ggx",
            "--to",
            "radiance",
            "--out",
            out.to_str().unwrap(),
            "--walks",
            walks,
        ])
    };
    let e = run("1").fails_with(2).to_string();
    assert!(e.contains("walks per patch must be in [2,"), "{e}");
    run("2").ok();
    let xml = std::fs::read_to_string(&out).unwrap();
    assert!(xml.contains("Monte Carlo: 4 cosine-weighted incident directions per patch"));
}

/// A Radiance export whose walks will take long says so before it starts (as `eval` and
/// `albedo` do): 1e9 walks per patch announce hours, read from stderr while the run goes on,
/// which the test then stops. The default export says nothing.
#[test]
fn a_long_radiance_export_is_announced_before_it_runs() {
    use std::io::{BufRead, BufReader};
    let dir = CaseDir::new("export-long-run");
    let out = format!("{}/", dir.join("out").display());
    let fits = example_fits();
    let export = |extra: &[&'static str]| {
        let mut args = vec![
            "export", &fits, "--to", "radiance", "--sample", "frosted", "--model", "ggx", "--out",
            &out,
        ];
        args.extend_from_slice(extra);
        args
    };
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_stfit"))
        .args(export(&["--walks", "1000000000"]))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stderr.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        line.starts_with("note: the random walks of this export (1000000000 per Klems patch)")
            && (line.contains(" h (fewer --walks") || line.contains(" days (fewer --walks")),
        "{line}"
    );
    let quick = cli().run(&export(&["--layer", "interface"]));
    assert_eq!(quick.code, Some(0), "{}", quick.stderr);
    assert!(!quick.stderr.contains("note:"), "{}", quick.stderr);
}

/// appleseed refuses an eta above 2.5: that fit's refusal is printed on its own line, naming
/// the file, the fit and the target, the other fits are written (to stdout and to a folder
/// alike), and the command exits 1 with the count of refusals on its last line.
#[test]
fn a_refused_fit_does_not_stop_the_others() {
    let dir = CaseDir::new("export-refused");
    let mut file = example_file();
    file.fits.retain(|f| f.model.kind.name() == "ggx");
    for (fit, (sample, eta)) in file
        .fits
        .iter_mut()
        .zip([("a", 1.51), ("b", 2.8), ("c", 1.5)])
    {
        fit.sample = sample.into();
        fit.model.eta = eta;
    }
    let path = dir.file("mixed.json", file.to_json());
    let fits = path.to_str().unwrap();
    let check_stderr = |stderr: &str| {
        let refusal = format!("error: {fits}: sample 'b', ggx to appleseed: ");
        assert!(
            stderr
                .lines()
                .any(|l| l.starts_with(&refusal) && l.contains("eta 2.8")),
            "{stderr}"
        );
        assert_eq!(
            stderr.lines().last(),
            Some("error: 1 of 3 exports refused"),
            "{stderr}"
        );
    };
    let run = cli().run(&["export", fits, "--to", "appleseed"]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    check_stderr(&run.stderr);
    assert!(
        run.stdout.contains("name=\"a_ggx\"")
            && run.stdout.contains("name=\"c_ggx\"")
            && !run.stdout.contains("b_ggx"),
        "{}",
        run.stdout
    );
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let run = cli().run(&[
        "export",
        fits,
        "--to",
        "appleseed",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    check_stderr(&run.stderr);
    let mut written: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["a_ggx-appleseed.xml", "c_ggx-appleseed.xml"]);
}

/// The rmse figures of the summary lines an export prints on stderr, in order.
fn summary_rmses(stderr: &str) -> Vec<f64> {
    stderr
        .lines()
        .flat_map(|l| l.split("rmse sqrt(L): ").skip(1))
        .flat_map(|part| part.split(", ").map(|s| s.split(' ').next().unwrap()))
        .map(|v| v.parse::<f64>().unwrap_or_else(|_| panic!("{v}: {stderr}")))
        .collect()
}

/// A fit's scale is any positive number (data of 1e307 fit to a scale of 1e307, fits-format.md)
/// and is never applied; the translation's rmse, in the fit's units `sqrt(L)`, grows with its
/// square root. `L` at a peak times such a scale had overflowed: a GGX fit's export printed
/// `rmse sqrt(L): NaN` (exit 0) and a Beckmann fit's was refused ("the cost is not finite"),
/// while a scale of 1e-307 underflowed and was refused ("not a representable number").
#[test]
fn fits_of_huge_and_tiny_scales_export_with_finite_errors() {
    let dir = CaseDir::new("export-scales");
    let export = |path: &std::path::Path, model: &str| {
        let out = cli().run(&[
            "export",
            path.to_str().unwrap(),
            "--to",
            "pbrt-v4",
            "--sample",
            "frosted",
            "--model",
            model,
        ]);
        let text = out.ok().to_string();
        assert!(
            !text.contains("NaN") && !out.stderr.contains("NaN"),
            "{text}{}",
            out.stderr
        );
        summary_rmses(&out.stderr)
    };
    let plain = dir.file("plain.json", example_text());
    for (model, scale) in [
        ("beckmann", "1.00844442304944"),
        ("ggx", "0.9997120509270278"),
    ] {
        let expected = export(&plain, model);
        assert_eq!(expected.len(), 2, "{expected:?}");
        for exponent in [307, -307] {
            let factor = 10f64.powi(exponent);
            let edited = edited_fits(
                &dir,
                "scaled.json",
                &format!("\"scale\": {scale},"),
                &format!("\"scale\": {scale}e{exponent},"),
            );
            let got = export(&edited, model);
            // The plain figures have four decimals (0.0042).
            for (g, e) in got.iter().zip(&expected) {
                assert!(
                    (g / factor.sqrt() - e).abs() <= 5e-5 + 1e-3 * e,
                    "{model} at {factor:e}: {got:?}, expected {expected:?} times sqrt of it"
                );
            }
        }
    }
}
