//! `stfit.export`: stored fits as renderer materials or Radiance/WINDOW BSDF files
//! (`stfit-export`), with the targets, options and defaults of `stfit export`.

use std::path::PathBuf;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use stfit_export::radiance::{LayerKind, QuadratureRule, RadianceOptions};
use stfit_export::{
    BatchError, Destination, Selection, Target, export_fits, export_walks, radiance_walks_apply,
    select_fits,
};
use stfit_fit::{FitResult, FitsFile, ModelKind};

use crate::errors::{arg_error, export_error, os_error, value_error};
use crate::fit::PyFitResult;
use crate::long_run;

/// The target named as on the command line (`--to`).
fn target(name: &str) -> PyResult<Target> {
    Target::ALL
        .into_iter()
        .find(|t| t.name() == name)
        .ok_or_else(|| {
            let names: Vec<_> = Target::ALL.iter().map(|t| t.name()).collect();
            arg_error(
                "to",
                format!("unknown target '{name}' (expected {})", names.join(", ")),
            )
        })
}

/// The selection of `sample` and `model` (`beckmann`, `ggx`, `student-t`: gamma fitted,
/// `student-t-fixed`: gamma held), as `--sample` and `--model`.
fn selection(sample: Option<&str>, model: Option<&str>) -> PyResult<Selection> {
    let (kind, gamma_fixed) = match model {
        None => (None, None),
        Some("student-t-fixed") => (Some(ModelKind::StudentT), Some(true)),
        Some(name) => {
            let kind: ModelKind = name.parse().map_err(|_| {
                arg_error(
                    "model",
                    format!(
                        "unknown model '{name}' (expected beckmann, ggx, student-t or \
                         student-t-fixed)"
                    ),
                )
            })?;
            let fixed = (kind == ModelKind::StudentT).then_some(false);
            (Some(kind), fixed)
        }
    };
    Ok(Selection {
        sample: sample.map(str::to_owned),
        kind,
        gamma_fixed,
    })
}

/// The fits of `fits`: a `FitResult`, a sequence of them, or the path of a fits file; with
/// the file's name for messages.
fn fits_of(fits: &Bound<'_, PyAny>) -> PyResult<(Vec<FitResult>, Option<PathBuf>)> {
    if let Ok(one) = fits.cast::<PyFitResult>() {
        return Ok((vec![one.get().0.clone()], None));
    }
    if let Ok(path) = fits.extract::<PathBuf>() {
        let file = FitsFile::read(&path).map_err(|e| match e {
            stfit_fit::FitsFileError::Io { .. } => os_error(e),
            other => value_error(other),
        })?;
        return Ok((file.fits, Some(path)));
    }
    let list = fits
        .try_iter()
        .map_err(|_| type_error())?
        .map(|f| {
            f?.cast::<PyFitResult>()
                .map(|r| r.get().0.clone())
                .map_err(|_| type_error())
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok((list, None))
}

fn type_error() -> PyErr {
    PyTypeError::new_err("fits: expected a FitResult, a sequence of them or a fits file's path")
}

/// Exports stored fits as `stfit export` does: `fits` (a `FitResult`, a sequence of them, or
/// the path of a fits file) to the target `to` (`mitsuba3`, `pbrt-v4`, `cycles`, `appleseed`,
/// `openpbr`, `vray`, `radiance`), the fits selected by `sample` and `model`. Without `out`,
/// returns the text `stfit export` prints; with `out` a file, writes one file of each type
/// (the first at `out`, the others beside it with their extension), with `out` an existing
/// folder one file per fit named `ID-TARGET.EXT`, and returns the paths written. `layer`,
/// `absorption`, `walks` and `seed` are the options of `radiance` (defaults: the pane, no
/// absorption, 65,536 walks per patch, seed 1), refused with another target, and `walks` and
/// `seed` where nothing walks, even at their default values, as on the command line. Clamps and
/// other departures from the fit become Python warnings. A fit whose export is refused does not
/// stop the others: they are written (or their text made), then `stfit.ExportError` is raised
/// with the refusals (`refused`, each naming the file, fit and target), the paths `written`
/// and, without `out`, the `text` of the exports made.
#[pyfunction]
#[pyo3(signature = (fits, to, *, sample = None, model = None, out = None, layer = None,
    absorption = None, walks = None, seed = None))]
