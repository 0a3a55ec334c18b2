//! Goniophotometer files in the pab-opto "Mountain" text format, the output of the pg2
//! goniophotometer that Radiance's `pabopto2bsdf` reads (its manual page and
//! `src/cv/pabopto2bsdf.c` define the format): one file per incident direction and scattered
//! hemisphere, a header of `#` lines, then one line `theta phi value` per scattered direction.
//!
//! Header lines understood (others are ignored, as `pabopto2bsdf` does):
//!
//! - `#sample_name "NAME"`: the sample (files without one form an unnamed sample);
//! - `#format: theta phi DSF` or `BSDF` (`BRDF` and `BTDF` are accepted for `BSDF`, case
//!   ignored): the DSF is the BSDF times `|cos theta_out|`, and is divided by it on reading;
//! - `#intheta T`, `#inphi P`, or `#incident_angle T P`: the direction toward the light, polar
//!   angle from the front normal in [0, 180] (above 90 is the back side) and azimuth;
//! - `#upphi U`: rotates every azimuth alike, which an isotropic BSDF ignores;
//! - `#colorimetry: CIE-Y` (one value per line, the default) or `CIE-XYZ` (three, of which the
//!   Y, photometric, value is used).
//!
//! The front side is stfit's outside (+z), so the angles are those of a general measurement
//! file (`data-format.md`); every scattered direction of a file lies on one side.

use std::io::Write;
use std::path::Path;

use crate::conventions::{THETA_RANGE, spherical_from_deg, theta_in_range};
use crate::data::{Measurement, Sample};
use crate::load::{LoadError, LoadErrorKind, parse_finite};

/// How a pab-opto file gives its values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PabValue {
    /// The BSDF times `|cos theta_out|`.
    Dsf,
    /// The BSDF in 1/sr.
    Bsdf,
}

impl PabValue {
    /// The word of the `#format:` line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Dsf => "DSF",
            Self::Bsdf => "BSDF",
        }
    }
}

/// Header keys that mark a pab-opto file.
const PAB_KEYS: [&str; 6] = [
    "format:",
    "intheta",
    "inphi",
    "incident_angle",
    "sample_name",
    "colorimetry:",
];

/// Whether `bytes` look like a pab-opto file: among the `#` lines that open it, one starts
/// (after the `#` and any spaces) with a pab-opto header key: `format:`, `intheta`, `inphi`,
/// `incident_angle`, `sample_name` or `colorimetry:`.
pub fn is_pabopto(bytes: &[u8]) -> bool {
    let text = String::from_utf8_lossy(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes));
    text.lines()
        .take_while(|l| l.starts_with('#') || l.trim().is_empty())
        .any(|l| {
            let key = l[1.min(l.len())..].trim_start();
            PAB_KEYS.iter().any(|k| key.starts_with(k))
        })
}

