//! Goniophotometer files in the pab-opto "Mountain" text format, the output of the pg2
//! goniophotometer that Radiance's `pabopto2bsdf` reads (its manual page and
//! `src/cv/pabopto2bsdf.c` define the format): one file per incident direction and scattered
//! hemisphere, a header of `#` lines, then one line `theta phi value` per scattered direction.
//!
//! Header lines understood (others are ignored):
//!
//! - `#sample_name "NAME"`: the sample, trimmed and not empty (files without one form an
//!   unnamed sample);
//! - `#format: theta phi DSF` or `BSDF` (`BRDF` and `BTDF` are accepted for `BSDF`, case
//!   ignored): the DSF is the BSDF times `|cos theta_out|`, and is divided by it on reading;
//! - `#intheta T`, `#inphi P`, or `#incident_angle T P`: the direction toward the light, polar
//!   angle from the front normal in [0, 180] (above 90 is the back side) and azimuth;
//! - `#colorimetry: CIE-Y` (one value per line, the default) or `CIE-XYZ` (three, of which the
//!   Y, photometric, value is used).
//!
//! `#upphi U`, the azimuth of the sample's "up", is one of the lines ignored: `pabopto2bsdf`
//! adds `90 - U` to every azimuth of the file (incident and scattered) to put up on Radiance's
//! +y, a rotation that an isotropic BSDF does not see, so stfit takes the azimuths as written.
//! The files [`write_pabopto`] writes say `#upphi 90`, so that Radiance's azimuths are theirs.
//!
//! Each of these lines may appear once, except that `#intheta` and `#inphi` may come with an
//! `#incident_angle` that gives the same angles (as Radiance's `pabopto2xyz` writes them).
//! The front side is stfit's outside (+z), so the angles are those of a general measurement
//! file (`data-format.md`); every scattered direction of a file lies on one side. These are
//! Radiance's conventions too (`pabopto2bsdf` without `-t`): both directions are
//! `(sin theta cos phi, sin theta sin phi, cos theta)` pointing away from the surface, the
//! incident one toward the light, `theta < 90` on its front (+z) side, so a specular peak lies
//! at `phi + 180`.

use crate::pairs::format_number;
use std::path::Path;

use crate::conventions::{THETA_RANGE, reduced_azimuth_deg, spherical_from_deg, theta_in_range};
use crate::data::{Measurement, Sample};
use crate::load::{LoadError, LoadErrorKind, parse_finite};
use crate::synth::SynthError;

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

/// The header lines of a pab-opto file that this reader understands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Key {
    SampleName,
    Format,
    InTheta,
    InPhi,
    IncidentAngle,
    Colorimetry,
}

impl Key {
    const ALL: [Self; 6] = [
        Self::SampleName,
        Self::Format,
        Self::InTheta,
        Self::InPhi,
        Self::IncidentAngle,
        Self::Colorimetry,
    ];

    /// The word after the `#`.
    fn word(self) -> &'static str {
        match self {
            Self::SampleName => "sample_name",
            Self::Format => "format:",
            Self::InTheta => "intheta",
            Self::InPhi => "inphi",
            Self::IncidentAngle => "incident_angle",
            Self::Colorimetry => "colorimetry:",
        }
    }

    /// The header line's name in messages: the word with its `#`.
    fn column(self) -> String {
        format!("#{}", self.word())
    }

    /// The key `text` (a header line after its `#` and spaces) starts with, and the rest.
    fn split(text: &str) -> Option<(Self, &str)> {
        Self::ALL
            .into_iter()
            .find_map(|k| text.strip_prefix(k.word()).map(|rest| (k, rest)))
    }
}

/// Whether `bytes` look like a pab-opto file: among the `#` lines that open it, one starts
/// (after the `#` and any spaces) with a pab-opto header key: `format:`, `intheta`, `inphi`,
/// `incident_angle`, `sample_name` or `colorimetry:`.
pub fn is_pabopto(bytes: &[u8]) -> bool {
    let text = String::from_utf8_lossy(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes));
    text.lines()
        .take_while(|l| l.starts_with('#') || l.trim().is_empty())
        .filter_map(|l| l.strip_prefix('#'))
        .any(|rest| Key::split(rest.trim_start()).is_some())
}

/// An error of the pab-opto file `source` at its 1-based `line`, in the field `column`.
fn error(source: &Path, line: usize, column: &str, kind: LoadErrorKind) -> LoadError {
    LoadError {
        file: source.to_path_buf(),
        line: Some(line as u64),
        column: Some(column.to_owned()),
        kind,
    }
}

