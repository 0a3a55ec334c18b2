//! A set of stored fits exported at once, and the files that holds: what `stfit export` does
//! between reading the fits file and writing, so that every front end (the command line, the
//! Python package) selects, names and joins the same way. No I/O: the caller writes.

use std::path::{Path, PathBuf};

use stfit_fit::FitResult;
use thiserror::Error;

use stfit_core::walk::ScatteringOrders;

use crate::radiance::{LayerKind, RadianceOptions};
use crate::{
    Export, ExportError, ExportModel, Selection, Target, export_fit, file_name, fit_identifier,
    join,
};

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

/// A selected fit whose export was refused (an appleseed glass beyond its ior range, a pane
/// of a gamma the walks cannot take): one item of a [`Batch`], which the other fits' exports
/// do not depend on. Displayed as `sample 'x', ggx to appleseed: reason`.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{label} to {target}: {error}")]
pub struct Refused {
    /// The fit's [`FitResult::label`].
    pub label: String,
    /// The fit's identifier ([`fit_identifier`]).
    pub id: String,
    /// The target's command-line name ([`Target::name`]).
    pub target: &'static str,
    pub error: ExportError,
}

/// One selected fit: its export, or why it was refused (boxed: the refusal is the larger).
pub type Item = Result<FitExport, Box<Refused>>;

/// The exports of a set of fits and the texts they make at their destination. A refused fit
/// is an item like the others ([`Refused`]): the texts hold the exports that were made, and
/// the front end reports the refusals.
#[derive(Debug, Clone, PartialEq)]
pub struct Batch {
    /// One per selected fit, in the order of the fits.
    pub items: Vec<Item>,
    /// The texts of the exports made, in the order of writing; none when every fit was
    /// refused.
    pub outputs: Vec<Output>,
}

impl Batch {
    /// The exports made, in the order of the fits.
    pub fn exports(&self) -> impl Iterator<Item = &FitExport> {
        self.items.iter().filter_map(|i| i.as_ref().ok())
    }

    /// The refused fits, in the order of the fits.
    pub fn refused(&self) -> impl Iterator<Item = &Refused> {
        self.items
            .iter()
            .filter_map(|i| i.as_ref().err().map(|r| &**r))
    }

    /// `N of M exports refused`, or `None` when every export was made.
    pub fn refusal_summary(&self) -> Option<String> {
        let n = self.refused().count();
        (n > 0).then(|| format!("{n} of {} exports refused", self.items.len()))
    }
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
    /// Two selected fits have the same identifier ([`fit_identifier`]): their files, or their
    /// materials in one file, would overwrite each other. `first` and `second` are the fits'
    /// [`FitResult::label`]s.
    #[error(
        "{first} and {second} both export as '{id}' (every character outside [A-Za-z0-9] becomes '_'): rename a sample or select one of them (by sample and model)"
    )]
    SameName {
        first: String,
        second: String,
        id: String,
    },
    /// Two selected fits written to one folder have identifiers that differ only in case
    /// (samples `Frosted` and `frosted`): file systems that ignore case (macOS's and Windows'
    /// defaults) would write both to one file.
    #[error(
        "{first} and {second} export as '{id}' and '{other}', which name one file where file names ignore case (macOS, Windows): rename a sample, select one of them (by sample and model) or write them into one file"
    )]
    SameNameIgnoringCase {
        first: String,
        second: String,
        id: String,
        other: String,
    },
    /// One file destination whose name has the extension of a file type other than the first,
    /// which goes beside it with that extension: both would be written to `path`.
    #[error(
        "the {first} file and the {other} file would both be written to {path}: give a file name ending in .{first} (the {other} file goes beside it)"
    )]
    SamePath {
        path: String,
        first: &'static str,
        other: &'static str,
    },
}

/// Exports every fit of `fits` that `selection` matches to `target` (`radiance`: the options
/// of [`Target::Radiance`], ignored by the other targets) and lays out the texts for `dest`.
/// Fails before exporting anything when no fit matches, when Radiance would need several
/// files in one, or when two fits have the same identifier ([`BatchError::SameName`]; in a
/// folder, the same ignoring case, [`BatchError::SameNameIgnoringCase`]); fails before writing
/// anything when two files of one destination would have the same path, ignoring case
/// ([`BatchError::SamePath`]).
pub fn export_fits(
    fits: &[FitResult],
    selection: &Selection,
    target: Target,
    radiance: &RadianceOptions,
    dest: Destination<'_>,
) -> Result<Batch, BatchError> {
    let selected = select_fits(fits, selection, target, dest)?;
    let items: Vec<Item> = selected
        .into_iter()
        .map(|fit| {
            let id = fit_identifier(fit);
            match export_fit(fit, target, radiance) {
                Ok(export) => Ok(FitExport { id, export }),
                Err(error) => Err(Box::new(Refused {
                    label: fit.label(),
                    id,
                    target: target.name(),
                    error,
                })),
            }
        })
        .collect();
    let made: Vec<&FitExport> = items.iter().filter_map(|i| i.as_ref().ok()).collect();
    let outputs = outputs(&made, target, dest)?;
    Ok(Batch { items, outputs })
}