/// Reads one pab-opto file: its sample name (empty when the file has none) and its points, as
/// general measurements of the BSDF. Every problem names the file, the line and the field.
pub fn read_pabopto(source: &Path, bytes: &[u8]) -> Result<(String, Vec<Measurement>), LoadError> {
    let err = |line: usize, column: &str, kind| LoadError {
        file: source.to_path_buf(),
        line: Some(line as u64),
        column: Some(column.to_owned()),
        kind,
    };
    let text =
        std::str::from_utf8(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)).map_err(|e| {
            let line = bytes[..e.valid_up_to()]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1;
            err(line, "text", LoadErrorKind::NotUtf8)
        })?;
    let mut name = String::new();
    let mut value_form: Option<PabValue> = None;
    let (mut theta_i, mut phi_i): (Option<f64>, Option<f64>) = (None, None);
    // The line and header key that gave theta_i, for its range error.
    let mut theta_i_at = (1, "#intheta");
    let mut channels = 1;
    let mut raw: Vec<(usize, f64, f64, f64)> = Vec::new();
    let mut header_done = false;
    for (k, line) in text.lines().enumerate() {
        let n = k + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        if let Some(rest) = trimmed.strip_prefix('#') {
            if header_done {
                return Err(err(n, "#", LoadErrorKind::HeaderAfterData));
            }
            let rest = rest.trim_start();
            let number =
                |s: &str, column: &str| parse_finite(s).map_err(|kind| err(n, column, kind));
            if let Some(v) = rest.strip_prefix("sample_name") {
                let v = v.trim();
                name = v
                    .strip_prefix('"')
                    .and_then(|v| v.strip_suffix('"'))
                    .ok_or_else(|| err(n, "#sample_name", LoadErrorKind::Unquoted))?
                    .to_owned();
            } else if let Some(v) = rest.strip_prefix("format:") {
                let words: Vec<&str> = v.split_whitespace().collect();
                value_form = Some(match words.as_slice() {
                    ["theta", "phi", t] if t.eq_ignore_ascii_case("DSF") => PabValue::Dsf,
                    ["theta", "phi", t]
                        if ["BSDF", "BRDF", "BTDF"]
                            .iter()
                            .any(|f| t.eq_ignore_ascii_case(f)) =>
                    {
                        PabValue::Bsdf
                    }
                    _ => {
                        return Err(err(
                            n,
                            "#format:",
                            LoadErrorKind::UnknownFormat(v.trim().to_owned()),
                        ));
                    }
                });
            } else if let Some(v) = rest.strip_prefix("intheta") {
                theta_i = Some(number(v.trim(), "#intheta")?);
                theta_i_at = (n, "#intheta");
            } else if let Some(v) = rest.strip_prefix("inphi") {
                phi_i = Some(number(v.trim(), "#inphi")?);
            } else if let Some(v) = rest.strip_prefix("incident_angle") {
                let words: Vec<&str> = v.split_whitespace().collect();
                let [t, p] = words.as_slice() else {
                    return Err(err(
                        n,
                        "#incident_angle",
                        LoadErrorKind::Fields {
                            expected: 2,
                            found: words.len(),
                        },
                    ));
                };
                theta_i = Some(number(t, "#incident_angle")?);
                theta_i_at = (n, "#incident_angle");
                phi_i = Some(number(p, "#incident_angle")?);
            } else if let Some(v) = rest.strip_prefix("colorimetry:") {
                channels = match v.trim() {
                    c if c.eq_ignore_ascii_case("CIE-Y") => 1,
                    c if c.eq_ignore_ascii_case("CIE-XYZ") => 3,
                    c => {
                        return Err(err(
                            n,
                            "#colorimetry:",
                            LoadErrorKind::UnknownFormat(c.to_owned()),
                        ));
                    }
                };
            }
            continue;
        }
        header_done = true;
        let fields: Vec<&str> = trimmed.split_whitespace().collect();
        if fields.len() != 2 + channels {
            return Err(err(
                n,
                "theta phi value",
                LoadErrorKind::Fields {
                    expected: 2 + channels,
                    found: fields.len(),
                },
            ));
        }
        let number =
            |i: usize, column: &str| parse_finite(fields[i]).map_err(|kind| err(n, column, kind));
        let theta = number(0, "theta")?;
        if !theta_in_range(theta) {
            return Err(err(
                n,
                "theta",
                LoadErrorKind::AngleOutOfRange {
                    value: theta,
                    range: THETA_RANGE,
                },
            ));
        }
        let phi = number(1, "phi")?;
        // The photometric value: the only one for CIE-Y, the middle (Y) of an XYZ triplet.
        let value = number(2 + channels / 2, "value")?;
        if value < 0.0 {
            return Err(err(n, "value", LoadErrorKind::Negative(value)));
        }
        raw.push((n, theta, phi, value));
    }
    let form = value_form.ok_or_else(|| err(1, "#format:", LoadErrorKind::NoFormat))?;
    let (Some(ti), Some(pi)) = (theta_i, phi_i) else {
        return Err(err(1, "#intheta/#inphi", LoadErrorKind::NoIncidence));
    };
    if !theta_in_range(ti) {
        return Err(err(
            theta_i_at.0,
            theta_i_at.1,
            LoadErrorKind::AngleOutOfRange {
                value: ti,
                range: THETA_RANGE,
            },
        ));
    }
    if raw.is_empty() {
        return Err(err(1, "theta phi value", LoadErrorKind::NoRows));
    }
    let side = raw[0].1 < 90.0;
    let mut points = Vec::with_capacity(raw.len());
    for (n, theta, phi, value) in raw {
        if (theta < 90.0) != side {
            return Err(err(n, "theta", LoadErrorKind::BothSides));
        }
        let cos = spherical_from_deg(theta, phi).z.abs();
        let bsdf = match form {
            PabValue::Bsdf => value,
            PabValue::Dsf => value / cos,
        };
        points.push(Measurement::spherical(
            (ti, pi),
            (theta, phi),
            bsdf + 0.0,
            1.0,
        ));
    }
    Ok((name, points))
}

