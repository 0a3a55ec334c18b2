//! `stfit export`: end-to-end runs of the command, its outputs and its errors.

use std::path::PathBuf;
use std::process::Command;

fn stfit(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_stfit"))
        .args(args)
        .output()
        .expect("stfit runs")
}

fn example_fits() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fits/example-fits.json")
        .display()
        .to_string()
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stfit-export-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A pbrt-v4 export of one fit prints one Material line whose roughness is alpha^2 of a GGX
/// fit (pbrt's default remapping).
#[test]
fn pbrt_export_of_a_ggx_fit_prints_roughness_alpha_squared() {
    let out = stfit(&[
        "export",
        &example_fits(),
        "--to",
        "pbrt-v4",
        "--sample",
        "ground",
        "--model",
        "ggx",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let line = text.lines().find(|l| l.starts_with("Material")).unwrap();
    let r: f64 = line
        .split("\"float roughness\" [ ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((r.sqrt() - 0.3600539896675496).abs() < 1e-6, "{line}");
}

/// A Radiance export writes a WINDOW XML file with the four Klems blocks.
#[test]
fn radiance_export_writes_four_klems_blocks() {
    let path = temp("pane.xml");
    let out = stfit(&[
        "export",
        &example_fits(),
        "--to",
        "radiance",
        "--sample",
        "frosted",
        "--model",
        "student-t",
        "--samples",
        "64",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    assert!(xml.contains("is not applied"));
}

/// Invalid command-line values exit with 2, bad data with 1, naming the file and field.
#[test]
fn bad_values_and_bad_files_are_refused_with_the_right_exit_code() {
    let out = stfit(&[
        "export",
        &example_fits(),
        "--to",
        "radiance",
        "--absorption",
        "1.5",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let out = stfit(&[
        "export",
        &example_fits(),
        "--to",
        "mitsuba3",
        "--layer",
        "interface",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let out = stfit(&[
        "export",
        &example_fits(),
        "--to",
        "radiance",
        "--out",
        temp("x.xml").to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "several fits into one radiance file"
    );
    let bad = temp("bad.json");
    std::fs::write(
        &bad,
        r#"{"fits": [{"sample": "s", "model": "ggx", "scale": 1.0}]}"#,
    )
    .unwrap();
    let out = stfit(&["export", bad.to_str().unwrap(), "--to", "pbrt-v4"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.json") && err.contains("fits[0]") && err.contains("`alpha`"),
        "{err}"
    );
    std::fs::write(
        &bad,
        r#"{"fits": [{"sample": "s", "model": "ggx", "alpha": -1, "scale": 1.0}]}"#,
    )
    .unwrap();
    let out = stfit(&["export", bad.to_str().unwrap(), "--to", "pbrt-v4"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("alpha must be > 0"));
}
