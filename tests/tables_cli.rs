//! End-to-end tests of `stfit tables` and `stfit tables merge`: the files of every format, the
//! format from the extension, shards merged against one run byte for byte, the Cycles layout,
//! and invalid options (exit 2) and bad shard files (exit 1).

use stfit_test_support::{CaseDir, Cli};

fn cli() -> Cli {
    Cli::new(env!("CARGO_BIN_EXE_stfit"))
}

/// The path of `name` in `dir`, as an argument.
fn file(dir: &CaseDir, name: &str) -> String {
    dir.join(name).display().to_string()
}

/// Runs the binary and fails the test unless it succeeds with nothing on stderr (no progress
/// bar when stderr is not a terminal); returns stdout.
fn stfit_ok(args: &[&str]) -> String {
    let run = cli().run(args);
    assert!(
        run.stderr.is_empty(),
        "stfit {args:?} wrote to stderr: {}",
        run.stderr
    );
    run.ok().to_owned()
}

/// Runs the binary and fails the test unless it exits with `code` (without a panic or
/// anything on stdout); returns stderr.
fn stfit_fails(args: &[&str], code: i32) -> String {
    cli().run(args).fails_with(code).to_owned()
}

/// A small Student-T glass table with all orders.
const TABLE: [&str; 15] = [
    "tables",
    "--ndf",
    "student-t",
    "--gamma-grid",
    "1.8,3",
    "--alpha-grid",
    "sq:0.3:0.9:3",
    "--mu-grid",
    "0.25:1:2",
    "--eta-grid",
    "cycles-ior:0.4:0.6:2",
    "--orders",
    "all",
    "--walks",
    "4000",
];

fn with(extra: &[&str]) -> Vec<String> {
    TABLE
        .iter()
        .chain(extra)
        .map(|s| (*s).to_string())
        .collect()
}

fn run_ok(args: &[String]) -> String {
    stfit_ok(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

#[test]
fn csv_rows_cover_the_grid_with_the_documented_columns() {
    let dir = CaseDir::new("csv");
    let out = file(&dir, "t.csv");
    let said = run_ok(&with(&["--out", &out]));
    // 2 sides x 2 gamma x 2 eta x 2 mu x 3 alpha.
    assert_eq!(said, format!("48 cells -> {out}\n"));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "surface,ndf,masking,side,alpha,gamma,eta,k,mu,E_ss,R_ss,T_ss,E_avg,R_avg,T_avg,\
         E_all,E_all_stderr,R_all,R_all_stderr,T_all,T_all_stderr"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(&f[..3], ["dielectric", "student-t", "correlated"]);
            f[4..].iter().map(|v| v.parse().unwrap()).collect()
        })
        .collect();
    assert_eq!(rows.len(), 48);
    // alpha = x^2 at x = 0.3, 0.6, 0.9; eta = (1 + x^2) / (1 - x^2) at x = 0.4, 0.6.
    assert_eq!(rows[0][0], 0.09);
    assert!((rows[2][0] - 0.81).abs() < 1e-15);
    assert!((rows[0][2] - 1.16 / 0.84).abs() < 1e-15);
    for r in &rows {
        let (e_ss, r_ss, t_ss, e_all, se) = (r[5], r[6], r[7], r[11], r[12]);
        assert!(
            (e_ss - r_ss - t_ss).abs() < 1e-12 && e_ss > 0.0 && e_ss < 1.0,
            "{r:?}"
        );
        // Lossless glass: the furnace per cell.
        assert!((e_all - 1.0).abs() <= 4.0 * se, "{r:?}");
    }
}

#[test]
fn the_format_follows_the_extension_unless_given() {
    let dir = CaseDir::new("formats");
    let (npy, h, csv_named_h) = (file(&dir, "t.npy"), file(&dir, "t.h"), file(&dir, "c.h"));
    run_ok(&with(&["--out", &npy]));
    run_ok(&with(&["--out", &h]));
    run_ok(&with(&["--out", &csv_named_h, "--format", "csv"]));
    let bytes = std::fs::read(&npy).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let header =
        std::str::from_utf8(&bytes[10..10 + usize::from(u16::from_le_bytes([bytes[8], bytes[9]]))])
            .unwrap();
    assert!(header.contains("'shape': (2, 2, 2, 2, 3)"), "{header}");
    let c = std::fs::read_to_string(&h).unwrap();
    for name in [
        "table_student_t_glass_E[24]",
        "table_student_t_glass_Eavg[12]",
        "table_student_t_glass_inv_E[24]",
        "table_student_t_glass_inv_E_all_stderr[24]",
    ] {
        assert!(
            c.contains(&format!("static const float {name} = {{")),
            "{name} missing"
        );
    }
    assert!(
        std::fs::read_to_string(&csv_named_h)
            .unwrap()
            .starts_with("surface,ndf,")
    );
}

