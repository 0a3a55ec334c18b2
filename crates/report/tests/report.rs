//! Library-level tests of the report: files, sizes, text content, stored fits, errors.

use std::path::PathBuf;

use stfit_fit::{
    Dataset, FitResult, FitsFile, Gamma, Loss, Measurement, Model, ModelKind, Optimizer, Sample,
};
use stfit_report::{
    ModelSlot, ReportError, ReportOptions, YScale, clip_below, file_stem, file_stems,
    fits_markdown, fmt_sig, render_report, walk_seconds,
};

const ANGLES: [f64; 4] = [0.0, 30.0, 60.0, 80.0];

/// The single-scattering model (eta 1.51, separable masking); `gamma` used by Student-T only.
fn params(kind: ModelKind, alpha: f64, gamma: f64, scale: f64) -> Model {
    let gamma = if kind == ModelKind::StudentT {
        Gamma::Free(gamma)
    } else {
        Gamma::NotApplicable
    };
    Model::single(kind, alpha, gamma, scale)
}

/// A sample made with the single-scattering model, 4 x 75 points over the Walter range of
/// `theta_o`, with a deterministic small wobble standing in for measurement noise.
fn synth_sample(name: &str, truth: Model, wobble: f64) -> Sample {
    let mut points = Vec::new();
    for (a, &ti) in ANGLES.iter().enumerate() {
        for k in 0..75 {
            let to = 105.82 + (253.89 - 105.82) * k as f64 / 74.0;
            let l = truth.predict(&[(ti, to)]).unwrap()[0];
            let noise = 1.0 + wobble * ((k * 7 + a * 3) as f64).sin();
            points.push(Measurement::in_plane(ti, to, l * noise, 1.0));
        }
    }
    Sample {
        name: name.to_string(),
        points,
    }
}

fn dataset() -> Dataset {
    Dataset {
        source: PathBuf::from("synthetic"),
        samples: vec![
            synth_sample(
                "frosted-like",
                params(ModelKind::StudentT, 0.25, 2.6, 1.0),
                0.05,
            ),
            synth_sample(
                "ground glass",
                params(ModelKind::StudentT, 0.4, 1.9, 0.8),
                0.03,
            ),
        ],
    }
}

/// rmse of sqrt(L) of a model over a sample, computed here independently of the report.
fn rmse(sample: &Sample, p: &Model) -> f64 {
    let ss: f64 = sample
        .points
        .iter()
        .map(|m| {
            let l = p.predict_points(std::slice::from_ref(m)).unwrap()[0];
            (m.value.sqrt() - l.sqrt()).powi(2)
        })
        .sum();
    (ss / sample.points.len() as f64).sqrt()
}

fn fit(sample: &Sample, mut p: Model, gamma_fixed: bool) -> FitResult {
    if let (true, Some(g)) = (gamma_fixed, p.gamma.value()) {
        p.gamma = Gamma::Fixed(g);
    }
    FitResult {
        sample: sample.name.clone(),
        model: p,
        loss: Loss::Sqrt,
        optimizer: Optimizer::NelderMead,
        multiple_term: None,
        rmse_sqrt_l: rmse(sample, &p),
        n_points: sample.points.len(),
        alpha_stderr: Some(0.001),
        gamma_stderr: p.gamma.is_free().then_some(0.05),
        scale_stderr: Some(0.004),
        iterations: 42,
        data: None,
        warnings: Vec::new(),
        stfit_version: "test".into(),
        eta_fixed: true,
        scale_fixed: false,
        log_floor: None,
        eta_stderr: None,
        measured: sample.measured(),
    }
}

/// Plausible fits of all four models for every sample (parameters near the truth, rmse exact).
fn fits(data: &Dataset) -> Vec<FitResult> {
    let mut out = Vec::new();
    for (i, s) in data.samples.iter().enumerate() {
        let a = [0.25, 0.4][i];
        out.push(fit(
            s,
            params(ModelKind::Beckmann, a * 0.9, 0.0, 0.9),
            false,
        ));
        out.push(fit(s, params(ModelKind::Ggx, a * 0.8, 0.0, 1.1), false));
        out.push(fit(s, params(ModelKind::StudentT, a, 3.0, 1.0), true));
        out.push(fit(
            s,
            params(ModelKind::StudentT, a * 1.01, [2.6, 1.9][i], 0.99),
            false,
        ));
    }
    out
}

fn out_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn svg(report: &stfit_report::Report, name: &str) -> String {
    String::from_utf8(report.file(name).expect(name).contents.clone()).unwrap()
}

fn png_size(bytes: &[u8]) -> (u32, u32, png::ColorType) {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    (info.width, info.height, info.color_type)
}

