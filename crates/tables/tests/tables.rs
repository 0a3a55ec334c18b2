//! Whole tables: the furnace of all orders per cell, determinism across thread counts, shards
//! merged against one run (byte for byte, every format), the file formats as documented in
//! tables-format.md, and refused specifications.

use stfit_core::walk::ScatteringOrders;
use stfit_tables::compute::{self, Shard, Table};
use stfit_tables::format::{Format, shard};
use stfit_tables::grid::Axis;
use stfit_tables::single::{Quadrature, TableMasking};
use stfit_tables::{Family, Side, SpecError, Surface, TableSpec, compute_table};

fn axis(s: &str) -> Axis {
    s.parse().unwrap()
}

/// A small dielectric table with walks.
fn spec(family: Family, orders: ScatteringOrders) -> TableSpec {
    TableSpec {
        family,
        surface: Surface::Dielectric,
        masking: TableMasking::Correlated,
        orders,
        sides: vec![Side::Outside, Side::Inside],
        alpha: axis("0.2,0.8"),
        gamma: (family == Family::StudentT).then(|| axis("1.8,4")),
        eta: Some(axis("1.5")),
        mu: axis("0.3,0.9"),
        walks: 20_000,
        seed: 3,
    }
}

fn table(spec: &TableSpec) -> Table {
    compute_table(spec, &Quadrature::default(), &|_| {}).unwrap()
}