/// An incident angle and the header line that gave it.
#[derive(Debug, Clone, Copy)]
struct Given {
    value: f64,
    key: Key,
    line: usize,
}

/// The header of a pab-opto file as far as it has been read.
#[derive(Debug, Default)]
struct Header {
    name: Option<String>,
    form: Option<PabValue>,
    theta_i: Option<Given>,
    phi_i: Option<Given>,
    /// The names of a data line's value fields: `value` (CIE-Y) or `X`, `Y`, `Z` (CIE-XYZ).
    values: Option<&'static [&'static str]>,
    /// The line of every key met so far.
    seen: Vec<(Key, usize)>,
}

impl Header {
    /// Reads header line `n`, `text` being what follows its `#` and spaces. Lines of other
    /// keys are ignored. Refused: a key met before, and an incident angle that another key
    /// gave otherwise (`#intheta 60` with `#incident_angle 30 0`); the same angle given both
    /// ways alike, as Radiance's `pabopto2xyz` writes it, is read.
    fn read(&mut self, source: &Path, n: usize, text: &str) -> Result<(), LoadError> {
        let Some((key, rest)) = Key::split(text) else {
            return Ok(());
        };
        let err = |kind| error(source, n, &key.column(), kind);
        if let Some(&(_, first)) = self.seen.iter().find(|(k, _)| *k == key) {
            return Err(err(LoadErrorKind::RepeatedHeader {
                first: first as u64,
            }));
        }
        self.seen.push((key, n));
        let given = |s: &str| {
            parse_finite(s)
                .map(|value| Given {
                    value,
                    key,
                    line: n,
                })
                .map_err(err)
        };
        // A polar angle is checked on its line, so that a problem of a later (data) line is
        // not reported first.
        let polar = |s: &str| {
            let given = given(s)?;
            if theta_in_range(given.value) {
                Ok(given)
            } else {
                Err(err(LoadErrorKind::AngleOutOfRange {
                    value: given.value,
                    range: THETA_RANGE,
                }))
            }
        };
        match key {
            Key::SampleName => self.name = Some(sample_name(rest).map_err(err)?),
            Key::Format => self.form = Some(value_form(rest).map_err(err)?),
            Key::Colorimetry => self.values = Some(colorimetry(rest).map_err(err)?),
            Key::InTheta => give(source, &mut self.theta_i, polar(rest.trim())?, f64::eq)?,
            Key::InPhi => give(source, &mut self.phi_i, given(rest.trim())?, same_azimuth)?,
            Key::IncidentAngle => {
                let words: Vec<&str> = rest.split_whitespace().collect();
                let [t, p] = words.as_slice() else {
                    return Err(err(LoadErrorKind::Fields {
                        expected: 2,
                        found: words.len(),
                    }));
                };
                let (t, p) = (polar(t)?, given(p)?);
                give(source, &mut self.theta_i, t, f64::eq)?;
                give(source, &mut self.phi_i, p, same_azimuth)?;
            }
        }
        Ok(())
    }

    /// The value names of a data line, `value` unless `#colorimetry: CIE-XYZ` was given.
    fn values(&self) -> &'static [&'static str] {
        self.values.unwrap_or(&["value"])
    }
}

/// Whether two azimuths in degrees are the same direction: equal after reduction by whole
/// turns ([`reduced_azimuth_deg`]: `360` and `0`, `-90` and `270`).
fn same_azimuth(a: &f64, b: &f64) -> bool {
    reduced_azimuth_deg(*a) == reduced_azimuth_deg(*b)
}

/// Sets the incident angle in `slot` to `new`, refusing a value that is not `same` as the one
/// an earlier header line gave.
fn give(
    source: &Path,
    slot: &mut Option<Given>,
    new: Given,
    same: fn(&f64, &f64) -> bool,
) -> Result<(), LoadError> {
    match *slot {
        Some(old) if !same(&old.value, &new.value) => Err(error(
            source,
            new.line,
            &new.key.column(),
            LoadErrorKind::IncidenceConflict {
                other: format!("{} {}", old.key.column(), old.value),
                other_line: old.line as u64,
            },
        )),
        Some(_) => Ok(()),
        None => {
            *slot = Some(new);
            Ok(())
        }
    }
}