#[test]
fn merged_shards_are_the_file_of_one_run() {
    let dir = CaseDir::new("shards");
    let mut shards = Vec::new();
    for k in 1..=3 {
        let path = file(&dir, &format!("shard{k}.json"));
        let said = run_ok(&with(&["--shard", &format!("{k}/3"), "--out", &path]));
        assert!(said.starts_with(&format!("shard {k}/3: ")), "{said}");
        shards.push(path);
    }
    for fmt in ["csv", "npy", "c"] {
        let whole = file(&dir, &format!("whole.{fmt}"));
        run_ok(&with(&["--out", &whole, "--format", fmt]));
        let merged = file(&dir, &format!("merged.{fmt}"));
        let mut args = vec!["tables", "merge", "--format", fmt, "--out", &merged];
        args.extend(shards.iter().rev().map(String::as_str));
        let said = stfit_ok(&args);
        assert_eq!(said, format!("3 shards, 48 cells -> {merged}\n"));
        assert_eq!(
            std::fs::read(&merged).unwrap(),
            std::fs::read(&whole).unwrap(),
            "{fmt}: merge differs from one run"
        );
    }
}

#[test]
fn bad_shard_files_fail_with_exit_1_naming_the_file() {
    let dir = CaseDir::new("bad-shards");
    let (one, two, junk) = (
        file(&dir, "s1.json"),
        file(&dir, "s2.json"),
        file(&dir, "junk.json"),
    );
    run_ok(&with(&["--shard", "1/2", "--out", &one]));
    let out = file(&dir, "m.csv");
    let err = stfit_fails(&["tables", "merge", "--out", &out, &one], 1);
    assert!(err.contains("missing shards: 2/2"), "{err}");
    let err = stfit_fails(&["tables", "merge", "--out", &out, &one, &one], 1);
    assert!(err.contains(&one) && err.contains("also given"), "{err}");
    // A shard of another table.
    let mut other = with(&["--shard", "2/2", "--out", &two]);
    other[14] = "5000".into();
    run_ok(&other);
    let err = stfit_fails(&["tables", "merge", "--out", &out, &one, &two], 1);
    assert!(err.contains(&two) && err.contains("differs"), "{err}");
    std::fs::write(&junk, "surface,ndf\n").unwrap();
    let err = stfit_fails(&["tables", "merge", "--out", &out, &junk], 1);
    assert!(err.contains(&junk) && err.contains("line 1"), "{err}");
    let err = stfit_fails(
        &["tables", "merge", "--out", &out, &file(&dir, "none.json")],
        1,
    );
    assert!(err.contains("cannot read"), "{err}");
    assert!(!std::path::Path::new(&out).exists());
}

#[test]
fn shard_values_and_axes_are_checked_at_the_merge() {
    let dir = CaseDir::new("edited-shards");
    let shard = file(&dir, "s.json");
    run_ok(
        &[
            "tables",
            "--ndf",
            "ggx",
            "--alpha-grid",
            "0.1:0.5:3",
            "--mu-grid",
            "1",
            "--eta-grid",
            "1.5",
            "--orders",
            "all",
            "--walks",
            "100",
            "--shard",
            "1/1",
            "--out",
            &shard,
        ]
        .map(String::from),
    );
    let text = std::fs::read_to_string(&shard).unwrap();
    // Replaces the number after the first `key`.
    let edit = |key: &str, value: &str| {
        let start = text.find(key).unwrap() + key.len();
        let end = start + text[start..].find([',', '}']).unwrap();
        format!("{}{value}{}", &text[..start], &text[end..])
    };
    let out = file(&dir, "m.csv");
    for (name, edited, message) in [
        (
            "negative.json",
            edit("\"single\":{\"reflected\":", "-5.0"),
            "line 0, cell 0 (mu 1): single.reflected (R_ss) = -5 is not in [0, 1] (tolerance 1e-5)",
        ),
        (
            "huge.json",
            edit("\"stderr\":", "1e300"),
            "walk.reflected.stderr (R_all_stderr) = 1e300 is not in [0, 1]",
        ),
        (
            "relabelled.json",
            text.replace(
                "\"values\":[0.1,0.30000000000000004,0.5]",
                "\"values\":[0.1,0.2,0.5]",
            ),
            "alpha axis values [0.1, 0.2, 0.5] are not what lin gives at the parameters",
        ),
    ] {
        assert_ne!(edited, text, "{name}");
        let path = dir.file(name, edited).display().to_string();
        let err = stfit_fails(&["tables", "merge", "--out", &out, &path], 1);
        assert!(err.contains(&path) && err.contains(message), "{err}");
    }
    assert!(!std::path::Path::new(&out).exists());
    // Within the tolerance, a negative fraction is accepted and written as 0, never below.
    let slightly = dir.file("slightly.json", edit("\"single\":{\"reflected\":", "-9e-6"));
    run_ok(
        &[
            "tables",
            "merge",
            "--out",
            &out,
            &slightly.display().to_string(),
        ]
        .map(String::from),
    );
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut rows = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let r_ss = header.iter().position(|h| *h == "R_ss").unwrap();
    let first: Vec<&str> = rows.next().unwrap().split(',').collect();
    assert_eq!(first[r_ss].parse::<f64>().unwrap(), 0.0, "{csv}");
}