#[test]
fn lossless_surfaces_pass_the_furnace_in_every_cell() {
    // E_all = E_ss (quadrature, height-correlated) + orders >= 2 (walks) = 1 within the
    // walks' standard error, for glass from both sides and for mirror facets.
    let mut mirror = spec(Family::Ggx, ScatteringOrders::All);
    mirror.surface = Surface::Mirror;
    mirror.eta = None;
    mirror.sides = vec![Side::Outside];
    for s in [
        spec(Family::Ggx, ScatteringOrders::All),
        spec(Family::StudentT, ScatteringOrders::All),
        spec(Family::Beckmann, ScatteringOrders::All),
        mirror,
    ] {
        let t = table(&s);
        for l in &t.lines {
            for c in &l.cells {
                let w = c.walk.unwrap();
                assert!(
                    (w.total.mean - 1.0).abs() <= 4.0 * w.total.stderr,
                    "{:?} {:?} line {}: E_all {} +- {}",
                    s.family,
                    s.surface,
                    l.index,
                    w.total.mean,
                    w.total.stderr
                );
                assert!(w.total.stderr > 0.0 && w.total.stderr < 0.01);
                // The split adds up.
                let sum = w.reflected.mean + w.transmitted.mean;
                assert!((sum - w.total.mean).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn a_fresnel_conductor_loses_energy_and_its_multiple_scattering_is_positive() {
    let mut s = spec(Family::Ggx, ScatteringOrders::Multiple);
    s.surface = Surface::Conductor { n: 0.2, k: 3.5 };
    s.eta = None;
    s.sides = vec![Side::Outside];
    let t = table(&s);
    for c in t.lines.iter().flat_map(|l| &l.cells) {
        let w = c.walk.unwrap();
        assert!(
            w.total.mean > 0.0 && c.single.total() + w.total.mean < 1.0,
            "{c:?}"
        );
        assert_eq!(w.transmitted.mean, 0.0);
    }
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let s = spec(Family::StudentT, ScatteringOrders::All);
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| Format::Csv.write(&table(&s)))
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one, two, "1 and 2 threads differ");
}

#[test]
fn shards_merged_equal_one_run_byte_for_byte() {
    let s = spec(Family::StudentT, ScatteringOrders::All);
    let whole = table(&s);
    let files: Vec<(String, String)> = (1..=3)
        .map(|k| {
            let sh = Shard { index: k, count: 3 };
            let lines = compute::compute(&s, sh, &Quadrature::default(), &|_| {}).unwrap();
            (
                format!("shard{k}.json"),
                shard::write(&s, sh, &lines).unwrap(),
            )
        })
        .collect();
    // Any order of the files.
    let shuffled = vec![files[2].clone(), files[0].clone(), files[1].clone()];
    let merged = shard::merge(&shuffled).unwrap();
    for f in [Format::Csv, Format::Npy, Format::C] {
        assert_eq!(f.write(&merged), f.write(&whole), "{f:?}");
    }
    // A missing, repeated or foreign shard is refused, naming the file.
    let missing = shard::merge(&files[..2]).unwrap_err().to_string();
    assert!(missing.contains("missing shards: 3/3"), "{missing}");
    let twice = vec![files[0].clone(), files[1].clone(), files[0].clone()];
    let err = shard::merge(&twice).unwrap_err().to_string();
    assert!(
        err.contains("shard1.json") && err.contains("also given"),
        "{err}"
    );
    let mut other = s.clone();
    other.seed = 4;
    let sh = Shard { index: 3, count: 3 };
    let lines = compute::compute(&other, sh, &Quadrature::default(), &|_| {}).unwrap();
    let foreign = vec![
        files[0].clone(),
        files[1].clone(),
        (
            "other.json".into(),
            shard::write(&other, sh, &lines).unwrap(),
        ),
    ];
    let err = shard::merge(&foreign).unwrap_err().to_string();
    assert!(
        err.contains("other.json") && err.contains("differs"),
        "{err}"
    );
    let err = shard::merge(&[("junk.json".into(), "{\"format\": 3}".into())])
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("junk.json: not a shard file"), "{err}");
}

/// A shard file with a key its format does not define (at the top, in the specification, its
/// surface or an axis, in a line, in a cell) is refused, naming the file and the key, as fits files refuse
/// theirs: a misspelt key would otherwise read as nothing. A leading byte-order mark is
/// skipped, as in fits files.
#[test]
fn shard_files_refuse_unknown_keys_and_skip_a_byte_order_mark() {
    let s = spec(Family::Ggx, ScatteringOrders::Single);
    let sh = Shard { index: 1, count: 1 };
    let lines = compute::compute(&s, sh, &Quadrature::default(), &|_| {}).unwrap();
    let text = shard::write(&s, sh, &lines).unwrap();
    let whole = shard::merge(&[("s.json".into(), text.clone())]).unwrap();
    let with_bom = shard::merge(&[("s.json".into(), format!("\u{feff}{text}"))]).unwrap();
    assert_eq!(Format::Csv.write(&with_bom), Format::Csv.write(&whole));
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    let edits: [fn(&mut serde_json::Value); 6] = [
        |v| v["comment"] = 1.into(),
        |v| v["spec"]["surface"]["comment"] = 1.into(),
        |v| v["spec"]["comment"] = 1.into(),
        |v| v["spec"]["alpha"]["comment"] = 1.into(),
        |v| v["lines"][0]["comment"] = 1.into(),
        |v| v["lines"][0]["cells"][0]["comment"] = 1.into(),
    ];
    for (k, edit) in edits.into_iter().enumerate() {
        let mut v = value.clone();
        edit(&mut v);
        let err = shard::merge(&[("s.json".into(), v.to_string())])
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("s.json: not a shard file") && err.contains("unknown field `comment`"),
            "edit {k}: {err}"
        );
    }
}

/// A shard whose count is far beyond the table's lines (an edited file) is refused, naming the
/// file, before anything is sized by that count: a count of 1e18 had panicked ("capacity
/// overflow").
#[test]
fn a_shard_count_beyond_the_table_is_refused_not_allocated() {
    let s = spec(Family::Ggx, ScatteringOrders::Single);
    let sh = Shard { index: 1, count: 1 };
    let lines = compute::compute(&s, sh, &Quadrature::default(), &|_| {}).unwrap();
    let text = shard::write(&s, sh, &lines).unwrap();
    for count in ["1000000000000000000", "18446744073709551615"] {
        let edited = text.replace(
            "\"shard\":{\"index\":1,\"count\":1}",
            &format!("\"shard\":{{\"index\":1,\"count\":{count}}}"),
        );
        assert_ne!(edited, text);
        let err = shard::merge(&[("huge.json".into(), edited)])
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("huge.json: ") && err.contains("the table has only"),
            "{err}"
        );
    }
}

/// A shard with the wrong lines is refused with a message that lists them shortly and says
/// where they first differ: the whole lists of indices had been printed, 1.5 MB for a shard
/// of 100,000 lines missing its last.
#[test]
fn a_shard_with_the_wrong_lines_is_described_shortly() {
    let mut s = spec(Family::Ggx, ScatteringOrders::Single);
    s.alpha = axis("0.1:0.5:40");
    let sh = Shard { index: 1, count: 2 };
    let lines = compute::compute(&s, sh, &Quadrature::default(), &|_| {}).unwrap();
    assert_eq!(lines.len(), 40);
    let mut short = lines.clone();
    short.pop();
    let err = shard::merge(&[("s.json".into(), shard::write(&s, sh, &short).unwrap())])
        .unwrap_err()
        .to_string();
    assert_eq!(
        err,
        "s.json: shard 1/2 must hold lines [0, 2, 4, 6, 8, ..., 76, 78] (40 lines) of the \
         table, holds [0, 2, 4, 6, 8, ..., 74, 76] (39 lines): it ends after 39 lines, before \
         line 78"
    );
    let mut swapped = lines;
    swapped.swap(20, 21);
    let err = shard::merge(&[("s.json".into(), shard::write(&s, sh, &swapped).unwrap())])
        .unwrap_err()
        .to_string();
    assert!(
        err.ends_with(": its line 21 is 42, where line 40 belongs"),
        "{err}"
    );
}