#[test]
fn report_writes_every_file() {
    let data = dataset();
    let dir = out_dir("every-file");
    let report =
        stfit_report::write_report(&data, &fits(&data), &dir, &ReportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let mut expected = vec!["fits.md".to_string()];
    for stem in ["frosted-like", "ground_glass"] {
        for kind in ["fits", "residuals"] {
            for ext in ["svg", "png"] {
                expected.push(format!("{stem}-{kind}.{ext}"));
            }
        }
    }
    for fig in ["overview", "ndf"] {
        for ext in ["svg", "png"] {
            expected.push(format!("{fig}.{ext}"));
        }
    }
    let mut names: Vec<String> = report.files.iter().map(|f| f.name.clone()).collect();
    names.sort();
    expected.sort();
    assert_eq!(names, expected);
    for name in &expected {
        let on_disk = std::fs::read(dir.join(name)).unwrap();
        assert!(on_disk.len() > 100, "{name} is nearly empty");
        assert_eq!(on_disk, report.file(name).unwrap().contents, "{name}");
    }
}

#[test]
fn svgs_contain_panel_titles_and_legends() {
    let data = dataset();
    let all = fits(&data);
    let report = render_report(&data, &all, &ReportOptions::default()).unwrap();
    let fig = svg(&report, "frosted-like-fits.svg");
    for slot in ModelSlot::ALL {
        assert!(
            fig.contains(slot.title()),
            "missing panel title {}",
            slot.title()
        );
    }
    let ggx = &all[1];
    for needle in [
        "frosted-like: measured transmission",
        &format!("α = {}", fmt_sig(ggx.model.alpha, 4)),
        "γ = 3 (fixed)",
        "γ = 2.600",
        &format!("scale = {}", fmt_sig(ggx.model.scale, 4)),
        &format!("rmse √L = {}", fmt_sig(ggx.rmse_sqrt_l, 3)),
        "measured",
        "model",
        "θi = 0°",
        "θi = 30°",
        "θi = 60°",
        "θi = 80°",
        "θo (degrees)",
        "√L",
    ] {
        assert!(fig.contains(needle), "fit figure lacks `{needle}`");
    }
    let res = svg(&report, "ground_glass-residuals.svg");
    for needle in [
        "residuals",
        "θi = 80°",
        "√L measured − √L model",
        "Student-T, γ free",
    ] {
        assert!(res.contains(needle), "residual figure lacks `{needle}`");
    }
    let overview = svg(&report, "overview.svg");
    for needle in [
        "frosted-like · Beckmann",
        "ground glass · Student-T, γ free",
        "θi = 60°",
    ] {
        assert!(overview.contains(needle), "overview lacks `{needle}`");
    }
    let ndf = svg(&report, "ndf.svg");
    for needle in ["D(θm)", "GGX", "frosted-like", "ground glass"] {
        assert!(ndf.contains(needle), "NDF figure lacks `{needle}`");
    }
}

#[test]
fn pngs_have_the_stated_sizes() {
    let data = dataset();
    let report = render_report(&data, &fits(&data), &ReportOptions::default()).unwrap();
    for name in ["frosted-like-fits.png", "ground_glass-residuals.png"] {
        let (w, h, c) = png_size(&report.file(name).unwrap().contents);
        assert_eq!((w, h, c), (1600, 1200, png::ColorType::Rgb), "{name}");
    }
    let (w, h, _) = png_size(&report.file("overview.png").unwrap().contents);
    assert_eq!((w, h), (1800, 100 + 400 * 2));
    let (w, h, _) = png_size(&report.file("ndf.png").unwrap().contents);
    assert_eq!((w, h), (2 * 820, 100 + 560));
}

#[test]
fn pngs_decode_and_are_not_blank() {
    let data = dataset();
    let report = render_report(&data, &fits(&data), &ReportOptions::default()).unwrap();
    let bytes = &report.file("frosted-like-fits.png").unwrap().contents;
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes.as_slice()))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut buf).unwrap();
    let white = buf.chunks(3).filter(|p| p == &[255, 255, 255]).count();
    let total = buf.len() / 3;
    // Mostly white background, but with a real amount of ink (axes, text, markers, curves).
    assert!(
        white < total * 97 / 100 && white > total / 2,
        "white {white} of {total}"
    );
    // The first incidence angle's colour (Okabe-Ito blue) is drawn.
    assert!(buf.chunks(3).any(|p| p == [0x00, 0x72, 0xB2]));
}

#[test]
fn report_from_stored_fits_equals_report_from_memory() {
    let data = dataset();
    let all = fits(&data);
    let json = FitsFile::new(all.clone()).to_json();
    let stored = FitsFile::from_json("test", &json).unwrap().fits;
    assert_eq!(stored, all);
    let opts = ReportOptions::default();
    let a = render_report(&data, &all, &opts).unwrap();
    let b = render_report(&data, &stored, &opts).unwrap();
    assert_eq!(a, b);
}

