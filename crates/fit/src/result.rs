//! What a fit reports, and the versioned file of stored fits (`fits-format.md`).
//!
//! A [`FitResult`] carries everything needed to evaluate the fitted model again (its
//! [`Model`]), how it was fitted and what it was fitted to, so that anything downstream (the
//! report, export, Python) uses it without being told again.

use std::path::Path;
use stfit_core::error::show;

use serde::{Deserialize, Serialize};

use stfit_core::ScatteringOrders;

use crate::data::Measured;
use crate::model::Model;
use crate::options::{
    Loss, MultipleTerm, Optimizer, check_fit_eta, check_fit_walks, check_log_floor,
};

/// The result of fitting one model to one sample (one record of the fits JSON).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitResult {
    /// The sample's name (empty for a file without a `sample` column).
    pub sample: String,
    /// The fitted model: NDF, alpha, gamma, scale, eta, masking, orders, walks and seed (in
    /// JSON, its keys sit beside the others).
    #[serde(flatten)]
    pub model: Model,
    /// True when eta was held at its value rather than fitted (absent in files written before
    /// eta could be fitted: true).
    #[serde(default = "held")]
    pub eta_fixed: bool,
    /// True when the scale was held at its value rather than fitted (absent in files written
    /// before it could be held: false).
    #[serde(default)]
    pub scale_fixed: bool,
    pub loss: Loss,
    /// The floor of the log loss relative to the sample's largest value (`None` for the other
    /// losses).
    #[serde(default)]
    pub log_floor: Option<f64>,
    pub optimizer: Optimizer,
    /// How an all-orders fit computed the orders >= 2 term while it searched (`surrogate` or
    /// `exact`, `--multiple-term`); `None` (JSON `null`) for single scattering, and in files
    /// written before the option existed (whose all-orders fits used exact walks).
    #[serde(default)]
    pub multiple_term: Option<MultipleTerm>,
    /// What the fitted points measure: `L`, the BSDF, or both (absent in files written before
    /// general files: `L`).
    #[serde(default)]
    pub measured: Measured,
    /// Root-mean-square residual of the square root of the measured quantity ([`Self::measured`])
    /// over the fitted points (weight > 0); the key keeps its stfit 0.1 name.
    pub rmse_sqrt_l: f64,
    /// Number of fitted points.
    pub n_points: usize,
    /// Standard errors (heteroscedasticity-robust, see [`crate::fit`]); `None` (JSON `null`)
    /// where undefined: a fixed or absent parameter, or a curvature that does not determine it.
    pub alpha_stderr: Option<f64>,
    pub gamma_stderr: Option<f64>,
    #[serde(default)]
    pub eta_stderr: Option<f64>,
    pub scale_stderr: Option<f64>,
    /// Why the fit cannot be trusted as it stands, if it cannot (absent in older files: none).
    /// A fit with warnings has no standard errors.
    #[serde(default)]
    pub warnings: Vec<FitWarning>,
    /// Iterations of the local optimiser, summed over its starts.
    pub iterations: u64,
    /// The data file the sample was read from, as given (`None` for data not from a file).
    pub data: Option<String>,
    /// The version of stfit that made the fit.
    pub stfit_version: String,
}

/// Why a fit cannot be trusted as it stands. In JSON an object with a `kind` and its details,
/// such as `{"kind": "at-bound", "parameter": "alpha", "bound": 20.0}` (`fits-format.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum FitWarning {
    /// A parameter ended on a bound of the search: the data want a value outside the searched
    /// range (or outside the model family).
    AtBound { parameter: String, bound: f64 },
    /// The curvature of the loss at the optimum is singular: some parameter, or combination of
    /// them, is not determined by the data.
    SingularCurvature,
    /// Fewer informative points (distinct direction pairs with positive weight and a value not
    /// zero) than fitted parameters.
    FewInformativePoints {
        informative: usize,
        parameters: usize,
    },
    /// The model is not differentiable in a parameter at the optimum: it jumps or kinks within
    /// the finite-difference step (eta where a data point's refraction half vector turns
    /// horizontal, or where total internal reflection sets in), so the optimum may be pinned
    /// on that edge and a linearisation gives no valid standard error.
    NotDifferentiable { parameter: String },
    /// More than half (`share`) of a free eta's information comes from the pairs inside the
    /// glass of one total-reflection onset (the index `onset` at and above which they are
    /// totally internally reflected: a pair, its mirror image, its reverse). Just below its
    /// onset a pair's model changes with the square root of the distance to it, so its slope in
    /// eta is unbounded: eta and its standard error then rest on that pair's noise, the
    /// linearisation behind standard errors fails, and the fit can be drawn onto the onset.
    TotalReflectionOnset { onset: f64, share: f64 },
}

