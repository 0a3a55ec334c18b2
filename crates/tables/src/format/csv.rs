//! CSV: one row per cell, in cell order, with a header row (see `tables-format.md`).

use super::{has_gamma, index_columns, quantity_columns, rows};
use crate::compute::Table;
use std::fmt::Write;

/// The CSV text of a table: the columns `surface, ndf, masking, side, alpha, gamma, eta, k, mu`
/// describe the cell (`gamma` is empty for Beckmann and 2 for GGX; `eta` and `k` are the
/// dielectric's `n_inside / n_outside` and 0, the conductor's `n` and `k`, or empty for mirror
/// facets), then the quantity columns (`E_ss`, `R_ss`, ..., as tables-format.md lists them).
/// Numbers are written in the shortest form that reads back to the same `f64` (Rust's `{:?}`:
/// `0.5`, `2.0`, `1e-8`).
pub fn write(table: &Table) -> String {
    let spec = &table.spec;
    let quantities = quantity_columns(spec);
    let mut out = String::from("surface,ndf,masking,side,alpha,gamma,eta,k,mu");
    for c in &quantities {
        out.push(',');
        out.push_str(c.name);
    }
    out.push('\n');
    let opt = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:?}"));
    for row in rows(table) {
        let line = row.line;
        let (eta, k) = index_columns(spec, line);
        let gamma = if has_gamma(spec) {
            spec.gamma_value(line)
        } else {
            None
        };
        let _ = write!(
            out,
            "{},{},{},{},{:?},{},{},{},{:?}",
            spec.surface.name(),
            spec.family.name(),
            spec.masking.name(),
            spec.sides[line.side].name(),
            spec.alpha.values[line.alpha],
            opt(gamma),
            opt(eta),
            opt(k),
            row.mu,
        );
        for c in &quantities {
            let _ = write!(out, ",{:?}", (c.get)(&row));
        }
        out.push('\n');
    }
    out
}
