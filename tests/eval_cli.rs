//! End-to-end tests of `stfit eval`: output matches the library; bad input and bad parameters
//! give a non-zero exit and an error naming the problem, never a panic.

use stfit_test_support::{Cli, Run};

use stfit_core::Vec3;
use stfit_core::bsdf::{AnalyticBsdf, Masking, RoughDielectric};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT, TabulatedStudentT};

fn run(args: &[&str], stdin: &str) -> Run {
    let mut all = vec!["eval"];
    all.extend_from_slice(args);
    let out = Cli::new(env!("CARGO_BIN_EXE_stfit")).run_with_stdin(&all, stdin);
    assert!(!out.stderr.contains("panicked"), "panic: {}", out.stderr);
    out
}

const HEADER: &str = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z";

/// Direction pairs covering reflection and transmission from both sides, normal incidence,
/// grazing and unreachable configurations.
fn pairs() -> Vec<(Vec3, Vec3)> {
    let d = |theta_deg: f64, phi: f64| {
        stfit_core::math::spherical_direction(theta_deg.to_radians(), phi)
    };
    let mut v = vec![
        (Vec3::z(), Vec3::z()),
        (Vec3::z(), -Vec3::z()),
        (-Vec3::z(), Vec3::z()),
        (d(90.0, 0.0), d(120.0, 3.0)),
    ];
    for (ti, to) in [
        (10.0, 170.0),
        (60.0, 150.0),
        (60.0, 60.0),
        (80.0, 100.0),
        (130.0, 40.0),
        (160.0, 150.0),
    ] {
        for phi in [0.0, 1.0, std::f64::consts::PI] {
            v.push((d(ti, 0.3), d(to, 0.3 + phi)));
        }
    }
    v
}

fn input(pairs: &[(Vec3, Vec3)]) -> String {
    let mut s = format!("{HEADER}\n");
    for (wi, wo) in pairs {
        s += &format!("{},{},{},{},{},{}\n", wi.x, wi.y, wi.z, wo.x, wo.y, wo.z);
    }
    s
}

#[test]
fn output_matches_the_library() {
    let pairs = pairs();
    let text = input(&pairs);
    let configs: [(&[&str], AnyNdf); 3] = [
        (
            &["--ndf", "beckmann", "--alpha", "0.3"],
            Beckmann::new(0.3).unwrap().into(),
        ),
        (
            &["--ndf", "ggx", "--alpha", "0.45"],
            Ggx::new(0.45).unwrap().into(),
        ),
        (
            &["--ndf", "student-t", "--alpha", "0.45", "--gamma", "3"],
            StudentT::new(0.45, 3.0).unwrap().into(),
        ),
    ];
    for (ndf_args, ndf) in configs {
        for (masking_args, masking) in [
            (&[][..], Masking::Separable),
            (&["--masking", "separable"][..], Masking::Separable),
            (&["--masking", "correlated"][..], Masking::Correlated),
        ] {
            for eta in [1.51, 0.7] {
                let eta_text = eta.to_string();
                let mut args = ndf_args.to_vec();
                args.extend_from_slice(masking_args);
                args.extend_from_slice(&["--eta", &eta_text]);
                let out = run(&args, &text);
                assert_eq!(out.code, Some(0), "{args:?}: {}", out.stderr);
                let bsdf = RoughDielectric::new(ndf, eta, masking).unwrap();
                // A Student-T is evaluated through its interpolated Lambda fractions.
                let want_f_cos = |wi: Vec3, wo: Vec3| match ndf {
                    AnyNdf::StudentT(st) => bsdf.with_ndf(TabulatedStudentT::new(st)).f_cos(wi, wo),
                    _ => bsdf.f_cos(wi, wo),
                };
                let mut lines = out.stdout.lines();
                assert_eq!(lines.next(), Some(format!("{HEADER},f_cos").as_str()));
                let mut nonzero = 0;
                for (row, (wi, wo)) in lines.zip(&pairs) {
                    let fields: Vec<f64> = row.split(',').map(|f| f.parse().unwrap()).collect();
                    assert_eq!(fields.len(), 7, "{row}");
                    assert_eq!(fields[..6], [wi.x, wi.y, wi.z, wo.x, wo.y, wo.z]);
                    let want = want_f_cos(*wi, *wo);
                    assert_eq!(fields[6], want, "{args:?}: {row}");
                    nonzero += usize::from(want > 0.0);
                }
                assert_eq!(out.stdout.lines().count(), pairs.len() + 1);
                assert!(
                    nonzero > pairs.len() / 2,
                    "{args:?}: only {nonzero} non-zero"
                );
            }
        }
    }
}