/// Whether the walks of [`RadianceOptions`] (walks per patch and their seed) enter the Radiance
/// export of the fits `selection` picks: always for the pane; for the interface only through
/// the orders >= 2 of an all-orders fit (a single-scattering interface is integrated by
/// quadrature). Front ends refuse walk options that would be ignored. True when nothing is
/// selected: there is nothing to ignore them, and the export itself says that no fit matches.
pub fn radiance_walks_apply(fits: &[FitResult], selection: &Selection, layer: LayerKind) -> bool {
    let mut selected = fits.iter().filter(|f| selection.matches(f)).peekable();
    layer == LayerKind::Pane
        || selected.peek().is_none()
        || selected.any(|f| f.model.orders == ScatteringOrders::All)
}

/// The fits of `fits` that `selection` picks, for an export to `target` written to `dest`,
/// after the checks of [`export_fits`] that come before any export: some fit matches, Radiance
/// needs a folder for several fits, and identifiers are distinct.
pub fn select_fits<'a>(
    fits: &'a [FitResult],
    selection: &Selection,
    target: Target,
    dest: Destination<'_>,
) -> Result<Vec<&'a FitResult>, BatchError> {
    let selected: Vec<&FitResult> = fits.iter().filter(|f| selection.matches(f)).collect();
    if selected.is_empty() {
        return Err(BatchError::NoMatch);
    }
    if target == Target::Radiance && selected.len() > 1 && !matches!(dest, Destination::Folder(_)) {
        return Err(BatchError::OneFilePerFit);
    }
    distinct_identifiers(&selected, matches!(dest, Destination::Folder(_)))?;
    Ok(selected)
}

/// Estimated wall time, in seconds, of the random walks of the Radiance export of `selected`
/// ([`select_fits`]; [`crate::radiance::walk_seconds`] summed over the fits), for a note
/// before a long run. A fit that cannot be exported counts 0: [`export_fits`] reports it.
pub fn radiance_walk_seconds(selected: &[&FitResult], radiance: &RadianceOptions) -> f64 {
    selected
        .iter()
        .filter_map(|f| ExportModel::from_fit(f).ok())
        .map(|m| crate::radiance::walk_seconds(&m, radiance).unwrap_or(0.0))
        .sum()
}

/// Estimated wall time, in seconds, of the random walks of an export of `selected`
/// ([`select_fits`]) to a renderer target (not Radiance, whose walks
/// [`radiance_walk_seconds`] estimates), for a note before a long run: the reference over the
/// sphere of directions of each all-orders fit runs the fit's own walks
/// ([`Reference::walk_seconds`](crate::translate::Reference::walk_seconds), summed over the
/// fits). A fit that cannot be exported counts 0: [`export_fits`] reports it.
pub fn reference_walk_seconds(selected: &[&FitResult]) -> f64 {
    selected
        .iter()
        .filter_map(|f| ExportModel::from_fit(f).ok())
        .map(|m| crate::translate::Reference::walk_seconds(&m).unwrap_or(0.0))
        .sum()
}

/// The random walks of an export of `selected` ([`select_fits`]) to `target`, for a note before
/// a long run ([`export_walks`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ExportWalks {
    /// Their estimated wall time, in seconds ([`radiance_walk_seconds`] for Radiance,
    /// [`reference_walk_seconds`] for a renderer).
    pub seconds: f64,
    /// What they are.
    pub what: String,
    /// Whether they are the all-orders fits' own walks (made shorter by fits with fewer walks),
    /// rather than the export's (`--walks` of Radiance).
    pub fits_own: bool,
}

/// The random walks of an export of `selected` to `target` ([`ExportWalks`]).
pub fn export_walks(
    selected: &[&FitResult],
    target: Target,
    radiance: &RadianceOptions,
) -> ExportWalks {
    if target == Target::Radiance {
        ExportWalks {
            seconds: radiance_walk_seconds(selected, radiance),
            what: format!(
                "the random walks of this export ({} per Klems patch)",
                radiance.walks_per_patch
            ),
            fits_own: false,
        }
    } else {
        ExportWalks {
            seconds: reference_walk_seconds(selected),
            what: "the all-orders fits' own random walks, which give their values over the \
                   sphere of directions the translation is measured on,"
                .to_owned(),
            fits_own: true,
        }
    }
}