/// The name of a `#sample_name "NAME"` line: in double quotes, trimmed as a CSV sample name
/// is, and not empty.
fn sample_name(rest: &str) -> Result<String, LoadErrorKind> {
    let name = rest
        .trim()
        .strip_prefix('"')
        .and_then(|v| v.strip_suffix('"'))
        .ok_or(LoadErrorKind::Unquoted)?
        .trim();
    if name.is_empty() {
        return Err(LoadErrorKind::EmptySampleName);
    }
    Ok(name.to_owned())
}

/// The value form of a `#format: theta phi DSF` (or `BSDF`, `BRDF`, `BTDF`, case ignored) line.
fn value_form(rest: &str) -> Result<PabValue, LoadErrorKind> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    match words.as_slice() {
        ["theta", "phi", t] if t.eq_ignore_ascii_case("DSF") => Ok(PabValue::Dsf),
        ["theta", "phi", t]
            if ["BSDF", "BRDF", "BTDF"]
                .iter()
                .any(|f| t.eq_ignore_ascii_case(f)) =>
        {
            Ok(PabValue::Bsdf)
        }
        _ => Err(LoadErrorKind::UnknownFormat(rest.trim().to_owned())),
    }
}

/// The value names of a `#colorimetry: CIE-Y` or `CIE-XYZ` line.
fn colorimetry(rest: &str) -> Result<&'static [&'static str], LoadErrorKind> {
    match rest.trim() {
        c if c.eq_ignore_ascii_case("CIE-Y") => Ok(&["value"]),
        c if c.eq_ignore_ascii_case("CIE-XYZ") => Ok(&["X", "Y", "Z"]),
        c => Err(LoadErrorKind::UnknownFormat(c.to_owned())),
    }
}

/// Reads one pab-opto file: its sample name (empty when the file has none) and its points, as
/// general measurements of the BSDF. Every problem names the file, the line and the field:
/// besides the format's own rules, a header line given twice, incident angles that two header
/// lines give differently, an empty sample name, any value field (X and Z of CIE-XYZ included)
/// that is not a finite number `>= 0`, and a DSF whose BSDF (DSF / |cos theta|) overflows.
pub fn read_pabopto(source: &Path, bytes: &[u8]) -> Result<(String, Vec<Measurement>), LoadError> {
    let err = |line: usize, column: &str, kind| error(source, line, column, kind);
    let text =
        std::str::from_utf8(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)).map_err(|e| {
            let line = bytes[..e.valid_up_to()]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1;
            err(line, "text", LoadErrorKind::NotUtf8)
        })?;
    let mut header = Header::default();
    let mut raw: Vec<(usize, f64, f64, f64)> = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let n = k + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        if let Some(rest) = trimmed.strip_prefix('#') {
            if !raw.is_empty() {
                return Err(err(n, "#", LoadErrorKind::HeaderAfterData));
            }
            header.read(source, n, rest.trim_start())?;
            continue;
        }
        let (theta, phi, value) = data_line(source, n, trimmed, header.values())?;
        raw.push((n, theta, phi, value));
    }
    let form = header
        .form
        .ok_or_else(|| err(1, "#format:", LoadErrorKind::NoFormat))?;
    let (Some(ti), Some(pi)) = (header.theta_i, header.phi_i) else {
        return Err(err(1, "#intheta/#inphi", LoadErrorKind::NoIncidence));
    };
    if raw.is_empty() {
        return Err(err(1, "theta phi value", LoadErrorKind::NoRows));
    }
    let values = header.values();
    let photometric = values[values.len() / 2];
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
        if !bsdf.is_finite() {
            return Err(err(
                n,
                photometric,
                LoadErrorKind::Overflow {
                    value,
                    derived: "BSDF = DSF / |cos theta|",
                },
            ));
        }
        points.push(Measurement::spherical(
            (ti.value, pi.value),
            (theta, phi),
            bsdf + 0.0,
            1.0,
        ));
    }
    Ok((header.name.unwrap_or_default(), points))
}