/// Writes a general sample as pab-opto files into the folder `dir` (created if missing), one
/// per incident direction and scattered side, named `NAME_THETA_PHI_R.txt` (reflection) or
/// `_T.txt` (transmission), values as `form`, preceded by `comment` lines. Returns the paths.
/// The sample name must not contain a double quote.
pub fn write_pabopto(
    dir: &Path,
    sample: &Sample,
    form: PabValue,
    comment: Option<&str>,
) -> std::io::Result<Vec<std::path::PathBuf>> {
    std::fs::create_dir_all(dir)?;
    // Files in order of first appearance of (incidence, side).
    let mut files: Vec<((f64, f64, bool), Vec<u8>)> = Vec::new();
    for p in &sample.points {
        let Some(((theta_i_deg, phi_i_deg), (theta_o_deg, phi_o_deg))) = p.spherical_angles()
        else {
            return Err(std::io::Error::other(
                "only general samples (spherical angles) can be written as pab-opto files",
            ));
        };
        let reflect = (theta_i_deg < 90.0) == (theta_o_deg < 90.0);
        let key = (theta_i_deg, phi_i_deg, reflect);
        let slot = match files.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                let mut head = Vec::new();
                if let Some(comment) = comment {
                    for line in comment.lines() {
                        writeln!(head, "# {line}")?;
                    }
                }
                writeln!(head, "#sample_name \"{}\"", sample.name)?;
                writeln!(head, "#format: theta phi {}", form.name())?;
                writeln!(head, "#intheta {theta_i_deg}")?;
                writeln!(head, "#inphi {phi_i_deg}")?;
                writeln!(head, "#upphi 0")?;
                writeln!(head, "#colorimetry: CIE-Y")?;
                files.push((key, head));
                files.len() - 1
            }
        };
        let cos = spherical_from_deg(theta_o_deg, phi_o_deg).z.abs();
        let value = match form {
            PabValue::Bsdf => p.value,
            PabValue::Dsf => p.value * cos,
        };
        writeln!(files[slot].1, "{theta_o_deg} {phi_o_deg} {value}")?;
    }
    let stem: String = if sample.name.is_empty() {
        "sample".into()
    } else {
        sample
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    };
    let mut paths = Vec::new();
    for ((ti, pi, reflect), bytes) in files {
        let side = if reflect { "R" } else { "T" };
        let path = dir.join(format!("{stem}_{ti}_{pi}_{side}.txt"));
        std::fs::write(&path, bytes)?;
        paths.push(path);
    }
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Angles;

    fn read(text: &str) -> Result<(String, Vec<Measurement>), LoadError> {
        read_pabopto(Path::new("m.txt"), text.as_bytes())
    }

    /// The manual page's example: DSF values are divided by |cos theta_out|.
    #[test]
    fn the_manual_example_reads_as_a_bsdf() {
        let (name, pts) = read(
            "#sample_name \"frosted\"\n#format: theta phi DSF\n#incident_angle 82.5 180\n\
             84.968 125.790 0.009744\n84.889 125.610 0.007737\n",
        )
        .unwrap();
        assert_eq!(name, "frosted");
        assert_eq!(pts.len(), 2);
        let want = 0.009744 / 84.968f64.to_radians().cos();
        assert!((pts[0].value - want).abs() < 1e-15);
        assert_eq!(
            pts[0].angles,
            Angles::Spherical {
                theta_i_deg: 82.5,
                phi_i_deg: 180.0,
                theta_o_deg: 84.968,
                phi_o_deg: 125.79
            }
        );
        assert!(is_pabopto(b"#format: theta phi BSDF\n"));
        assert!(!is_pabopto(b"# stfit synth\nsample,theta_i_deg\n"));
    }

    /// XYZ triplets use their Y value; a file written and read back gives the same values.
    #[test]
    fn xyz_and_round_trips() {
        let (_, pts) = read(
            "#format: theta phi BSDF\n#intheta 30\n#inphi 0\n#colorimetry: CIE-XYZ\n\
             150 10 0.1 0.2 0.3\n",
        )
        .unwrap();
        assert_eq!(pts[0].value, 0.2);
        let sample = Sample {
            name: "g".into(),
            points: vec![
                Measurement::spherical((30.0, 0.0), (40.0, 180.0), 0.5, 1.0),
                Measurement::spherical((30.0, 0.0), (150.0, 10.0), 0.25, 1.0),
            ],
        };
        let dir = std::env::temp_dir().join(format!("stfit-pab-{}", std::process::id()));
        for form in [PabValue::Dsf, PabValue::Bsdf] {
            let paths = write_pabopto(&dir, &sample, form, Some("made by a test")).unwrap();
            assert_eq!(paths.len(), 2, "one reflection and one transmission file");
            let mut back = Vec::new();
            for p in &paths {
                let (name, pts) = read_pabopto(p, &std::fs::read(p).unwrap()).unwrap();
                assert_eq!(name, "g");
                back.extend(pts);
            }
            for (a, b) in back.iter().zip(&sample.points) {
                assert_eq!(a.angles, b.angles);
                assert!((a.value - b.value).abs() <= 1e-15 * b.value, "{form:?}");
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Malformed files name their line and field.
    #[test]
    fn errors_name_line_and_field() {
        let head = "#format: theta phi DSF\n#intheta 30\n#inphi 0\n";
        let cases = [
            ("#intheta 30\n#inphi 0\n10 0 1\n", 1, "#format:"),
            ("#format: theta phi DSF\n10 0 1\n", 1, "#intheta/#inphi"),
            ("#format: theta phi XYZ\n", 1, "#format:"),
            (&format!("{head}10 0\n") as &str, 4, "theta phi value"),
            (&format!("{head}10 x 1\n"), 4, "phi"),
            (&format!("{head}90 0 1\n"), 4, "theta"),
            (&format!("{head}10 0 -1\n"), 4, "value"),
            (&format!("{head}10 0 1\n170 0 1\n"), 5, "theta"),
            (&format!("{head}10 0 1\n#inphi 3\n"), 5, "#"),
            (head, 1, "theta phi value"),
            (
                "#format: theta phi DSF\n#intheta 90\n#inphi 0\n10 0 1\n",
                2,
                "#intheta",
            ),
            (
                "#format: theta phi BSDF\n#incident_angle 0\n",
                2,
                "#incident_angle",
            ),
            ("#sample_name g\n", 1, "#sample_name"),
            (
                "#format: theta phi BSDF\n#colorimetry: RGB\n",
                2,
                "#colorimetry:",
            ),
        ];
        for (text, line, column) in cases {
            let e = read(text).unwrap_err();
            assert_eq!(
                (e.line, e.column.as_deref()),
                (Some(line), Some(column)),
                "{text:?}: {e}"
            );
        }
    }
}