impl std::fmt::Display for FitWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::AtBound { parameter, bound } => write!(
                f,
                "{parameter} ended on the search bound {bound}: the data want a value outside \
                 the searched range"
            ),
            Self::SingularCurvature => f.write_str(
                "the curvature at the optimum is singular: the data do not determine every \
                 parameter",
            ),
            Self::FewInformativePoints {
                informative,
                parameters,
            } => write!(
                f,
                "only {informative} informative points (distinct direction pairs with weight > 0 and \
                 value not 0) for \
                 {parameters} fitted parameters"
            ),
            Self::NotDifferentiable { parameter } => write!(
                f,
                "the model is not differentiable in {parameter} at the optimum (it jumps or \
                 kinks there): the fit may sit on that edge and has no standard errors"
            ),
            Self::TotalReflectionOnset { onset, share } => write!(
                f,
                "{:.0}% of the information on eta comes from the pairs inside the glass that \
                 turn totally reflected at eta = {onset:.5}: near that index their model changes \
                 with the square root of the distance to it, so eta rests on their noise and may \
                 be drawn onto the index, and the fit has no standard errors; hold eta at a known \
                 index",
                share * 100.0
            ),
        }
    }
}

/// The value of `eta_fixed` in files written before eta could be fitted.
fn held() -> bool {
    true
}

impl FitResult {
    /// The fit as named in messages: its sample and model, such as
    /// `sample 'frosted', student-t (gamma = 3)`.
    pub fn label(&self) -> String {
        format!(
            "sample '{}', {}",
            crate::data::short(&self.sample),
            self.model.label()
        )
    }

    /// One fit from the JSON text of a record of a fits file (`fits-format.md`), checked as a
    /// fits file checks each of its records: no key this version does not define, every number
    /// in its documented range ([`FitResult::check`]). The message names the key or field.
    pub fn from_json(text: &str) -> Result<Self, String> {
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let fit: Self = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if let Some(reason) = unknown_fit_key(&value, &fit) {
            return Err(reason);
        }
        fit.check()?;
        Ok(fit)
    }

    /// Whether the fit carries warnings (and so no standard errors).
    pub fn flagged(&self) -> bool {
        !self.warnings.is_empty()
    }

    /// Checks that every number of the fit is in its documented range (`fits-format.md`): a
    /// model that can be evaluated ([`Model::check`]) whose eta is the glass of a fit
    /// ([`check_fit_eta`]: in [1.05, 3]), a log floor in [1e-12, 1] if given
    /// ([`check_log_floor`]), a finite
    /// `rmse_sqrt_l` >= 0 and standard errors `null` or finite and > 0. The message names the
    /// field.
    pub fn check(&self) -> Result<(), String> {
        // A fit's walks are those an all-orders fit accepts, [2, 1e9], not a model's [1, 1e9]:
        // checked first, so that the message states the fit's range.
        if let (ScatteringOrders::All, Some(walks)) = (self.model.orders, self.model.walks) {
            check_fit_walks(walks).map_err(|_| {
                format!("walks must be in [2, 1e9] for an all-orders fit, got {walks}")
            })?;
        }
        self.model.check().map_err(|e| e.to_string())?;
        check_fit_eta(self.model.eta).map_err(|e| e.to_string())?;
        if let Some(floor) = self.log_floor {
            check_log_floor(floor).map_err(|_| {
                format!(
                    "log_floor must be in [1e-12, 1], got {}",
                    stfit_core::error::show(floor)
                )
            })?;
        }
        if self.n_points == 0 {
            return Err("n_points must be at least 1, got 0".to_owned());
        }
        if !(self.rmse_sqrt_l.is_finite() && self.rmse_sqrt_l >= 0.0) {
            return Err(format!(
                "rmse_sqrt_l must be finite and >= 0, got {}",
                show(self.rmse_sqrt_l)
            ));
        }
        let stderrs = [
            ("alpha_stderr", self.alpha_stderr),
            ("gamma_stderr", self.gamma_stderr),
            ("eta_stderr", self.eta_stderr),
            ("scale_stderr", self.scale_stderr),
        ];
        for (name, value) in stderrs {
            if let Some(v) = value {
                positive(name, v)?;
            }
        }
        self.check_consistent()
    }

