//! Synthetic measurements of known truth: model values on an angle grid with seeded noise,
//! written in the measurement format of `data-format.md`.

use std::io::{self, Write};
use std::path::Path;

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64;
use thiserror::Error;

use crate::conventions::{
    THETA_I_RANGE, THETA_O_RANGE, THETA_RANGE, theta_i_in_range, theta_in_range, theta_o_in_range,
};
use crate::data::{Angles, Measurement, Sample};
use crate::fit::FitError;
use crate::load::{
    COL_BSDF, COL_L, COL_PHI_I, COL_PHI_O, COL_SAMPLE, COL_THETA_I, COL_THETA_O, LoadError,
    read_header,
};
use crate::model::Model;
use crate::pairs::format_number;
use stfit_core::error::show;

/// Most points one synthetic sample may have (guards against a mistyped grid step).
pub const MAX_POINTS: usize = 1_000_000;

/// The header line [`write_csv`] writes for in-plane samples.
pub const HEADER: [&str; 4] = [COL_SAMPLE, COL_THETA_I, COL_THETA_O, COL_L];

/// The header line [`write_csv`] writes for general samples.
pub const GENERAL_HEADER: [&str; 6] = [
    COL_SAMPLE,
    COL_THETA_I,
    COL_PHI_I,
    COL_THETA_O,
    COL_PHI_O,
    COL_BSDF,
];

/// An invalid synthesis request, or a file that cannot be written.
#[derive(Debug, Error)]
pub enum SynthError {
    /// The true model cannot be evaluated (alpha, gamma, scale, eta, orders, masking, walks).
    #[error(transparent)]
    Model(#[from] FitError),
    /// The noise level must be finite and >= 0.
    #[error("noise must be finite and >= 0, got {}", show(*.0))]
    Noise(f64),
    /// An angle outside the range of its column.
    #[error("{column} = {} is out of range; must be in {range}", show(*value))]
    Angle {
        column: &'static str,
        value: f64,
        range: &'static str,
    },
    /// An empty list of angles.
    #[error("no {0} angles given")]
    NoAngles(&'static str),
    /// Too many points: the number of points (`u128::MAX` for more than it holds).
    #[error("the grid has {} points; at most {MAX_POINTS} are allowed", count_text(*.0))]
    TooManyPoints(u128),
    /// The sample name cannot be written as a data row.
    #[error(
        "sample name '{}' is not allowed: it must be non-empty, have no control characters \
         and neither start with '#' nor start or end with whitespace (a reader trims it)",
        crate::data::short(.0)
    )]
    SampleName(String),
    /// The file to append to cannot be read, or has another header.
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error("{path}: cannot append: {reason}")]
    Append { path: String, reason: String },
    #[error("{path}: cannot write: {source}")]
    Io { path: String, source: io::Error },
    /// In-plane and general samples in one file.
    #[error("in-plane and general samples cannot share a file")]
    MixedForms,
}

/// The angle grid of a synthetic sample.
#[derive(Debug, Clone, PartialEq)]
pub enum Grid {
    /// An in-plane grid (the Walter form): every incidence `theta_i` (outer loop, [0, 90)) with
    /// every transmitted direction `theta_o` (inner loop, (90, 270)); the values are `L`.
    InPlane {
        theta_i_deg: Vec<f64>,
        theta_o_deg: Vec<f64>,
    },
    /// A general grid: every incidence direction `(theta_i, phi_i)` (outer loops, theta outer)
    /// with every outgoing direction `(theta_o, phi_o)` (inner loops), polar angles in [0, 180]
    /// without 90, so both sides, reflection and transmission; the values are the BSDF.
    Spherical {
        theta_i_deg: Vec<f64>,
        phi_i_deg: Vec<f64>,
        theta_o_deg: Vec<f64>,
        phi_o_deg: Vec<f64>,
    },
}