#[test]
fn fit_order_does_not_change_the_report() {
    let data = dataset();
    let all = fits(&data);
    let mut reversed = all.clone();
    reversed.reverse();
    let opts = ReportOptions::default();
    let a = render_report(&data, &all, &opts).unwrap();
    let b = render_report(&data, &reversed, &opts).unwrap();
    assert_eq!(a, b);
}

#[test]
fn linear_scale_changes_the_axis() {
    let data = dataset();
    let all = fits(&data);
    let opts = ReportOptions {
        y_scale: YScale::Linear,
    };
    let report = render_report(&data, &all, &opts).unwrap();
    let fig = svg(&report, "frosted-like-fits.svg");
    assert!(
        !fig.contains("√L<") && !fig.contains(">√L"),
        "linear plot labelled sqrt"
    );
    assert!(svg(&report, "frosted-like-residuals.svg").contains("L measured − L model"));
    let sqrt = render_report(&data, &all, &ReportOptions::default()).unwrap();
    assert_ne!(svg(&sqrt, "frosted-like-fits.svg"), fig);
}

#[test]
fn missing_fits_leave_panels_with_data_only() {
    let data = dataset();
    let some: Vec<FitResult> = fits(&data)
        .into_iter()
        .filter(|f| f.model.kind == ModelKind::Ggx)
        .collect();
    let report = render_report(&data, &some, &ReportOptions::default()).unwrap();
    let fig = svg(&report, "frosted-like-fits.svg");
    assert_eq!(fig.matches("not fitted").count(), 3);
    let md = svg(&report, "fits.md");
    assert_eq!(
        md.lines()
            .filter(|l| l.starts_with("| ") && l.contains("GGX"))
            .count(),
        2
    );
    assert!(!md.contains("Beckmann |"));
    // No fits at all still draws the data.
    let bare = render_report(&data, &[], &ReportOptions::default()).unwrap();
    assert_eq!(
        svg(&bare, "frosted-like-fits.svg")
            .matches("not fitted")
            .count(),
        4
    );
}

#[test]
fn a_stored_rmse_the_data_does_not_reproduce_is_reported() {
    let data = dataset();
    let mut all = fits(&data);
    all[0].rmse_sqrt_l *= 1.5;
    let report = render_report(&data, &all, &ReportOptions::default()).unwrap();
    assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
    assert!(report.warnings[0].contains("frosted-like") && report.warnings[0].contains("Beckmann"));
    // fits.md, whose table shows the stored rmse, says so too.
    let md = String::from_utf8(report.file("fits.md").unwrap().contents.clone()).unwrap();
    let section = md
        .split("## Not reproduced")
        .nth(1)
        .expect("a Not reproduced section");
    assert!(
        section.contains("frosted-like") && section.contains("Beckmann"),
        "{md}"
    );
    assert!(section.find("## Figures").is_some(), "{md}");
    // Each fit is drawn with its own model: fits that claim another eta than the one their
    // rmse was computed with do not reproduce it.
    let mut other_eta = fits(&data);
    other_eta.iter_mut().for_each(|f| f.model.eta = 1.4);
    let report = render_report(&data, &other_eta, &ReportOptions::default()).unwrap();
    assert_eq!(report.warnings.len(), 8);
    assert!(
        report.warnings[0].contains("eta 1.4"),
        "{}",
        report.warnings[0]
    );
}

#[test]
fn fits_markdown_lists_every_fit_and_marks_the_best() {
    let data = dataset();
    let all = fits(&data);
    let report = render_report(&data, &all, &ReportOptions::default()).unwrap();
    let md = svg(&report, "fits.md");
    let rows: Vec<&str> = md
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| sample"))
        .collect();
    assert_eq!(rows.len(), all.len());
    for (row, f) in rows.iter().zip(&all) {
        assert!(row.contains(&fmt_sig(f.model.alpha, 4)), "{row}");
        assert!(
            row.contains(&format!("| {} |", ModelSlot::of(f).title())),
            "{row}"
        );
    }
    for (i, s) in data.samples.iter().enumerate() {
        let mine = &all[i * 4..i * 4 + 4];
        let best = mine
            .iter()
            .min_by(|a, b| a.rmse_sqrt_l.total_cmp(&b.rmse_sqrt_l))
            .unwrap();
        let bold = format!("**{}**", fmt_sig(best.rmse_sqrt_l, 4));
        let bold_rows: Vec<_> = rows.iter().filter(|r| r.contains(&bold)).collect();
        assert_eq!(bold_rows.len(), 1, "{}", s.name);
        assert!(bold_rows[0].contains(ModelSlot::of(best).title()));
    }
    assert!(md.contains("(frosted-like-fits.png)") && md.contains("(ground_glass-residuals.png)"));
    let direct = fits_markdown(
        &[("x", all[..4].iter().collect())],
        &[],
        &[],
        true,
        &ReportOptions::default(),
    );
    assert!(
        direct.contains(
            "| x | Student-T, γ fixed | single scattering, separable masking, sqrt loss | \
             0.2500 ± 0.0010 | 3.000 (fixed) | 1.510 (fixed) |"
        ),
        "{direct}"
    );
    assert!(direct.contains("Figures of in-plane data plot sqrt(L)."));
    // Without in-plane samples no panel has that y axis; a log-loss fit says its loss.
    let mut log_fit = all[0].clone();
    log_fit.loss = stfit_fit::Loss::Log;
    log_fit.log_floor = Some(1e-3);
    let general = fits_markdown(
        &[("x", vec![&log_fit])],
        &[],
        &[],
        false,
        &ReportOptions::default(),
    );
    assert!(!general.contains("Figures of in-plane"), "{general}");
    assert!(
        general.contains("separable masking, log loss |"),
        "{general}"
    );
}

