//! `stfit eval`: the single-scattering rough dielectric (Walter et al. 2007) at directions read
//! from CSV.
//!
//! Input on stdin: a header with the columns `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z` (any order; other
//! columns are passed through), then one row per direction pair, unit vectors in the local
//! frame (z > 0 outside, index 1; z < 0 inside, index eta). Output on stdout: the same rows
//! with a column `f_cos = f(wi, wo) |wo.z|` appended: reflection or transmission by the sides
//! of `wi` and `wo`, no radiance `1/eta^2` scaling.

use std::io::{BufWriter, Read, Write};

use clap::ValueEnum;
use stfit_core::Vec3;
use stfit_core::bsdf::{Masking, RoughDielectric};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};

/// The direction columns the input must have, in the order `(wi, wo)`.
const COLUMNS: [&str; 6] = ["wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"];

/// The appended output column.
const OUTPUT_COLUMN: &str = "f_cos";

/// Largest accepted `| |w| - 1 |`: directions are checked, never silently normalised.
const UNIT_TOLERANCE: f64 = 1e-6;

/// A microfacet normal distribution by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NdfName {
    Beckmann,
    Ggx,
    #[value(name = "student-t")]
    StudentT,
}

/// A Smith masking model by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum MaskingName {
    /// G1(wi) G1(wo), as Walter et al. 2007 and the published fits.
    #[default]
    Separable,
    /// Height-correlated Smith masking.
    Correlated,
}

impl From<MaskingName> for Masking {
    fn from(m: MaskingName) -> Self {
        match m {
            MaskingName::Separable => Masking::Separable,
            MaskingName::Correlated => Masking::Correlated,
        }
    }
}

/// Arguments of `stfit eval`.
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// Microfacet normal distribution.
    #[arg(long, value_enum)]
    pub ndf: NdfName,
    /// Roughness alpha (> 0).
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Student-T shape gamma (> 3/2); required with, and only allowed with, --ndf student-t.
    #[arg(long, allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// Relative index of refraction n_inside / n_outside (> 0, != 1).
    #[arg(long, allow_negative_numbers = true)]
    pub eta: f64,
    /// Masking-shadowing model.
    #[arg(long, value_enum, default_value_t)]
    pub masking: MaskingName,
}

impl Args {
    /// The NDF these arguments describe, or an error naming the bad parameter.
    pub fn ndf(&self) -> Result<AnyNdf, String> {
        let ndf: AnyNdf = match (self.ndf, self.gamma) {
            (NdfName::StudentT, None) => {
                return Err("--ndf student-t requires --gamma".into());
            }
            (NdfName::StudentT, Some(gamma)) => StudentT::new(self.alpha, gamma)
                .map_err(|e| format!("invalid Student-T parameters: {e}"))?
                .into(),
            (ndf, Some(_)) => {
                let name = ndf.to_possible_value().expect("no skipped variants");
                return Err(format!(
                    "--gamma is only valid with --ndf student-t, not --ndf {}",
                    name.get_name()
                ));
            }
            (NdfName::Beckmann, None) => Beckmann::new(self.alpha)
                .map_err(|e| format!("invalid NDF parameters: {e}"))?
                .into(),
            (NdfName::Ggx, None) => Ggx::new(self.alpha)
                .map_err(|e| format!("invalid NDF parameters: {e}"))?
                .into(),
        };
        Ok(ndf)
    }

    /// The rough dielectric these arguments describe.
    pub fn bsdf(&self) -> Result<RoughDielectric<AnyNdf>, String> {
        RoughDielectric::new(self.ndf()?, self.eta, self.masking.into())
            .map_err(|e| format!("invalid --eta: {e}"))
    }
}

/// Runs `stfit eval`: CSV from stdin to stdout.
pub fn run(args: &Args) -> Result<(), String> {
    let bsdf = args.bsdf()?;
    let stdout = std::io::stdout().lock();
    eval_csv(&bsdf, std::io::stdin().lock(), BufWriter::new(stdout))
}

