//! C headers of `static const float` arrays in the layout of Blender Cycles'
//! `src/scene/shader.tables` (see `tables-format.md`).

use super::{Column, quantity_columns, rows};
use crate::compute::Table;
use crate::spec::{Side, Surface, TableSpec};
use std::fmt::Write;

/// The name prefix of a side's arrays: `table_<ndf>_glass` (light from outside) and
/// `table_<ndf>_glass_inv` (from inside) for dielectrics, as Cycles' `ggx_glass_E` and
/// `ggx_glass_inv_E`; `table_<ndf>` for mirror facets (Cycles' `ggx_E`);
/// `table_<ndf>_conductor` for Fresnel conductors.
pub fn prefix(spec: &TableSpec, side: Side) -> String {
    let ndf = spec.family.c_name();
    match (spec.surface, side) {
        (Surface::Dielectric, Side::Outside) => format!("table_{ndf}_glass"),
        (Surface::Dielectric, Side::Inside) => format!("table_{ndf}_glass_inv"),
        (Surface::Mirror, _) => format!("table_{ndf}"),
        (Surface::Conductor { .. }, _) => format!("table_{ndf}_conductor"),
    }
}

/// A float literal that reads back to the same `f32`: always with a decimal point or an
/// exponent, and the `f` suffix.
fn literal(v: f64) -> String {
    format!("{:?}f", v as f32)
}

/// Writes one array: `values` in rows of `row` numbers, a blank line after every `slice` rows.
fn array(out: &mut String, name: &str, values: &[f64], row: usize, slice: usize) {
    let _ = writeln!(out, "static const float {name}[{}] = {{", values.len());
    let rows: Vec<&[f64]> = values.chunks(row).collect();
    for (i, r) in rows.iter().enumerate() {
        let items: Vec<String> = r.iter().map(|&v| literal(v)).collect();
        let last = i + 1 == rows.len();
        let _ = writeln!(out, "  {}{}", items.join(", "), if last { "" } else { "," });
        if !last && (i + 1) % slice == 0 {
            out.push('\n');
        }
    }
    out.push_str("};\n\n");
}

/// The header text of a table: for each side, `<prefix>_E` (the single-scattering albedo,
/// `[gamma][eta][mu][alpha]` flattened with alpha fastest), `<prefix>_Eavg`
/// (`[gamma][eta][alpha]`), and with walks the walk columns (`<prefix>_E_all`,
/// `<prefix>_E_all_stderr`, ... or `..._ms`) laid out like `_E`. With one gamma this is Cycles'
/// 16 x 16 x 16 layout: `x` roughness, `y` mu, `z` the ior parameter.
pub fn write(table: &Table) -> String {
    let spec = &table.spec;
    let [_, n_gamma, n_eta, n_mu, n_alpha] = spec.shape();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "/* Directional albedo tables written by stfit-tables {}.",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        out,
        " * surface {}, ndf {}, masking {}, orders {}{}.",
        match spec.surface {
            Surface::Conductor { n, k } => format!("conductor (n = {n}, k = {k})"),
            s => s.name().to_string(),
        },
        spec.family.name(),
        spec.masking.name(),
        crate::spec::orders_str(spec.orders),
        if spec.walks_needed() {
            format!(", {} walks per cell, seed {}", spec.walks, spec.seed)
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        out,
        " * Layout: <prefix>_E[((g * {n_eta} + z) * {n_mu} + y) * {n_alpha} + x], \
         <prefix>_Eavg[(g * {n_eta} + z) * {n_alpha} + x]."
    );
    let _ = writeln!(out, " * x: alpha, {}", spec.alpha);
    let _ = writeln!(out, " * y: mu, {}", spec.mu);
    if let Some(eta) = &spec.eta {
        let _ = writeln!(out, " * z: eta = n_inside / n_outside, {eta}");
    }
    if let Some(gamma) = &spec.gamma {
        let _ = writeln!(out, " * g: gamma, {gamma}");
    }
    out.push_str(" * See tables-format.md of stfit. */\n\n");

    let rows = rows(table);
    let cells_per_side = n_gamma * n_eta * n_mu * n_alpha;
    // The single-scattering albedo (named `E` as in Cycles) and the walks' estimates.
    let quantities: Vec<Column> = quantity_columns(spec)
        .into_iter()
        .filter(|c| c.name == "E_ss" || c.walk)
        .collect();
    for (s, &side) in spec.sides.iter().enumerate() {
        let side_rows = &rows[s * cells_per_side..(s + 1) * cells_per_side];
        let p = prefix(spec, side);
        for c in &quantities {
            let values: Vec<f64> = side_rows.iter().map(c.get).collect();
            let name = if c.walk { c.name } else { "E" };
            array(&mut out, &format!("{p}_{name}"), &values, n_alpha, n_mu);
            if !c.walk {
                // The average: the mu = first row of each (gamma, eta) slice.
                let avg: Vec<f64> = side_rows
                    .chunks(n_mu * n_alpha)
                    .flat_map(|slice| slice[..n_alpha].iter().map(|r| r.average.total()))
                    .collect();
                array(&mut out, &format!("{p}_Eavg"), &avg, n_alpha, n_eta);
            }
        }
    }
    out
}