const GGX: [&str; 6] = ["--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5"];

/// Student-T at many pairs: `stfit eval` prints the values of the NDF's [`TabulatedStudentT`],
/// the form the Python package's `RoughDielectric.eval` uses, so the two agree digit for digit
/// (with the exact fractions about 1 value in 40 differed in its last digits), and within a
/// few ulps of the exact fractions.
#[test]
fn student_t_values_are_those_of_the_tabulated_fractions() {
    let mut pairs = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let ti = (2.0 + 4.4 * f64::from(i)).to_radians();
            let to = (1.0 + 4.45 * f64::from(j)).to_radians();
            let wi = stfit_core::math::spherical_direction(ti, 0.2);
            let wo = stfit_core::math::spherical_direction(to, 0.2 + 0.13 * f64::from(i + j));
            pairs.push((wi, wo));
        }
    }
    let text = input(&pairs);
    for (gamma, alpha) in [(1.6, 0.05), (2.8, 0.7), (3.0, 0.4)] {
        let st = StudentT::new(alpha, gamma).unwrap();
        for (masking, name) in [
            (Masking::Separable, "separable"),
            (Masking::Correlated, "correlated"),
        ] {
            let (g, a) = (gamma.to_string(), alpha.to_string());
            let args = [
                "--ndf",
                "student-t",
                "--alpha",
                &a,
                "--gamma",
                &g,
                "--eta",
                "1.5",
                "--masking",
                name,
            ];
            let out = run(&args, &text);
            assert_eq!(out.code, Some(0), "{args:?}: {}", out.stderr);
            let exact = RoughDielectric::new(AnyNdf::from(st), 1.5, masking).unwrap();
            let fast = exact.with_ndf(TabulatedStudentT::new(st));
            for (row, (wi, wo)) in out.stdout.lines().skip(1).zip(&pairs) {
                let got: f64 = row.rsplit(',').next().unwrap().parse().unwrap();
                assert_eq!(got, fast.f_cos(*wi, *wo), "{args:?}: {row}");
                let e = exact.f_cos(*wi, *wo);
                assert!(
                    (got - e).abs() <= 1e-13 * e.abs(),
                    "{args:?}: {row}: exact {e}"
                );
            }
        }
    }
}