/// Reads direction pairs as CSV from `input` and writes them with `f_cos` appended to
/// `output`. Fails on the first bad row with a message naming its line (and field); then
/// nothing is written, so a failed run never leaves a partial table behind.
pub fn eval_csv<R: Read, W: Write>(
    bsdf: &RoughDielectric<AnyNdf>,
    input: R,
    mut output: W,
) -> Result<(), String> {
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(input);
    let header = reader
        .headers()
        .map_err(|e| format!("reading the header: {e}"))?
        .clone();
    let index = column_indices(&header)?;
    let mut writer = csv::Writer::from_writer(Vec::new());
    let write_err = |e: csv::Error| format!("writing output: {e}");
    writer
        .write_record(header.iter().chain([OUTPUT_COLUMN]))
        .map_err(write_err)?;
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(read_error(&e)),
        }
        let line = record.position().map_or(0, csv::Position::line);
        if record.len() != header.len() {
            return Err(format!(
                "line {line}: expected {} fields, found {}",
                header.len(),
                record.len()
            ));
        }
        let mut v = [0.0; 6];
        for (k, (&i, name)) in index.iter().zip(COLUMNS).enumerate() {
            v[k] = parse_field(&record[i], line, name)?;
        }
        let wi = unit_vector(Vec3::new(v[0], v[1], v[2]), line, "wi")?;
        let wo = unit_vector(Vec3::new(v[3], v[4], v[5]), line, "wo")?;
        let f = format_number(bsdf.f_cos(wi, wo));
        writer
            .write_record(record.iter().chain([f.as_str()]))
            .map_err(write_err)?;
    }
    let table = writer
        .into_inner()
        .map_err(|e| format!("writing output: {}", e.error()))?;
    output
        .write_all(&table)
        .and_then(|()| output.flush())
        .map_err(|e| format!("writing output: {e}"))
}

/// Positions of [`COLUMNS`] in the header; an error if one is missing or repeated, or if the
/// output column already exists.
fn column_indices(header: &csv::StringRecord) -> Result<[usize; 6], String> {
    if header.is_empty() || header.iter().all(str::is_empty) {
        return Err(format!(
            "empty input: expected a header line {}",
            COLUMNS.join(",")
        ));
    }
    if header.iter().any(|h| h == OUTPUT_COLUMN) {
        return Err(format!(
            "line 1: the input already has a column {OUTPUT_COLUMN}"
        ));
    }
    let mut index = [0; 6];
    for (slot, name) in index.iter_mut().zip(COLUMNS) {
        let mut found = header.iter().enumerate().filter(|(_, h)| *h == name);
        *slot = match (found.next(), found.next()) {
            (Some((i, _)), None) => i,
            (None, _) => {
                return Err(format!(
                    "line 1: the header lacks column {name} (expected {})",
                    COLUMNS.join(",")
                ));
            }
            (Some(_), Some(_)) => return Err(format!("line 1: column {name} appears twice")),
        };
    }
    Ok(index)
}

/// A CSV read error, with its line when the parser knows it.
fn read_error(e: &csv::Error) -> String {
    match e.position() {
        Some(p) => format!("line {}: {e}", p.line()),
        None => format!("reading input: {e}"),
    }
}

fn parse_field(text: &str, line: u64, name: &str) -> Result<f64, String> {
    let x: f64 = text
        .parse()
        .map_err(|_| format!("line {line}, field {name}: cannot parse {text:?} as a number"))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(format!("line {line}, field {name}: {text:?} is not finite"))
    }
}

fn unit_vector(w: Vec3, line: u64, name: &str) -> Result<Vec3, String> {
    let norm = w.norm();
    if (norm - 1.0).abs() > UNIT_TOLERANCE {
        return Err(format!(
            "line {line}: {name} = ({}, {}, {}) is not a unit vector (norm {norm}); \
             directions must have |norm - 1| <= {UNIT_TOLERANCE:e}",
            w.x, w.y, w.z
        ));
    }
    Ok(w)
}

/// Shortest text that parses back to exactly `x`: plain decimals for moderate magnitudes,
/// scientific notation otherwise.
fn format_number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bsdf() -> RoughDielectric<AnyNdf> {
        RoughDielectric::new(Ggx::new(0.3).unwrap().into(), 1.5, Masking::Separable).unwrap()
    }

    fn eval_str(input: &str) -> Result<String, String> {
        let mut out = Vec::new();
        eval_csv(&bsdf(), input.as_bytes(), &mut out)?;
        Ok(String::from_utf8(out).unwrap())
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

    #[test]
    fn extra_columns_pass_through_in_any_order() {
        let out = eval_str("id,wo_x,wo_y,wo_z,wi_x,wi_y,wi_z\na,0,0,-1,0,0,1\n").unwrap();
        let mut lines = out.lines();
        assert_eq!(lines.next(), Some("id,wo_x,wo_y,wo_z,wi_x,wi_y,wi_z,f_cos"));
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(row[..7], ["a", "0", "0", "-1", "0", "0", "1"]);
        let want = bsdf().f_cos(Vec3::z(), -Vec3::z());
        assert_eq!(row[7].parse::<f64>().unwrap(), want);
    }

    #[test]
    fn header_errors() {
        assert!(eval_str("").unwrap_err().contains("empty input"));
        let e = eval_str("wi_x,wi_y,wi_z,wo_x,wo_y\n").unwrap_err();
        assert!(e.contains("lacks column wo_z"), "{e}");
        let e = eval_str("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,wi_x\n").unwrap_err();
        assert!(e.contains("wi_x appears twice"), "{e}");
        let e = eval_str("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,f_cos\n").unwrap_err();
        assert!(e.contains("already has a column f_cos"), "{e}");
    }
}
