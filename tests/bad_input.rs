//! Bad input to the `stfit` binary: every problem exits non-zero without a panic, and its message
//! names the file and, where the problem has them, the line and the column
//! (`error: <file>:<line>: column '<col>': <what>`, data-format.md).

use std::path::{Path, PathBuf};
use stfit_test_support::{CaseDir, Cli, Run};

const HEADER: &str = "sample,theta_i_deg,theta_o_deg,sqrt_L\n";

fn stfit(args: &[&str]) -> Run {
    Cli::new(env!("CARGO_BIN_EXE_stfit")).run(args)
}

/// Runs `stfit FILE args` and checks the failure: exit status `code`, no panic, and a message
/// `error: FILE[:line][: column 'col']: ...` containing `what`.
fn expect_error(
    path: &Path,
    args: &[&str],
    line: Option<u64>,
    column: Option<&str>,
    what: &str,
) -> String {
    let path_str = path.to_str().unwrap();
    let mut all = vec![path_str];
    all.extend_from_slice(args);
    let out = stfit(&all);
    let stderr = out.stderr.clone();
    assert_eq!(out.code, Some(1), "stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "stderr: {stderr}");
    assert!(out.stdout.is_empty(), "nothing on stdout on error");
    let mut prefix = format!("error: {path_str}");
    if let Some(line) = line {
        prefix += &format!(":{line}");
    }
    if let Some(column) = column {
        prefix += &format!(": column '{column}'");
    }
    prefix += ": ";
    assert!(
        stderr.starts_with(&prefix),
        "stderr {stderr:?} should start with {prefix:?}"
    );
    assert!(
        stderr.contains(what),
        "stderr {stderr:?} should say {what:?}"
    );
    stderr
}

/// A file holding `rows` after the standard header, with a bad field on line 3.
fn data(dir: &CaseDir, rows: &str) -> PathBuf {
    dir.file("data.csv", format!("{HEADER}a,0,180,1\n{rows}").as_bytes())
}

#[test]
fn missing_file() {
    let dir = CaseDir::new("missing");
    let path = dir.join("does-not-exist.csv");
    expect_error(&path, &[], None, None, "cannot read the file");
}

#[test]
fn empty_file() {
    let dir = CaseDir::new("empty");
    expect_error(&dir.file("e.csv", b""), &[], Some(1), None, "empty");
    let blank = dir.file("blank.csv", b"\xEF\xBB\xBF\n# comment\n   \n");
    expect_error(&blank, &[], Some(1), None, "empty");
}

#[test]
fn header_only() {
    let dir = CaseDir::new("header-only");
    let path = dir.file("h.csv", format!("# made by hand\n{HEADER}\n\n").as_bytes());
    expect_error(&path, &[], Some(2), None, "no measurements");
}

#[test]
fn missing_value_column() {
    let dir = CaseDir::new("no-value");
    let path = dir.file("v.csv", b"sample,theta_i_deg,theta_o_deg,l\na,0,180,1\n");
    expect_error(&path, &[], Some(1), Some("L or sqrt_L"), "the header has");
}

#[test]
fn missing_angle_column() {
    let dir = CaseDir::new("no-angle");
    let path = dir.file("v.csv", b"sample,theta_i_deg,L\na,0,1\n");
    expect_error(&path, &[], Some(1), Some("theta_o_deg"), "missing");
}

/// A column that changes how a file is read (`sample`, `weight`, `phi_i_deg`, `phi_o_deg`)
/// written in another case is refused: ignored, `Sample` would merge every sample into one fit
/// and `Weight` would weigh every point 1. With the exact name present, a variant is an extra
/// column, ignored.
#[test]
fn case_variant_of_a_column_that_changes_the_reading() {
    let dir = CaseDir::new("case-variant");
    let merged = dir.file(
        "s.csv",
        b"Sample,theta_i_deg,theta_o_deg,L\na,0,180,1\nb,0,180,2\n",
    );
    let e = expect_error(&merged, &[], Some(1), Some("sample"), "field 1 is 'Sample'");
    assert!(e.contains("case-sensitive"), "{e}");
    let weights = dir.file("w.csv", b"theta_i_deg,theta_o_deg,L,WEIGHT\n0,180,1,2\n");
    expect_error(
        &weights,
        &[],
        Some(1),
        Some("weight"),
        "field 4 is 'WEIGHT'",
    );
    let general = dir.file(
        "g.csv",
        b"theta_i_deg,Phi_i_deg,theta_o_deg,phi_o_deg,bsdf\n0,0,170,0,1\n",
    );
    expect_error(
        &general,
        &[],
        Some(1),
        Some("phi_i_deg"),
        "field 2 is 'Phi_i_deg'",
    );
    let both = dir.file(
        "both.csv",
        b"sample,Sample,theta_i_deg,theta_o_deg,L\na,x,0,180,1\na,y,30,200,1\na,z,60,140,1\n",
    );
    let out = stfit(&[both.to_str().unwrap(), "--model", "ggx"]);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
}

#[test]
fn duplicated_value_column() {
    let dir = CaseDir::new("dup-value");
    let twice = dir.file("twice.csv", b"theta_i_deg,theta_o_deg,L,L\n0,180,1,1\n");
    expect_error(&twice, &[], Some(1), Some("L"), "appears twice");
    let both = dir.file("both.csv", b"theta_i_deg,theta_o_deg,L,sqrt_L\n0,180,1,1\n");
    expect_error(&both, &[], Some(1), Some("sqrt_L"), "both present");
}

#[test]
fn non_numeric_value() {
    let dir = CaseDir::new("non-numeric");
    let path = data(&dir, "a,0,18O,1\n");
    expect_error(
        &path,
        &[],
        Some(3),
        Some("theta_o_deg"),
        "'18O' is not a number",
    );
    let empty = data(&dir, "a,0,180,\n");
    expect_error(&empty, &[], Some(3), Some("sqrt_L"), "empty value");
}

#[test]
fn nan_value() {
    let dir = CaseDir::new("nan");
    let path = data(&dir, "a,0,180,NaN\n");
    expect_error(&path, &[], Some(3), Some("sqrt_L"), "not a finite number");
}

#[test]
fn infinite_value() {
    let dir = CaseDir::new("inf");
    let path = data(&dir, "a,inf,180,1\n");
    expect_error(
        &path,
        &[],
        Some(3),
        Some("theta_i_deg"),
        "not a finite number",
    );
    let big = data(&dir, "a,0,180,1e999\n");
    expect_error(&big, &[], Some(3), Some("sqrt_L"), "not a finite number");
}

/// A finite `sqrt_L` whose square `L` overflows is refused on reading, at its line and column
/// (the fit used to fail on an infinite `L` at a 0-based "point" without a line).
#[test]
fn sqrt_l_whose_square_overflows() {
    let dir = CaseDir::new("sqrt-overflow");
    let path = data(&dir, "a,30,170,1e200\n");
    expect_error(
        &path,
        &[],
        Some(3),
        Some("sqrt_L"),
        "1e200 is too large: L = sqrt_L^2 overflows",
    );
}

/// A nonzero number that reads as 0 (`1e-400`, or a `sqrt_L` whose square underflows) is
/// refused at its line and column in every data reader. Such values had been read as 0, and a
/// file of them refused as "every measured value is zero", which contradicts the file.
#[test]
fn nonzero_numbers_that_read_as_zero() {
    let dir = CaseDir::new("underflow");
    let too_small = "is not 0 but too small to be represented";
    let l = dir.file(
        "l.csv",
        b"theta_i_deg,theta_o_deg,L\n0,180,1e-400\n0,170,1e-400\n30,170,1e-400\n30,190,1e-400\n",
    );
    expect_error(
        &l,
        &[],
        Some(2),
        Some("L"),
        &format!("'1e-400' {too_small}"),
    );
    let sqrt = data(&dir, "a,30,170,1e-170\n");
    expect_error(
        &sqrt,
        &[],
        Some(3),
        Some("sqrt_L"),
        "1e-170 is too small: L = sqrt_L^2 underflows to 0",
    );
    let weight = dir.file(
        "w.csv",
        b"theta_i_deg,theta_o_deg,L,weight\n0,180,1,1\n0,181,1,1e-400\n",
    );
    expect_error(&weight, &[], Some(3), Some("weight"), too_small);
    let general = dir.file(
        "g.csv",
        b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf\n30,0,150,0,1\n30,0,160,0,1e-400\n",
    );
    expect_error(&general, &[], Some(3), Some("bsdf"), too_small);
    let pab = dir.file(
        "m.txt",
        b"#format: theta phi BSDF\n#intheta 30\n#inphi 0\n150 0 1e-400\n",
    );
    expect_error(&pab, &[], Some(4), Some("value"), too_small);
    // Subnormal values are read: the fit refuses the sample for its largest value, in its own
    // words, not as unreadable.
    let tiny = dir.file(
        "t.csv",
        b"theta_i_deg,theta_o_deg,L\n0,180,1e-310\n0,170,0\n30,170,1e-320\n30,190,0\n",
    );
    let out = stfit(&[tiny.to_str().unwrap(), "--model", "ggx"]);
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    assert!(
        out.stderr
            .contains("the largest value is 1e-310, below the normal range")
            && !out.stderr.contains(too_small),
        "{}",
        out.stderr
    );
}

#[test]
fn negative_values() {
    let dir = CaseDir::new("negative");
    let path = data(&dir, "a,0,180,-0.01\n");
    expect_error(&path, &[], Some(3), Some("sqrt_L"), "negative");
    let weight = dir.file(
        "w.csv",
        b"theta_i_deg,theta_o_deg,L,weight\n0,180,1,1\n0,181,1,-1\n",
    );
    expect_error(&weight, &[], Some(3), Some("weight"), "negative");
}

#[test]
fn angles_out_of_range() {
    let dir = CaseDir::new("angles");
    for (row, column) in [
        ("a,90,180,1", "theta_i_deg"),
        ("a,-5,180,1", "theta_i_deg"),
        ("a,0,90,1", "theta_o_deg"),
        ("a,0,270,1", "theta_o_deg"),
        ("a,0,0,1", "theta_o_deg"),
        ("a,0,300,1", "theta_o_deg"),
    ] {
        let path = data(&dir, &format!("{row}\n"));
        expect_error(&path, &[], Some(3), Some(column), "out of range");
    }
}

#[test]
fn short_and_long_rows() {
    let dir = CaseDir::new("short");
    let path = data(&dir, "a,0,180\n");
    expect_error(&path, &[], Some(3), Some("sqrt_L"), "the row has 3 fields");
    let long = data(&dir, "a, b,0,180,1\n");
    expect_error(&long, &[], Some(3), Some("extra field 5"), "unquoted comma");
}

#[test]
fn bytes_that_are_not_utf8() {
    let dir = CaseDir::new("utf8");
    let mut bytes = format!("{HEADER}a,0,180,1\n").into_bytes();
    bytes.extend_from_slice(b"gr\xE9s,0,180,1\n");
    let path = dir.file("latin1.csv", &bytes);
    expect_error(&path, &[], Some(3), Some("sample"), "not valid UTF-8");
    let header = dir.file("h.csv", b"theta_i_deg,theta_o_deg,\xFF\n0,180,1\n");
    expect_error(
        &header,
        &[],
        Some(1),
        Some("header field 3"),
        "not valid UTF-8",
    );
}

#[test]
fn sample_not_in_file() {
    let dir = CaseDir::new("sample");
    let path = dir.file(
        "s.csv",
        format!("{HEADER}a,0,180,1\nb,0,180,1\n").as_bytes(),
    );
    let stderr = expect_error(
        &path,
        &["--sample", "c"],
        None,
        Some("sample"),
        "no sample named 'c'",
    );
    assert!(stderr.contains("'a', 'b'"), "lists the samples: {stderr}");
    let unnamed = dir.file("u.csv", b"theta_i_deg,theta_o_deg,L\n0,180,1\n");
    expect_error(
        &unnamed,
        &["--sample", "a"],
        None,
        Some("sample"),
        "no 'sample' column",
    );
}

#[test]
fn all_weights_zero() {
    let dir = CaseDir::new("weights");
    let path = dir.file(
        "w.csv",
        b"sample,theta_i_deg,theta_o_deg,L,weight\na,0,180,1,1\nb,0,180,1,0\n",
    );
    expect_error(
        &path,
        &[],
        Some(3),
        Some("weight"),
        "every weight of sample 'b'",
    );
}

/// Invalid flags exit with status 2 and a message naming the flag, never a panic.
#[test]
fn invalid_fit_flags() {
    let dir = CaseDir::new("flags");
    let path = data(&dir, "");
    let p = path.to_str().unwrap();
    for (args, what) in [
        (
            vec![p, "--gamma", "1.5"],
            "--gamma: gamma must be in (1.5, 1e15]",
        ),
        (vec![p, "--gamma", "nan"], "--gamma"),
        (
            vec![p, "--model", "ggx", "--gamma", "3"],
            "needs --model student-t",
        ),
        (
            vec![p, "--model", "all", "--gamma", "3"],
            "needs --model student-t",
        ),
        (vec![p, "--eta", "1"], "--eta"),
        (vec![p, "--eta", "-1.5"], "--eta"),
        (
            vec![p, "--model", "cook-torrance"],
            "invalid value 'cook-torrance'",
        ),
        (vec![p, "--eta", "abc"], "invalid value 'abc'"),
        (vec![p, "--out", p], "refusing to overwrite"),
        (vec![], "required"),
    ] {
        let out = stfit(&args);
        let stderr = out.stderr.clone();
        assert_eq!(out.code, Some(2), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(
            stderr.contains(what),
            "{args:?}: {stderr:?} should say {what:?}"
        );
    }
}

/// `--out` onto a data file is refused (exit 2) whatever path names it: a file inside a data
/// folder given, or a hard link to a data file. Both had been overwritten with the fits.
#[test]
fn out_onto_a_data_file_by_any_path_is_refused() {
    let dir = CaseDir::new("out-onto-data");
    let path = data(&dir, "a,30,170,0.5\na,30,190,0.7\n");
    let before = std::fs::read(&path).unwrap();
    let folder = dir.path().to_str().unwrap();
    let p = path.to_str().unwrap();
    let link = dir.path().join(".link.csv");
    let mut cases = vec![(vec![folder, "--out", p], p)];
    #[cfg(unix)]
    {
        std::fs::hard_link(&path, &link).unwrap();
        cases.push((vec![p, "--out", link.to_str().unwrap()], p));
    }
    for (args, named) in cases {
        let out = stfit(&args);
        assert_eq!(out.code, Some(2), "{args:?}: {}", out.stderr);
        assert!(
            out.stderr.contains(&format!(
                "is the input file {named}; refusing to overwrite it"
            )),
            "{args:?}: {}",
            out.stderr
        );
        assert_eq!(std::fs::read(&path).unwrap(), before, "{args:?}");
    }
}

/// Runs `args`, which give `--out` (or a file written inside the folder it names) onto the
/// input `named`, and checks the refusal of the data-file guard: exit 2, nothing on stdout, the
/// input named, and `kept` (the input's path) as it was.
fn expect_out_refused(args: &[&str], named: &str, kept: &Path) {
    let before = std::fs::read(kept).unwrap();
    let out = stfit(args);
    assert_eq!(out.code, Some(2), "{args:?}: {}", out.stderr);
    assert!(
        out.stderr.contains(&format!(
            "is the input file {named}; refusing to overwrite it"
        )),
        "{args:?}: {}",
        out.stderr
    );
    assert!(out.stdout.is_empty(), "{args:?}: {}", out.stdout);
    assert_eq!(std::fs::read(kept).unwrap(), before, "{args:?}");
}

/// `stfit export FITS --out` onto the fits file it reads is refused like `stfit DATA --out`:
/// the same path, a hard link, the file written beside `--out FILE` (mitsuba3's `.py`) and the
/// one written into `--out DIR/`. Each had overwritten the fits.
#[test]
fn export_out_onto_its_fits_file_is_refused() {
    let dir = CaseDir::new("export-out-onto-fits");
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/fits/example-fits.json");
    let json = std::fs::read(example).unwrap();
    let fits = dir.file("fits.json", &json);
    let f = fits.to_str().unwrap();
    expect_out_refused(&["export", f, "--to", "cycles", "--out", f], f, &fits);
    #[cfg(unix)]
    {
        let link = dir.join("link.py");
        std::fs::hard_link(&fits, &link).unwrap();
        let l = link.to_str().unwrap();
        expect_out_refused(&["export", f, "--to", "cycles", "--out", l], f, &fits);
    }
    let beside = dir.file("scene.py", &json);
    let b = beside.to_str().unwrap();
    let xml = dir.join("scene.xml");
    let x = xml.to_str().unwrap();
    expect_out_refused(&["export", b, "--to", "mitsuba3", "--out", x], b, &beside);
    assert!(!xml.exists(), "nothing written");
    let folder = dir.join("out");
    std::fs::create_dir(&folder).unwrap();
    let inside = folder.join("frosted_beckmann-mitsuba3.py");
    std::fs::write(&inside, &json).unwrap();
    let i = inside.to_str().unwrap();
    let slashed = format!("{}{}", folder.display(), std::path::MAIN_SEPARATOR);
    let args = [
        "export", i, "--to", "mitsuba3", "--sample", "frosted", "--model", "beckmann", "--out",
        &slashed,
    ];
    expect_out_refused(&args, i, &inside);
}

/// `stfit tables merge SHARD... --out` onto one of its shards is refused, by path or hard link.
#[test]
fn tables_merge_out_onto_a_shard_is_refused() {
    let dir = CaseDir::new("merge-out-onto-shard");
    let shard = dir.join("s.json");
    let s = shard.to_str().unwrap();
    let table = [
        "tables",
        "--ndf",
        "ggx",
        "--alpha-grid",
        "0.3,0.6",
        "--mu-grid",
        "0.5,1",
        "--eta-grid",
        "1.5",
        "--side",
        "outside",
        "--shard",
        "1/1",
        "--out",
        s,
    ];
    stfit(&table).ok();
    expect_out_refused(&["tables", "merge", s, "--out", s], s, &shard);
    #[cfg(unix)]
    {
        let link = dir.join("merged.csv");
        std::fs::hard_link(&shard, &link).unwrap();
        let l = link.to_str().unwrap();
        expect_out_refused(&["tables", "merge", s, "--out", l], s, &shard);
    }
}

/// `stfit report` refuses to write a file of its folder that is one of the files it reads: the
/// stored fits (`--fits DIR/fits.md`) or a data file (here a hard link `DIR/overview.svg`).
#[test]
fn report_out_onto_an_input_is_refused() {
    let dir = CaseDir::new("report-out-onto-input");
    let root = env!("CARGO_MANIFEST_DIR");
    let example = std::fs::read(format!("{root}/fits/example.csv")).unwrap();
    let json = std::fs::read(format!("{root}/fits/example-fits.json")).unwrap();
    let data = dir.file("data.csv", &example);
    let d = data.to_str().unwrap();
    let folder = dir.join("report");
    std::fs::create_dir(&folder).unwrap();
    let o = folder.to_str().unwrap();
    let fits_md = folder.join("fits.md");
    std::fs::write(&fits_md, &json).unwrap();
    let m = fits_md.to_str().unwrap();
    expect_out_refused(&["report", d, "--fits", m, "--out", o], m, &fits_md);
    #[cfg(unix)]
    {
        let fits = dir.file("fits.json", &json);
        std::fs::hard_link(&data, folder.join("overview.svg")).unwrap();
        let args = ["report", d, "--fits", fits.to_str().unwrap(), "--out", o];
        expect_out_refused(&args, d, &data);
    }
}

/// `stfit synth` validates its arguments the same way.
#[test]
fn invalid_synth_flags() {
    let base = ["synth", "--alpha", "0.2"];
    for (extra, what) in [
        (vec!["--model", "student-t"], "student-t needs a gamma"),
        (
            vec!["--model", "ggx", "--gamma", "3"],
            "beckmann and ggx take none",
        ),
        (
            vec!["--model", "student-t", "--gamma", "1.2"],
            "gamma must be in (1.5, 1e15]",
        ),
        (
            vec!["--model", "ggx", "--scale", "0"],
            "scale must be finite and > 0",
        ),
        (
            vec!["--model", "ggx", "--noise", "-0.1"],
            "noise must be finite",
        ),
        (vec!["--model", "ggx", "--eta", "inf"], "--eta"),
        (
            vec!["--model", "ggx", "--theta-i", "0,90"],
            "theta_i_deg = 90 is out of range",
        ),
        (
            vec!["--model", "ggx", "--theta-o", "80:200:2"],
            "theta_o_deg = 80",
        ),
        (
            vec!["--model", "ggx", "--theta-o", "106:254:0"],
            "step must be > 0",
        ),
        (
            vec!["--model", "ggx", "--theta-o", "1;2"],
            "'1;2' is not a number",
        ),
        (vec!["--model", "ggx", "--sample", "#x"], "sample name"),
        (vec!["--model", "ggx", "--append"], "--out"),
        (vec!["--model", "all"], "invalid value 'all'"),
    ] {
        let mut args = base.to_vec();
        args.extend(extra);
        let out = stfit(&args);
        let stderr = out.stderr.clone();
        assert_eq!(out.code, Some(2), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(
            stderr.contains(what),
            "{args:?}: {stderr:?} should say {what:?}"
        );
        assert!(out.stdout.is_empty(), "{args:?}: no partial file on stdout");
    }
    let out = stfit(&["synth", "--model", "ggx", "--alpha", "-0.1"]);
    assert_eq!(out.code, Some(2));
    assert!(out.stderr.clone().contains("alpha must be in [1e-8, 100]"));
}

/// An input that is a device is refused before it is read, by every reader of files: `/dev/zero`
/// never ends, and reading it whole had exhausted memory (exit 137). A pipe is read.
#[cfg(unix)]
#[test]
fn a_device_as_input_is_refused_before_it_is_read() {
    let dir = CaseDir::new("device-input");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    for args in [
        vec!["/dev/zero"],
        vec!["report", "/dev/zero", "--out", out],
        vec!["export", "/dev/zero", "--to", "mitsuba3", "--out", out],
        vec!["tables", "merge", "/dev/zero", "--out", out],
    ] {
        let run = stfit(&args);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("/dev/zero") && run.stderr.contains("not a file or a pipe"),
            "{args:?}: {}",
            run.stderr
        );
    }
    // A pipe is still read: the example on stdin fits.
    let example =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/fits/example.csv")).unwrap();
    let run = Cli::new(env!("CARGO_BIN_EXE_stfit"))
        .run_with_stdin(&["/dev/stdin", "--model", "ggx"], &example);
    assert!(run.ok().contains("frosted"));
}

/// An output folder that is an existing file is refused in words by every command that writes
/// a folder (`export --out DIR/`, `report --out`, `synth --pabopto`): it had said only 'File
/// exists'.
#[test]
fn an_output_folder_that_is_a_file_is_named_as_such() {
    let dir = CaseDir::new("folder-is-a-file");
    let file = dir.join("taken");
    std::fs::write(&file, "x").unwrap();
    let file = file.to_str().unwrap();
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/fits/example.csv");
    let fits = concat!(env!("CARGO_MANIFEST_DIR"), "/fits/example-fits.json");
    let slashed = format!("{file}{}", std::path::MAIN_SEPARATOR);
    let below = format!("{file}{}sub", std::path::MAIN_SEPARATOR);
    for args in [
        vec!["export", fits, "--to", "mitsuba3", "--out", &slashed],
        vec!["report", example, "--out", file],
        vec!["report", example, "--out", &below],
        vec![
            "synth",
            "--model",
            "ggx",
            "--alpha",
            "0.3",
            "--grid",
            "general",
            "--pabopto",
            "dsf",
            "--out",
            file,
        ],
    ] {
        let run = stfit(&args);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("taken") && run.stderr.contains("exists and is not a folder"),
            "{args:?}: {}",
            run.stderr
        );
    }
}

/// A fits file with a misspelt key in one fit (`warning` for `warnings`) is refused by `export`
/// and `report` (exit 1, naming the file, the fit and the key), where it had read as a fit
/// without warnings.
#[test]
fn a_misspelt_key_in_a_fits_file_is_refused() {
    let dir = CaseDir::new("fits-unknown-key");
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/fits/example-fits.json");
    let text = std::fs::read_to_string(example).unwrap();
    let misspelt = text.replacen("\"warnings\"", "\"warning\"", 1);
    assert_ne!(misspelt, text);
    let fits = dir.file("fits.json", misspelt.as_bytes());
    let f = fits.to_str().unwrap();
    let out_dir = dir.join("out");
    let o = out_dir.to_str().unwrap();
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/fits/example.csv").to_owned();
    for args in [
        vec!["export", f, "--to", "cycles", "--out", o],
        vec!["report", &data, "--fits", f, "--out", o],
    ] {
        let out = stfit(&args);
        assert_eq!(out.code, Some(1), "{args:?}: {}", out.stderr);
        assert!(
            out.stderr
                .starts_with(&format!("error: {f}: fit 0 (sample 'frosted'"))
                && out.stderr.contains("unknown key \"warning\""),
            "{args:?}: {}",
            out.stderr
        );
    }
}