impl Grid {
    /// The Walter grid: incidence 0, 30, 60, 80; `theta_o` 106 to 254 by 2 (300 points).
    pub fn in_plane_default() -> Self {
        Self::InPlane {
            theta_i_deg: vec![0.0, 30.0, 60.0, 80.0],
            theta_o_deg: (0..75).map(|k| 106.0 + 2.0 * k as f64).collect(),
        }
    }

    /// A general grid of 1,620 points: light from outside at 0, 30, 60 degrees and from inside
    /// at 120, 150 (azimuth 0), outgoing polar angles 5 to 175 by 10 and azimuths 0 to 340 by 20.
    pub fn spherical_default() -> Self {
        Self::Spherical {
            theta_i_deg: vec![0.0, 30.0, 60.0, 120.0, 150.0],
            phi_i_deg: vec![0.0],
            theta_o_deg: (0..18).map(|k| 5.0 + 10.0 * k as f64).collect(),
            phi_o_deg: (0..18).map(|k| 20.0 * k as f64).collect(),
        }
    }

    /// Checks every angle list: non-empty, each angle in its column's range.
    fn check(&self) -> Result<(), SynthError> {
        match self {
            Self::InPlane {
                theta_i_deg,
                theta_o_deg,
            } => {
                check_angles(COL_THETA_I, theta_i_deg, THETA_I_RANGE, theta_i_in_range)?;
                check_angles(COL_THETA_O, theta_o_deg, THETA_O_RANGE, theta_o_in_range)
            }
            Self::Spherical {
                theta_i_deg,
                phi_i_deg,
                theta_o_deg,
                phi_o_deg,
            } => {
                check_angles(COL_THETA_I, theta_i_deg, THETA_RANGE, theta_in_range)?;
                check_angles(COL_PHI_I, phi_i_deg, "finite values", f64::is_finite)?;
                check_angles(COL_THETA_O, theta_o_deg, THETA_RANGE, theta_in_range)?;
                check_angles(COL_PHI_O, phi_o_deg, "finite values", f64::is_finite)
            }
        }
    }

    /// Number of points, exact up to `u128::MAX` (which stands for more): four lists of
    /// millions of angles each, which a usize product saturated, reported 2^64 - 1 points.
    fn len(&self) -> u128 {
        let lists: &[&Vec<f64>] = match self {
            Self::InPlane {
                theta_i_deg,
                theta_o_deg,
            } => &[theta_i_deg, theta_o_deg],
            Self::Spherical {
                theta_i_deg,
                phi_i_deg,
                theta_o_deg,
                phi_o_deg,
            } => &[theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg],
        };
        lists
            .iter()
            .fold(1u128, |n, l| n.saturating_mul(l.len() as u128))
    }

    /// The grid's points with value 0 and weight 1, in row order.
    fn points(&self) -> Vec<Measurement> {
        match self {
            Self::InPlane {
                theta_i_deg,
                theta_o_deg,
            } => theta_i_deg
                .iter()
                .flat_map(|&ti| {
                    theta_o_deg
                        .iter()
                        .map(move |&to| Measurement::in_plane(ti, to, 0.0, 1.0))
                })
                .collect(),
            Self::Spherical {
                theta_i_deg,
                phi_i_deg,
                theta_o_deg,
                phi_o_deg,
            } => {
                // At most MAX_POINTS: the grid was checked.
                let mut out = Vec::with_capacity(self.len() as usize);
                for &ti in theta_i_deg {
                    for &pi in phi_i_deg {
                        for &to in theta_o_deg {
                            for &po in phi_o_deg {
                                out.push(Measurement::spherical((ti, pi), (to, po), 0.0, 1.0));
                            }
                        }
                    }
                }
                out
            }
        }
    }
}

/// What to synthesise: a model, an angle grid and the noise.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthSpec {
    /// The true model: NDF, scale, eta, masking and orders (for orders all, its walks and their
    /// seed).
    pub model: Model,
    pub grid: Grid,
    /// Relative noise sigma: each value is `max(0, v (1 + sigma z))`, z standard normal.
    pub noise: f64,
    /// Seed of the noise (a PCG-64 stream); the same seed gives the same file.
    pub seed: u64,
    /// The sample name written in the `sample` column.
    pub name: String,
}

