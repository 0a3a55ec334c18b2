//! Shard files: one slice of a table (`--shard K/N`) with the specification it belongs to, as
//! JSON, and their merge into the table a single run computes.

use crate::compute::{LineResult, Shard, Table};
use crate::error::ShardError;
use crate::spec::TableSpec;
use serde::{Deserialize, Serialize};

/// The `format` tag of a shard file.
pub const FORMAT: &str = "stfit-tables-shard";
/// The version of the shard file format.
pub const VERSION: u32 = 1;

/// The contents of a shard file.
#[derive(Debug, Serialize, Deserialize)]
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
        let file: ShardFile = serde_json::from_str(text).map_err(|e| ShardError::Parse {
            file: name.clone(),
            message: format!("not a shard file of stfit tables: {e}"),
        })?;
        if file.format != FORMAT || file.version != VERSION {
            return Err(mismatch(format!(
                "format '{}' version {} (expected '{FORMAT}' version {VERSION})",
                file.format, file.version
            )));
        }
        file.spec
            .check()
            .map_err(|e| mismatch(format!("invalid table specification: {e}")))?;
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
                "shard {shard} must hold lines {expected:?} of the table, holds {got:?}"
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
        }
        lines.extend(file.lines);
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
