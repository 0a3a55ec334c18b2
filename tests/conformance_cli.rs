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
    assert!(recorded.contains("--phi-o=-170:170:20"), "{recorded}");
    let dir = CaseDir::new("negative-azimuths");
    assert_eq!(shell(&dir, recorded), text.as_bytes(), "{recorded}");
}

/// Runs the command line a synth file records (`# stfit synth ...`, the comment's first line)
/// with `sh -c` in `dir`, the binary under test being `stfit` on the `PATH`; returns its
/// standard output, after checking that it succeeded.
fn shell(dir: &CaseDir, recorded: &str) -> Vec<u8> {
    let command = recorded
        .strip_prefix("# ")
        .filter(|c| c.starts_with("stfit synth "))
        .unwrap_or_else(|| panic!("not a recorded command: {recorded}"));
    let bin = Path::new(env!("CARGO_BIN_EXE_stfit")).parent().unwrap();
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut paths = vec![bin.to_path_buf()];
    paths.extend(std::env::split_paths(&path));
    let out = std::process::Command::new("sh")
        .arg("-c")
        .arg(command)
        .current_dir(dir.path())
        .env("PATH", std::env::join_paths(paths).unwrap())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{command}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// data-format.md: `synth` records "the exact command that made the file": pasted into a POSIX
/// shell it writes the same file, byte for byte. The recorded command had left out `--out`
/// and `--pabopto` and had not quoted a sample name with a space (`--sample my glass`), so it
/// wrote something else, or failed.
#[test]
fn the_recorded_command_writes_the_same_file_again() {
    let dir = CaseDir::new("recorded-command");
    let small = [
        "synth",
        "--model",
        "student-t",
        "--alpha",
        "0.3",
        "--gamma",
        "2.5",
        "--noise",
        "0.05",
        "--theta-i",
        "0, 30",
        "--theta-o",
        "150:210:20",
        "--sample",
        "my 'glass' $HOME",
    ];
    // A CSV file, a relative path with a space and a quote, written in the case folder.
    let run_in = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_stfit"))
            .args(args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    let name = "it's a file.csv";
    let mut args = small.to_vec();
    args.extend(["--seed", "7", "--out", name]);
    run_in(&args);
    let file = dir.join(name);
    let first = std::fs::read(&file).unwrap();
    let text = String::from_utf8(first.clone()).unwrap();
    let recorded = text.lines().next().unwrap();
    assert!(
        recorded.contains(r"--sample 'my '\''glass'\'' $HOME'"),
        "{recorded}"
    );
    std::fs::remove_file(&file).unwrap();
    assert!(shell(&dir, recorded).is_empty());
    assert_eq!(std::fs::read(&file).unwrap(), first, "{recorded}");

    // Two samples appended to one file: the recorded commands, run in order, write it again.
    let both = dir.join("both.csv");
    for seed in ["1", "2"] {
        let mut args = small.to_vec();
        args.extend(["--seed", seed, "--out", "both.csv", "--append"]);
        run_in(&args);
    }
    let first = std::fs::read(&both).unwrap();
    let text = String::from_utf8(first.clone()).unwrap();
    std::fs::remove_file(&both).unwrap();
    let commands: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("# stfit synth"))
        .collect();
    assert_eq!(commands.len(), 2, "{text}");
    for c in &commands {
        assert!(c.ends_with(" --out both.csv --append"), "{c}");
        shell(&dir, c);
    }
    assert_eq!(std::fs::read(&both).unwrap(), first);

    // pab-opto files in a folder, negative azimuths given with `=`.
    let folder = dir.join("pab folder");
    let listing = stfit(&[
        "synth",
        "--grid",
        "general",
        "--model",
        "ggx",
        "--alpha",
        "0.3",
        "--theta-i",
        "30,150",
        "--phi-i=-90",
        "--theta-o",
        "40,140",
        "--phi-o",
        "0:180:90",
        "--sample",
        "a b",
        "--pabopto",
        "dsf",
        "--out",
        p(&folder),
    ])
    .ok()
    .to_owned();
    let files: Vec<(String, Vec<u8>)> = listing
        .lines()
        .map(|f| (f.to_owned(), std::fs::read(f).unwrap()))
        .collect();
    assert_eq!(files.len(), 4, "{listing}");
    let text = String::from_utf8(files[0].1.clone()).unwrap();
    let recorded = text.lines().next().unwrap();
    assert!(recorded.contains("--pabopto dsf --out "), "{recorded}");
    std::fs::remove_dir_all(&folder).unwrap();
    assert_eq!(String::from_utf8(shell(&dir, recorded)).unwrap(), listing);
    for (f, bytes) in &files {
        assert_eq!(&std::fs::read(f).unwrap(), bytes, "{f}");
    }
}
