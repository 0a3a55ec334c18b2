//! The exit codes of README.md's table, for every command: 0 on success, 2 for invalid
//! command-line values (parameters included), 1 for bad input data; an error never panics and
//! prints nothing on stdout.

use stfit_test_support::{CaseDir, Cli};

fn cli() -> Cli {
    Cli::new(env!("CARGO_BIN_EXE_stfit"))
}

const PAIRS: &str = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,-1\n";
const BAD_PAIRS: &str = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n0,0,1,0,0,x\n";

#[test]
fn every_command_exits_0_on_success_2_on_bad_values_1_on_bad_data() {
    let dir = CaseDir::new("exit-codes");
    let data = dir.file(
        "data.csv",
        "theta_i_deg,theta_o_deg,L\n0,180,1\n0,170,0.5\n0,190,0.5\n30,200,0.4\n",
    );
    let bad = dir.file("bad.csv", "theta_i_deg,theta_o_deg,L\n0,180,-1\n");
    let fits = dir.join("fits.json");
    let bad_fits = dir.file("bad.json", "{\"version\": 1, \"fits\": [{}]}");
    let out = dir.join("report");
    let table = dir.join("table.csv");
    let (d, b, f, bf, o, t) = (
        data.to_str().unwrap(),
        bad.to_str().unwrap(),
        fits.to_str().unwrap(),
        bad_fits.to_str().unwrap(),
        out.to_str().unwrap(),
        table.to_str().unwrap(),
    );
    let ggx = ["--ndf", "ggx", "--alpha", "0.3", "--eta", "1.5"];
    fn with<'a>(head: &[&'a str], tail: &[&'a str]) -> Vec<&'a str> {
        [head, tail].concat()
    }
    let eval = |extra: &[&'static str]| with(&with(&["eval"], &ggx), extra);
    let albedo = |extra: &[&'static str]| {
        with(
            &with(&["albedo", "--theta-i", "30", "--walks", "1000"], &ggx),
            extra,
        )
    };
    let tables = |extra: &[&'static str]| {
        let grid = [
            "tables",
            "--ndf",
            "ggx",
            "--alpha-grid",
            "0.3",
            "--mu-grid",
            "0.5",
            "--eta-grid",
            "1.5",
            "--out",
            t,
        ];
        // A later value of an option replaces the earlier one.
        let mut args = grid.to_vec();
        for pair in extra.chunks(2) {
            match args.iter().position(|a| *a == pair[0]) {
                Some(i) => args[i + 1] = pair[1],
                None => args.extend(pair),
            }
        }
        args
    };
    // (arguments, stdin, expected exit code)
    let cases: Vec<(Vec<&str>, &str, i32)> = vec![
        (vec![d, "--model", "ggx", "--out", f], "", 0),
        (vec![d, "--model", "ggx", "--eta", "1"], "", 2),
        (vec![d, "--model", "ggx", "--gamma", "3"], "", 2),
        (vec![d, "--orders", "multiple"], "", 2),
        (vec![d, "--scattering", "single"], "", 2),
        (vec![b], "", 1),
        (vec!["synth", "--model", "ggx", "--alpha", "0.3"], "", 0),
        (vec!["synth", "--model", "ggx", "--alpha", "-0.3"], "", 2),
        (
            vec![
                "synth",
                "--model",
                "ggx",
                "--alpha",
                "0.3",
                "--theta-i",
                "95",
            ],
            "",
            2,
        ),
        (eval(&[]), PAIRS, 0),
        (eval(&["--orders", "all", "--walks", "100"]), PAIRS, 0),
        (eval(&["--alpha", "0"]), PAIRS, 2),
        (
            eval(&["--orders", "all", "--masking", "separable"]),
            PAIRS,
            2,
        ),
        (eval(&["--samples", "10"]), PAIRS, 2),
        (eval(&[]), BAD_PAIRS, 1),
        (albedo(&[]), "", 0),
        (albedo(&["--theta-i", "90"]), "", 2),
        (albedo(&["--walks", "0"]), "", 2),
        (vec!["report", d, "--fits", f, "--out", o], "", 0),
        (
            vec!["report", d, "--fits", f, "--eta", "1.4", "--out", o],
            "",
            2,
        ),
        (vec!["report", d, "--fits", bf, "--out", o], "", 1),
        (vec!["report", b, "--out", o], "", 1),
        (tables(&[]), "", 0),
        (tables(&["--alpha-grid", "0"]), "", 2),
        (tables(&["--orders", "all", "--walks", "0"]), "", 2),
        (vec!["tables", "merge", "--out", t, bf], "", 1),
        (vec!["export", f, "--to", "pbrt-v4"], "", 0),
        (vec!["export", f, "--to", "blender"], "", 2),
        (
            vec!["export", f, "--to", "radiance", "--absorption", "1"],
            "",
            2,
        ),
        (
            vec!["export", f, "--to", "mitsuba3", "--layer", "interface"],
            "",
            2,
        ),
        (vec!["export", bf, "--to", "mitsuba3"], "", 1),
        (vec!["--no-such-flag"], "", 2),
    ];
    for (args, stdin, code) in cases {
        let run = cli().run_with_stdin(&args, stdin);
        if code == 0 {
            run.ok();
        } else {
            let stderr = run.fails_with(code);
            assert!(stderr.contains("error"), "{args:?}: {stderr}");
        }
    }
}
