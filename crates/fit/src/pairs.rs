//! Tables of direction pairs, the input and output of `stfit eval`: CSV with the columns
//! `wi_x, wi_y, wi_z, wo_x, wo_y, wo_z` (any order; other columns are passed through), one
//! pair of unit vectors in the local frame per row (z > 0 outside, `wi` toward the light), read
//! with the text rules of every stfit file (`data-format.md`: byte-order mark, comments, blank
//! lines, quoting) and errors that name the source, the line and the column.

use std::io::{self, Write};
use std::path::Path;

use stfit_core::Vec3;
use stfit_core::error::show;

use crate::load::{LoadError, LoadErrorKind, records_until_quote_problem, text_fields};

/// The direction columns, in the order `(wi, wo)`.
pub const PAIR_COLUMNS: [&str; 6] = ["wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"];

/// The value column appended to the table: `f(wi, wo) |wo.z|`.
pub const VALUE_COLUMN: &str = "f_cos";

/// The standard-error column appended after it for Monte Carlo estimates.
pub const STDERR_COLUMN: &str = "f_cos_stderr";

/// Largest accepted `| |w| - 1 |`: directions are checked; an accepted one is then scaled to
/// unit length ([`stfit_core::math::to_unit`]; exactly unit input is kept as it is).
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// True for the norm of a unit vector: `|norm - 1| <= UNIT_TOLERANCE` up to the rounding of
/// decimal input (false for NaN): a few units in the last place of 1 are forgiven, so that
/// `(0, 0, 0.999999)`, whose binary norm is 1 - 1.00000000003e-6, is accepted as the tolerance
/// reads in decimal. The one test of the library's unit-direction precondition, for files and
/// for arrays.
#[inline]
pub fn is_unit_norm(norm: f64) -> bool {
    (norm - 1.0).abs() <= UNIT_TOLERANCE + 4.0 * f64::EPSILON
}

/// True for a direction's `z` that is subnormal (nonzero and below 2.2e-308 in magnitude).
#[inline]
fn is_subnormal_z(z: f64) -> bool {
    z != 0.0 && z.abs() < f64::MIN_POSITIVE
}

/// Why a direction is not one the library takes: the one test behind every direction read from
/// a file or passed as an array ([`direction_problem`]), and its message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DirectionProblem {
    /// A coordinate that is NaN or infinite.
    NotFinite,
    /// Finite coordinates whose norm is not 1 to [`UNIT_TOLERANCE`] ([`is_unit_norm`]); the
    /// norm as the message states it, without the overflow or underflow of its squares.
    NotUnit { norm: f64 },
    /// A unit vector whose `z` is subnormal: `1 / |z|` (in the BSDF, the visible-normal density,
    /// Smith's `Lambda`) overflows, where a `z` of 0 is the horizon.
    SubnormalZ(f64),
}

impl std::fmt::Display for DirectionProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotFinite => f.write_str("a coordinate is not a finite number"),
            Self::NotUnit { norm } => {
                let norm = if norm.is_finite() {
                    show(*norm)
                } else {
                    "above 1.8e308".to_owned()
                };
                write!(
                    f,
                    "not a unit vector (norm {norm}); directions must have |norm - 1| <= \
                     {UNIT_TOLERANCE:e}"
                )
            }
            Self::SubnormalZ(z) => write!(
                f,
                "z = {} is below the normal range of doubles (2.2e-308), where 1 / |z| \
                 overflows; give 0 for a direction on the horizon",
                show(*z)
            ),
        }
    }
}

/// Why `w` is not a direction the library takes, if it is not: a non-finite coordinate, a norm
/// not 1 ([`is_unit_norm`] of the plain norm, the library's own), or a subnormal `z`.
pub fn direction_problem(w: Vec3) -> Option<DirectionProblem> {
    if !(w.x.is_finite() && w.y.is_finite() && w.z.is_finite()) {
        return Some(DirectionProblem::NotFinite);
    }
    let norm = w.norm();
    if !is_unit_norm(norm) {
        // The plain norm decides; a norm whose squares overflowed or underflowed is stated as
        // it is.
        let norm = if norm == 0.0 || norm.is_infinite() {
            scaled_norm(w)
        } else {
            norm
        };
        return Some(DirectionProblem::NotUnit { norm });
    }
    is_subnormal_z(w.z).then_some(DirectionProblem::SubnormalZ(w.z))
}