/// A number of points as an error states it: `more than 2^128 - 2` for `u128::MAX`.
fn count_text(n: u128) -> String {
    if n == u128::MAX {
        format!("more than {}", u128::MAX - 1)
    } else {
        n.to_string()
    }
}

impl SynthSpec {
    /// Checks every parameter, returning the first problem.
    pub fn validate(&self) -> Result<(), SynthError> {
        self.model.check()?;
        if !(self.noise.is_finite() && self.noise >= 0.0) {
            return Err(SynthError::Noise(self.noise));
        }
        self.grid.check()?;
        let n = self.grid.len();
        if n > MAX_POINTS as u128 {
            return Err(SynthError::TooManyPoints(n));
        }
        let name_ok = !self.name.is_empty()
            && !self.name.starts_with('#')
            && !self.name.starts_with(char::is_whitespace)
            && !self.name.ends_with(char::is_whitespace)
            && !self.name.chars().any(char::is_control);
        if !name_ok {
            return Err(SynthError::SampleName(self.name.clone()));
        }
        Ok(())
    }

    /// Estimated wall time, in seconds, of the random walks of [`SynthSpec::sample`] on rayon's
    /// current pool, for a note before a long run ([`Model::walk_seconds`] at the grid's
    /// points); 0 for single scattering. Refuses what [`SynthSpec::sample`] refuses.
    pub fn walk_seconds(&self) -> Result<f64, SynthError> {
        self.validate()?;
        Ok(self.model.walk_seconds(&self.grid.points())?)
    }

    /// What the random walks of [`SynthSpec::sample`] are, for a note before a long run.
    pub fn walks_description(&self) -> String {
        format!(
            "the random walks of the orders >= 2 term ({} walks per incident direction)",
            self.model.walks.unwrap_or(0)
        )
    }

    /// The synthetic sample: at every grid point, in row order, the model value
    /// ([`Model::predict_points`]: `L` for an in-plane grid, the BSDF for a general one) with
    /// multiplicative noise `max(0, v (1 + noise z))`, `z ~ N(0, 1)` drawn in row order from
    /// PCG-64 seeded with `seed`.
    pub fn sample(&self) -> Result<Sample, SynthError> {
        self.validate()?;
        let mut points = self.grid.points();
        let values = self.model.predict_points(&points)?;
        let mut rng = Pcg64::seed_from_u64(self.seed);
        for (k, (p, v)) in points.iter_mut().zip(values).enumerate() {
            let z: f64 = StandardNormal.sample(&mut rng);
            p.value = (v * (1.0 + self.noise * z)).max(0.0);
            if !p.value.is_finite() {
                return Err(SynthError::Model(FitError::NotRepresentable(format!(
                    "point {} (counting from 1): the value {v:e} with noise {} overflows",
                    k + 1,
                    show(self.noise)
                ))));
            }
        }
        Ok(Sample {
            name: self.name.clone(),
            points,
        })
    }
}