/// Reads data line `n` (`text`, trimmed) of fields `theta phi` and `values`: the angles and
/// the photometric value (the only one, or Y of X Y Z). Every value must be a finite number
/// `>= 0`, and theta in `[0, 180]` without 90.
fn data_line(
    source: &Path,
    n: usize,
    text: &str,
    values: &[&str],
) -> Result<(f64, f64, f64), LoadError> {
    let err = |column: &str, kind| error(source, n, column, kind);
    let fields: Vec<&str> = text.split_whitespace().collect();
    if fields.len() != 2 + values.len() {
        return Err(err(
            &format!("theta phi {}", values.join(" ")),
            LoadErrorKind::Fields {
                expected: 2 + values.len(),
                found: fields.len(),
            },
        ));
    }
    let number = |i: usize, column: &str| parse_finite(fields[i]).map_err(|kind| err(column, kind));
    let theta = number(0, "theta")?;
    if !theta_in_range(theta) {
        return Err(err(
            "theta",
            LoadErrorKind::AngleOutOfRange {
                value: theta,
                range: THETA_RANGE,
            },
        ));
    }
    let phi = number(1, "phi")?;
    let mut read = Vec::with_capacity(values.len());
    for (i, &column) in values.iter().enumerate() {
        let value = number(2 + i, column)?;
        if value < 0.0 {
            return Err(err(column, LoadErrorKind::Negative(value)));
        }
        read.push(value);
    }
    Ok((theta, phi, read[read.len() / 2]))
}