/// Each bad input fails with exit code 1 and a message naming the line and the column, in the
/// format of every stfit input (`<file>:<line>: column '<col>': ...`).
#[test]
fn bad_rows_name_their_line() {
    let good = "0,0,1,0,0,-1";
    let cases: [(&str, &[&str]); 9] = [
        (
            "0,0,x,0,0,-1",
            &["<stdin>:3", "column 'wi_z'", "'x' is not a number"],
        ),
        (
            "0,0,1,0,0",
            &[
                "<stdin>:3",
                "column 'wo_z'",
                "the row has 5 fields, the header 6",
            ],
        ),
        (
            "0,0,1,0,0,-1,7",
            &[
                "<stdin>:3",
                "column 'extra field 7'",
                "the row has 7 fields",
            ],
        ),
        (
            "0,0,1,0,,-1",
            &["<stdin>:3", "column 'wo_y'", "empty value"],
        ),
        (
            "0,0,1.1,0,0,-1",
            &["<stdin>:3", "wi_x, wi_y, wi_z", "not a unit vector"],
        ),
        (
            "0,0,1,0.6,0,-0.6",
            &["<stdin>:3", "wo_x, wo_y, wo_z", "not a unit vector"],
        ),
        (
            "0,0,1,0,0,-1.000002",
            &["<stdin>:3", "wo_x, wo_y, wo_z", "not a unit vector"],
        ),
        (
            "0,0,inf,0,0,-1",
            &["<stdin>:3", "column 'wi_z'", "not a finite number"],
        ),
        (
            "NaN,0,1,0,0,-1",
            &["<stdin>:3", "column 'wi_x'", "not a finite number"],
        ),
    ];
    for (row, needles) in cases {
        let out = run(&GGX, &format!("{HEADER}\n{good}\n{row}\n{good}\n"));
        assert_eq!(out.code, Some(1), "{row}: {}", out.stderr);
        assert!(out.stderr.starts_with("error: "), "{row}: {}", out.stderr);
        assert!(
            out.stdout.is_empty(),
            "{row}: partial output {}",
            out.stdout
        );
        for needle in needles {
            assert!(
                out.stderr.contains(needle),
                "{row}: {:?} lacks {needle:?}",
                out.stderr
            );
        }
    }
    // A direction within the tolerance of unit length is accepted as is.
    let out = run(&GGX, &format!("{HEADER}\n0,0,1.0000005,0,0,-1\n"));
    assert_eq!(out.code, Some(0), "{}", out.stderr);
}

#[test]
fn bad_headers_are_errors() {
    let cases: [(&str, &str); 4] = [
        ("", "the file is empty"),
        (
            "wi_x,wi_y,wi_z,wo_x,wo_y\n0,0,1,0,0\n",
            "column 'wo_z': missing from the header",
        ),
        (
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,wo_z\n",
            "column 'wo_z': appears twice",
        ),
        (
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,f_cos\n",
            "column 'f_cos': is written by stfit",
        ),
    ];
    for (text, needle) in cases {
        let out = run(&GGX, text);
        assert_eq!(out.code, Some(1), "{text:?}: {}", out.stderr);
        assert!(out.stderr.contains(needle), "{text:?}: {}", out.stderr);
    }
}

#[test]
fn invalid_parameters_are_rejected() {
    let text = format!("{HEADER}\n0,0,1,0,0,-1\n");
    let cases: [(&[&str], &str); 9] = [
        (
            &["--ndf", "ggx", "--alpha", "0", "--eta", "1.5"],
            "alpha must be in [1e-8, 100]",
        ),
        (
            &["--ndf", "ggx", "--alpha", "-1", "--eta", "1.5"],
            "alpha must be in [1e-8, 100]",
        ),
        (
            &["--ndf", "beckmann", "--alpha", "nan", "--eta", "1.5"],
            "alpha must be finite",
        ),
        (
            &["--ndf", "ggx", "--alpha", "0.3", "--eta", "1"],
            "eta must be in [0.01, 100]",
        ),
        (
            &["--ndf", "ggx", "--alpha", "0.3", "--eta", "-2"],
            "eta must be in [0.01, 100]",
        ),
        (
            &["--ndf", "ggx", "--alpha", "0.3", "--eta", "inf"],
            "eta must be finite",
        ),
        (
            &["--ndf", "student-t", "--alpha", "0.3", "--eta", "1.5"],
            "--gamma is required for student-t",
        ),
        (
            &[
                "--ndf",
                "student-t",
                "--alpha",
                "0.3",
                "--gamma",
                "1.5",
                "--eta",
                "1.5",
            ],
            "gamma must be in (1.5, 1e15]",
        ),
        (
            &[
                "--ndf", "ggx", "--alpha", "0.3", "--gamma", "3", "--eta", "1.5",
            ],
            "--gamma applies only to student-t",
        ),
    ];
    // Invalid parameters are invalid command-line values: exit code 2.
    for (args, needle) in cases {
        let out = run(args, &text);
        assert_eq!(out.code, Some(2), "{args:?}: {}", out.stderr);
        assert!(out.stderr.contains(needle), "{args:?}: {}", out.stderr);
        assert!(out.stdout.is_empty(), "{args:?}: {}", out.stdout);
    }
    // So are clap's own usage errors.
    for args in [
        &["--ndf", "cauchy", "--alpha", "0.3", "--eta", "1.5"][..],
        &["--ndf", "ggx", "--eta", "1.5"][..],
        &["--ndf", "ggx", "--alpha", "abc", "--eta", "1.5"][..],
        &[
            "--ndf",
            "ggx",
            "--alpha",
            "0.3",
            "--eta",
            "1.5",
            "--masking",
            "none",
        ][..],
    ] {
        let out = run(args, &text);
        assert_eq!(out.code, Some(2), "{args:?}: {}", out.stderr);
        assert!(
            out.stderr.starts_with("error: "),
            "{args:?}: {}",
            out.stderr
        );
    }
}