/// Refuses two fits with the same identifier ([`BatchError::SameName`]) and, when each fit
/// gets its own file (`files`), two whose identifiers differ only in case
/// ([`BatchError::SameNameIgnoringCase`]).
fn distinct_identifiers(fits: &[&FitResult], files: bool) -> Result<(), BatchError> {
    let ids: Vec<String> = fits.iter().map(|f| fit_identifier(f)).collect();
    for (k, id) in ids.iter().enumerate() {
        if let Some(j) = ids[..k].iter().position(|other| other == id) {
            return Err(BatchError::SameName {
                first: fits[j].label(),
                second: fits[k].label(),
                id: id.clone(),
            });
        }
        if !files {
            continue;
        }
        if let Some(j) = ids[..k].iter().position(|o| o.eq_ignore_ascii_case(id)) {
            return Err(BatchError::SameNameIgnoringCase {
                first: fits[j].label(),
                second: fits[k].label(),
                id: ids[j].clone(),
                other: id.clone(),
            });
        }
    }
    Ok(())
}

/// The texts of `exports` laid out for `dest` ([`Destination`]); refuses a file destination
/// that would receive two file types ([`BatchError::SamePath`]).
fn outputs(
    exports: &[&FitExport],
    target: Target,
    dest: Destination<'_>,
) -> Result<Vec<Output>, BatchError> {
    if exports.is_empty() {
        return Ok(Vec::new());
    }
    let joined = || join(&exports.iter().map(|e| e.export.clone()).collect::<Vec<_>>());
    Ok(match dest {
        Destination::Stdout => vec![Output {
            path: None,
            text: joined()
                .iter()
                .map(|f| f.text.as_str())
                .collect::<Vec<_>>()
                .join("\n"),
        }],
        Destination::File(out) => {
            let files = joined();
            if let Some(f) = files.iter().skip(1).find(|f| {
                // `scene.PY` and `scene.py` are one file where file names ignore case.
                out.extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| e.eq_ignore_ascii_case(f.extension))
            }) {
                return Err(BatchError::SamePath {
                    path: out.display().to_string(),
                    first: files[0].extension,
                    other: f.extension,
                });
            }
            files
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
                .collect()
        }
        Destination::Folder(dir) => exports
            .iter()
            .flat_map(|e| {
                e.export.files.iter().map(|f| Output {
                    path: Some(dir.join(file_name(&e.id, target, f.extension))),
                    text: f.text.clone(),
                })
            })
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first fit of the example fits (frosted, Beckmann) as sample `sample`.
    fn fit(sample: &str) -> FitResult {
        let text = include_str!("../../../fits/example-fits.json");
        let mut fit = stfit_fit::FitsFile::from_json("example", text)
            .unwrap()
            .fits[0]
            .clone();
        fit.sample = sample.into();
        fit
    }

    fn export(fits: &[FitResult], dest: Destination<'_>) -> Result<Batch, BatchError> {
        let all = Selection::default();
        export_fits(
            fits,
            &all,
            Target::PbrtV4,
            &RadianceOptions::default(),
            dest,
        )
    }

    /// The example's frosted GGX fit (an exact mapping for appleseed) as sample `sample` with
    /// eta `eta`.
    fn ggx_fit(sample: &str, eta: f64) -> FitResult {
        let text = include_str!("../../../fits/example-fits.json");
        let mut fit = stfit_fit::FitsFile::from_json("example", text)
            .unwrap()
            .fits
            .into_iter()
            .find(|f| f.model.kind == stfit_fit::ModelKind::Ggx)
            .unwrap();
        fit.sample = sample.into();
        fit.model.eta = eta;
        fit
    }

    /// appleseed refuses an eta above 2.5: that fit is a refused item, named with its target
    /// and reason, and the fits before and after it are exported and laid out, to one text and
    /// to a folder alike; a batch whose every fit is refused has no output.
    #[test]
    fn a_refused_fit_does_not_stop_the_others() {
        let fits = [ggx_fit("a", 1.51), ggx_fit("b", 2.8), ggx_fit("c", 1.5)];
        let all = Selection::default();
        let opts = RadianceOptions::default();
        let appleseed = |fits: &[FitResult], dest| {
            export_fits(fits, &all, Target::Appleseed, &opts, dest).unwrap()
        };
        for dest in [Destination::Stdout, Destination::Folder(Path::new("out"))] {
            let batch = appleseed(&fits, dest);
            let made: Vec<&str> = batch.exports().map(|e| e.id.as_str()).collect();
            assert_eq!(made, ["a_ggx", "c_ggx"]);
            let refused: Vec<String> = batch.refused().map(|r| r.to_string()).collect();
            assert_eq!(refused.len(), 1);
            assert!(
                refused[0].starts_with("sample 'b', ggx to appleseed: ")
                    && refused[0].contains("eta 2.8"),
                "{}",
                refused[0]
            );
            assert_eq!(
                batch.refusal_summary().as_deref(),
                Some("1 of 3 exports refused")
            );
            let text: String = batch.outputs.iter().map(|o| o.text.as_str()).collect();
            assert!(
                text.contains("name=\"a_ggx\"") && text.contains("name=\"c_ggx\""),
                "{text}"
            );
            assert!(!text.contains("b_ggx"), "{text}");
        }
        let batch = appleseed(&fits[1..2], Destination::Stdout);
        assert!(batch.outputs.is_empty() && batch.exports().next().is_none());
        assert_eq!(
            batch.refusal_summary().as_deref(),
            Some("1 of 1 exports refused")
        );
    }

    /// Samples whose names differ only outside [A-Za-z0-9] would write the same file: refused
    /// before anything is exported, naming both fits, to a folder and to one file alike.
    #[test]
    fn fits_with_the_same_identifier_are_refused() {
        let fits = [fit("a b"), fit("x"), fit("a_b")];
        for dest in [Destination::Folder(Path::new("out")), Destination::Stdout] {
            let e = export(&fits, dest).unwrap_err();
            assert!(matches!(e, BatchError::SameName { .. }), "{e}");
            let e = e.to_string();
            assert!(
                e.contains("sample 'a b'") && e.contains("sample 'a_b'") && e.contains("'a_b_"),
                "{e}"
            );
        }
        assert!(export(&fits[..2], Destination::Folder(Path::new("out"))).is_ok());
    }

    /// Identifiers that differ only in case (`Frosted` and `frosted`) would write one file in
    /// a folder on a file system that ignores case: refused there, naming both fits; in one
    /// file they are distinct names and are exported.
    #[test]
    fn identifiers_differing_in_case_alone_are_refused_in_a_folder() {
        let fits = [fit("Frosted"), fit("frosted")];
        let e = export(&fits, Destination::Folder(Path::new("out"))).unwrap_err();
        assert!(matches!(e, BatchError::SameNameIgnoringCase { .. }), "{e}");
        let e = e.to_string();
        assert!(
            e.contains("sample 'Frosted'")
                && e.contains("sample 'frosted'")
                && e.contains("'Frosted_beckmann'")
                && e.contains("'frosted_beckmann'"),
            "{e}"
        );
        let batch = export(&fits, Destination::Stdout).unwrap();
        assert_eq!(batch.exports().count(), 2);
    }

    /// Only all-orders fits run walks for their reference: a selection of single-scattering
    /// fits costs none; an all-orders fit (here the frosted example's Beckmann fit with 2,000
    /// walks per incidence) some.
    #[test]
    fn only_all_orders_fits_have_reference_walks() {
        let single = fit("s");
        assert_eq!(reference_walk_seconds(&[&single]), 0.0);
        let mut all = fit("a");
        all.model.orders = ScatteringOrders::All;
        all.model.masking = stfit_core::bsdf::Masking::Correlated;
        all.model.walks = Some(2000);
        all.model.seed = Some(1);
        let s = reference_walk_seconds(&[&single, &all]);
        assert!(s > 0.0 && s.is_finite(), "{s}");
    }

    /// Each character outside [A-Za-z0-9] becomes one `_`, whatever its length in UTF-8.
    #[test]
    fn identifiers_replace_each_character_once() {
        assert_eq!(fit_identifier(&fit("Ωμέγα é")), "________beckmann");
    }

    /// An identifier never starts with a digit (it names Python variables and functions):
    /// `_` goes before one that would.
    #[test]
    fn identifiers_do_not_start_with_a_digit() {
        assert_eq!(
            fit_identifier(&fit("2024 frosted")),
            "_2024_frosted_beckmann"
        );
        assert_eq!(fit_identifier(&fit("")), "_beckmann");
        assert_eq!(fit_identifier(&fit("x2")), "x2_beckmann");
    }

    /// One file named with the extension of a later file type would receive both: refused
    /// (Mitsuba writes .xml first, then .py beside it).
    #[test]
    fn one_file_that_would_receive_two_types_is_refused() {
        let fits = [fit("s")];
        let all = Selection::default();
        let opts = RadianceOptions::default();
        let mitsuba = |out: &str| {
            export_fits(
                &fits,
                &all,
                Target::Mitsuba3,
                &opts,
                Destination::File(Path::new(out)),
            )
        };
        for out in ["scene.py", "scene.PY", "dir.v2/scene.Py"] {
            let e = mitsuba(out).unwrap_err();
            assert!(matches!(e, BatchError::SamePath { .. }), "{out}: {e}");
            assert!(e.to_string().contains(out), "{e}");
        }
        let paths: Vec<_> = mitsuba("scene.xml")
            .unwrap()
            .outputs
            .into_iter()
            .map(|o| o.path.unwrap())
            .collect();
        assert_eq!(paths, [Path::new("scene.xml"), Path::new("scene.py")]);
    }
}