    /// Checks the keys that `fits-format.md` ties to others: a standard error is `null` for a
    /// parameter held or absent and for a fit with warnings, `log_floor` is `null` for losses
    /// other than `log`, and `multiple_term` is `null` for `orders` `single`.
    fn check_consistent(&self) -> Result<(), String> {
        let held = [
            (
                "gamma_stderr",
                self.gamma_stderr,
                !self.model.gamma.is_free(),
                "gamma is held or absent",
            ),
            (
                "scale_stderr",
                self.scale_stderr,
                self.scale_fixed,
                "scale_fixed is true",
            ),
            (
                "eta_stderr",
                self.eta_stderr,
                self.eta_fixed,
                "eta_fixed is true",
            ),
            (
                "alpha_stderr",
                self.alpha_stderr,
                self.flagged(),
                "the fit has warnings",
            ),
            (
                "gamma_stderr",
                self.gamma_stderr,
                self.flagged(),
                "the fit has warnings",
            ),
            (
                "scale_stderr",
                self.scale_stderr,
                self.flagged(),
                "the fit has warnings",
            ),
            (
                "eta_stderr",
                self.eta_stderr,
                self.flagged(),
                "the fit has warnings",
            ),
        ];
        for (name, value, undefined, why) in held {
            if let (Some(v), true) = (value, undefined) {
                return Err(format!("{name} must be null when {why}, got {}", show(v)));
            }
        }
        if let (Some(floor), false) = (self.log_floor, self.loss == Loss::Log) {
            return Err(format!(
                "log_floor must be null for a loss other than log, got {}",
                show(floor)
            ));
        }
        if self.model.orders == ScatteringOrders::Single && self.multiple_term.is_some() {
            return Err("multiple_term must be null for orders single".to_owned());
        }
        for w in &self.warnings {
            w.check(self.eta_fixed)?;
        }
        Ok(())
    }
}

impl FitWarning {
    /// `Ok` for a warning that a fit with eta held (`eta_fixed`) or fitted can carry, else
    /// what is wrong: a `parameter` that is not a searched shape parameter, or a
    /// total-reflection onset of a held eta, or with an onset or share out of its range.
    fn check(&self, eta_fixed: bool) -> Result<(), String> {
        match self {
            Self::AtBound { parameter, .. } | Self::NotDifferentiable { parameter } => {
                if !WARNED_PARAMETERS.contains(&parameter.as_str()) {
                    return Err(format!(
                        "a warning's parameter must be alpha, gamma or eta, got '{}'",
                        crate::data::short(parameter)
                    ));
                }
            }
            Self::SingularCurvature | Self::FewInformativePoints { .. } => {}
            Self::TotalReflectionOnset { onset, share } => {
                if eta_fixed {
                    return Err("a total-reflection-onset warning is one of a fitted eta \
                                (eta_fixed false)"
                        .to_owned());
                }
                if !(onset.is_finite() && *onset >= 1.0) {
                    return Err(format!(
                        "a total-reflection-onset warning's onset must be a finite index >= 1, \
                         got {}",
                        show(*onset)
                    ));
                }
                if !(*share > 0.0 && *share <= 1.0) {
                    return Err(format!(
                        "a total-reflection-onset warning's share must be in (0, 1], got {}",
                        show(*share)
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The parameters a warning can name: the searched shape parameters.
const WARNED_PARAMETERS: [&str; 3] = ["alpha", "gamma", "eta"];

/// `Ok` for a finite `value` > 0, else a message naming the field `name`.
fn positive(name: &str, value: f64) -> Result<(), String> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "{name} must be finite and > 0, got {}",
            show(value)
        ))
    }
}

/// The version of the fits file this stfit writes.
pub const FITS_VERSION: u32 = 1;

/// A file of stored fits: `{"version": 1, "fits": [FitResult, ...]}` (`fits-format.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitsFile {
    /// The format version, [`FITS_VERSION`].
    pub version: u32,
    pub fits: Vec<FitResult>,
}

/// Why stored fits could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FitsFileError {
    #[error("{path}: cannot read: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{0}: not a fits file: {1}")]
    Json(String, String),
    #[error(
        "{0}: the file has no format version: it was written by stfit 0.1, which did not \
         record eta, masking and orders; fit again to make a file of this version \
         (stfit DATA --model all --out FILE)"
    )]
    Unversioned(String),
    #[error(
        "{0}: format version {1} is not one this stfit reads (it reads version {FITS_VERSION})"
    )]
    Version(String, u64),
    #[error("{file}: fit {index} ({label}): {reason}")]
    InvalidFit {
        file: String,
        index: usize,
        label: String,
        reason: String,
    },
}

