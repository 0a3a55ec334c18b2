//! Synthetic measurements of known truth: model values on an angle grid with seeded noise,
//! written in the measurement format of `data-format.md`.

use std::io::{self, Write};
use std::path::Path;

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64;
use thiserror::Error;

use crate::conventions::{THETA_I_RANGE, THETA_O_RANGE, theta_i_in_range, theta_o_in_range};
use crate::data::{Measurement, Sample};
use crate::fit::FitError;
use crate::load::{COL_L, COL_SAMPLE, COL_THETA_I, COL_THETA_O, LoadError, read_header};
use crate::model::Model;

/// Most points one synthetic sample may have (guards against a mistyped grid step).
pub const MAX_POINTS: usize = 1_000_000;

/// The header line [`write_csv`] writes.
pub const HEADER: [&str; 4] = [COL_SAMPLE, COL_THETA_I, COL_THETA_O, COL_L];

/// An invalid synthesis request, or a file that cannot be written.
#[derive(Debug, Error)]
pub enum SynthError {
    /// The true model cannot be evaluated (alpha, gamma, scale, eta, orders, masking, walks).
    #[error(transparent)]
    Model(#[from] FitError),
    /// The noise level must be finite and >= 0.
    #[error("noise must be finite and >= 0, got {0}")]
    Noise(f64),
    /// An angle outside the range of its column.
    #[error("{column} = {value} is out of range; must be in {range}")]
    Angle {
        column: &'static str,
        value: f64,
        range: &'static str,
    },
    /// An empty list of angles.
    #[error("no {0} angles given")]
    NoAngles(&'static str),
    /// Too many points.
    #[error("the grid has {0} points; at most {MAX_POINTS} are allowed")]
    TooManyPoints(usize),
    /// The sample name cannot be written as a data row.
    #[error(
        "sample name {0:?} is not allowed: it must be non-empty, have no control characters \
         and not start with '#' or whitespace"
    )]
    SampleName(String),
    /// The file to append to cannot be read, or has another header.
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error("{path}: cannot append: {reason}")]
    Append { path: String, reason: String },
    #[error("{path}: cannot write: {source}")]
    Io { path: String, source: io::Error },
}

/// What to synthesise: a model, an angle grid and the noise.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthSpec {
    /// The true model: NDF, scale, eta, masking and orders (for orders all, its walks and their
    /// seed).
    pub model: Model,
    /// Incidence angles (degrees, [0, 90)); the outer loop of the rows.
    pub theta_i_deg: Vec<f64>,
    /// Transmitted directions (degrees, (90, 270)); the inner loop of the rows.
    pub theta_o_deg: Vec<f64>,
    /// Relative noise sigma: each value is `max(0, L (1 + sigma z))`, z standard normal.
    pub noise: f64,
    /// Seed of the noise (a PCG-64 stream); the same seed gives the same file.
    pub seed: u64,
    /// The sample name written in the `sample` column.
    pub name: String,
}