#[allow(clippy::too_many_arguments)]
pub fn export(
    py: Python<'_>,
    fits: &Bound<'_, PyAny>,
    to: &str,
    sample: Option<&str>,
    model: Option<&str>,
    out: Option<PathBuf>,
    layer: Option<&str>,
    absorption: Option<&Bound<'_, PyAny>>,
    walks: Option<&Bound<'_, PyAny>>,
    seed: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let target = target(to)?;
    let absorption = crate::numbers::opt_float("absorption", absorption)?;
    let walks = walks.map(crate::ints::walks).transpose()?;
    let seed = seed.map(crate::ints::seed).transpose()?;
    let defaults = RadianceOptions::default();
    let radiance = RadianceOptions {
        layer: match layer {
            None => defaults.layer,
            Some("pane") => LayerKind::Pane,
            Some("interface") => LayerKind::Interface,
            Some(other) => {
                return Err(arg_error(
                    "layer",
                    format!("unknown layer '{other}' (expected pane or interface)"),
                ));
            }
        },
        absorption: absorption.unwrap_or(defaults.absorption),
        walks_per_patch: walks.unwrap_or(defaults.walks_per_patch),
        seed: seed.unwrap_or(defaults.seed),
        rule: QuadratureRule::DEFAULT,
    };
    radiance.check().map_err(value_error)?;
    let given = layer.is_some() || absorption.is_some() || walks.is_some() || seed.is_some();
    if target != Target::Radiance && given {
        return Err(value_error(
            "layer, absorption, walks and seed apply to to='radiance' only",
        ));
    }
    let selection = selection(sample, model)?;
    let (fits, file) = fits_of(fits)?;
    if (walks.is_some() || seed.is_some())
        && !radiance_walks_apply(&fits, &selection, radiance.layer)
    {
        return Err(value_error(
            "walks and seed apply to the pane and to the orders >= 2 of all-orders fits; the \
             interface of the selected single-scattering fits is integrated by quadrature, \
             without walks",
        ));
    }
    let dest = match out.as_deref() {
        None => Destination::Stdout,
        Some(p) if p.is_dir() => Destination::Folder(p),
        Some(p) => Destination::File(p),
    };
    // The walks of the export, announced when long (a selection the export refuses is
    // reported by it).
    if let Ok(selected) = select_fits(&fits, &selection, target, dest) {
        let walks = py.detach(|| export_walks(&selected, target, &radiance));
        let shorter = if walks.fits_own {
            "fits with fewer walks make it shorter"
        } else {
            long_run::FEWER_WALKS
        };
        long_run::warn_if_long(py, walks.seconds, &walks.what, shorter)?;
    }
    let batch = py
        .detach(|| export_fits(&fits, &selection, target, &radiance, dest))
        .map_err(|e| match (e, &file) {
            (e @ BatchError::OneFilePerFit, _) => value_error(e),
            (e, Some(path)) => value_error(format!("{}: {e}", path.display())),
            (e, None) => value_error(e),
        })?;
    let warn = py.import("warnings")?;
    for e in batch.exports() {
        for w in &e.export.warnings {
            warn.call_method1("warn", (format!("{}: {w}", e.id),))?;
        }
    }
    let refused: Vec<String> = batch.refused().map(|r| r.to_string()).collect();
    let summary = batch.refusal_summary();
    // The refusals of a fits file name it, as the command line's lines do.
    let refusal_error = |written: Vec<PathBuf>, text: Option<String>| {
        let lines: Vec<String> = refused
            .iter()
            .map(|r| match &file {
                Some(path) => format!("{}: {r}", path.display()),
                None => r.clone(),
            })
            .collect();
        let message = format!(
            "{}:\n{}",
            summary.clone().unwrap_or_default(),
            lines.join("\n")
        );
        export_error(py, message, lines, written, text)
    };
    if out.is_none() {
        let text = batch
            .outputs
            .into_iter()
            .map(|o| o.text)
            .collect::<String>();
        if summary.is_some() {
            return Err(refusal_error(Vec::new(), Some(text)));
        }
        return Ok(text.into_pyobject(py)?.into_any().unbind());
    }
    let mut written = Vec::with_capacity(batch.outputs.len());
    for o in batch.outputs {
        let path = o
            .path
            .expect("a file destination names every output's path");
        std::fs::write(&path, &o.text)
            .map_err(|e| os_error(format!("{}: cannot write: {e}", path.display())))?;
        written.push(path);
    }
    if summary.is_some() {
        return Err(refusal_error(written, None));
    }
    Ok(written.into_pyobject(py)?.into_any().unbind())
}