/// Writes a general sample as pab-opto files into the folder `dir` (created if missing), one
/// per incident direction and scattered side, named `NAME_THETA_PHI_R.txt` (reflection) or
/// `_T.txt` (transmission), values as `form`, preceded by `comment` lines. Returns the paths.
/// `NAME` is the first [`MAX_SAMPLE_CHARS`](crate::files::MAX_SAMPLE_CHARS) characters of the sample name, each outside
/// `[A-Za-z0-9-]` becoming `_` (`sample` for an unnamed sample), and the angles are written as
/// in the files, in the shortest form that reads back to them, in exponent form outside
/// `[1e-4, 1e15)` (`1e-300`, not 300 zeros): a name is at most about 160 bytes, so valid
/// angles never make one that a file system refuses.
/// The sample name must not contain a double quote; an unnamed sample's files have no
/// `#sample_name` line. An error names the folder or the file that could not be written.
pub fn write_pabopto(
    dir: &Path,
    sample: &Sample,
    form: PabValue,
    comment: Option<&str>,
) -> Result<Vec<std::path::PathBuf>, SynthError> {
    let io_at = |path: &Path| {
        let path = path.display().to_string();
        move |source| SynthError::Io { path, source }
    };
    crate::files::create_folder(dir).map_err(io_at(dir))?;
    // Files in order of first appearance of (incidence, side).
    let mut files: Vec<((f64, f64, bool), String)> = Vec::new();
    for p in &sample.points {
        let Some(((theta_i_deg, phi_i_deg), (theta_o_deg, phi_o_deg))) = p.spherical_angles()
        else {
            return Err(io_at(dir)(std::io::Error::other(
                "only general samples (spherical angles) can be written as pab-opto files",
            )));
        };
        let reflect = (theta_i_deg < 90.0) == (theta_o_deg < 90.0);
        let key = (theta_i_deg, phi_i_deg, reflect);
        let slot = match files.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                let mut head = String::new();
                if let Some(comment) = comment {
                    for line in comment.lines() {
                        head.push_str(&format!("# {line}\n"));
                    }
                }
                if !sample.name.is_empty() {
                    head.push_str(&format!("#sample_name \"{}\"\n", sample.name));
                }
                head.push_str(&format!("#format: theta phi {}\n", form.name()));
                head.push_str(&format!("#intheta {}\n", format_number(theta_i_deg)));
                head.push_str(&format!("#inphi {}\n", format_number(phi_i_deg)));
                // Up at azimuth 90: pabopto2bsdf's rotation `90 - upphi` is then 0, and
                // Radiance's azimuths are stfit's.
                head.push_str("#upphi 90\n");
                head.push_str("#colorimetry: CIE-Y\n");
                files.push((key, head));
                files.len() - 1
            }
        };
        let cos = spherical_from_deg(theta_o_deg, phi_o_deg).z.abs();
        let value = match form {
            PabValue::Bsdf => p.value,
            PabValue::Dsf => p.value * cos,
        };
        files[slot].1.push_str(&format!(
            "{} {} {}\n",
            format_number(theta_o_deg),
            format_number(phi_o_deg),
            format_number(value)
        ));
    }
    let stem: String = if sample.name.is_empty() {
        "sample".into()
    } else {
        sample
            .name
            .chars()
            .take(crate::files::MAX_SAMPLE_CHARS)
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
        let path = dir.join(format!(
            "{stem}_{}_{}_{side}.txt",
            format_number(ti),
            format_number(pi)
        ));
        std::fs::write(&path, bytes).map_err(io_at(&path))?;
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

    /// An incident polar angle out of range is reported on its own line, before the problems
    /// of later lines: it had been checked only once every line was read, so a bad data line
    /// further down was reported instead (data-format.md: reading stops at the first problem).
    #[test]
    fn an_incident_angle_out_of_range_is_the_first_problem_of_its_file() {
        for (head, key) in [
            ("#intheta 200\n#inphi 0\n", "#intheta"),
            ("#incident_angle 90 0\n", "#incident_angle"),
        ] {
            let e = read(&format!("#format: theta phi BSDF\n{head}150 10 abc\n")).unwrap_err();
            assert_eq!(
                (e.line, e.column.as_deref()),
                (Some(2), Some(key)),
                "{head}: {e}"
            );
            assert!(
                matches!(e.kind, LoadErrorKind::AngleOutOfRange { .. }),
                "{e}"
            );
        }
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

    /// A file opening with a line of non-ASCII whitespace (a no-break space, an ideographic
    /// space) is told apart without a panic, as the same file with an ASCII blank line is.
    #[test]
    fn opening_line_of_multibyte_whitespace_is_not_pabopto() {
        assert!(!is_pabopto(
            "\u{a0}\ntheta_i_deg,theta_o_deg,L\n".as_bytes()
        ));
        assert!(is_pabopto("\u{3000}\n#format: theta phi BSDF\n".as_bytes()));
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

    /// A header line given twice is refused at its second line, naming the first, even with
    /// the same value; `#intheta`/`#inphi` and `#incident_angle` may both be given only when
    /// they agree (Radiance's `pabopto2xyz` writes all three).
    #[test]
    fn repeated_and_conflicting_header_lines_are_refused() {
        let head = "#sample_name \"x\"\n#format: theta phi DSF\n#intheta 30\n#inphi 0\n";
        let cases = [
            ("#intheta 60\n", "#intheta", 3),
            ("#inphi 0\n", "#inphi", 4),
            ("#format: theta phi BSDF\n", "#format:", 2),
            ("#sample_name \"y\"\n", "#sample_name", 1),
            (
                "#colorimetry: CIE-Y\n#colorimetry: CIE-Y\n",
                "#colorimetry:",
                5,
            ),
            (
                "#incident_angle 30 0\n#incident_angle 30 0\n",
                "#incident_angle",
                5,
            ),
        ];
        for (extra, column, first) in cases {
            let e = read(&format!("{head}{extra}150 0 1\n")).unwrap_err();
            let line = 4 + extra.lines().count() as u64;
            assert_eq!(
                (e.line, e.column.as_deref(), e.kind),
                (
                    Some(line),
                    Some(column),
                    LoadErrorKind::RepeatedHeader { first }
                ),
                "{extra:?}"
            );
        }
        let e = read(&format!("{head}#intheta 60\n150 0 1\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "m.txt:5: column '#intheta': given again; line 3 gave it already, and each header \
             line may appear once"
        );
        let e = read(&format!("{head}#incident_angle 30 5\n150 0 1\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "m.txt:5: column '#incident_angle': disagrees with '#inphi 0' on line 4"
        );
        let e = read("#format: theta phi DSF\n#incident_angle 30 0\n#intheta 60\n150 0 1\n")
            .unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref()),
            (Some(3), Some("#intheta")),
            "{e}"
        );
        assert_eq!(
            e.kind,
            LoadErrorKind::IncidenceConflict {
                other: "#incident_angle 30".into(),
                other_line: 2,
            }
        );
        let (_, pts) = read(&format!("{head}#incident_angle 30 0\n150 0 1\n")).unwrap();
        assert_eq!(pts[0].spherical_angles().unwrap().0, (30.0, 0.0));
        // Azimuths a whole turn apart are the same incidence (data-format.md).
        for phi in ["360", "-360", "720"] {
            let (_, pts) = read(&format!("{head}#incident_angle 30 {phi}\n150 0 1\n")).unwrap();
            assert_eq!(pts[0].spherical_angles().unwrap().0, (30.0, 0.0), "{phi}");
        }
    }

    /// A sample name is trimmed and must not be empty, as a CSV file's `sample` field; an
    /// unnamed sample is written without a `#sample_name` line and reads back unnamed.
    #[test]
    fn sample_names_are_trimmed_and_not_empty() {
        let body = "#format: theta phi BSDF\n#intheta 30\n#inphi 0\n150 0 1\n";
        for name in ["\"\"", "\"  \""] {
            let e = read(&format!("#sample_name {name}\n{body}")).unwrap_err();
            assert_eq!(
                (e.line, e.column.as_deref(), e.kind),
                (
                    Some(1),
                    Some("#sample_name"),
                    LoadErrorKind::EmptySampleName
                ),
                "{name}"
            );
        }
        let (name, _) = read(&format!("#sample_name \" a b \"\n{body}")).unwrap();
        assert_eq!(name, "a b");
        let sample = Sample {
            name: String::new(),
            points: vec![Measurement::spherical((30.0, 0.0), (150.0, 0.0), 1.0, 1.0)],
        };
        let dir = std::env::temp_dir().join(format!("stfit-pab-unnamed-{}", std::process::id()));
        let paths = write_pabopto(&dir, &sample, PabValue::Bsdf, None).unwrap();
        let bytes = std::fs::read(&paths[0]).unwrap();
        assert!(!String::from_utf8_lossy(&bytes).contains("#sample_name"));
        assert_eq!(read_pabopto(&paths[0], &bytes).unwrap().0, "");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Every value of a line is checked, X and Z of an XYZ triplet too, and a DSF whose BSDF
    /// (DSF / |cos theta|) overflows near grazing is refused at its line.
    #[test]
    fn every_value_is_checked_and_dsf_overflow_refused() {
        let head = "#format: theta phi DSF\n#intheta 30\n#inphi 0\n";
        let xyz = format!("{head}#colorimetry: CIE-XYZ\n150 0 1 1 1\n");
        let cases = [
            (
                format!("{xyz}150 10 -5 0.2 0.3\n"),
                "X",
                LoadErrorKind::Negative(-5.0),
            ),
            (
                format!("{xyz}150 10 0.1 0.2 nan\n"),
                "Z",
                LoadErrorKind::NonFinite("nan".into()),
            ),
            (
                format!("{xyz}150 10 0.1 -0.2 0.3\n"),
                "Y",
                LoadErrorKind::Negative(-0.2),
            ),
            (
                format!("{xyz}90.0000000001 0 1 1e300 1\n"),
                "Y",
                LoadErrorKind::Overflow {
                    value: 1e300,
                    derived: "BSDF = DSF / |cos theta|",
                },
            ),
        ];
        for (text, column, kind) in cases {
            let e = read(&text).unwrap_err();
            assert_eq!(
                (e.line, e.column.as_deref(), e.kind),
                (Some(6), Some(column), kind),
                "{text:?}"
            );
        }
        let e = read(&format!("{head}150 0 1\n90.0000000001 0 1e300\n")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "m.txt:5: column 'value': 1e300 is too large: BSDF = DSF / |cos theta| overflows to \
             infinity"
        );
        let bsdf = head.replace("DSF", "BSDF");
        let (_, pts) = read(&format!("{bsdf}90.0000000001 0 1e300\n")).unwrap();
        assert_eq!(pts[0].value, 1e300);
    }

    /// A nonzero number that reads as 0 is refused at its line and field, in the header and in
    /// the data; a subnormal value is read as it is.
    #[test]
    fn nonzero_numbers_that_read_as_zero_are_refused() {
        let head = "#format: theta phi BSDF\n#intheta 30\n#inphi 0\n";
        let cases = [
            (format!("{head}150 0 1\n160 0 1e-400\n"), 5, "value"),
            (format!("{head}150 1e-999 1\n"), 4, "phi"),
            (
                "#format: theta phi DSF\n#intheta 3e-330\n#inphi 0\n150 0 1\n".to_owned(),
                2,
                "#intheta",
            ),
            (
                format!("{head}#colorimetry: CIE-XYZ\n150 0 1 1 -1e-400\n"),
                5,
                "Z",
            ),
        ];
        for (text, line, column) in cases {
            let e = read(&text).unwrap_err();
            assert_eq!(
                (e.line, e.column.as_deref()),
                (Some(line), Some(column)),
                "{text:?}"
            );
            assert!(
                matches!(e.kind, LoadErrorKind::Unrepresentable(_)),
                "{text:?}: {e}"
            );
        }
        let (_, pts) = read(&format!("{head}150 0 1e-310\n")).unwrap();
        assert_eq!(pts[0].value, 1e-310);
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
            ("#sample_name \"\"\n", 1, "#sample_name"),
            (
                &format!("{head}#colorimetry: CIE-XYZ\n10 0 1 2\n"),
                5,
                "theta phi X Y Z",
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