impl FitsFile {
    /// The file of `fits` in the current version.
    pub fn new(fits: Vec<FitResult>) -> Self {
        Self {
            version: FITS_VERSION,
            fits,
        }
    }

    /// The JSON text of the file, pretty-printed, ending in a line break.
    pub fn to_json(&self) -> String {
        let mut text =
            serde_json::to_string_pretty(self).expect("fits are plain data and serialise");
        text.push('\n');
        text
    }

    /// Parses stored fits; `source` names them in errors. Refuses files without a version (made
    /// by stfit 0.1) or of another version, and fits with a number outside its documented range
    /// ([`FitResult::check`]).
    pub fn from_json(source: &str, text: &str) -> Result<Self, FitsFileError> {
        let file = Self::from_json_unchecked(source, text)?;
        for (index, fit) in file.fits.iter().enumerate() {
            fit.check().map_err(|reason| FitsFileError::InvalidFit {
                file: source.to_owned(),
                index,
                label: fit.label(),
                reason,
            })?;
        }
        Ok(file)
    }

    /// [`FitsFile::from_json`] without checking each fit: for readers that name such fits and
    /// go on with the others (`stfit report` warns and leaves their curves out) rather than
    /// refuse the file. A leading UTF-8 byte order mark is skipped.
    pub fn from_json_unchecked(source: &str, text: &str) -> Result<Self, FitsFileError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let json = |e: serde_json::Error| FitsFileError::Json(source.to_owned(), e.to_string());
        let value: serde_json::Value = serde_json::from_str(text).map_err(json)?;
        // Only an object: serde would also take the array `[version, fits]`, which is not the
        // format and would pass any version unchecked.
        if !value.is_object() {
            return Err(FitsFileError::Json(
                source.to_owned(),
                "expected a JSON object with the keys \"version\" and \"fits\"".to_owned(),
            ));
        }
        match value.get("version") {
            None if value.get("fits").is_some() => {
                return Err(FitsFileError::Unversioned(source.to_owned()));
            }
            Some(v) if v.as_u64() != Some(u64::from(FITS_VERSION)) => {
                return Err(match v.as_u64() {
                    Some(n) => FitsFileError::Version(source.to_owned(), n),
                    None => FitsFileError::Json(
                        source.to_owned(),
                        format!(
                            "\"version\" must be a whole number (this stfit reads version \
                             {FITS_VERSION}), got {v}"
                        ),
                    ),
                });
            }
            _ => {}
        }
        // Parsed from the text itself, not the `Value`, so every number keeps its exact bits.
        let file: Self =
            serde_json::from_str(text).map_err(|e| match first_unreadable_fit(&value) {
                Some((index, label)) => FitsFileError::InvalidFit {
                    file: source.to_owned(),
                    index,
                    label,
                    reason: e.to_string(),
                },
                None => json(e),
            })?;
        if let Some(key) = unknown_key(&value, &["version", "fits"]) {
            return Err(FitsFileError::Json(
                source.to_owned(),
                format!(
                    "unknown key \"{}\" (a fits file of version {FITS_VERSION} has the keys \
                     \"version\" and \"fits\")",
                    crate::data::short(key)
                ),
            ));
        }
        let records = value["fits"].as_array().map_or(&[][..], Vec::as_slice);
        for (index, (record, fit)) in records.iter().zip(&file.fits).enumerate() {
            if let Some(reason) = unknown_fit_key(record, fit) {
                return Err(FitsFileError::InvalidFit {
                    file: source.to_owned(),
                    index,
                    label: fit.label(),
                    reason,
                });
            }
        }
        Ok(file)
    }

    /// Reads stored fits from `path` ([`FitsFile::from_json`]).
    pub fn read(path: &Path) -> Result<Self, FitsFileError> {
        Self::from_json(&path.display().to_string(), &read_text(path)?)
    }

    /// Reads stored fits from `path` ([`FitsFile::from_json_unchecked`]).
    pub fn read_unchecked(path: &Path) -> Result<Self, FitsFileError> {
        Self::from_json_unchecked(&path.display().to_string(), &read_text(path)?)
    }
}

/// The first key of the JSON object `object` that is not one of `known`.
fn unknown_key<'v>(object: &'v serde_json::Value, known: &[&str]) -> Option<&'v str> {
    object
        .as_object()?
        .keys()
        .map(String::as_str)
        .find(|key| !known.contains(key))
}