#[test]
fn every_line_is_in_exactly_one_shard() {
    let s = spec(Family::StudentT, ScatteringOrders::Single);
    let n = s.lines();
    assert_eq!(n, 2 * 2 * 2);
    let mut seen = vec![0; n];
    for k in 1..=n {
        for i in (Shard { index: k, count: n }).lines(n) {
            seen[i] += 1;
        }
    }
    assert!(seen.iter().all(|&c| c == 1));
    assert!(
        Shard {
            index: 1,
            count: n + 1
        }
        .check(n)
        .is_err()
    );
    for bad in ["0/3", "4/3", "1", "a/b", "1/0"] {
        assert!(bad.parse::<Shard>().is_err(), "{bad}");
    }
}

/// The `.npy` header dictionary and the data bytes.
fn npy_parts(bytes: &[u8]) -> (String, &[u8]) {
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    assert_eq!((10 + len) % 64, 0, "header not padded to 64 bytes");
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(header.ends_with('\n'));
    (header.trim_end().to_string(), &bytes[10 + len..])
}

#[test]
fn the_files_hold_the_same_numbers_in_the_documented_layouts() {
    let s = spec(Family::StudentT, ScatteringOrders::All);
    let t = table(&s);
    let csv = String::from_utf8(Format::Csv.write(&t)).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header,
        [
            "surface",
            "ndf",
            "masking",
            "side",
            "alpha",
            "gamma",
            "eta",
            "k",
            "mu",
            "E_ss",
            "R_ss",
            "T_ss",
            "E_avg",
            "R_avg",
            "T_avg",
            "E_all",
            "E_all_stderr",
            "R_all",
            "R_all_stderr",
            "T_all",
            "T_all_stderr"
        ]
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), s.cells());
    // Cell order: side, gamma, eta, mu, then alpha fastest.
    assert_eq!(
        &rows[0][..9],
        [
            "dielectric",
            "student-t",
            "correlated",
            "outside",
            "0.2",
            "1.8",
            "1.5",
            "0.0",
            "0.3"
        ]
    );
    assert_eq!((rows[1][4], rows[1][8]), ("0.8", "0.3"));
    assert_eq!((rows[2][4], rows[2][8]), ("0.2", "0.9"));
    assert_eq!(rows[4][5], "4.0");
    assert_eq!(rows[8][3], "inside");
    let e_ss: Vec<f64> = rows.iter().map(|r| r[9].parse().unwrap()).collect();

    // .npy: one record per cell, C order (side, gamma, eta, mu, alpha).
    let npy = Format::Npy.write(&t);
    let (dict, data) = npy_parts(&npy);
    assert!(dict.contains("'fortran_order': False"), "{dict}");
    assert!(dict.contains("'shape': (2, 2, 1, 2, 2)"), "{dict}");
    assert!(dict.starts_with("{'descr': [('side', '|u1'), ('surface', '|S10'), ('ndf', '|S9'), ('masking', '|S15'), ('alpha', '<f8'), ('gamma', '<f8'), ('eta', '<f8'), ('mu', '<f8'), ('E_ss', '<f8')"), "{dict}");
    let fields = dict.matches("'<f8'").count();
    let record = 1 + 34 + 8 * fields;
    assert_eq!(data.len(), record * s.cells());
    for (i, rec) in data.chunks(record).enumerate() {
        assert_eq!(rec[0], u8::from(i >= 8), "side of record {i}");
        // surface |S10, ndf |S9, masking |S15: NUL-padded.
        assert_eq!(
            &rec[1..35],
            b"dielectricstudent-tcorrelated\0\0\0\0\0",
            "text of record {i}"
        );
        let field = |k: usize| f64::from_le_bytes(rec[35 + 8 * k..43 + 8 * k].try_into().unwrap());
        assert_eq!(field(4), e_ss[i], "E_ss of record {i}");
        assert_eq!(
            field(3),
            rows[i][8].parse::<f64>().unwrap(),
            "mu of record {i}"
        );
    }

    // C header: per side E[g][z][y][x] as floats, then Eavg[g][z][x], then the walk arrays.
    let c = String::from_utf8(Format::C.write(&t)).unwrap();
    let array = |name: &str| -> Vec<f32> {
        let start = c
            .find(&format!("static const float {name}["))
            .unwrap_or_else(|| panic!("{name}"));
        let body = &c[start..];
        let (open, close) = (body.find('{').unwrap(), body.find('}').unwrap());
        body[open + 1..close]
            .split(',')
            .map(|v| v.trim().trim_end_matches('f').parse().unwrap())
            .collect()
    };
    let out = array("table_student_t_glass_E");
    let inv = array("table_student_t_glass_inv_E");
    assert_eq!(out.len(), 8);
    for i in 0..8 {
        assert_eq!(out[i], e_ss[i] as f32);
        assert_eq!(inv[i], e_ss[8 + i] as f32);
    }
    let avg = array("table_student_t_glass_Eavg");
    assert_eq!(avg.len(), 4);
    assert_eq!(avg[1], rows[1][12].parse::<f64>().unwrap() as f32);
    assert_eq!(avg[2], rows[4][12].parse::<f64>().unwrap() as f32);
    for name in [
        "E_all",
        "E_all_stderr",
        "R_all",
        "R_all_stderr",
        "T_all",
        "T_all_stderr",
    ] {
        assert_eq!(
            array(&format!("table_student_t_glass_{name}")).len(),
            8,
            "{name}"
        );
    }
}

