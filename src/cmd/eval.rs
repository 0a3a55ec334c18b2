//! `stfit eval`: the single-scattering rough dielectric (Walter et al. 2007) at directions read
//! from CSV.
//!
//! Input on stdin: a header with the columns `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z` (any order; other
//! columns are passed through), then one row per direction pair, unit vectors in the local
//! frame (z > 0 outside, index 1; z < 0 inside, index eta). Output on stdout: the same rows
//! with a column `f_cos = f(wi, wo) |wo.z|` appended: reflection or transmission by the sides
//! of `wi` and `wo`, no radiance `1/eta^2` scaling. With `--scattering multiple|all` the value
//! is a random-walk estimate (rows sharing a `wi` share one set of walks) and a column
//! `f_cos_stderr` follows. `--walk null` uses the null-scattering walk instead, which also
//! takes the full-sphere NDFs `--ndf vmf` and `--ndf porous` with conductor or Lambertian
//! facets (`--facet`); every order is then a walk estimate.

use std::io::{BufWriter, Read, Write};

use super::surface::{self, Estimators, FacetKind, NdfKind, SurfaceArgs, Walk};
use super::{CmdError, CmdResult};
use clap::ValueEnum;
use stfit_core::Vec3;
use stfit_core::bsdf::{Masking, RoughDielectric};
use stfit_core::ndf::{AnyNdf, Beckmann, Ggx, StudentT};

/// The direction columns the input must have, in the order `(wi, wo)`.
const COLUMNS: [&str; 6] = ["wi_x", "wi_y", "wi_z", "wo_x", "wo_y", "wo_z"];

/// The standard-error column appended by the random walk.
const STDERR_COLUMN: &str = "f_cos_stderr";

/// The appended output column.
const OUTPUT_COLUMN: &str = "f_cos";

/// Largest accepted `| |w| - 1 |`: directions are checked, never silently normalised.
const UNIT_TOLERANCE: f64 = 1e-6;

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
    #[command(flatten)]
    pub surface: SurfaceArgs,
    /// Masking-shadowing model (single scattering only; the random walk's masking is height
    /// correlated by construction).
    #[arg(long, value_enum, default_value_t)]
    pub masking: MaskingName,
    /// Scattering orders: `single` is the analytic BSDF above (height-field walk, dielectric
    /// facets); `multiple` (order >= 2) and `all` are estimated by the random walk, with a
    /// column `f_cos_stderr`.
    #[arg(long, value_enum, default_value_t = super::albedo::Scattering::Single)]
    pub scattering: super::albedo::Scattering,
    /// Random walks per distinct `wi` (multiple and all).
    #[arg(long, default_value_t = 100_000)]
    pub samples: u64,
    /// Seed of the random walks (multiple and all).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

impl Args {
    /// The NDF these arguments describe, or an error naming the bad parameter.
    pub fn ndf(&self) -> Result<AnyNdf, String> {
        let alpha = self
            .surface
            .alpha
            .ok_or("--alpha is required for this --ndf")?;
        let ndf: AnyNdf = match (self.surface.ndf, self.surface.gamma) {
            (NdfKind::Vmf | NdfKind::Porous, _) => {
                return Err("--ndf vmf and --ndf porous need --walk null".into());
            }
            (NdfKind::StudentT, None) => {
                return Err("--ndf student-t requires --gamma".into());
            }
            (NdfKind::StudentT, Some(gamma)) => StudentT::new(alpha, gamma)
                .map_err(|e| format!("invalid Student-T parameters: {e}"))?
                .into(),
            (ndf, Some(_)) => {
                let name = ndf.to_possible_value().expect("no skipped variants");
                return Err(format!(
                    "--gamma is only valid with --ndf student-t, not --ndf {}",
                    name.get_name()
                ));
            }
            (NdfKind::Beckmann, None) => Beckmann::new(alpha)
                .map_err(|e| format!("invalid NDF parameters: {e}"))?
                .into(),
            (NdfKind::Ggx, None) => Ggx::new(alpha)
                .map_err(|e| format!("invalid NDF parameters: {e}"))?
                .into(),
        };
        Ok(ndf)
    }

    /// The rough dielectric these arguments describe.
    pub fn bsdf(&self) -> Result<RoughDielectric<AnyNdf>, String> {
        let eta = self
            .surface
            .eta
            .ok_or("--eta is required for --facet dielectric")?;
        RoughDielectric::new(self.ndf()?, eta, self.masking.into())
            .map_err(|e| format!("invalid --eta: {e}"))
    }
}