/// Why the record `record`, read as `fit`, has a key that a fit of this version does not
/// define, if it has one. Such a key is refused rather than ignored: a misspelt optional key
/// (`warning` for `warnings`, `measure` for `measured`) would otherwise read as its default and
/// change what the fit means without a word. Every key a fit defines is written for every fit
/// (absent values as `null`), so the keys of `fit` written back are exactly the known ones.
fn unknown_fit_key(record: &serde_json::Value, fit: &FitResult) -> Option<String> {
    let written = serde_json::to_value(fit).expect("fits are plain data and serialise");
    let known: Vec<&str> = written.as_object()?.keys().map(String::as_str).collect();
    if let Some(key) = unknown_key(record, &known) {
        return Some(format!(
            "unknown key \"{}\" (fits-format.md lists the keys of a fit of version \
             {FITS_VERSION})",
            crate::data::short(key)
        ));
    }
    // Each warning has the keys of its kind, written back the same way.
    let warnings = record.get("warnings")?.as_array()?;
    warnings
        .iter()
        .zip(&fit.warnings)
        .enumerate()
        .find_map(|(k, (w, warning))| {
            let written = serde_json::to_value(warning).expect("warnings serialise");
            let known: Vec<&str> = written.as_object()?.keys().map(String::as_str).collect();
            unknown_key(w, &known).map(|key| {
                format!(
                    "unknown key \"{}\" in warning {k} (a {} warning has the keys {})",
                    crate::data::short(key),
                    written["kind"].as_str().unwrap_or("?"),
                    known
                        .iter()
                        .map(|k| format!("\"{k}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })
        })
}

/// The index of the first record of `file`'s `fits` array that is not a [`FitResult`], and
/// its label as far as the record tells it (`sample 'frosted'`), so that a key of the wrong
/// type or a contradiction between `gamma` and `gamma_fixed` names its fit.
fn first_unreadable_fit(file: &serde_json::Value) -> Option<(usize, String)> {
    let fits = file.get("fits")?.as_array()?;
    fits.iter().enumerate().find_map(|(index, record)| {
        serde_json::from_value::<FitResult>(record.clone())
            .is_err()
            .then(|| {
                let label = match record.get("sample").and_then(|s| s.as_str()) {
                    Some(sample) => format!("sample '{}'", crate::data::short(sample)),
                    None => "no sample".to_owned(),
                };
                (index, label)
            })
    })
}

/// The text of a fits file.
fn read_text(path: &Path) -> Result<String, FitsFileError> {
    crate::files::read_input_text(path).map_err(|source| FitsFileError::Io {
        path: path.display().to_string(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A version-1 record written before eta and the scale could be fitted or held (no
    /// `eta_fixed`, `scale_fixed`, `log_floor`, `eta_stderr`) reads as what it was: eta held,
    /// the scale fitted.
    #[test]
    fn records_from_before_free_eta_read_with_eta_held() {
        let text = r#"{"version": 1, "fits": [{
            "sample": "s", "model": "ggx", "alpha": 0.2, "gamma": null, "gamma_fixed": false,
            "scale": 1.5,
            "eta": 1.51, "masking": "separable", "orders": "single", "walks": null,
            "seed": null, "loss": "sqrt", "optimizer": "nelder-mead", "rmse_sqrt_l": 0.01,
            "n_points": 10, "alpha_stderr": 0.001, "gamma_stderr": null,
            "scale_stderr": 0.01, "iterations": 40, "data": "d.csv", "stfit_version": "0.2.0"
        }]}"#;
        let file = FitsFile::from_json("old.json", text).unwrap();
        let fit = &file.fits[0];
        assert!(fit.eta_fixed && !fit.scale_fixed);
        assert_eq!((fit.log_floor, fit.eta_stderr), (None, None));
        assert_eq!(fit.measured, Measured::L);
        assert_eq!(fit.model.eta, 1.51);
        assert_eq!(fit.multiple_term, None);
    }

    /// `multiple_term` is written as `surrogate`, `exact` or `null` and read back.
    #[test]
    fn multiple_term_round_trips() {
        let text = r#"{"version": 1, "fits": [{
            "sample": "s", "model": "ggx", "alpha": 0.2, "gamma": null, "gamma_fixed": false,
            "scale": 1.5, "eta": 1.51, "masking": "correlated", "orders": "all",
            "walks": 2000, "seed": 1, "loss": "sqrt", "optimizer": "nelder-mead",
            "multiple_term": "exact", "rmse_sqrt_l": 0.01,
            "n_points": 10, "alpha_stderr": 0.001, "gamma_stderr": null,
            "scale_stderr": 0.01, "iterations": 40, "data": "d.csv", "stfit_version": "0.2.0"
        }]}"#;
        let file = FitsFile::from_json("f.json", text).unwrap();
        assert_eq!(file.fits[0].multiple_term, Some(MultipleTerm::Exact));
        let again = FitsFile::from_json("g.json", &file.to_json()).unwrap();
        assert_eq!(again.fits, file.fits);
        assert!(file.to_json().contains("\"multiple_term\": \"exact\""));
    }

    /// The record of `records_from_before_free_eta_read_with_eta_held` with `key` set to
    /// `value` (a JSON text).
    fn with(key: &str, value: &str) -> String {
        let mut v: serde_json::Value = serde_json::from_str(
            r#"{"version": 1, "fits": [{
            "sample": "s", "model": "student-t", "alpha": 0.2, "gamma": 3.0,
            "gamma_fixed": false, "scale": 1.5, "eta": 1.51, "masking": "separable",
            "orders": "single", "walks": null, "seed": null, "loss": "sqrt",
            "optimizer": "nelder-mead", "rmse_sqrt_l": 0.01, "n_points": 10,
            "alpha_stderr": 0.001, "gamma_stderr": 0.1, "scale_stderr": 0.01,
            "iterations": 40, "data": "d.csv", "stfit_version": "0.2.0"
        }]}"#,
        )
        .unwrap();
        v["fits"][0][key] = serde_json::from_str(value).unwrap();
        v.to_string()
    }

    /// A key that a fit of this version does not define is refused, naming the fit and the
    /// key: a misspelt optional key (`warning`, `measure`) would otherwise read as its default.
    /// Every key a fit defines is read, and so is a file with no fits.
    #[test]
    fn unknown_keys_are_refused() {
        for (key, value) in [
            ("warning", r#"[{"kind": "singular-curvature"}]"#),
            ("measure", r#""bsdf""#),
        ] {
            let err = FitsFile::from_json("f.json", &with(key, value))
                .unwrap_err()
                .to_string();
            assert!(
                err.starts_with("f.json: fit 0 (sample 's', student-t): unknown key")
                    && err.contains(&format!("\"{key}\"")),
                "{err}"
            );
        }
        // Inside a warning too: each kind has its own keys and no others.
        for (warning, key) in [
            (r#"{"kind": "singular-curvature", "note": "x"}"#, "note"),
            (
                r#"{"kind": "at-bound", "parameter": "alpha", "bound": 20.0, "side": 1}"#,
                "side",
            ),
        ] {
            let mut v: serde_json::Value = serde_json::from_str(&with("eta", "1.51")).unwrap();
            v["fits"][0]["warnings"] = serde_json::from_str(&format!("[{warning}]")).unwrap();
            let err = FitsFile::from_json("f.json", &v.to_string())
                .unwrap_err()
                .to_string();
            assert!(
                err.starts_with(&format!(
                    "f.json: fit 0 (sample 's', student-t): unknown key \"{key}\" in warning 0 \
                     (a "
                )),
                "{err}"
            );
        }
        let mut v: serde_json::Value = serde_json::from_str(&with("eta", "1.51")).unwrap();
        v["comment"] = "x".into();
        let err = FitsFile::from_json("f.json", &v.to_string())
            .unwrap_err()
            .to_string();
        assert!(err.contains("unknown key \"comment\""), "{err}");
        let full = FitsFile::from_json("f.json", &with("eta", "1.51"))
            .unwrap()
            .to_json();
        assert!(FitsFile::from_json("g.json", &full).is_ok());
        assert!(FitsFile::from_json("e.json", r#"{"version": 1, "fits": []}"#).is_ok());
    }

    /// Every number outside its documented range is refused when the file is read, the
    /// message naming the file, the fit and the field; the ends of the ranges are read.
    #[test]
    fn numbers_outside_their_documented_ranges_are_refused() {
        for (key, value) in [
            ("eta", "0.5"),
            ("eta", "1.04"),
            ("eta", "3.01"),
            ("eta", "10"),
            ("eta", "100"),
            ("alpha", "0"),
            ("gamma", "1.5"),
            ("scale", "-1"),
            ("rmse_sqrt_l", "-1"),
            ("alpha_stderr", "-0.1"),
            ("gamma_stderr", "0"),
            ("scale_stderr", "-1e-3"),
            ("eta_stderr", "-1"),
            ("log_floor", "0"),
            ("n_points", "0"),
        ] {
            let e = FitsFile::from_json("f.json", &with(key, value))
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("f.json: fit 0 (sample 's', student-t): ") && e.contains(key),
                "{key} {value}: {e}"
            );
        }
        for (key, value) in [
            ("eta", "1.05"),
            ("eta", "3"),
            ("rmse_sqrt_l", "0"),
            ("alpha_stderr", "null"),
        ] {
            FitsFile::from_json("f.json", &with(key, value)).unwrap();
        }
    }

    /// Keys that contradict the others are refused, naming the key: a standard error of a
    /// parameter held or absent, or of a fit with warnings; a log floor for another loss; a
    /// multiple term for single scattering.
    #[test]
    fn keys_that_contradict_each_other_are_refused() {
        let edit = |edits: &[(&str, &str)]| {
            let mut v: serde_json::Value = serde_json::from_str(&with("eta", "1.51")).unwrap();
            for (key, value) in edits {
                v["fits"][0][*key] = serde_json::from_str(value).unwrap();
            }
            FitsFile::from_json("f.json", &v.to_string()).map_err(|e| e.to_string())
        };
        for (edits, key) in [
            (&[("gamma_fixed", "true")][..], "gamma_stderr"),
            (&[("scale_fixed", "true")], "scale_stderr"),
            (&[("eta_stderr", "0.01")], "eta_stderr"),
            (
                &[("warnings", r#"[{"kind": "singular-curvature"}]"#)],
                "alpha_stderr",
            ),
            (&[("log_floor", "0.001")], "log_floor"),
            (&[("multiple_term", r#""exact""#)], "multiple_term"),
        ] {
            let e = edit(edits).unwrap_err();
            assert!(
                e.contains(key) && e.contains("must be null"),
                "{edits:?}: {e}"
            );
        }
        // A warning names one of the searched parameters.
        let warned = |w: &str| {
            edit(&[
                ("warnings", w),
                ("alpha_stderr", "null"),
                ("gamma_stderr", "null"),
                ("scale_stderr", "null"),
            ])
        };
        for w in [
            r#"[{"kind": "at-bound", "parameter": "beta", "bound": 20.0}]"#,
            r#"[{"kind": "not-differentiable", "parameter": "scale"}]"#,
        ] {
            let e = warned(w).unwrap_err();
            assert!(
                e.contains("parameter must be alpha, gamma or eta"),
                "{w}: {e}"
            );
        }
        warned(r#"[{"kind": "at-bound", "parameter": "gamma", "bound": 501.5}]"#).unwrap();
        // A total-reflection onset is an index >= 1 of a fit of eta, with a share in (0, 1].
        let onset = |w: &str, eta_fixed: &str| {
            edit(&[
                ("warnings", w),
                ("eta_fixed", eta_fixed),
                ("alpha_stderr", "null"),
                ("gamma_stderr", "null"),
                ("scale_stderr", "null"),
            ])
        };
        for (w, eta_fixed, needle) in [
            (r#"{"onset": 0.5, "share": 0.9}"#, "false", "onset must be"),
            (r#"{"onset": 1.45, "share": 1.5}"#, "false", "share must be"),
            (r#"{"onset": 1.45, "share": 0}"#, "false", "share must be"),
            (r#"{"onset": 1.45, "share": 0.9}"#, "true", "fitted eta"),
        ] {
            let w = format!(r#"[{{"kind": "total-reflection-onset", {}]"#, &w[1..]);
            let e = onset(&w, eta_fixed).unwrap_err();
            assert!(e.contains(needle), "{w}: {e}");
        }
        onset(
            r#"[{"kind": "total-reflection-onset", "onset": 1.449, "share": 0.94}]"#,
            "false",
        )
        .unwrap();
        for edits in [
            &[("gamma_fixed", "true"), ("gamma_stderr", "null")][..],
            &[("eta_fixed", "false"), ("eta_stderr", "0.01")],
            &[("loss", r#""log""#), ("log_floor", "0.001")],
            &[
                ("warnings", r#"[{"kind": "singular-curvature"}]"#),
                ("alpha_stderr", "null"),
                ("gamma_stderr", "null"),
                ("scale_stderr", "null"),
            ],
        ] {
            edit(edits).unwrap();
        }
        // An all-orders fit's walks are those a fit accepts: at least 2.
        let all_orders = |walks: &str| {
            edit(&[
                ("orders", r#""all""#),
                ("masking", r#""correlated""#),
                ("walks", walks),
                ("seed", "1"),
                ("multiple_term", r#""surrogate""#),
            ])
        };
        all_orders("2").unwrap();
        let e = all_orders("1").unwrap_err();
        assert!(e.contains("walks must be in [2, 1e9]"), "{e}");
    }

    /// A record that is not a fit at all (a key of the wrong type, or `gamma_fixed` true with
    /// `gamma` null) is refused naming its index and sample, and the line of the fault.
    #[test]
    fn an_unreadable_record_names_its_fit() {
        let mut v: serde_json::Value = serde_json::from_str(&with("eta", "1.51")).unwrap();
        let mut second = v["fits"][0].clone();
        second["sample"] = "etched".into();
        second["gamma_fixed"] = true.into();
        second["gamma"] = serde_json::Value::Null;
        v["fits"].as_array_mut().unwrap().push(second);
        let text = serde_json::to_string_pretty(&v).unwrap();
        let e = FitsFile::from_json("f.json", &text)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("f.json: fit 1 (sample 'etched'): ")
                && e.contains("gamma_fixed is true but gamma is null")
                && e.contains("line "),
            "{e}"
        );
        let e = FitsFile::from_json("f.json", &with("n_points", "\"ten\""))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("f.json: fit 0 (sample 's'): "), "{e}");
    }

    /// The example of `fits-format.md` is a fits file this stfit reads, and stfit writes it back
    /// with the same keys in the same order.
    #[test]
    fn the_documented_example_reads_and_is_written_in_its_key_order() {
        let page = include_str!("../../../fits-format.md");
        let start = page.find("```json\n").expect("the page has a JSON example") + 8;
        let example = &page[start..start + page[start..].find("```").unwrap()];
        let file = FitsFile::from_json("fits-format.md", example).unwrap();
        let keys = |text: &str| -> Vec<String> {
            text.lines()
                .filter_map(|l| l.trim().strip_prefix('"'))
                .filter_map(|l| l.split_once("\":").map(|(k, _)| k.to_owned()))
                .collect()
        };
        assert_eq!(keys(example), keys(&file.to_json()));
    }

    /// An all-orders fit's walks outside [2, 1e9] are refused with that range, on both sides
    /// (above 1e9 the model's own check had answered first, with its range [1, 1e9]).
    #[test]
    fn walks_of_an_all_orders_fit_are_refused_with_the_fits_range() {
        for walks in ["1", "1000000001"] {
            let mut v: serde_json::Value = serde_json::from_str(&with("eta", "1.51")).unwrap();
            for (key, value) in [
                ("orders", r#""all""#),
                ("masking", r#""correlated""#),
                ("gamma", "3"),
                ("seed", "1"),
                ("walks", walks),
            ] {
                v["fits"][0][key] = serde_json::from_str(value).unwrap();
            }
            let e = FitsFile::from_json("f.json", &v.to_string())
                .unwrap_err()
                .to_string();
            assert!(
                e.ends_with(&format!(
                    "walks must be in [2, 1e9] for an all-orders fit, got {walks}"
                )),
                "{e}"
            );
        }
    }

    /// Only a JSON object is a fits file: the array `[version, fits]`, which serde would
    /// read as the same struct, was accepted with any version. A version that is not a whole
    /// number is refused with a message that says so (it had said "must be a number" of 1.0).
    #[test]
    fn only_an_object_with_a_whole_version_is_a_fits_file() {
        let text = with("eta", "1.51");
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        for version in [1, 2] {
            let array = format!("[{version}, {}]", value["fits"]);
            let e = FitsFile::from_json("f.json", &array)
                .unwrap_err()
                .to_string();
            assert_eq!(
                e,
                "f.json: not a fits file: expected a JSON object with the keys \"version\" and \
                 \"fits\""
            );
        }
        for version in ["1.0", "-1", "\"1\""] {
            let mut v = value.clone();
            v["version"] = serde_json::from_str(version).unwrap();
            let e = FitsFile::from_json("f.json", &v.to_string())
                .unwrap_err()
                .to_string();
            assert_eq!(
                e,
                format!(
                    "f.json: not a fits file: \"version\" must be a whole number (this stfit \
                     reads version 1), got {version}"
                )
            );
        }
    }

    /// A file that starts with a UTF-8 byte order mark (as some editors save) reads as without.
    #[test]
    fn a_leading_byte_order_mark_is_skipped() {
        let text = with("eta", "1.51");
        let file = FitsFile::from_json("f.json", &format!("\u{feff}{text}")).unwrap();
        assert_eq!(file, FitsFile::from_json("f.json", &text).unwrap());
    }
}