#[test]
fn bad_fits_are_typed_errors() {
    let data = dataset();
    let opts = ReportOptions::default();
    let mut f = fits(&data);
    f[0].sample = "nope".into();
    assert!(matches!(
        render_report(&data, &f, &opts),
        Err(ReportError::UnknownSample { .. })
    ));

    let mut f = fits(&data);
    f[1] = f[0].clone();
    assert!(matches!(
        render_report(&data, &f, &opts),
        Err(ReportError::DuplicateFit { .. })
    ));

    let mut f = fits(&data);
    f[2].n_points -= 1;
    assert!(matches!(
        render_report(&data, &f, &opts),
        Err(ReportError::PointCount { .. })
    ));

    for bad in [
        |f: &mut FitResult| f.model.alpha = -0.1,
        |f: &mut FitResult| f.model.alpha = f64::NAN,
        |f: &mut FitResult| f.model.scale = 0.0,
        |f: &mut FitResult| f.model.gamma = Gamma::Free(1.2),
        |f: &mut FitResult| f.model.gamma = Gamma::NotApplicable,
        |f: &mut FitResult| f.model.eta = 1.0,
    ] {
        // A stored model that cannot be evaluated is named, its panel shows the data alone and
        // the other fits are still drawn.
        let mut f = fits(&data);
        bad(&mut f[3]);
        let report = render_report(&data, &f, &opts).unwrap();
        let label = f[3].label();
        let named: Vec<_> = report
            .warnings
            .iter()
            .filter(|w| w.contains(&label) && w.contains("cannot be evaluated"))
            .collect();
        assert_eq!(named.len(), 1, "{:?}", report.warnings);
        let md = String::from_utf8(
            report
                .files
                .iter()
                .find(|x| x.name == "fits.md")
                .unwrap()
                .contents
                .clone(),
        )
        .unwrap();
        assert!(md.contains("## Not drawn") && md.contains(&label), "{md}");
        let sample = &f[3].sample;
        let rows = md
            .lines()
            .filter(|l| l.starts_with(&format!("| {sample} |")))
            .count();
        assert_eq!(rows, 3, "{md}");
        let good = render_report(&data, &fits(&data), &opts).unwrap();
        assert!(
            !good
                .warnings
                .iter()
                .any(|w| w.contains("cannot be evaluated"))
        );
    }

    let empty = Dataset {
        source: "x".into(),
        samples: vec![],
    };
    assert!(matches!(
        render_report(&empty, &[], &opts),
        Err(ReportError::NoSamples)
    ));
}

/// Samples whose names map to one file name (`a b` and `a_b`; `Frosted` and `frosted`, one
/// file where names ignore case) are all reported: the later one's files get a suffix, and
/// fits.md links each sample's figures under the sample's own name.
#[test]
fn samples_of_one_file_name_get_files_of_their_own() {
    let data = dataset();
    let named = |names: [&str; 4]| Dataset {
        source: "x".into(),
        samples: names
            .iter()
            .enumerate()
            .map(|(k, &name)| Sample {
                name: name.into(),
                ..data.samples[k % 2].clone()
            })
            .collect(),
    };
    let clash = named(["a b", "a_b", "Frosted", "frosted"]);
    let report = render_report(&clash, &[], &ReportOptions::default()).unwrap();
    for stem in ["a_b", "a_b-2", "Frosted", "frosted-2"] {
        for kind in ["fits", "residuals"] {
            for ext in ["svg", "png"] {
                let name = format!("{stem}-{kind}.{ext}");
                assert!(report.file(&name).is_some(), "no {name}");
            }
        }
    }
    assert_eq!(report.files.len(), 4 * 4 + 4 + 1);
    let md = svg(&report, "fits.md");
    for (sample, stem) in [
        ("a b", "a_b"),
        ("a_b", "a_b-2"),
        ("Frosted", "Frosted"),
        ("frosted", "frosted-2"),
    ] {
        let line =
            format!("- {sample}: [fits]({stem}-fits.png), [residuals]({stem}-residuals.png)");
        assert!(md.lines().any(|l| l == line), "{line} not in {md}");
    }
    // Each figure is titled with its own sample's name.
    for (file, own, other) in [
        ("a_b-fits.svg", "a b", "a_b"),
        ("a_b-2-fits.svg", "a_b", "a b"),
        ("frosted-2-fits.svg", "frosted", "Frosted"),
    ] {
        let text = svg(&report, file);
        assert!(
            text.contains(&format!("{own}: measured transmission"))
                && !text.contains(&format!("{other}: measured transmission")),
            "{file}"
        );
    }
}

