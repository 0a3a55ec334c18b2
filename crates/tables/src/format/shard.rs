//! Shard files: one slice of a table (`--shard K/N`) with the specification it belongs to, as
//! JSON, and their merge into the table a single run computes.

use crate::compute::{LineResult, Shard, Table, Value};
use crate::error::ShardError;
use crate::single::{Albedo, TableMasking};
use crate::spec::TableSpec;
use serde::{Deserialize, Serialize};
use stfit_core::error::show;
use stfit_core::walk::ScatteringOrders;

/// The `format` tag of a shard file.
pub const FORMAT: &str = "stfit-tables-shard";
/// The version of the shard file format.
pub const VERSION: u32 = 1;

/// How far a value read from a shard may lie outside what it can be (fractions in `[0, 1]`,
/// sums of fractions): ten times the largest quadrature error measured (tables-format.md).
pub const TOLERANCE: f64 = 1e-5;

/// The contents of a shard file.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ShardFile {
    format: String,
    version: u32,
    spec: TableSpec,
    shard: Shard,
    lines: Vec<LineResult>,
}

/// The JSON text of a shard: its specification, which slice it is, and its lines. Numbers are
/// written in the shortest form that reads back to the same `f64`, so a merge loses nothing.
pub fn write(
    spec: &TableSpec,
    shard: Shard,
    lines: &[LineResult],
) -> Result<String, serde_json::Error> {
    let file = ShardFile {
        format: FORMAT.into(),
        version: VERSION,
        spec: spec.clone(),
        shard,
        lines: lines.to_vec(),
    };
    let mut text = serde_json::to_string(&file)?;
    text.push('\n');
    Ok(text)
}

/// Joins shard files, given as `(name, contents)`, into the table one run of their
/// specification computes. Every shard `1..=N` of one specification must be given exactly
/// once, each with exactly its lines.
pub fn merge(files: &[(String, String)]) -> Result<Table, ShardError> {
    let mut reference: Option<(TableSpec, usize)> = None;
    let mut seen: Vec<Option<String>> = Vec::new();
    let mut lines: Vec<LineResult> = Vec::new();
    for (name, text) in files {
        let mismatch = |message: String| ShardError::Mismatch {
            file: name.clone(),
            message,
        };
        let unreadable = |message: String| ShardError::Parse {
            file: name.clone(),
            message: format!("not a shard file of stfit tables: {message}"),
        };
        // A leading byte-order mark is skipped, as the fits reader does.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let file: ShardFile = serde_json::from_str(text).map_err(|e| unreadable(e.to_string()))?;
        // The surface is an internally tagged enum, whose extra keys serde's
        // deny_unknown_fields does not see: its keys are those it writes back.
        let read: serde_json::Value =
            serde_json::from_str(text).map_err(|e| unreadable(e.to_string()))?;
        let known =
            serde_json::to_value(file.spec.surface).map_err(|e| unreadable(e.to_string()))?;
        if let (Some(given), Some(known)) = (read["spec"]["surface"].as_object(), known.as_object())
            && let Some(key) = given.keys().find(|k| !known.contains_key(*k))
        {
            return Err(unreadable(format!("unknown field `{key}` in spec.surface")));
        }
        if file.format != FORMAT || file.version != VERSION {
            return Err(mismatch(format!(
                "format '{}' version {} (expected '{FORMAT}' version {VERSION})",
                file.format, file.version
            )));
        }
        file.spec
            .check()
            .map_err(|e| mismatch(format!("invalid table specification: {e}")))?;
        // Before anything is sized by the count: a count beyond the table's lines (1e18) is
        // refused here, not allocated.
        file.shard
            .check(file.spec.lines())
            .map_err(|e| mismatch(e.to_string()))?;
        let (spec, count) = reference.get_or_insert_with(|| {
            seen = vec![None; file.shard.count];
            (file.spec.clone(), file.shard.count)
        });
        if file.spec != *spec {
            return Err(mismatch(format!(
                "its table specification differs from that of {}",
                files[0].0
            )));
        }
        let shard = file.shard;
        if shard.count != *count || shard.index == 0 || shard.index > shard.count {
            return Err(mismatch(format!(
                "shard {shard} does not belong to a split into {count}"
            )));
        }
        shard
            .check(spec.lines())
            .map_err(|e| mismatch(e.to_string()))?;
        if let Some(other) = &seen[shard.index - 1] {
            return Err(mismatch(format!("shard {shard} is also given as {other}")));
        }
        seen[shard.index - 1] = Some(name.clone());
        let expected: Vec<usize> = shard.lines(spec.lines()).collect();
        let got: Vec<usize> = file.lines.iter().map(|l| l.index).collect();
        if got != expected {
            return Err(mismatch(format!(
                "shard {shard} must hold lines {} of the table, holds {}{}",
                line_list(&expected),
                line_list(&got),
                first_difference(&expected, &got)
            )));
        }
        for l in &file.lines {
            if l.cells.len() != spec.mu.len()
                || l.cells
                    .iter()
                    .any(|c| c.walk.is_some() != spec.walks_needed())
            {
                return Err(mismatch(format!(
                    "line {} does not have the {} cells of the specification",
                    l.index,
                    spec.mu.len()
                )));
            }
            check_values(spec, l).map_err(|m| mismatch(format!("line {}, {m}", l.index)))?;
        }
        // What the checks accept within the tolerance is moved into range, so that the
        // merged table keeps the promise of tables-format.md: E_ss and E_avg in [0, 1].
        lines.extend(file.lines.into_iter().map(|mut l| {
            l.average = l.average.into_range(TOLERANCE);
            for c in &mut l.cells {
                c.single = c.single.into_range(TOLERANCE);
            }
            l
        }));
    }
    let Some((spec, count)) = reference else {
        return Err(ShardError::Incomplete("no shard files given".into()));
    };
    let missing: Vec<String> = seen
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(k, _)| format!("{}/{count}", k + 1))
        .collect();
    if !missing.is_empty() {
        return Err(ShardError::Incomplete(format!(
            "missing shards: {}",
            missing.join(", ")
        )));
    }
    lines.sort_unstable_by_key(|l| l.index);
    Ok(Table { spec, lines })
}