/// The appended columns (f_cos, f_cos_stderr) of each row of a successful walk run.
fn walk_rows(args: &[&str], input: &str) -> Vec<(f64, f64)> {
    let out = run(args, input);
    assert_eq!(out.code, Some(0), "{args:?}: {}", out.stderr);
    let mut lines = out.stdout.lines();
    assert_eq!(
        lines.next(),
        Some(format!("{HEADER},f_cos,f_cos_stderr").as_str())
    );
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').skip(6).map(|x| x.parse().unwrap()).collect();
            (v[0], v[1])
        })
        .collect()
}

/// `f(a, b) = f(b, a)` for reflection by the null walk on full-sphere NDFs: rows `(a, b)` and
/// `(b, a)` give `f_cos / |wo.z|` equal within 4 standard errors.
#[test]
fn full_sphere_walks_are_reciprocal() {
    let a = Vec3::new(-0.5, 0.1, 0.8).normalize();
    let b = Vec3::new(0.7, -0.3, 0.4).normalize();
    let row = |x: Vec3, y: Vec3| format!("{},{},{},{},{},{}\n", x.x, x.y, x.z, y.x, y.y, y.z);
    let input = format!("{HEADER}\n{}{}", row(a, b), row(b, a));
    let cases: &[&[&str]] = &[
        &["--ndf", "vmf", "--kappa", "3", "--facet", "conductor"],
        &[
            "--ndf",
            "porous",
            "--base",
            "beckmann",
            "--alpha",
            "0.5",
            "--porosity",
            "0.3",
            "--facet",
            "lambertian",
            "--reflectance",
            "0.9",
        ],
        &[
            "--ndf",
            "vmf",
            "--kappa",
            "8",
            "--facet",
            "conductor",
            "--n",
            "1.2",
            "--k",
            "2.5",
            "--orders",
            "multiple",
        ],
    ];
    for case in cases {
        let mut args = vec!["--walk", "null", "--walks", "30000"];
        args.extend_from_slice(case);
        let rows = walk_rows(&args, &input);
        let (fab, sab) = (rows[0].0 / b.z, rows[0].1 / b.z);
        let (fba, sba) = (rows[1].0 / a.z, rows[1].1 / a.z);
        assert!(fab > 0.0 && fba > 0.0, "{case:?}: {rows:?}");
        assert!(
            (fab - fba).abs() <= 4.0 * sab.hypot(sba),
            "{case:?}: f(a,b) {fab} +- {sab}, f(b,a) {fba} +- {sba}"
        );
    }
}