/// `|w|` without the overflow or underflow of its squares (`|(1e200, 0, 0)|` is 1e200, not
/// infinity; `|(1e-200, 0, 0)|` is 1e-200, not 0): infinite only above the largest double.
fn scaled_norm(w: Vec3) -> f64 {
    let m = w.amax();
    if m == 0.0 { 0.0 } else { m * (w / m).norm() }
}

/// A table of direction pairs: its header and rows as read (trimmed fields), and the pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct PairTable {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
    pub pairs: Vec<(Vec3, Vec3)>,
}

/// Reads a table of direction pairs from `bytes`; `source` names it in errors (`<stdin>` for
/// standard input). Fails at the first bad field, naming its line and column.
pub fn read_pairs(source: &Path, bytes: &[u8]) -> Result<PairTable, LoadError> {
    let err = |line: Option<u64>, column: Option<&str>, kind| LoadError {
        file: source.to_path_buf(),
        line,
        column: column.map(str::to_owned),
        kind,
    };
    // A quoting problem is reported after the problems of the rows before it, as data files do.
    let (records, pending) = records_until_quote_problem(source, bytes)?;
    let mut records = records.into_iter();
    let Some((header_line, header_record)) = records.next() else {
        let expected = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z";
        return Err(
            pending.unwrap_or_else(|| err(Some(1), None, LoadErrorKind::Empty { expected }))
        );
    };
    let header: Vec<String> = text_fields(source, header_line, &header_record, |i| {
        format!("header field {}", i + 1)
    })?
    .into_iter()
    .map(str::to_owned)
    .collect();
    for out in [VALUE_COLUMN, STDERR_COLUMN] {
        if header.iter().any(|h| h == out) {
            return Err(err(Some(header_line), Some(out), LoadErrorKind::Reserved));
        }
    }
    let mut index = [0usize; 6];
    for (slot, name) in index.iter_mut().zip(PAIR_COLUMNS) {
        let mut found = header.iter().enumerate().filter(|(_, h)| *h == name);
        *slot = match (found.next(), found.next()) {
            (Some((i, _)), None) => i,
            (None, _) => {
                return Err(err(
                    Some(header_line),
                    Some(name),
                    LoadErrorKind::MissingColumn {
                        found: crate::load::header_list(&header),
                    },
                ));
            }
            (Some((a, _)), Some((b, _))) => {
                return Err(err(
                    Some(header_line),
                    Some(name),
                    LoadErrorKind::DuplicateColumn {
                        first: a + 1,
                        second: b + 1,
                    },
                ));
            }
        };
    }
    let mut rows = Vec::new();
    let mut pairs = Vec::new();
    for (line, record) in records {
        let fields = text_fields(source, line, &record, |i| {
            header
                .get(i)
                .cloned()
                .unwrap_or_else(|| format!("extra field {}", i + 1))
        })?;
        if fields.len() > header.len() {
            return Err(err(
                Some(line),
                Some(&format!("extra field {}", header.len() + 1)),
                LoadErrorKind::LongRow {
                    found: fields.len(),
                    expected: header.len(),
                },
            ));
        }
        if fields.len() < header.len() {
            return Err(err(
                Some(line),
                Some(&header[fields.len()]),
                LoadErrorKind::ShortRow {
                    found: fields.len(),
                    expected: header.len(),
                },
            ));
        }
        let mut v = [0.0; 6];
        for (k, &i) in index.iter().enumerate() {
            v[k] = crate::load::parse_finite(fields[i])
                .map_err(|kind| err(Some(line), Some(&header[i]), kind))?;
        }
        let mut pair = [Vec3::zeros(); 2];
        for (side, w) in pair.iter_mut().enumerate() {
            *w = Vec3::new(v[3 * side], v[3 * side + 1], v[3 * side + 2]);
            if let Some(problem) = direction_problem(*w) {
                let column = match problem {
                    DirectionProblem::SubnormalZ(_) => PAIR_COLUMNS[3 * side + 2].to_owned(),
                    _ => PAIR_COLUMNS[3 * side..3 * side + 3].join(", "),
                };
                return Err(err(
                    Some(line),
                    Some(&column),
                    LoadErrorKind::Direction(problem),
                ));
            }
        }
        let [wi, wo] = pair.map(stfit_core::math::to_unit);
        pairs.push((wi, wo));
        rows.push(fields.into_iter().map(str::to_owned).collect());
    }
    if let Some(problem) = pending {
        return Err(problem);
    }
    Ok(PairTable {
        header,
        rows,
        pairs,
    })
}