/// Line indices as a message lists them: all of up to 10, else the first 5, the last 2 and
/// how many, so that a shard of a million lines is not echoed whole.
fn line_list(lines: &[usize]) -> String {
    if lines.len() <= 10 {
        return format!("{lines:?}");
    }
    let head: Vec<String> = lines[..5].iter().map(usize::to_string).collect();
    let tail: Vec<String> = lines[lines.len() - 2..]
        .iter()
        .map(usize::to_string)
        .collect();
    format!(
        "[{}, ..., {}] ({} lines)",
        head.join(", "),
        tail.join(", "),
        lines.len()
    )
}

/// Where two long lists of line indices first differ, for a message that cannot show them
/// whole ([`line_list`]); empty when both are short enough to be shown.
fn first_difference(expected: &[usize], got: &[usize]) -> String {
    if expected.len() <= 10 && got.len() <= 10 {
        return String::new();
    }
    let k = expected.iter().zip(got).take_while(|(e, g)| e == g).count();
    match (expected.get(k), got.get(k)) {
        (Some(e), Some(g)) => format!(": its line {} is {g}, where line {e} belongs", k + 1),
        (Some(e), None) => format!(": it ends after {k} lines, before line {e}"),
        (None, Some(g)) => format!(
            ": its line {} is {g}, after the last one it must hold",
            k + 1
        ),
        (None, None) => String::new(),
    }
}

/// Checks that `v`, the value `label` names, is in `[lo, hi]` within [`TOLERANCE`].
fn within(label: &str, v: f64, lo: f64, hi: f64) -> Result<(), String> {
    if v.is_finite() && v >= lo - TOLERANCE && v <= hi + TOLERANCE {
        return Ok(());
    }
    Err(format!(
        "{label} = {} is not in [{lo}, {hi}] (tolerance {TOLERANCE:e})",
        show(v)
    ))
}