/// Writes `samples` with `comment` to the file at `path`: replacing it, or with `append`
/// adding the rows to it (creating it if needed, or writing it whole if it is empty; an
/// existing file must be a regular file, start with the header [`write_csv`] writes, read by
/// the loader's rules, and end with a line break).
pub fn write_file(
    path: &Path,
    samples: &[Sample],
    comment: Option<&str>,
    append: bool,
) -> Result<(), SynthError> {
    let display = path.display().to_string();
    // An empty regular file (made by `touch`) is appended to as a new one, header first.
    let empty = std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.len() == 0);
    let header = !append || !path.exists() || empty;
    if !header && !path.is_file() {
        // A device or a pipe would be read to its end to check the header: /dev/full never
        // ends.
        return Err(SynthError::Append {
            path: display,
            reason: "not a regular file (a folder, a device or a pipe): --append adds rows to \
                     a CSV file"
                .into(),
        });
    }
    if !header {
        let expected = csv_header(samples)?.join(",");
        let (bytes, found) = read_header(path)?;
        match found {
            Some((_, h)) if h.join(",") == expected => {}
            Some((line, h)) => {
                return Err(SynthError::Append {
                    path: format!("{display}:{line}"),
                    reason: format!("the header is '{}', synth writes '{expected}'", h.join(",")),
                });
            }
            None => {
                return Err(SynthError::Append {
                    path: display,
                    reason: "the file has no header line".into(),
                });
            }
        }
        if !bytes.ends_with(b"\n") {
            return Err(SynthError::Append {
                path: display,
                reason: "the file does not end with a line break".into(),
            });
        }
    }
    let mut buf = Vec::new();
    write_csv(&mut buf, samples, header, comment)?;
    let io = |source| SynthError::Io {
        path: display.clone(),
        source,
    };
    if append {
        std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .and_then(|mut f| f.write_all(&buf))
            .map_err(io)
    } else {
        std::fs::write(path, &buf).map_err(io)
    }
}

fn check_angles(
    column: &'static str,
    angles: &[f64],
    range: &'static str,
    ok: impl Fn(f64) -> bool,
) -> Result<(), SynthError> {
    if angles.is_empty() {
        return Err(SynthError::NoAngles(column));
    }
    match angles.iter().find(|&&t| !ok(t)) {
        Some(&value) => Err(SynthError::Angle {
            column,
            value,
            range,
        }),
        None => Ok(()),
    }
}

/// The header [`write_csv`] writes for `samples`: [`HEADER`] for in-plane samples,
/// [`GENERAL_HEADER`] for general ones; samples of both forms cannot share a file.
pub fn csv_header(samples: &[Sample]) -> Result<&'static [&'static str], SynthError> {
    let in_plane = samples.iter().all(Sample::is_in_plane);
    let general = samples
        .iter()
        .all(|s| s.points.iter().all(|p| p.in_plane_angles().is_none()));
    match (in_plane, general) {
        (true, _) => Ok(&HEADER),
        (false, true) => Ok(&GENERAL_HEADER),
        (false, false) => Err(SynthError::MixedForms),
    }
}

/// Writes samples as data rows, preceded by the header line when `header` is true and by
/// `comment` (each of its lines prefixed with `# `) when given: in-plane samples as
/// `sample,theta_i_deg,theta_o_deg,L`, general ones as
/// `sample,theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,bsdf`. Numbers are written in Rust's
/// shortest form that reads back to the same `f64`.
pub fn write_csv<W: Write>(
    mut out: W,
    samples: &[Sample],
    header: bool,
    comment: Option<&str>,
) -> Result<(), SynthError> {
    let columns = csv_header(samples)?;
    let io = |e: csv::Error| SynthError::Io {
        path: "output".into(),
        source: e.into(),
    };
    if let Some(comment) = comment {
        for line in comment.lines() {
            writeln!(out, "# {line}").map_err(|e| io(e.into()))?;
        }
    }
    let mut writer = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(&mut out);
    if header {
        writer.write_record(columns).map_err(io)?;
    }
    for sample in samples {
        for p in &sample.points {
            let mut row = vec![sample.name.clone()];
            match p.angles {
                Angles::InPlane {
                    theta_i_deg,
                    theta_o_deg,
                } => row.extend([theta_i_deg, theta_o_deg].map(format_number)),
                Angles::Spherical {
                    theta_i_deg,
                    phi_i_deg,
                    theta_o_deg,
                    phi_o_deg,
                } => {
                    row.extend([theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg].map(format_number))
                }
            }
            row.push(format_number(p.value));
            writer.write_record(&row).map_err(io)?;
        }
    }
    writer.flush().map_err(|e| io(e.into()))?;
    Ok(())
}