#[test]
fn the_cycles_layout_of_a_dielectric_is_refused_with_walks_before_any_work() {
    let dir = CaseDir::new("cycles-walks");
    let out = file(&dir, "t.csv");
    let err = stfit_fails(
        &[
            "tables", "--ndf", "ggx", "--layout", "cycles", "--orders", "all", "--out", &out,
        ],
        2,
    );
    assert!(
        err.contains("--layout cycles for a dielectric is for --orders single only")
            && err.contains("differ from 1 by at least 0.005"),
        "{err}"
    );
    assert!(!std::path::Path::new(&out).exists());
}

#[test]
fn the_cycles_layout_writes_cycles_arrays() {
    let dir = CaseDir::new("cycles");
    let h = file(&dir, "ggx.h");
    let said = stfit_ok(&[
        "tables",
        "--ndf",
        "ggx",
        "--surface",
        "conductor",
        "--layout",
        "cycles",
        "--out",
        &h,
    ]);
    assert_eq!(said, format!("1024 cells -> {h}\n"));
    let c = std::fs::read_to_string(&h).unwrap();
    assert!(
        c.contains("static const float table_ggx_E[1024] = {"),
        "{c}"
    );
    assert!(c.contains("static const float table_ggx_Eavg[32] = {"));
    let values: Vec<f32> = {
        let start = c.find("table_ggx_E[1024]").unwrap();
        let body = &c[start..];
        body[body.find('{').unwrap() + 1..body.find('}').unwrap()]
            .split(',')
            .map(|v| v.trim().trim_end_matches('f').parse().unwrap())
            .collect()
    };
    // alpha = 1e-8 at x = 0 reflects everything; at alpha = 1 (x = 31) and normal incidence
    // (y = 31) GGX mirror facets reflect 1 - ln 2 in single scattering.
    assert!((values[0] - 1.0).abs() < 1e-6 && (values[31 * 32] - 1.0).abs() < 1e-6);
    let one_minus_ln2 = 1.0 - std::f32::consts::LN_2;
    assert!(
        (values[31 * 32 + 31] - one_minus_ln2).abs() < 1e-6,
        "{}",
        values[1023]
    );
}

#[test]
fn invalid_options_exit_with_status_2() {
    let dir = CaseDir::new("usage");
    let out = file(&dir, "t.csv");
    let base = [
        "tables",
        "--ndf",
        "ggx",
        "--alpha-grid",
        "0.1,0.5",
        "--mu-grid",
        "0.5,1",
        "--eta-grid",
        "1.5",
        "--out",
        &out,
    ];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--alpha-grid", "0:1:3"], "alpha axis value 0"),
        (vec!["--alpha-grid", "sq:0:1"], "START:END:COUNT"),
        (vec!["--mu-grid", "0.5,x"], "not a finite number"),
        (vec!["--eta-grid", "0.8"], "eta axis value 0.8"),
        (vec!["--gamma-grid", "3"], "--gamma-grid applies only"),
        (vec!["--walks", "10"], "--walks and --seed apply only"),
        (vec!["--layout", "cycles"], "conflicts with --layout cycles"),
        (vec!["--shard", "3/2"], "K/N"),
        (vec!["--shard", "1/9"], "only 4 lines"),
        (
            vec!["--shard", "1/2", "--format", "csv"],
            "--format does not apply",
        ),
        (vec!["--surface", "conductor"], "--eta-grid applies only"),
        (vec!["--n", "0.2"], "--n and --k apply only"),
        (vec!["--orders", "all", "--walks", "0"], "walks per cell"),
        (
            vec!["--alpha-grid", "0.5:0.5:3"],
            "COUNT 3 needs START < END",
        ),
        (
            vec!["--alpha-grid", "0.3,0.3"],
            "strictly increasing, got 0.3 then 0.3",
        ),
        (
            vec!["--mu-grid", "1,0.5"],
            "strictly increasing, got 1 then 0.5",
        ),
        (vec!["--alpha-grid", "sq:-2:1:3"], "sq needs START >= 0"),
        (
            vec!["--eta-grid", "1.0000000001", "--orders", "all"],
            "eta axis value 1.0000000001 cannot be walked",
        ),
    ];
    for (extra, message) in cases {
        let mut args: Vec<&str> = base.to_vec();
        // Replace an option already given, else append.
        if let Some(i) = args.iter().position(|a| *a == extra[0]) {
            args[i + 1] = extra[1];
            args.extend(&extra[2..]);
        } else {
            args.extend(&extra);
        }
        let err = stfit_fails(&args, 2);
        assert!(
            err.contains(message),
            "{args:?}: expected '{message}' in: {err}"
        );
    }
    let err = stfit_fails(
        &[
            "tables",
            "--ndf",
            "student-t",
            "--alpha-grid",
            "0.1",
            "--mu-grid",
            "1",
            "--eta-grid",
            "1.5",
            "--out",
            &out,
        ],
        2,
    );
    assert!(err.contains("--gamma-grid is required"), "{err}");
    let err = stfit_fails(
        &["tables", "--ndf", "ggx", "--mu-grid", "1", "--out", &out],
        2,
    );
    assert!(err.contains("--alpha-grid is required"), "{err}");
    assert!(!std::path::Path::new(&out).exists());
}