/// Checks a single-scattering albedo, the field `name` (CSV columns `*_<suffix>`): reflected,
/// transmitted and their sum are fractions.
fn check_albedo(name: &str, suffix: &str, a: &Albedo) -> Result<(), String> {
    let r = format!("{name}.reflected (R_{suffix})");
    within(&r, a.reflected, 0.0, 1.0)?;
    let t = format!("{name}.transmitted (T_{suffix})");
    within(&t, a.transmitted, 0.0, 1.0)?;
    let e = format!("{name}.reflected + {name}.transmitted (E_{suffix})");
    within(&e, a.total(), 0.0, 1.0)
}

/// Checks the values of a line read from a shard against what they can be: single-scattering
/// albedos and their averages are fractions ([`check_albedo`]); a walk's standard errors are
/// in `[0, 1]`; its means are fractions for orders >= 2, and for all orders `E_ss` (the
/// height-correlated one: the cell's own with that masking) plus a fraction; its total is
/// reflected plus transmitted; its truncated flux is a fraction. All within [`TOLERANCE`].
fn check_values(spec: &TableSpec, line: &LineResult) -> Result<(), String> {
    check_albedo("average", "avg", &line.average)?;
    let suffix = match spec.orders {
        ScatteringOrders::All => "all",
        _ => "ms",
    };
    for (y, cell) in line.cells.iter().enumerate() {
        let at = |m: String| format!("cell {y} (mu {}): {m}", spec.mu.values[y]);
        check_albedo("single", "ss", &cell.single).map_err(at)?;
        let Some(w) = &cell.walk else { continue };
        let first = match spec.orders {
            ScatteringOrders::All if spec.masking == TableMasking::Correlated => Some(cell.single),
            _ => None,
        };
        let parts = [
            ("reflected", "R", w.reflected, first.map(|a| a.reflected)),
            (
                "transmitted",
                "T",
                w.transmitted,
                first.map(|a| a.transmitted),
            ),
            ("total", "E", w.total, first.map(|a| a.total())),
        ];
        for (name, letter, value, first) in parts {
            check_walk(spec, name, letter, value, first).map_err(at)?;
        }
        let sum = w.reflected.mean + w.transmitted.mean;
        if (w.total.mean - sum).abs() > TOLERANCE {
            return Err(at(format!(
                "walk.total.mean (E_{suffix}) = {} is not walk.reflected.mean + \
                 walk.transmitted.mean = {}",
                show(w.total.mean),
                show(sum)
            )));
        }
        within("walk.truncated", w.truncated, 0.0, 1.0).map_err(at)?;
    }
    Ok(())
}

/// Checks one walk estimate, the field `walk.<name>` (CSV column `<letter>_all` or
/// `<letter>_ms`): its standard error is in `[0, 1]`; its mean, less `first` (the cell's
/// `<letter>_ss` when it is the all-orders estimate's first order), is a fraction, and with all
/// orders but no `first`, it is at most 2.
fn check_walk(
    spec: &TableSpec,
    name: &str,
    letter: &str,
    v: Value,
    first: Option<f64>,
) -> Result<(), String> {
    let column = match spec.orders {
        ScatteringOrders::All => format!("{letter}_all"),
        _ => format!("{letter}_ms"),
    };
    let stderr = format!("walk.{name}.stderr ({column}_stderr)");
    within(&stderr, v.stderr, 0.0, 1.0)?;
    let mean = format!("walk.{name}.mean ({column})");
    match (first, spec.orders) {
        (Some(first), _) => within(&format!("{mean} - {letter}_ss"), v.mean - first, 0.0, 1.0),
        (None, ScatteringOrders::All) => within(&mean, v.mean, 0.0, 2.0),
        (None, _) => within(&mean, v.mean, 0.0, 1.0),
    }
}