impl SynthSpec {
    /// Checks every parameter, returning the first problem.
    pub fn validate(&self) -> Result<(), SynthError> {
        self.model.check()?;
        if !(self.noise.is_finite() && self.noise >= 0.0) {
            return Err(SynthError::Noise(self.noise));
        }
        check_angles(
            COL_THETA_I,
            &self.theta_i_deg,
            THETA_I_RANGE,
            theta_i_in_range,
        )?;
        check_angles(
            COL_THETA_O,
            &self.theta_o_deg,
            THETA_O_RANGE,
            theta_o_in_range,
        )?;
        let n = self
            .theta_i_deg
            .len()
            .saturating_mul(self.theta_o_deg.len());
        if n > MAX_POINTS {
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

    /// The synthetic sample: for each `theta_i` (outer) and `theta_o` (inner), the model value
    /// ([`Model::predict`]) with multiplicative noise `max(0, L (1 + noise z))`, `z ~ N(0, 1)`
    /// drawn in row order from PCG-64 seeded with `seed`.
    pub fn sample(&self) -> Result<Sample, SynthError> {
        self.validate()?;
        let angles: Vec<(f64, f64)> = self
            .theta_i_deg
            .iter()
            .flat_map(|&ti| self.theta_o_deg.iter().map(move |&to| (ti, to)))
            .collect();
        let l = self.model.predict(&angles)?;
        let mut rng = Pcg64::seed_from_u64(self.seed);
        let points = angles
            .iter()
            .zip(l)
            .map(|(&(theta_i_deg, theta_o_deg), l)| {
                let z: f64 = StandardNormal.sample(&mut rng);
                Measurement {
                    theta_i_deg,
                    theta_o_deg,
                    l: (l * (1.0 + self.noise * z)).max(0.0),
                    weight: 1.0,
                }
            })
            .collect();
        Ok(Sample {
            name: self.name.clone(),
            points,
        })
    }
}

/// Writes `samples` with `comment` to the file at `path`: replacing it, or with `append`
/// adding the rows to it (creating it if needed; an existing file must start with the header
/// [`write_csv`] writes, read by the loader's rules, and end with a line break).
pub fn write_file(
    path: &Path,
    samples: &[Sample],
    comment: Option<&str>,
    append: bool,
) -> Result<(), SynthError> {
    let display = path.display().to_string();
    let header = !append || !path.exists();
    if !header {
        let expected = HEADER.join(",");
        match read_header(path)? {
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
        let ends_with_break = std::fs::read(path)
            .map(|b| b.ends_with(b"\n"))
            .unwrap_or(false);
        if !ends_with_break {
            return Err(SynthError::Append {
                path: display,
                reason: "the file does not end with a line break".into(),
            });
        }
    }
    let mut buf = Vec::new();
    write_csv(&mut buf, samples, header, comment).expect("writing to memory");
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

/// Writes samples as data rows `sample,theta_i_deg,theta_o_deg,L`, preceded by the header line
/// when `header` is true and by `comment` (each of its lines prefixed with `# `) when given.
/// Numbers are written in Rust's shortest form that reads back to the same `f64`.
pub fn write_csv<W: Write>(
    mut out: W,
    samples: &[Sample],
    header: bool,
    comment: Option<&str>,
) -> io::Result<()> {
    if let Some(comment) = comment {
        for line in comment.lines() {
            writeln!(out, "# {line}")?;
        }
    }
    let mut writer = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(&mut out);
    if header {
        writer.write_record(HEADER)?;
    }
    for sample in samples {
        for p in &sample.points {
            writer.write_record([
                sample.name.as_str(),
                &p.theta_i_deg.to_string(),
                &p.theta_o_deg.to_string(),
                &p.l.to_string(),
            ])?;
        }
    }
    writer.flush()?;
    Ok(())
}

/// Parses an angle list: comma-separated items, each a number or an inclusive range
/// `start:stop:step` (`step > 0`, `stop >= start`). Range values are `start + k step`, rounded
/// to 1e-9 degrees so that decimal steps give decimal angles.
pub fn parse_angle_list(text: &str) -> Result<Vec<f64>, String> {
    let mut angles = Vec::new();
    for item in text.split(',') {
        let item = item.trim();
        let parts: Vec<&str> = item.split(':').collect();
        let num = |s: &str| -> Result<f64, String> {
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
                let round = |x: f64| (x * 1e9).round() / 1e9;
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

#[cfg(test)]
mod tests {
    use super::*;
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
            theta_i_deg: vec![0.0, 30.0, 60.0, 80.0],
            theta_o_deg: parse_angle_list("106:254:2").unwrap(),
            noise: 0.0,
            seed: 7,
            name: "frosted".into(),
        }
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
        let angles: Vec<_> = sample
            .points
            .iter()
            .map(|p| (p.theta_i_deg, p.theta_o_deg))
            .collect();
        let l = s.model.predict(&angles).unwrap();
        assert!(sample.points.iter().zip(&l).all(|(p, l)| p.l == *l));
        assert!(sample.points.iter().any(|p| p.l > 0.1));
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
            .filter(|(_, c)| c.l > 0.0)
            .map(|(n, c)| n.l / c.l - 1.0)
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
            (|s| s.theta_i_deg = vec![90.0], "theta_i_deg"),
            (|s| s.theta_o_deg = vec![], "theta_o_deg"),
            (|s| s.theta_o_deg = vec![270.0], "theta_o_deg"),
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

    /// Multiple scattering adds the walk's orders >= 2 to the height-correlated single
    /// scattering: more light everywhere, deterministic for a seed.
    #[test]
    fn multiple_scattering_sample_adds_to_single_scattering() {
        let mut s = spec();
        s.model.alpha = 0.6;
        s.theta_o_deg = parse_angle_list("110:250:10").unwrap();
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
            .map(|(a, b)| (a.l, b.l))
            .fold((0.0, 0.0), |(x, y), (a, b)| (x + a, y + b));
        assert!(
            single
                .points
                .iter()
                .zip(&multi.points)
                .all(|(a, b)| b.l >= a.l),
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
