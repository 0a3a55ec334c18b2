//! End-to-end checks that well-formed files written from the documents alone
//! (`data-format.md`, `fits-format.md`) are read as the documents say.

use std::path::Path;

use stfit_test_support::{CaseDir, Cli, Run};

fn stfit(args: &[&str]) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run(args)
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The data rows of a CSV text (comment lines and the header left out).
fn rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

/// data-format.md, General files: "azimuths that differ by whole turns (360 degrees) are the
/// same direction, exactly". A negative azimuth had been reduced to (-360, 0], whose sine and
/// cosine differ in the last bits from those of its positive twin: `synth` wrote other values
/// at `-330` than at `30`, and a file with every azimuth shifted by -360 fitted to other
/// digits.
#[test]
fn azimuths_a_whole_turn_apart_are_the_same_direction_exactly() {
    let dir = CaseDir::new("conformance-azimuth-turns");
    let synth = |phi_i: &str, phi_o: &str| {
        stfit(&[
            "synth",
            "--grid",
            "general",
            "--model",
            "ggx",
            "--alpha",
            "0.3",
            "--theta-i",
            "30,150",
            &format!("--phi-i={phi_i}"),
            "--theta-o",
            "40,140",
            &format!("--phi-o={phi_o}"),
        ])
        .ok()
        .to_owned()
    };
    let values =
        |text: &str| -> Vec<String> { rows(text).into_iter().map(|r| r[5].clone()).collect() };
    let base = values(&synth("280", "30,100"));
    for (phi_i, phi_o) in [
        ("-80", "30,100"),
        ("280", "-330,-260"),
        ("-440", "390,-620"),
    ] {
        assert_eq!(
            values(&synth(phi_i, phi_o)),
            base,
            "--phi-i {phi_i} --phi-o {phi_o}"
        );
    }

    // A file and its copy with every azimuth a turn lower fit to the same digits.
    let text = synth("0,280", "0:340:20");
    let file = dir.file("turns.csv", &text);
    let shifted: String = text
        .lines()
        .map(|l| {
            let mut f: Vec<String> = l.split(',').map(str::to_owned).collect();
            if !l.starts_with('#') && f[0] != "sample" {
                for k in [2, 4] {
                    f[k] = (f[k].parse::<f64>().unwrap() - 360.0).to_string();
                }
            }
            f.join(",") + "\n"
        })
        .collect();
    let other = dir.file("turns-shifted.csv", shifted);
    let fit = |path: &Path| {
        let json = stfit(&[p(path), "--model", "ggx", "--eta", "free", "--json"])
            .ok()
            .to_owned();
        let mut v: serde_json::Value = serde_json::from_str(&json).unwrap();
        v["fits"][0]["data"] = serde_json::Value::Null;
        v
    };
    assert_eq!(fit(&file), fit(&other));
}

/// data-format.md: azimuths of a general grid are "any finite value", and `synth` "records the
/// exact command that made the file" in its comment lines. `--phi-i -90` and `--phi-o -170:..`
/// were refused by the argument parser as unknown flags (`unexpected argument '-9' found`), and
/// so the command a file records for negative azimuths given as `--phi-o=-170:170:20` did not
/// run again.
#[test]
fn synth_takes_negative_azimuths_and_its_recorded_command_runs_again() {
    let text = stfit(&[
        "synth",
        "--grid",
        "general",
        "--model",
        "ggx",
        "--alpha",
        "0.3",
        "--theta-i",
        "30",
        "--phi-i",
        "-90",
        "--theta-o",
        "40,140",
        "--phi-o",
        "-170:170:20",
    ])
    .ok()
    .to_owned();
    let data = rows(&text);
    assert_eq!(data.len(), 2 * 18, "{text}");
    assert!(data.iter().all(|r| r[2] == "-90"), "{text}");
    assert_eq!(data[0][4], "-170");
    let recorded = text.lines().next().unwrap();
    let args: Vec<&str> = recorded
        .strip_prefix("# stfit ")
        .unwrap()
        .split_whitespace()
        .skip(1)
        .collect();
    assert!(args.contains(&"-170:170:20"), "{recorded}");
    assert_eq!(stfit(&args).ok(), text, "{recorded}");
}
