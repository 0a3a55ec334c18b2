//! NumPy `.npy` (format version 1.0, written by hand): one structured array with one record
//! per cell and the shape of the table (see `tables-format.md`).

use super::{has_gamma, index_columns, quantity_columns, rows};
use crate::compute::Table;
use crate::spec::{Side, Surface, TableSpec};

/// The value of a text field for a table.
type TextOf = fn(&TableSpec) -> &'static str;

/// The text fields of every record, as in the CSV: name, `numpy` type (a NUL-padded byte
/// string of the longest value's length) and the value of a table.
const TEXT_FIELDS: [(&str, &str, TextOf); 3] = [
    ("surface", "|S10", |s| s.surface.name()),
    ("ndf", "|S9", |s| s.family.name()),
    ("masking", "|S15", |s| s.masking.name()),
];

/// Length of a `|S<n>` type.
fn text_len(ty: &str) -> usize {
    ty[2..].parse().unwrap_or(0)
}

/// The `.npy` bytes of a table: a C-ordered structured array of shape `(sides, gamma, eta,
/// mu, alpha)` (an axis that does not apply has length 1) whose records hold `side` (`|u1`: 0
/// outside, 1 inside), `surface`, `ndf` and `masking` (byte strings, the CSV's names), the
/// cell's `alpha`, `gamma` (not for Beckmann), `eta` (not for mirrors), `k` (conductors), `mu`,
/// then the CSV's quantity columns in the same order, each little-endian `f8`.
pub fn write(table: &Table) -> Vec<u8> {
    let spec = &table.spec;
    let quantities = quantity_columns(spec);
    let gamma = has_gamma(spec);
    let eta = spec.surface != Surface::Mirror;
    let k = matches!(spec.surface, Surface::Conductor { .. });
    let mut fields: Vec<(&str, &str)> = vec![("side", "|u1")];
    fields.extend(TEXT_FIELDS.iter().map(|&(name, ty, _)| (name, ty)));
    fields.push(("alpha", "<f8"));
    if gamma {
        fields.push(("gamma", "<f8"));
    }
    if eta {
        fields.push(("eta", "<f8"));
    }
    if k {
        fields.push(("k", "<f8"));
    }
    fields.push(("mu", "<f8"));
    fields.extend(quantities.iter().map(|c| (c.name, "<f8")));
    let descr: Vec<String> = fields
        .iter()
        .map(|(name, ty)| format!("('{name}', '{ty}')"))
        .collect();
    let shape: Vec<String> = spec.shape().iter().map(|n| n.to_string()).collect();
    let mut header = format!(
        "{{'descr': [{}], 'fortran_order': False, 'shape': ({}), }}",
        descr.join(", "),
        shape.join(", ")
    );
    // Magic (6) + version (2) + header length (2) + header, padded with spaces and ended by a
    // newline to a multiple of 64 bytes.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let text_bytes: usize = TEXT_FIELDS.iter().map(|f| text_len(f.1)).sum();
    let record = 1 + text_bytes + 8 * (fields.len() - 1 - TEXT_FIELDS.len());
    let mut text = Vec::with_capacity(text_bytes);
    for (_, ty, value) in TEXT_FIELDS {
        let mut bytes = value(spec).as_bytes().to_vec();
        bytes.resize(text_len(ty), 0);
        text.extend_from_slice(&bytes);
    }
    let mut out = Vec::with_capacity(10 + header.len() + record * spec.cells());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for row in rows(table) {
        let line = row.line;
        let (eta_value, k_value) = index_columns(spec, line);
        // `line.side` indexes `spec.sides`, which may be `[Inside]` alone.
        out.push(u8::from(spec.sides[line.side] == Side::Inside));
        out.extend_from_slice(&text);
        let mut put = |v: f64| out.extend_from_slice(&v.to_le_bytes());
        put(spec.alpha.values[line.alpha]);
        if gamma {
            put(spec.gamma_value(line).unwrap_or(2.0));
        }
        if eta {
            put(eta_value.unwrap_or(0.0));
        }
        if k {
            put(k_value.unwrap_or(0.0));
        }
        put(row.mu);
        for c in &quantities {
            put((c.get)(&row));
        }
    }
    out
}