/// The stems of `file_stems`: a sample's own stem unless an earlier sample took it (in any
/// case), else the first free `-2`, `-3`, ... that is no sample's own stem either.
#[test]
fn file_stems_are_distinct_ignoring_case() {
    assert_eq!(file_stems(["a", "b"]), ["a", "b"]);
    assert_eq!(file_stems(["a b", "a_b", "a/b"]), ["a_b", "a_b-2", "a_b-3"]);
    assert_eq!(
        file_stems(["Frosted", "frosted", "FROSTED"]),
        ["Frosted", "frosted-2", "FROSTED-3"]
    );
    // A sample literally named like a suffix keeps its name; the suffix skips it, in any case
    // and wherever that sample comes.
    assert_eq!(file_stems(["a", "A", "a-2"]), ["a", "A-3", "a-2"]);
    assert_eq!(file_stems(["a-2", "a", "a"]), ["a-2", "a", "a-3"]);
    assert_eq!(
        file_stems(["a", "a", "A-2", "a-3"]),
        ["a", "a-4", "A-2", "a-3"]
    );
    // A suffix already given is not given twice.
    assert_eq!(file_stems(["x", "x", "x"]), ["x", "x-2", "x-3"]);
    // The unnamed sample's stem is `sample`, which a sample of that name then shares.
    assert_eq!(file_stems(["", "sample"]), ["sample", "sample-2"]);
    let stems = file_stems(["a b", "A_B", "a_b-2", "a.b", "a?b", "A?B"]);
    let mut lower: Vec<String> = stems.iter().map(|s| s.to_ascii_lowercase()).collect();
    lower.sort();
    lower.dedup();
    assert_eq!(lower.len(), stems.len(), "{stems:?}");
}

#[test]
fn file_stems_are_safe() {
    assert_eq!(file_stem("frosted"), "frosted");
    assert_eq!(file_stem("ground glass/2"), "ground_glass_2");
    assert_eq!(file_stem(""), "sample");
    assert_eq!(file_stem("../x"), ".._x");
    // A 300-character name had made 'File name too long' after part of the report was
    // written: stems keep the first 100 characters, as export's file names do.
    assert_eq!(file_stem(&"ü".repeat(300)), "_".repeat(100));
}

#[test]
fn clip_below_cuts_at_the_floor_in_log_space() {
    let pts = [
        (0.0, 1.0),
        (1.0, 1e-2),
        (2.0, 1e-6),
        (3.0, 1e-2),
        (4.0, 1e-1),
    ];
    let pieces = clip_below(&pts, 1e-3);
    assert_eq!(pieces.len(), 2);
    // ln y is linear between 1e-2 and 1e-6: 1e-3 is a quarter of the way.
    assert_eq!(pieces[0].len(), 3);
    approx::assert_relative_eq!(pieces[0][2].0, 1.25, epsilon = 1e-12);
    assert_eq!(pieces[0][2].1, 1e-3);
    approx::assert_relative_eq!(pieces[1][0].0, 2.75, epsilon = 1e-12);
    assert_eq!(&pieces[1][1..], &pts[3..]);
    assert_eq!(clip_below(&pts, 10.0), Vec::<Vec<(f64, f64)>>::new());
    assert_eq!(clip_below(&pts, 1e-9), vec![pts.to_vec()]);
}

#[test]
fn ticks_are_short_and_never_negative_zero() {
    use stfit_report::fmt_tick;
    assert_eq!(fmt_tick(-1e-17, 1.2), "0");
    assert_eq!(fmt_tick(0.7000000000000001, 1.2), "0.7");
    assert_eq!(fmt_tick(0.30000000000000004, 3.2), "0.3");
    assert_eq!(fmt_tick(-0.4, 1.2), "-0.4");
    assert_eq!(fmt_tick(2.0, 3.2), "2");
    assert_eq!(fmt_tick(0.0125, 0.05), "0.0125");
    assert_eq!(fmt_tick(25000.0, 50000.0), "25000");
}

