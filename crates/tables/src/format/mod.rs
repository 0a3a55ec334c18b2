//! The files a table is written to: CSV, NumPy `.npy` and C headers in Cycles' layout (all
//! documented in `tables-format.md`), and the shard files that [`shard::merge`] joins.
//!
//! Every writer is a pure function of the [`Table`], so a table merged from shards is written
//! byte for byte as the single run would write it.

pub mod c_header;
pub mod csv;
pub mod npy;
pub mod shard;

use crate::compute::{CellResult, Table, WalkResult};
use crate::single::Albedo;
use crate::spec::{Family, Line, Surface, TableSpec};
use std::path::Path;
use std::str::FromStr;
use stfit_core::walk::ScatteringOrders;

/// An output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Csv,
    Npy,
    C,
}

impl Format {
    /// The format named by a file's extension: `.npy`; `.h`, `.hpp`, `.c`, `.inc` for C; CSV
    /// otherwise.
    pub fn from_path(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some("npy") => Self::Npy,
            Some("h" | "hpp" | "c" | "inc") => Self::C,
            _ => Self::Csv,
        }
    }

    /// The file contents of a table in this format.
    pub fn write(self, table: &Table) -> Vec<u8> {
        match self {
            Self::Csv => csv::write(table).into_bytes(),
            Self::Npy => npy::write(table),
            Self::C => c_header::write(table).into_bytes(),
        }
    }
}

impl FromStr for Format {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "csv" => Ok(Self::Csv),
            "npy" => Ok(Self::Npy),
            "c" => Ok(Self::C),
            other => Err(format!("unknown format '{other}' (expected csv, npy or c)")),
        }
    }
}

/// One numeric quantity of a cell, as a CSV column and an `.npy` field.
pub(crate) struct Column {
    pub name: &'static str,
    pub get: fn(&Row) -> f64,
    /// True for the random walks' estimates.
    pub walk: bool,
}

/// A cell with what its columns are read from.
pub(crate) struct Row<'a> {
    pub line: Line,
    pub mu: f64,
    pub cell: &'a CellResult,
    pub average: Albedo,
}

/// The suffix of the walk columns: `all` for all orders, `ms` for orders >= 2.
pub(crate) fn walk_suffix(spec: &TableSpec) -> Option<&'static str> {
    match spec.orders {
        ScatteringOrders::Single => None,
        ScatteringOrders::Multiple => Some("ms"),
        ScatteringOrders::All => Some("all"),
    }
}

/// The quantities of every cell, in column order: the single-scattering albedo and its split,
/// the line's average and its split, and the walks' estimates with their standard errors.
pub(crate) fn quantity_columns(spec: &TableSpec) -> Vec<Column> {
    let mut cols = vec![
        Column {
            name: "E_ss",
            get: |r| r.cell.single.total(),
            walk: false,
        },
        Column {
            name: "R_ss",
            get: |r| r.cell.single.reflected,
            walk: false,
        },
        Column {
            name: "T_ss",
            get: |r| r.cell.single.transmitted,
            walk: false,
        },
        Column {
            name: "E_avg",
            get: |r| r.average.total(),
            walk: false,
        },
        Column {
            name: "R_avg",
            get: |r| r.average.reflected,
            walk: false,
        },
        Column {
            name: "T_avg",
            get: |r| r.average.transmitted,
            walk: false,
        },
    ];
    if let Some(suffix) = walk_suffix(spec) {
        let names: [&'static str; 6] = if suffix == "all" {
            [
                "E_all",
                "E_all_stderr",
                "R_all",
                "R_all_stderr",
                "T_all",
                "T_all_stderr",
            ]
        } else {
            [
                "E_ms",
                "E_ms_stderr",
                "R_ms",
                "R_ms_stderr",
                "T_ms",
                "T_ms_stderr",
            ]
        };
        let getters: [fn(&Row) -> f64; 6] = [
            |r| walk_of(r).total.mean,
            |r| walk_of(r).total.stderr,
            |r| walk_of(r).reflected.mean,
            |r| walk_of(r).reflected.stderr,
            |r| walk_of(r).transmitted.mean,
            |r| walk_of(r).transmitted.stderr,
        ];
        cols.extend(names.into_iter().zip(getters).map(|(name, get)| Column {
            name,
            get,
            walk: true,
        }));
    }
    cols
}

/// The walk results of a row (zero for a table without walks, which has no walk column).
fn walk_of(r: &Row) -> WalkResult {
    r.cell.walk.unwrap_or_default()
}

/// The cells of a table in cell order, as rows.
pub(crate) fn rows(table: &Table) -> Vec<Row<'_>> {
    let spec = &table.spec;
    let mut rows: Vec<(usize, Row)> = Vec::with_capacity(spec.cells());
    for l in &table.lines {
        let line = spec.line(l.index);
        for (y, cell) in l.cells.iter().enumerate() {
            let row = Row {
                line,
                mu: spec.mu.values[y],
                cell,
                average: l.average,
            };
            rows.push((spec.cell_index(line, y), row));
        }
    }
    rows.sort_unstable_by_key(|r| r.0);
    rows.into_iter().map(|r| r.1).collect()
}

/// The real part of the conductor's index (or the dielectric's eta) and its imaginary part,
/// for the `eta` and `k` columns; `None` where they do not apply (mirror facets).
pub(crate) fn index_columns(spec: &TableSpec, line: Line) -> (Option<f64>, Option<f64>) {
    match spec.surface {
        Surface::Dielectric => (spec.eta_value(line), Some(0.0)),
        Surface::Conductor { n, k } => (Some(n), Some(k)),
        Surface::Mirror => (None, None),
    }
}

/// Whether the gamma column applies (not to Beckmann).
pub(crate) fn has_gamma(spec: &TableSpec) -> bool {
    spec.family != Family::Beckmann
}