/// A table of more cells than can be held is refused before any work, naming its shape and
/// the limit: four axes of 4096 nodes (each within its own limit) made 2^37 lines, whose list
/// alone was an allocation of a terabyte that aborted the process (exit 134), and a shard of
/// it scanned them for days.
#[test]
fn a_table_too_large_to_hold_is_refused_before_any_work() {
    let dir = CaseDir::new("too-large");
    let out = file(&dir, "t.csv");
    let shard = file(&dir, "s.json");
    let axes = [
        "tables",
        "--ndf",
        "student-t",
        "--gamma-grid",
        "log:1.6:40:4096",
        "--alpha-grid",
        "log:1e-8:4:4096",
        "--mu-grid",
        "log:1e-4:1:4096",
        "--eta-grid",
        "log:1.01:100:4096",
    ];
    for tail in [
        vec!["--out", out.as_str()],
        vec!["--shard", "1/1000000000", "--out", shard.as_str()],
    ] {
        let args: Vec<&str> = axes.iter().copied().chain(tail).collect();
        let err = stfit_fails(&args, 2);
        assert!(
            err.contains("2 x 4096 x 4096 x 4096 x 4096")
                && err.contains("more than the 16777216 a table may have"),
            "{err}"
        );
    }
    // Past the limit by a little: 2 sides x 2 x 3 x 2048 x 1024 = 1.5 x 2^24 cells.
    let err = stfit_fails(
        &[
            "tables",
            "--ndf",
            "student-t",
            "--gamma-grid",
            "2,3",
            "--alpha-grid",
            "0.1:1:1024",
            "--mu-grid",
            "0.1:1:2048",
            "--eta-grid",
            "1.3,1.5,1.7",
            "--out",
            &out,
        ],
        2,
    );
    assert!(err.contains("25165824 cells"), "{err}");
    assert!(!std::path::Path::new(&out).exists());
}

/// A table whose random walks take long says so before they start, as the other commands
/// that run walks do: with 1e9 walks per cell the first line on stderr, read while the run
/// goes on and then stopped, is the note, in minutes, hours or days; with 1,000 walks there is
/// none.
#[test]
fn a_table_whose_walks_take_long_says_so_before_it_runs() {
    let dir = CaseDir::new("tables-long-run");
    let out = file(&dir, "t.csv");
    let table = |walks: &'static str| {
        [
            "tables",
            "--ndf",
            "ggx",
            "--alpha-grid",
            "0.3,0.6",
            "--mu-grid",
            "0.5",
            "--eta-grid",
            "1.5",
            "--orders",
            "all",
            "--walks",
            walks,
            "--out",
            &out,
        ]
        .map(String::from)
    };
    let args = table("1000000000");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let line = cli()
        .first_stderr_line(&args, std::time::Duration::from_secs(120))
        .expect("no line on stderr within 120 s");
    assert!(
        line.starts_with(
            "note: the random walks of the table (1000000000 per cell) will take about "
        ) && [" min", " h", " days"]
            .iter()
            .any(|unit| line.ends_with(&format!(
                "{unit} (fewer --walks or fewer nodes make it shorter)\n"
            ))),
        "{line}"
    );
    let args = table("1000");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let run = cli().run(&args);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(!run.stderr.contains("note:"), "{}", run.stderr);
}