#[test]
fn fmt_sig_formats() {
    assert_eq!(fmt_sig(0.123456, 4), "0.1235");
    assert_eq!(fmt_sig(3.0, 4), "3.000");
    assert_eq!(fmt_sig(1234.5, 3), "1234");
    assert_eq!(fmt_sig(0.0, 3), "0");
    assert_eq!(fmt_sig(1.5e-5, 2), "0.000015");
    assert_eq!(fmt_sig(1.5e-6, 2), "1.5e-6");
    assert_eq!(fmt_sig(f64::NAN, 2), "NaN");
}

#[test]
fn an_unnamed_sample_gets_a_file_name_and_a_title() {
    let data = Dataset {
        source: PathBuf::from("x"),
        samples: vec![synth_sample("", params(ModelKind::Ggx, 0.3, 0.0, 1.0), 0.0)],
    };
    let f = vec![fit(
        &data.samples[0],
        params(ModelKind::Ggx, 0.3, 0.0, 1.0),
        false,
    )];
    let report = render_report(&data, &f, &ReportOptions::default()).unwrap();
    assert!(report.warnings.is_empty());
    assert!(svg(&report, "sample-fits.svg").contains("(unnamed): measured transmission"));
    assert!(svg(&report, "overview.svg").contains("(unnamed) · GGX"));
    // The exact model has zero residual everywhere.
    assert!(
        svg(&report, "fits.md")
            .contains("| (unnamed) | GGX | single scattering, separable masking, sqrt loss | 0.3000 ± 0.0010 | - | 1.510 (fixed) | 1.000 ± 0.0040 | **0** |")
    );
}

#[test]
fn points_of_weight_zero_are_drawn_hollow_and_left_out_of_the_rmse() {
    let truth = params(ModelKind::StudentT, 0.3, 2.2, 1.0);
    let mut sample = synth_sample("weighted", truth, 0.0);
    // Stray light on a few points, excluded from the fit by weight 0.
    for m in sample.points.iter_mut().step_by(10) {
        m.value += 0.05;
        m.weight = 0.0;
    }
    let fitted = sample.points.iter().filter(|m| m.weight > 0.0).count();
    let mut f = fit(&sample, truth, false);
    f.n_points = fitted;
    f.rmse_sqrt_l = 0.0;
    let data = Dataset {
        source: PathBuf::from("x"),
        samples: vec![sample],
    };
    let dir = out_dir("weights");
    let report =
        stfit_report::write_report(&data, &[f.clone()], &dir, &ReportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert!(svg(&report, "weighted-fits.svg").contains("weight 0, not fitted"));
    // A fit that counted every point belongs to other data.
    f.n_points = data.samples[0].points.len();
    assert!(matches!(
        render_report(&data, &[f], &ReportOptions::default()),
        Err(ReportError::PointCount { .. })
    ));
}

#[test]
fn stored_fits_round_trip_every_float_exactly() {
    // serde_json parses floats exactly only with its `float_roundtrip` feature; without it a
    // report from stored fits can differ from one that fits first in the last bit.
    let data = dataset();
    let template = fits(&data)[0].clone();
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let many: Vec<FitResult> = (0..2000)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let v = f64::from_bits((x >> 12) | 0x3FF0_0000_0000_0000) - 1.0;
            FitResult {
                model: Model {
                    alpha: v,
                    scale: v * 1e4,
                    ..template.model
                },
                rmse_sqrt_l: v * 1e-3,
                ..template.clone()
            }
        })
        .collect();
    let json = FitsFile::new(many.clone()).to_json();
    assert_eq!(FitsFile::from_json("test", &json).unwrap().fits, many);
}

