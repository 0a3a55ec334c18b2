//! End-to-end tests of `stfit eval`: output matches the library; bad input and bad parameters
//! give a non-zero exit and an error naming the problem, never a panic.

use std::io::Write;
use std::process::{Command, Stdio};

use stfit_core::Vec3;
use stfit_core::bsdf::{Masking, RoughDielectric};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};

struct Output {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn run(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_stfit"))
        .arg("eval")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run stfit");
    // The process may exit before reading everything (bad parameters): ignore broken pipes.
    let _ = child.stdin.take().unwrap().write_all(stdin.as_bytes());
    let out = child.wait_with_output().unwrap();
    let o = Output {
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    };
    assert!(!o.stderr.contains("panicked"), "panic: {}", o.stderr);
    o
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
                let mut lines = out.stdout.lines();
                assert_eq!(lines.next(), Some(format!("{HEADER},f_cos").as_str()));
                let mut nonzero = 0;
                for (row, (wi, wo)) in lines.zip(&pairs) {
                    let fields: Vec<f64> = row.split(',').map(|f| f.parse().unwrap()).collect();
                    assert_eq!(fields.len(), 7, "{row}");
                    assert_eq!(fields[..6], [wi.x, wi.y, wi.z, wo.x, wo.y, wo.z]);
                    let want = bsdf.f_cos(*wi, *wo);
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

/// Each bad input fails with exit code 1 and a message naming the line (and field).
#[test]
fn bad_rows_name_their_line() {
    let good = "0,0,1,0,0,-1";
    let cases: [(&str, &[&str]); 9] = [
        ("0,0,x,0,0,-1", &["line 3", "field wi_z", "\"x\""]),
        ("0,0,1,0,0", &["line 3", "expected 6 fields, found 5"]),
        ("0,0,1,0,0,-1,7", &["line 3", "expected 6 fields, found 7"]),
        ("0,0,1,0,,-1", &["line 3", "field wo_y"]),
        ("0,0,1.1,0,0,-1", &["line 3", "wi", "not a unit vector"]),
        ("0,0,1,0.6,0,-0.6", &["line 3", "wo", "not a unit vector"]),
        (
            "0,0,1,0,0,-1.000002",
            &["line 3", "wo", "not a unit vector"],
        ),
        ("0,0,inf,0,0,-1", &["line 3", "field wi_z", "not finite"]),
        ("NaN,0,1,0,0,-1", &["line 3", "field wi_x", "not finite"]),
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
        ("", "empty input"),
        ("wi_x,wi_y,wi_z,wo_x,wo_y\n0,0,1,0,0\n", "lacks column wo_z"),
        ("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,wo_z\n", "wo_z appears twice"),
        (
            "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,f_cos\n",
            "already has a column f_cos",
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
            "alpha must be > 0",
        ),
        (
            &["--ndf", "ggx", "--alpha", "-1", "--eta", "1.5"],
            "alpha must be > 0",
        ),
        (
            &["--ndf", "beckmann", "--alpha", "nan", "--eta", "1.5"],
            "alpha must be finite",
        ),
        (
            &["--ndf", "ggx", "--alpha", "0.3", "--eta", "1"],
            "eta must be > 0 and != 1",
        ),
        (
            &["--ndf", "ggx", "--alpha", "0.3", "--eta", "-2"],
            "eta must be > 0 and != 1",
        ),
        (
            &["--ndf", "ggx", "--alpha", "0.3", "--eta", "inf"],
            "eta must be finite",
        ),
        (
            &["--ndf", "student-t", "--alpha", "0.3", "--eta", "1.5"],
            "requires --gamma",
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
            "gamma must be > 3/2",
        ),
        (
            &[
                "--ndf", "ggx", "--alpha", "0.3", "--gamma", "3", "--eta", "1.5",
            ],
            "--gamma is only valid with --ndf student-t",
        ),
    ];
    for (args, needle) in cases {
        let out = run(args, &text);
        assert_eq!(out.code, Some(1), "{args:?}: {}", out.stderr);
        assert!(out.stderr.contains(needle), "{args:?}: {}", out.stderr);
        assert!(out.stdout.is_empty(), "{args:?}: {}", out.stdout);
    }
    // Usage errors are clap's: exit code 2.
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