#[test]
fn a_table_of_the_inside_side_alone_records_side_1_in_the_npy() {
    // The `side` field is the side itself (0 outside, 1 inside), not its position in the
    // table: with `--side inside` alone every record has 1, as the CSV says `inside`.
    let mut s = spec(Family::Ggx, ScatteringOrders::Single);
    s.sides = vec![Side::Inside];
    let t = table(&s);
    let csv = String::from_utf8(Format::Csv.write(&t)).unwrap();
    assert!(
        csv.lines()
            .skip(1)
            .all(|r| r.split(',').nth(3) == Some("inside"))
    );
    let npy = Format::Npy.write(&t);
    let (dict, data) = npy_parts(&npy);
    let record = 1 + 34 + 8 * dict.matches("'<f8'").count();
    assert_eq!(data.len(), record * s.cells());
    for (i, rec) in data.chunks(record).enumerate() {
        assert_eq!(rec[0], 1, "side of record {i}");
    }
}

#[test]
fn specifications_outside_the_supported_range_are_refused() {
    let base = spec(Family::Ggx, ScatteringOrders::Single);
    let refused = |edit: &dyn Fn(&mut TableSpec)| {
        let mut s = base.clone();
        edit(&mut s);
        s.check().unwrap_err()
    };
    let e = refused(&|s| s.alpha = axis("0,0.5"));
    assert!(matches!(e, SpecError::Axis { axis: "alpha", .. }), "{e}");
    assert!(
        refused(&|s| s.alpha = axis("5"))
            .to_string()
            .contains("supported range")
    );
    assert!(matches!(
        refused(&|s| s.mu = axis("0:1:3")),
        SpecError::Axis { axis: "mu", .. }
    ));
    assert!(matches!(
        refused(&|s| s.eta = Some(axis("1.0"))),
        SpecError::Axis { axis: "eta", .. }
    ));
    assert!(matches!(
        refused(&|s| s.eta = Some(axis("0.67"))),
        SpecError::Axis { axis: "eta", .. }
    ));
    refused(&|s| s.eta = None);
    refused(&|s| s.gamma = Some(axis("3")));
    refused(&|s| {
        s.family = Family::StudentT;
        s.gamma = Some(axis("1.55"));
    });
    refused(&|s| s.sides = vec![Side::Inside, Side::Outside]);
    refused(&|s| {
        s.surface = Surface::Mirror;
        s.eta = None;
    });
    refused(&|s| {
        s.surface = Surface::Conductor { n: -1.0, k: 0.0 };
        s.eta = None;
        s.sides = vec![Side::Outside];
    });
    refused(&|s| {
        s.orders = ScatteringOrders::All;
        s.walks = 0;
    });
}

#[test]
fn the_cycles_layout_has_cycles_nodes() {
    let s = TableSpec::cycles(
        Family::Ggx,
        Surface::Dielectric,
        TableMasking::ReflectionForm,
        ScatteringOrders::Single,
        None,
    );
    s.check().unwrap();
    assert_eq!(s.shape(), [2, 1, 16, 16, 16]);
    assert_eq!(s.sides, [Side::Outside, Side::Inside]);
    let eta = s.eta.as_ref().unwrap();
    for i in 0..16 {
        let r = (i as f64 / 15.0).clamp(1e-4, 1.0);
        assert_eq!(s.alpha.values[i], r * r);
        assert_eq!(s.mu.values[i], (i as f64 / 15.0).clamp(1e-4, 1.0));
        let t = (i as f64 / 15.0).clamp(1e-4, 0.99);
        assert_eq!(eta.values[i], (1.0 + t * t) / (1.0 - t * t));
    }
    let m = TableSpec::cycles(
        Family::Ggx,
        Surface::Mirror,
        TableMasking::Correlated,
        ScatteringOrders::Single,
        None,
    );
    m.check().unwrap();
    assert_eq!(m.shape(), [1, 1, 1, 32, 32]);
}
