//! A set of stored fits exported at once, and the files that holds: what `stfit export` does
//! between reading the fits file and writing, so that every front end (the command line, the
//! Python package) selects, names and joins the same way. No I/O: the caller writes.

use std::path::{Path, PathBuf};

use stfit_fit::FitResult;
use thiserror::Error;

use crate::radiance::RadianceOptions;
use crate::{Export, ExportError, Selection, Target, export_fit, file_name, fit_identifier, join};

/// Where the files of an export go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Destination<'a> {
    /// One text: the exports' files joined by type ([`join`]), the types separated by a blank
    /// line, as printed to stdout.
    Stdout,
    /// One file of each type: the first at this path, the others beside it with their own
    /// extension (`scene.xml`, `scene.py`).
    File(&'a Path),
    /// An existing folder: one file per fit and type, named by [`file_name`].
    Folder(&'a Path),
}

/// One selected fit's export.
#[derive(Debug, Clone, PartialEq)]
pub struct FitExport {
    /// The fit's identifier ([`fit_identifier`]), its material name.
    pub id: String,
    pub export: Export,
}

/// A text to write: to `path`, or to stdout when `path` is `None`.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    pub path: Option<PathBuf>,
    pub text: String,
}

/// The exports of a set of fits and the texts they make at their destination.
#[derive(Debug, Clone, PartialEq)]
pub struct Batch {
    /// In the order of the fits.
    pub exports: Vec<FitExport>,
    /// In the order of writing.
    pub outputs: Vec<Output>,
}

/// Why a set of fits could not be exported.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BatchError {
    /// The selection left no fit.
    #[error("no fit matches the selection")]
    NoMatch,
    /// Radiance writes one BSDF file per fit, so several fits need a folder.
    #[error(
        "radiance writes one BSDF file per fit: select one fit (by sample and model) or write into an existing folder"
    )]
    OneFilePerFit,
    /// The export of one fit failed; `label` is the fit's [`FitResult::label`].
    #[error("{label}: {error}")]
    Fit { label: String, error: ExportError },
}

/// Exports every fit of `fits` that `selection` matches to `target` (`radiance`: the options
/// of [`Target::Radiance`], ignored by the other targets) and lays out the texts for `dest`.
/// Fails before exporting anything when no fit matches or when Radiance would need several
/// files in one.
pub fn export_fits(
    fits: &[FitResult],
    selection: &Selection,
    target: Target,
    radiance: &RadianceOptions,
    dest: Destination<'_>,
) -> Result<Batch, BatchError> {
    let selected: Vec<&FitResult> = fits.iter().filter(|f| selection.matches(f)).collect();
    if selected.is_empty() {
        return Err(BatchError::NoMatch);
    }
    if target == Target::Radiance && selected.len() > 1 && !matches!(dest, Destination::Folder(_)) {
        return Err(BatchError::OneFilePerFit);
    }
    let exports = selected
        .into_iter()
        .map(|fit| {
            let export = export_fit(fit, target, radiance).map_err(|error| BatchError::Fit {
                label: fit.label(),
                error,
            })?;
            Ok(FitExport {
                id: fit_identifier(fit),
                export,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let outputs = outputs(&exports, target, dest);
    Ok(Batch { exports, outputs })
}

/// The texts of `exports` laid out for `dest` ([`Destination`]).
fn outputs(exports: &[FitExport], target: Target, dest: Destination<'_>) -> Vec<Output> {
    let joined = || join(&exports.iter().map(|e| e.export.clone()).collect::<Vec<_>>());
    match dest {
        Destination::Stdout => vec![Output {
            path: None,
            text: joined()
                .iter()
                .map(|f| f.text.as_str())
                .collect::<Vec<_>>()
                .join("\n"),
        }],
        Destination::File(out) => joined()
            .into_iter()
            .enumerate()
            .map(|(k, f)| Output {
                path: Some(if k == 0 {
                    out.to_path_buf()
                } else {
                    out.with_extension(f.extension)
                }),
                text: f.text,
            })
            .collect(),
        Destination::Folder(dir) => exports
            .iter()
            .flat_map(|e| {
                e.export.files.iter().map(|f| Output {
                    path: Some(dir.join(file_name(&e.id, target, f.extension))),
                    text: f.text.clone(),
                })
            })
            .collect(),
    }
}