/// Runs `stfit eval`: CSV from stdin to stdout. Bad parameters of the closed-form BSDF and bad
/// input are failures (exit status 1); bad options of the random walk are usage errors (2).
pub fn run(args: &Args) -> CmdResult {
    let stdout = std::io::stdout().lock();
    let analytic = args.scattering == super::albedo::Scattering::Single
        && args.surface.walk == Walk::Heightfield
        && args.surface.facet == FacetKind::Dielectric
        && !matches!(args.surface.ndf, NdfKind::Vmf | NdfKind::Porous);
    if analytic {
        for (missing, name) in [
            (args.surface.alpha.is_none(), "--alpha"),
            (args.surface.eta.is_none(), "--eta"),
        ] {
            if missing {
                return Err(CmdError::Usage(format!("{name} is required")));
            }
        }
        let bsdf = args.bsdf().map_err(CmdError::Failed)?;
        return eval_csv(&bsdf, std::io::stdin().lock(), BufWriter::new(stdout))
            .map_err(CmdError::Failed);
    }
    if args.samples == 0 {
        return Err(CmdError::Usage("--samples must be at least 1".into()));
    }
    let (ndf, facet) = args.surface.options().check()?;
    let walk = surface::walker(ndf, facet, args.surface.walk, args.scattering.into())?;
    let input = std::io::stdin().lock();
    eval_walk_csv(
        walk.as_ref(),
        args.samples,
        args.seed,
        input,
        BufWriter::new(stdout),
    )
    .map_err(CmdError::Failed)
}

/// As [`eval_csv`] for the random walk: reads every row, estimates `f_cos` for all rows that
/// share a `wi` from one set of `samples` walks (seeded by `seed` and the first line of the
/// group), and appends `f_cos` and `f_cos_stderr`.
pub fn eval_walk_csv<R: Read, W: Write>(
    walk: &dyn Estimators,
    samples: u64,
    seed: u64,
    input: R,
    mut output: W,
) -> Result<(), String> {
    let (mut reader, header) = open_csv(input)?;
    if header.iter().any(|h| h == STDERR_COLUMN) {
        return Err(format!("the input already has a column {STDERR_COLUMN}"));
    }
    let index = column_indices(&header)?;
    let mut rows = Vec::new();
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(read_error(&e)),
        }
        let (wi, wo) = parse_pair(&record, &header, &index)?;
        rows.push((record.clone(), wi, wo));
    }
    // Rows grouped by wi (exact components), in order of first appearance.
    let mut groups: Vec<(Vec3, Vec<usize>)> = Vec::new();
    for (k, (_, wi, _)) in rows.iter().enumerate() {
        match groups.iter_mut().find(|(w, _)| w == wi) {
            Some((_, members)) => members.push(k),
            None => groups.push((*wi, vec![k])),
        }
    }
    let mut values = vec![(0.0, 0.0); rows.len()];
    for (g, (wi, members)) in groups.iter().enumerate() {
        let wos: Vec<Vec3> = members.iter().map(|&k| rows[k].2).collect();
        let est = walk.eval_many(*wi, &wos, samples, seed.wrapping_add(g as u64));
        for (&k, e) in members.iter().zip(est) {
            values[k] = (e.mean, e.stderr);
        }
    }
    let mut writer = csv::Writer::from_writer(Vec::new());
    let write_err = |e: csv::Error| format!("writing output: {e}");
    writer
        .write_record(header.iter().chain([OUTPUT_COLUMN, STDERR_COLUMN]))
        .map_err(write_err)?;
    for ((record, _, _), (f, se)) in rows.iter().zip(values) {
        let (f, se) = (format_number(f), format_number(se));
        writer
            .write_record(record.iter().chain([f.as_str(), se.as_str()]))
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

/// The directions of one data row, checked to be unit vectors.
fn parse_pair(
    record: &csv::StringRecord,
    header: &csv::StringRecord,
    index: &[usize; 6],
) -> Result<(Vec3, Vec3), String> {
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
    Ok((wi, wo))
}

/// A CSV reader over `input` (rows may differ in length, fields are trimmed) and its header.
fn open_csv<R: Read>(input: R) -> Result<(csv::Reader<R>, csv::StringRecord), String> {
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(input);
    let header = reader
        .headers()
        .map_err(|e| format!("reading the header: {e}"))?
        .clone();
    Ok((reader, header))
}

/// Reads direction pairs as CSV from `input` and writes them with `f_cos` appended to
/// `output`. Fails on the first bad row with a message naming its line (and field); then
/// nothing is written, so a failed run never leaves a partial table behind.
pub fn eval_csv<R: Read, W: Write>(
    bsdf: &RoughDielectric<AnyNdf>,
    input: R,
    mut output: W,
) -> Result<(), String> {
    let (mut reader, header) = open_csv(input)?;
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
        let (wi, wo) = parse_pair(&record, &header, &index)?;
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