/// The null walk on a height field reproduces the height-field walk, conductor facets.
#[test]
fn null_walk_matches_the_height_field_walk_in_eval() {
    let a = Vec3::new(-0.6, 0.0, 0.8);
    let b = Vec3::new(0.3, 0.4, 0.5f64.sqrt()).normalize();
    let input = format!(
        "{HEADER}\n{},{},{},{},{},{}\n",
        a.x, a.y, a.z, b.x, b.y, b.z
    );
    let common = [
        "--ndf",
        "ggx",
        "--alpha",
        "0.7",
        "--facet",
        "conductor",
        "--orders",
        "all",
        "--walks",
        "40000",
    ];
    let mut null = vec!["--walk", "null"];
    null.extend_from_slice(&common);
    let mut hf = vec!["--walk", "heightfield", "--seed", "5"];
    hf.extend_from_slice(&common);
    let (x, y) = (walk_rows(&null, &input)[0], walk_rows(&hf, &input)[0]);
    assert!((x.0 - y.0).abs() <= 4.0 * x.1.hypot(y.1), "{x:?} vs {y:?}");
}

/// Bad options of the walk are usage errors (exit code 2) that name the option.
#[test]
fn bad_walk_options_are_usage_errors() {
    let input = format!("{HEADER}\n0,0,1,0,0,1\n");
    let cases: &[(&[&str], &str)] = &[
        (
            &["--ndf", "vmf", "--kappa", "3", "--facet", "conductor"],
            "walk null",
        ),
        (
            &["--ndf", "vmf", "--kappa", "3", "--walk", "null"],
            "dielectric",
        ),
        (
            &["--ndf", "vmf", "--walk", "null", "--facet", "conductor"],
            "kappa",
        ),
        (
            &[
                "--ndf",
                "vmf",
                "--kappa",
                "-1",
                "--walk",
                "null",
                "--facet",
                "conductor",
            ],
            "kappa",
        ),
        (
            &[
                "--ndf",
                "porous",
                "--base",
                "ggx",
                "--alpha",
                "0.4",
                "--walk",
                "null",
                "--facet",
                "conductor",
            ],
            "porosity",
        ),
        (
            &[
                "--ndf",
                "porous",
                "--alpha",
                "0.4",
                "--porosity",
                "0.2",
                "--walk",
                "null",
                "--facet",
                "conductor",
            ],
            "base",
        ),
        (
            &[
                "--ndf",
                "ggx",
                "--alpha",
                "0.4",
                "--facet",
                "lambertian",
                "--orders",
                "all",
            ],
            "reflectance",
        ),
        (
            &[
                "--ndf",
                "ggx",
                "--alpha",
                "0.4",
                "--facet",
                "conductor",
                "--eta",
                "1.5",
                "--walk",
                "null",
            ],
            "eta",
        ),
        (
            &[
                "--ndf",
                "vmf",
                "--kappa",
                "3",
                "--walk",
                "null",
                "--facet",
                "conductor",
                "--walks",
                "0",
            ],
            "walks",
        ),
    ];
    for (args, word) in cases {
        let out = run(args, &input);
        assert_eq!(out.code, Some(2), "{args:?}: {}", out.stderr);
        assert!(out.stderr.contains(word), "{args:?}: {}", out.stderr);
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}

/// An empty stdin is bad data (exit 1) whose message shows the header eval reads, not a
/// measurement file's.
#[test]
fn empty_stdin_names_the_pair_header() {
    let out = run(&["--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5"], "");
    let e = out.fails_with(1);
    assert!(e.contains("'wi_x,wi_y,wi_z,wo_x,wo_y,wo_z'"), "{e}");
    assert!(!e.contains("sqrt_L"), "{e}");
}

/// A direction far from unit length names its norm in a few digits: not `inf` where the squares
/// overflow, not `0` where they underflow, not 300 digits.
#[test]
fn not_unit_messages_show_the_norm_briefly() {
    for (row, norm) in [
        ("1e300,0,0,0,0,1", "norm 1e300"),
        ("0,-1e200,0,0,0,1", "norm 1e200"),
        ("1e150,0,0,0,0,1", "norm 1e150"),
        ("1e-300,0,0,0,0,1", "norm 1e-300"),
        ("1.5e308,1.5e308,1.5e308,0,0,1", "norm above 1.8e308"),
    ] {
        let out = run(&GGX, &format!("{HEADER}\n{row}\n"));
        assert_eq!(out.code, Some(1), "{row}: {}", out.stderr);
        assert!(
            out.stderr.contains("<stdin>:2") && out.stderr.contains(norm),
            "{row}: {}",
            out.stderr
        );
        assert!(out.stderr.len() < 200, "{row}: {}", out.stderr);
    }
}

/// A direction whose `z` is subnormal (a unit vector to the tolerance) is refused naming its
/// line and column: the BSDF's `1 / |z|` overflowed, and eval failed with 'row 1: the BSDF
/// value is not finite', naming neither the input nor its line.
#[test]
fn subnormal_z_names_line_and_column() {
    for (row, column) in [
        ("1,0,1e-320,0,0,1", "column 'wi_z'"),
        ("0,0,1,-1,0,-5e-324", "column 'wo_z'"),
        ("1,0,1e-308,0,0,-1", "column 'wi_z'"),
    ] {
        for orders in ["single", "all"] {
            let mut args = GGX.to_vec();
            args.extend(["--orders", orders]);
            if orders == "all" {
                args.extend(["--walks", "100"]);
            }
            let out = run(&args, &format!("{HEADER}\n0,0,1,0,0,-1\n{row}\n"));
            assert_eq!(out.code, Some(1), "{row}: {}", out.stderr);
            for needle in ["<stdin>:3", column, "below the normal range"] {
                assert!(out.stderr.contains(needle), "{row}: {}", out.stderr);
            }
        }
    }
    // The smallest normal z and an exact 0 (the horizon) are evaluated.
    let out = run(
        &GGX,
        &format!("{HEADER}\n1,0,2.2250738585072014e-308,0,0,1\n1,0,0,0,0,1\n"),
    );
    assert_eq!(out.code, Some(0), "{}", out.stderr);
}

/// Directions accepted within the unit tolerance (here typed with 6 decimals: norms 1 - 5.0e-7
/// and 1 - 4.0e-7) are scaled to unit length before evaluation: near-grazing reflection at
/// alpha 1e-4 gives the value of the unit directions, to rounding. Taken as they were, their
/// excess norms tilted the half vector by 5e-5 (half the roughness: the value came out 1.56
/// times too large); with the half vector of the unit directions but the cosines unscaled, the
/// value was still 5.0e-7 off.
#[test]
fn near_unit_directions_are_scaled_to_unit_length() {
    let (wi, wo) = (
        Vec3::new(0.999999, 0.0, 0.001),
        Vec3::new(-0.999999, 0.0, 0.0011),
    );
    let typed = format!("{HEADER}\n0.999999,0,0.001,-0.999999,0,0.0011\n");
    let (ui, uo) = (wi.normalize(), wo.normalize());
    let unit = format!(
        "{HEADER}\n{:?},0,{:?},{:?},0,{:?}\n",
        ui.x, ui.z, uo.x, uo.z
    );
    let value = |stdin: &str| -> f64 {
        let out = run(&["--ndf", "ggx", "--alpha", "1e-4", "--eta", "1.5"], stdin);
        assert_eq!(out.code, Some(0), "{}", out.stderr);
        let row = out.stdout.lines().nth(1).expect("a row").to_owned();
        row.rsplit(',').next().unwrap().parse().unwrap()
    };
    let (a, b) = (value(&typed), value(&unit));
    assert!(b > 0.0 && ((a - b) / b).abs() < 1e-9, "typed {a}, unit {b}");
    // The library itself keeps exactly unit input bit for bit.
    let exact = Vec3::new(0.6, 0.0, 0.8);
    assert_eq!(stfit_core::math::to_unit(exact), exact);
}