impl PairTable {
    /// Writes the table with the column `f_cos` (`values[j]` for row `j`) appended, and with
    /// `f_cos_stderr` after it when `stderr` is given (an empty field where a standard error
    /// is undefined). Numbers are written by [`format_number`].
    pub fn write_with<W: Write>(
        &self,
        out: W,
        values: &[f64],
        stderr: Option<&[Option<f64>]>,
    ) -> io::Result<()> {
        let mut writer = csv::Writer::from_writer(out);
        let extra: &[&str] = if stderr.is_some() {
            &[VALUE_COLUMN, STDERR_COLUMN]
        } else {
            &[VALUE_COLUMN]
        };
        writer.write_record(
            self.header
                .iter()
                .map(String::as_str)
                .chain(extra.iter().copied()),
        )?;
        for (j, row) in self.rows.iter().enumerate() {
            let value = format_number(values[j]);
            let se = stderr.map(|se| se[j].map_or_else(String::new, format_number));
            writer.write_record(
                row.iter()
                    .map(String::as_str)
                    .chain(std::iter::once(value.as_str()))
                    .chain(se.as_deref()),
            )?;
        }
        writer.flush()
    }
}

/// Shortest text that parses back to exactly `x`: plain decimals for moderate magnitudes,
/// scientific notation otherwise.
pub fn format_number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tolerance reads as written in decimal: norms of 1 -/+ 1e-6 typed in decimal are
    /// accepted, one digit further out is refused.
    #[test]
    fn the_unit_tolerance_holds_at_its_decimal_ends() {
        for norm in [0.999999, 1.000001, 1.0, 1.0 - 5e-7] {
            assert!(is_unit_norm(norm), "{norm}");
        }
        for norm in [0.9999989, 1.0000011, f64::NAN, 0.0] {
            assert!(!is_unit_norm(norm), "{norm}");
        }
    }

    fn read(text: &str) -> Result<PairTable, LoadError> {
        read_pairs(Path::new("<stdin>"), text.as_bytes())
    }

    #[test]
    fn numbers_round_trip() {
        for x in [
            0.0,
            1.0,
            0.1,
            1.234_567_890_123e-7,
            3.5e20,
            12345.678,
            1e-300,
        ] {
            assert_eq!(format_number(x).parse::<f64>().unwrap(), x);
        }
    }

    /// Columns in any order, extra columns passed through, comments and a BOM skipped.
    #[test]
    fn pairs_are_read_in_any_column_order() {
        let t = read("\u{feff}# made by hand\nid,wo_x,wo_y,wo_z,wi_x,wi_y,wi_z\na,0,0,-1,0,0,1\n")
            .unwrap();
        assert_eq!(t.pairs, vec![(Vec3::z(), -Vec3::z())]);
        assert_eq!(t.rows[0][0], "a");
        let mut out = Vec::new();
        t.write_with(&mut out, &[0.5], None).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "id,wo_x,wo_y,wo_z,wi_x,wi_y,wi_z,f_cos\na,0,0,-1,0,0,1,0.5\n"
        );
    }

    /// Errors name the line (comments counted) and the column.
    #[test]
    fn errors_name_line_and_column() {
        let head = "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n";
        let e = read(&format!("{head}# c\n0,0,1,0,0,x\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "<stdin>:3: column 'wo_z': 'x' is not a number"
        );
        let e = read(&format!("{head}0,0,1,0,0.5,-1\n")).unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref()),
            (Some(2), Some("wo_x, wo_y, wo_z"))
        );
        // An earlier row's problem comes before a later row's quoting, as in data files.
        let e = read("id,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\nb,0,0,x,0,0,-1\n\"c\"d,0,0,1,0,0,-1\n")
            .unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref()),
            (Some(2), Some("wi_z")),
            "{e}"
        );
        let e = read("id,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z\n\"c\"d,0,0,1,0,0,-1\n").unwrap_err();
        assert_eq!(e.line, Some(2), "{e}");
        let e = read("wi_x,wi_y,wi_z,wo_x,wo_y\n").unwrap_err();
        assert_eq!(e.column.as_deref(), Some("wo_z"));
        assert!(read("").is_err());
        assert!(read(&format!("{head}0,0,1,0,0\n")).is_err());
        assert!(read(&format!("{head}0,0,1,0,0,-1,7\n")).is_err());
        assert!(read("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,f_cos\n").is_err());
    }
}