/// Parses an angle list: comma-separated items, each a number or an inclusive range
/// `start:stop:step` (`step > 0`, `stop >= start`). Range values are `start + k step`, rounded
/// to 1e-9 degrees so that decimal steps give decimal angles.
pub fn parse_angle_list(text: &str) -> Result<Vec<f64>, String> {
    let mut angles = Vec::new();
    for item in text.split(',') {
        let item = item.trim();
        if item.is_empty() {
            return Err(format!("empty item in the list '{text}'"));
        }
        let parts: Vec<&str> = item.split(':').collect();
        let num = |s: &str| -> Result<f64, String> {
            if s.trim().is_empty() {
                return Err(format!("empty number in '{item}'"));
            }
            let x: f64 = s
                .trim()
                .parse()
                .map_err(|_| format!("'{s}' is not a number (in '{item}')"))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(format!("'{s}' is not finite"))
            }
        };
        match parts.as_slice() {
            [x] => angles.push(num(x)?),
            [start, stop, step] => {
                let (start, stop, step) = (num(start)?, num(stop)?, num(step)?);
                if step <= 0.0 {
                    return Err(format!("step must be > 0 in '{item}'"));
                }
                if stop < start {
                    return Err(format!("stop must be >= start in '{item}'"));
                }
                let count = ((stop - start) / step + 1e-9).floor() + 1.0;
                if count > MAX_POINTS as f64 {
                    return Err(format!("'{item}' has more than {MAX_POINTS} angles"));
                }
                // Beyond 1e7 degrees a double has no digits below 1e-9 to round (and
                // `x * 1e9` could overflow).
                let round = |x: f64| {
                    if x.abs() < 1e7 {
                        (x * 1e9).round() / 1e9
                    } else {
                        x
                    }
                };
                angles.extend((0..count as usize).map(|k| round(start + k as f64 * step)));
            }
            _ => {
                return Err(format!(
                    "'{item}' is neither a number nor a range start:stop:step"
                ));
            }
        }
    }
    Ok(angles)
}