#[test]
fn fits_of_the_fitting_engine_are_reproduced_without_warnings() {
    // The report's rmse, recomputed from the data and the fitted parameters, agrees with the
    // one the fitting engine stores, so its model curves are the fitted ones.
    let data = dataset();
    let mut all = Vec::new();
    for s in &data.samples {
        all.extend(stfit_fit::fit_all(s, &stfit_fit::FitOptions::default()).unwrap());
    }
    assert_eq!(all.len(), 8);
    let report = render_report(&data, &all, &ReportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let fig = svg(&report, "ground_glass-fits.svg");
    assert_eq!(fig.matches("not fitted").count(), 0);
}

/// A general sample (reflection and transmission, light from both sides, out of plane) gets
/// its plane-of-incidence and polar-residual figures, SVG and PNG, no overview, and tables
/// that name what was measured (the BSDF) and the fitted eta; the fitted models reproduce
/// their stored rmse.
#[test]
fn general_samples_get_plane_and_polar_figures() {
    let truth = Model {
        eta: 1.45,
        ..params(ModelKind::Ggx, 0.3, 0.0, 1.2)
    };
    let sample = stfit_fit::SynthSpec {
        model: truth,
        grid: stfit_fit::Grid::spherical_default(),
        noise: 0.02,
        seed: 3,
        name: "general glass".into(),
    }
    .sample()
    .unwrap();
    let opts = stfit_fit::FitOptions {
        eta: stfit_fit::Parameter::Free,
        ..Default::default()
    };
    let fits = stfit_fit::fit_all(&sample, &opts).unwrap();
    assert!(fits.iter().all(|f| f.measured == stfit_fit::Measured::Bsdf));
    let data = Dataset {
        source: PathBuf::from("general"),
        samples: vec![sample],
    };
    let report = render_report(&data, &fits, &ReportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let mut names: Vec<&str> = report.files.iter().map(|f| f.name.as_str()).collect();
    names.sort_unstable();
    assert_eq!(
        names,
        [
            "fits.md",
            "general_glass-plane.png",
            "general_glass-plane.svg",
            "general_glass-polar.png",
            "general_glass-polar.svg",
            "ndf.png",
            "ndf.svg",
        ]
    );
    let plane = svg(&report, "general_glass-plane.svg");
    for text in [
        "GGX",
        "Student-T, γ free",
        "rmse √BSDF",
        "η = 1.4",
        "θi = 150°",
    ] {
        assert!(plane.contains(text), "plane figure lacks {text:?}");
    }
    // Light from inside (theta_i 120, 150) is on the side |x| > 90: the title says which side
    // |x| < 90 is, not that it is the light's.
    assert!(
        plane.contains("|x| &lt; 90 outside the glass")
            || plane.contains("|x| < 90 outside the glass"),
        "the plane figure's title does not say |x| < 90 is outside"
    );
    assert!(!plane.contains("on the side of the light"));
    let polar = svg(&report, "general_glass-polar.svg");
    assert!(polar.contains("residuals"), "polar figure has no title");
    for name in ["general_glass-plane.png", "general_glass-polar.png"] {
        let (w, h, _) = png_size(&report.file(name).unwrap().contents);
        assert!(w >= 800 && h >= 600, "{name}: {w} x {h}");
    }
    let md = String::from_utf8(report.file("fits.md").unwrap().contents.clone()).unwrap();
    assert!(md.contains("| rmse sqrt(BSDF) |"), "{md}");
    assert!(md.contains("`bsdf = scale * f`"), "{md}");
    let ggx_row = md
        .lines()
        .find(|l| l.starts_with("| general glass | GGX |"))
        .expect("a GGX row");
    let eta_cell = ggx_row.split(" | ").nth(5).unwrap();
    let eta: f64 = eta_cell.split(" ± ").next().unwrap().parse().unwrap();
    assert!(
        (eta - 1.45).abs() < 0.005 && eta_cell.contains(" ± "),
        "{ggx_row}"
    );
}

/// The figure titles name the scattering orders of the fits drawn: an all-orders fit is not
/// called a single-scattering fit.
#[test]
fn figure_titles_name_the_orders_of_the_fits() {
    let truth = params(ModelKind::Ggx, 0.3, 0.0, 1.0);
    let sample = synth_sample("all orders", truth, 0.02);
    let all = Model {
        masking: stfit_fit::Masking::Correlated,
        orders: stfit_fit::ScatteringOrders::All,
        walks: Some(2000),
        seed: Some(1),
        ..truth
    };
    let stored = vec![fit(&sample, all, false)];
    let data = Dataset {
        source: PathBuf::from("synthetic"),
        samples: vec![sample],
    };
    let report = render_report(&data, &stored, &ReportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    for name in ["all_orders-fits.svg", "overview.svg"] {
        let text = svg(&report, name);
        assert!(
            text.contains("all-orders fits"),
            "{name} does not say all orders"
        );
        assert!(
            !text.contains("single-scattering"),
            "{name} says single scattering"
        );
    }
    let single = dataset();
    let report = render_report(&single, &fits(&single), &ReportOptions::default()).unwrap();
    assert!(svg(&report, "overview.svg").contains("single-scattering fits"));
}

/// The time the report's walks will take is estimated from those walks: nothing for
/// single-scattering fits, some time for an all-orders fit, for a hand-edited 1e9 walks per
/// incident direction far beyond the 10 s that a note announces, and for fits that the report
/// refuses nothing.
#[test]
fn the_walks_of_all_orders_fits_are_timed_before_they_run() {
    let opts = ReportOptions::default();
    let single = dataset();
    assert_eq!(walk_seconds(&single, &fits(&single), &opts), 0.0);
    let truth = params(ModelKind::Ggx, 0.3, 0.0, 1.0);
    let sample = synth_sample("all orders", truth, 0.02);
    let all = |walks| Model {
        masking: stfit_fit::Masking::Correlated,
        orders: stfit_fit::ScatteringOrders::All,
        walks: Some(walks),
        seed: Some(1),
        ..truth
    };
    let data = Dataset {
        source: PathBuf::from("synthetic"),
        samples: vec![sample.clone()],
    };
    let few = fit(&sample, all(2000), false);
    let seconds = walk_seconds(&data, std::slice::from_ref(&few), &opts);
    assert!(seconds > 0.0 && seconds < 10.0, "{seconds}");
    // Hand-edited, as in a fits file: the stored rmse is that of 2000 walks.
    let mut many = few.clone();
    many.model.walks = Some(1_000_000_000);
    let seconds = walk_seconds(&data, std::slice::from_ref(&many), &opts);
    assert!(seconds > 100.0, "{seconds}");
    let mut foreign = many;
    foreign.n_points += 1;
    assert_eq!(walk_seconds(&data, &[foreign], &opts), 0.0);
}

/// A sample that mixes in-plane and general points (files of both forms merged by name, one
/// scale fitted to all) is drawn in both forms, each figure with its own points, and its
/// stored rmse, over all its points, is reproduced without a warning.
#[test]
fn a_sample_mixing_in_plane_and_general_points_is_drawn_whole() {
    let truth = params(ModelKind::Ggx, 0.3, 0.0, 1.0);
    let mut sample = synth_sample("mixed", truth, 0.03);
    let general = stfit_fit::SynthSpec {
        model: truth,
        grid: stfit_fit::Grid::spherical_default(),
        noise: 0.02,
        seed: 3,
        name: "mixed".into(),
    }
    .sample()
    .unwrap();
    sample.points.extend(general.points);
    let stored = stfit_fit::fit_all(&sample, &Default::default()).unwrap();
    assert!(
        stored
            .iter()
            .all(|f| f.measured == stfit_fit::Measured::Both)
    );
    let data = Dataset {
        source: PathBuf::from("mixed"),
        samples: vec![sample],
    };
    let report = render_report(&data, &stored, &ReportOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    for name in [
        "mixed-fits.svg",
        "mixed-residuals.svg",
        "mixed-plane.svg",
        "mixed-polar.svg",
        "overview.svg",
        "ndf.svg",
    ] {
        assert!(report.file(name).is_some(), "no {name}");
    }
    // The 300 in-plane points are drawn in each of the four panels of the fits figure.
    let fits_svg = svg(&report, "mixed-fits.svg");
    assert!(fits_svg.matches("<circle").count() >= 4 * 300);
    let md = String::from_utf8(report.file("fits.md").unwrap().contents.clone()).unwrap();
    assert_eq!(md.lines().filter(|l| l.starts_with("| mixed |")).count(), 4);
    assert_eq!(md.lines().filter(|l| l.starts_with("- mixed: ")).count(), 1);
}

/// Two incident directions at the same `theta_i` and other azimuths are told apart in the plane
/// figure: each has its own colour, as its legend entry says.
#[test]
fn incidences_at_one_theta_and_two_azimuths_get_two_colours() {
    let truth = params(ModelKind::Ggx, 0.3, 0.0, 1.0);
    let sample = stfit_fit::SynthSpec {
        model: truth,
        grid: stfit_fit::Grid::Spherical {
            theta_i_deg: vec![30.0],
            phi_i_deg: vec![0.0, 90.0],
            theta_o_deg: (0..18).map(|k| 5.0 + 10.0 * k as f64).collect(),
            phi_o_deg: (0..18).map(|k| 20.0 * k as f64).collect(),
        },
        noise: 0.0,
        seed: 1,
        name: "azimuths".into(),
    }
    .sample()
    .unwrap();
    let stored = vec![fit(&sample, truth, false)];
    let data = Dataset {
        source: PathBuf::from("azimuths"),
        samples: vec![sample],
    };
    let report = render_report(&data, &stored, &ReportOptions::default()).unwrap();
    let plane = svg(&report, "azimuths-plane.svg");
    // The legend's line glyphs (stroke width 3): grey for "model", then one per incidence.
    let colours: Vec<&str> = plane
        .split("<polyline")
        .skip(1)
        .filter(|e| e.contains(r#"stroke-width="3""#))
        .filter_map(|e| e.split(r#"stroke=""#).nth(1)?.split('"').next())
        .filter(|c| *c != "#555555")
        .collect();
    assert_eq!(colours.len(), 2, "{colours:?}");
    assert_ne!(
        colours[0], colours[1],
        "both incidences are drawn in {}",
        colours[0]
    );
}
