//! Synthetic measurements of known truth: model values on an angle grid with seeded noise,
//! written in the measurement format of `data-format.md`.

use std::io::{self, Write};

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64;
use stfit_core::ParamError;
use stfit_core::bsdf::Masking;
use thiserror::Error;

use crate::data::{Measurement, Sample};
use crate::load::{COL_L, COL_SAMPLE, COL_THETA_I, COL_THETA_O};
use crate::model::{ModelKind, ModelParams, Scattering};

/// Most points one synthetic sample may have (guards against a mistyped grid step).
pub const MAX_POINTS: usize = 1_000_000;

/// The header line [`write_csv`] writes.
pub const HEADER: [&str; 4] = [COL_SAMPLE, COL_THETA_I, COL_THETA_O, COL_L];

/// An invalid synthesis request.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SynthError {
    /// alpha, gamma or eta out of range.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// gamma given for a model that has none, or missing for Student-T.
    #[error("{0}")]
    Gamma(&'static str),
    /// The calibration scale must be finite and > 0.
    #[error("scale must be finite and > 0, got {0}")]
    Scale(f64),
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
    /// A multiple-scattering request that makes no sense (no walks, separable masking).
    #[error("{0}")]
    Scattering(&'static str),
    /// Too many points.
    #[error("the grid has {0} points; at most {MAX_POINTS} are allowed")]
    TooManyPoints(usize),
    /// The sample name cannot be written as a data row.
    #[error(
        "sample name {0:?} is not allowed: it must be non-empty, have no control characters \
         and not start with '#' or whitespace"
    )]
    SampleName(String),
}

/// What to synthesise: a model, an angle grid and the noise.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthSpec {
    /// The true model. `gamma` is used only by Student-T.
    pub params: ModelParams,
    /// Whether `params.gamma` was given (it must be for Student-T and must not be otherwise).
    pub gamma_given: bool,
    /// Relative index of the glass.
    pub eta: f64,
    /// Smith masking; must be `Correlated` for `Scattering::Multiple` (the random walk is
    /// height-correlated by construction).
    pub masking: Masking,
    /// Single scattering, or all orders (the walk's order >= 2 estimate added to the
    /// height-correlated single-scattering BTDF, as fitted by `Scattering::Multiple`).
    pub scattering: Scattering,
    /// Random walks per incidence angle for `Scattering::Multiple` (> 0 there), seeded with
    /// `seed`.
    pub walks: u64,
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
        let p = &self.params;
        match (p.kind, self.gamma_given) {
            (ModelKind::StudentT, false) => {
                return Err(SynthError::Gamma("student-t needs a gamma (> 3/2)"));
            }
            (ModelKind::Beckmann | ModelKind::Ggx, true) => {
                return Err(SynthError::Gamma(
                    "gamma is a Student-T parameter; beckmann and ggx take none",
                ));
            }
            _ => {}
        }
        // Validates alpha and (for Student-T) gamma.
        p.ndf()?;
        stfit_core::error::check_eta(self.eta)?;
        if !(p.scale.is_finite() && p.scale > 0.0) {
            return Err(SynthError::Scale(p.scale));
        }
        if !(self.noise.is_finite() && self.noise >= 0.0) {
            return Err(SynthError::Noise(self.noise));
        }
        if self.scattering == Scattering::Multiple {
            if self.masking != Masking::Correlated {
                return Err(SynthError::Scattering(
                    "multiple scattering is height-correlated by construction: use correlated \
                     masking",
                ));
            }
            if self.walks == 0 {
                return Err(SynthError::Scattering(
                    "multiple scattering needs at least one random walk per incidence angle",
                ));
            }
        }
        check_angles(COL_THETA_I, &self.theta_i_deg, "[0, 90)", |t| {
            (0.0..90.0).contains(&t)
        })?;
        check_angles(COL_THETA_O, &self.theta_o_deg, "(90, 270)", |t| {
            t > 90.0 && t < 270.0
        })?;
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
    /// (single scattering, [`ModelParams::l_single`], or all orders,
    /// [`ModelParams::l_multiple_batch`] with `walks` walks per incidence from `seed`) with
    /// multiplicative noise `max(0, L (1 + noise z))`, `z ~ N(0, 1)` drawn in row order from
    /// PCG-64 seeded with `seed`.
    pub fn sample(&self) -> Result<Sample, SynthError> {
        self.validate()?;
        let angles: Vec<(f64, f64)> = self
            .theta_i_deg
            .iter()
            .flat_map(|&ti| self.theta_o_deg.iter().map(move |&to| (ti, to)))
            .collect();
        let l = match self.scattering {
            Scattering::Single => angles
                .iter()
                .map(|&(ti, to)| self.params.l_single(ti, to, self.eta, self.masking))
                .collect::<Result<Vec<f64>, ParamError>>()?,
            Scattering::Multiple => self
                .params
                .l_multiple_batch(&angles, self.eta, self.walks, self.seed)?,
        };
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
    use std::path::Path;

    fn spec() -> SynthSpec {
        SynthSpec {
            params: ModelParams {
                kind: ModelKind::StudentT,
                alpha: 0.2,
                gamma: 3.0,
                scale: 1.5,
            },
            gamma_given: true,
            eta: 1.51,
            masking: Masking::Separable,
            scattering: Scattering::Single,
            walks: 1,
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
        for p in &sample.points {
            let l = s
                .params
                .l_single(p.theta_i_deg, p.theta_o_deg, s.eta, s.masking)
                .unwrap();
            assert_eq!(p.l, l);
        }
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
            (|s| s.params.alpha = 0.0, "alpha"),
            (|s| s.params.gamma = 1.5, "gamma"),
            (|s| s.gamma_given = false, "gamma"),
            (
                |s| {
                    s.params.kind = ModelKind::Ggx;
                },
                "gamma",
            ),
            (|s| s.eta = 1.0, "eta"),
            (|s| s.params.scale = -1.0, "scale"),
            (|s| s.noise = f64::NAN, "noise"),
            (|s| s.theta_i_deg = vec![90.0], "theta_i_deg"),
            (|s| s.theta_o_deg = vec![], "theta_o_deg"),
            (|s| s.theta_o_deg = vec![270.0], "theta_o_deg"),
            (|s| s.name = "#x".into(), "sample name"),
            (|s| s.name = String::new(), "sample name"),
            (|s| s.scattering = Scattering::Multiple, "height-correlated"),
            (
                |s| {
                    s.scattering = Scattering::Multiple;
                    s.masking = Masking::Correlated;
                    s.walks = 0;
                },
                "random walk",
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
        s.params.alpha = 0.6;
        s.theta_o_deg = parse_angle_list("110:250:10").unwrap();
        s.masking = Masking::Correlated;
        let single = s.sample().unwrap();
        s.scattering = Scattering::Multiple;
        s.walks = 2000;
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