/// `word` as one word of a POSIX shell command: as it is when every character is one a shell
/// takes literally (ASCII letters, digits and `_@%+=:,./-`), else between single quotes, each
/// `'` inside written `'\''`; the empty word is `''`. For the command line that `stfit synth`
/// records in its files, which pasted into a shell writes the file again.
pub fn shell_word(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_@%+=:,./-".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        word.to_owned()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}

/// The option `flag` with `value` as shell words: `--flag VALUE`, or `--flag=VALUE` for a
/// value that starts with `-` (which a parser would otherwise take for a flag).
pub fn shell_option(flag: &str, value: &str) -> String {
    let sep = if value.starts_with('-') { '=' } else { ' ' };
    format!("{flag}{sep}{}", shell_word(value))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Words a shell takes literally stay as they are; others are single-quoted, a quote
    /// inside too; a value starting with `-` is joined to its flag.
    #[test]
    fn shell_words_quote_what_a_shell_would_change() {
        assert_eq!(shell_word("0:340:20"), "0:340:20");
        assert_eq!(shell_word("/tmp/a-b_c.csv"), "/tmp/a-b_c.csv");
        assert_eq!(shell_word("my glass"), "'my glass'");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
        assert_eq!(shell_word(""), "''");
        assert_eq!(shell_word("$HOME*"), "'$HOME*'");
        assert_eq!(shell_word("verre\u{e9}"), "'verre\u{e9}'");
        assert_eq!(shell_option("--phi-i", "-90,90"), "--phi-i=-90,90");
        assert_eq!(shell_option("--sample", "a b"), "--sample 'a b'");
    }
    use crate::load::load_bytes;
    use crate::model::{Gamma, ModelKind};
    use stfit_core::ScatteringOrders;
    use stfit_core::bsdf::Masking;

    fn spec() -> SynthSpec {
        SynthSpec {
            model: Model {
                kind: ModelKind::StudentT,
                alpha: 0.2,
                gamma: Gamma::Fixed(3.0),
                scale: 1.5,
                eta: 1.51,
                masking: Masking::Separable,
                orders: ScatteringOrders::Single,
                walks: None,
                seed: None,
            },
            grid: Grid::InPlane {
                theta_i_deg: vec![0.0, 30.0, 60.0, 80.0],
                theta_o_deg: parse_angle_list("106:254:2").unwrap(),
            },
            noise: 0.0,
            seed: 7,
            name: "frosted".into(),
        }
    }

    fn set_in_plane(s: &mut SynthSpec, theta_i_deg: Vec<f64>, theta_o_deg: Vec<f64>) {
        s.grid = Grid::InPlane {
            theta_i_deg,
            theta_o_deg,
        };
    }

    #[test]
    fn angle_lists() {
        assert_eq!(
            parse_angle_list("0, 30,60,80").unwrap(),
            [0.0, 30.0, 60.0, 80.0]
        );
        let r = parse_angle_list("106:254:2").unwrap();
        assert_eq!((r.len(), r[0], r[74]), (75, 106.0, 254.0));
        assert_eq!(
            parse_angle_list("170:170.3:0.1,200").unwrap(),
            [170.0, 170.1, 170.2, 170.3, 200.0]
        );
        // Huge azimuth ranges stay finite: the rounding to 1e-9 degrees stops where a double
        // has no such digits.
        let huge = parse_angle_list("0:1e300:1e299").unwrap();
        assert_eq!((huge.len(), huge[10]), (11, 1e300));
        assert!(huge.iter().all(|v| v.is_finite()));
        for bad in ["", "a", "1:2", "1:2:0", "3:2:1", "1:2:3:4", "inf", "0,,1"] {
            assert!(parse_angle_list(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn noiseless_sample_is_the_model_and_round_trips_exactly() {
        let s = spec();
        let sample = s.sample().unwrap();
        assert_eq!(sample.points.len(), 300);
        let mut buf = Vec::new();
        write_csv(
            &mut buf,
            std::slice::from_ref(&sample),
            true,
            Some("truth\nline 2"),
        )
        .unwrap();
        let d = load_bytes(Path::new("synth.csv"), &buf).unwrap();
        assert_eq!(d.samples, vec![sample.clone()]);
        let l = s.model.predict_points(&sample.points).unwrap();
        assert!(sample.points.iter().zip(&l).all(|(p, l)| p.value == *l));
        assert!(sample.points.iter().any(|p| p.value > 0.1));
    }

    #[test]
    fn noise_is_seeded_multiplicative_and_about_sigma() {
        let mut s = spec();
        s.noise = 0.02;
        let a = s.sample().unwrap();
        assert_eq!(a, s.sample().unwrap());
        s.seed = 8;
        assert_ne!(a, s.sample().unwrap());
        s.noise = 0.0;
        let clean = s.sample().unwrap();
        let rel: Vec<f64> = a
            .points
            .iter()
            .zip(&clean.points)
            .filter(|(_, c)| c.value > 0.0)
            .map(|(n, c)| n.value / c.value - 1.0)
            .collect();
        let n = rel.len() as f64;
        let mean = rel.iter().sum::<f64>() / n;
        let sd = (rel.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        // With about 300 draws the sample sd is within 15% of sigma and the mean within
        // 4 standard errors of 0.
        assert!((sd / 0.02 - 1.0).abs() < 0.15, "sd {sd}");
        assert!(mean.abs() < 4.0 * 0.02 / n.sqrt(), "mean {mean}");
    }

    #[test]
    fn invalid_requests_are_rejected() {
        type Modify = fn(&mut SynthSpec);
        let cases: Vec<(Modify, &str)> = vec![
            (|s| s.model.alpha = 0.0, "alpha"),
            (|s| s.model.gamma = Gamma::Fixed(1.5), "gamma"),
            (|s| s.model.gamma = Gamma::NotApplicable, "gamma"),
            (|s| s.model.kind = ModelKind::Ggx, "gamma"),
            (|s| s.model.eta = 1.0, "eta"),
            (|s| s.model.scale = -1.0, "scale"),
            (|s| s.noise = f64::NAN, "noise"),
            (|s| set_in_plane(s, vec![90.0], vec![180.0]), "theta_i_deg"),
            (|s| set_in_plane(s, vec![0.0], vec![]), "theta_o_deg"),
            (|s| set_in_plane(s, vec![0.0], vec![270.0]), "theta_o_deg"),
            (
                |s| {
                    s.grid = Grid::Spherical {
                        theta_i_deg: vec![90.0],
                        phi_i_deg: vec![0.0],
                        theta_o_deg: vec![10.0],
                        phi_o_deg: vec![0.0],
                    }
                },
                "theta_i_deg",
            ),
            (|s| s.name = "#x".into(), "sample name"),
            (|s| s.name = String::new(), "sample name"),
            (
                |s| {
                    s.model.orders = ScatteringOrders::All;
                    s.model.walks = Some(10);
                    s.model.seed = Some(1);
                },
                "correlated",
            ),
            (
                |s| {
                    s.model.orders = ScatteringOrders::All;
                    s.model.masking = Masking::Correlated;
                    s.model.walks = Some(0);
                    s.model.seed = Some(1);
                },
                "walks",
            ),
            (
                |s| {
                    s.model.orders = ScatteringOrders::Multiple;
                    s.model.masking = Masking::Correlated;
                },
                "multiple",
            ),
        ];
        for (modify, word) in cases {
            let mut s = spec();
            modify(&mut s);
            let e = s.sample().unwrap_err().to_string();
            assert!(e.contains(word), "{e} should mention {word}");
        }
    }

    /// A grid of more points than a u64 counts is refused with its exact count: the product
    /// had saturated, and the error said 18446744073709551615 points.
    #[test]
    fn a_grid_too_large_states_its_exact_number_of_points() {
        let mut s = spec();
        let list = |lo: f64| {
            (0..70_000)
                .map(|k| lo + k as f64 * 1e-3)
                .collect::<Vec<_>>()
        };
        s.grid = Grid::Spherical {
            theta_i_deg: list(0.0),
            phi_i_deg: list(0.0),
            theta_o_deg: list(100.0),
            phi_o_deg: list(0.0),
        };
        let e = s.sample().unwrap_err().to_string();
        assert_eq!(
            e,
            "the grid has 24010000000000000000 points; at most 1000000 are allowed"
        );
        assert_eq!(
            count_text(u128::MAX),
            format!("more than {}", u128::MAX - 1)
        );
    }

    /// Multiple scattering adds the walk's orders >= 2 to the height-correlated single
    /// scattering: more light everywhere, deterministic for a seed.
    #[test]
    fn multiple_scattering_sample_adds_to_single_scattering() {
        let mut s = spec();
        s.model.alpha = 0.6;
        set_in_plane(
            &mut s,
            vec![0.0, 30.0, 60.0, 80.0],
            parse_angle_list("110:250:10").unwrap(),
        );
        s.model.masking = Masking::Correlated;
        let single = s.sample().unwrap();
        s.model.orders = ScatteringOrders::All;
        s.model.walks = Some(2000);
        s.model.seed = Some(s.seed);
        let multi = s.sample().unwrap();
        assert_eq!(multi, s.sample().unwrap());
        let (ls, lm): (f64, f64) = single
            .points
            .iter()
            .zip(&multi.points)
            .map(|(a, b)| (a.value, b.value))
            .fold((0.0, 0.0), |(x, y), (a, b)| (x + a, y + b));
        assert!(
            single
                .points
                .iter()
                .zip(&multi.points)
                .all(|(a, b)| b.value >= a.value),
            "orders >= 2 only add light"
        );
        // At alpha 0.6 multiple scattering is a few percent of the transmitted light.
        assert!(
            (1.005..1.5).contains(&(lm / ls)),
            "multiple / single {}",
            lm / ls
        );
    }
}
