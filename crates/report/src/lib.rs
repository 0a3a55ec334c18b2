//! stfit-report: Figure-1-style comparison plots of fitted microfacet models against measured
//! transmission through rough glass, as SVG and PNG, and a markdown table of the fits.
//!
//! The data convention of in-plane samples is that of `stfit-fit` (theory section 8): light
//! from air at `theta_i`, `theta_o` the transmitted direction inside the glass (180 degrees
//! straight through), and the plotted quantity `sqrt(L)` (the published view) or `L`. Each fit
//! is drawn with its own model
//! ([`stfit_fit::Model::predict`]): its eta, masking and scattering orders, as it was fitted.
//!
//! [`render_report`] draws everything in memory; [`Report::write_to`] writes it to a folder:
//!
//! - `<sample>-fits.{svg,png}`: four panels (Beckmann, GGX, Student-T with gamma fixed,
//!   Student-T with gamma free), measurements as markers and the model as lines, one colour per
//!   incidence angle (the same in every figure), 1600 x 1200 px;
//! - `<sample>-residuals.{svg,png}`: measured minus model, same layout;
//! - for a general sample (any direction pairs, `data-format.md`) instead of those two,
//!   `<sample>-plane.{svg,png}`: the measured and fitted BSDF in each incidence's plane of
//!   incidence, and `<sample>-polar.{svg,png}`: the residual of every point on two disks per
//!   incidence (the light's side and the other);
//! - `overview.{svg,png}`: the in-plane samples as rows, models as columns (not written
//!   without in-plane samples);
//! - `ndf.{svg,png}`: the fitted `D(theta_m)` on a log scale, one panel per sample;
//! - `fits.md`: every fit as a table.
//!
//! `<sample>` is the sample's [`file_stem`]; samples whose stems would name one file (ignoring
//! case) get `-2`, `-3`, ... appended in data order ([`file_stems`]), and `fits.md` links each
//! sample's figures under its own name.
//!
//! Text uses DejaVu Sans embedded from the `dejavu` crate; no system fonts or libraries are
//! needed.

mod error;
mod figures;
mod general;
mod render;
mod style;
mod table;
mod view;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use stfit_fit::{Dataset, FitResult, Sample};

pub use error::ReportError;
pub use figures::{clip_below, fmt_tick};
pub use style::fmt_sig;
pub use table::{fits_markdown, fits_table, warning_codes};
pub use view::{ModelSlot, NotDrawn};

use figures::{NdfFigure, OverviewFigure, SampleFigure};
use general::{GeneralView, PlaneFigure, PolarFigure};
use render::{Figure, render_png, render_svg};
use style::AnglePalette;
use view::SampleView;

/// The quantity on the vertical axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum YScale {
    /// `sqrt(L)`, the published view: tails and peak on one readable scale.
    #[default]
    Sqrt,
    /// `L` itself.
    Linear,
}

/// How to draw a report. The model of every curve comes from its fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReportOptions {
    pub y_scale: YScale,
}

/// One output file, in memory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReportFile {
    /// File name inside the report folder.
    pub name: String,
    pub contents: Vec<u8>,
}

/// A rendered report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Report {
    pub files: Vec<ReportFile>,
    /// Non-fatal findings, such as a stored rmse that the data and the fitted parameters do not
    /// reproduce (fits of other data, or made with other options).
    pub warnings: Vec<String>,
}

impl Report {
    /// The file called `name`, if the report has one.
    pub fn file(&self, name: &str) -> Option<&ReportFile> {
        self.files.iter().find(|f| f.name == name)
    }

    /// Writes every file into `dir` (created if missing) and returns their paths.
    pub fn write_to(&self, dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| ReportError::Io { path, source }
        };
        stfit_fit::files::create_folder(dir).map_err(io(dir))?;
        self.files
            .iter()
            .map(|f| {
                let path = dir.join(&f.name);
                std::fs::write(&path, &f.contents).map_err(io(&path))?;
                Ok(path)
            })
            .collect()
    }
}

/// The scattering orders and masking of a model, as tables and messages state them: for
/// example `single scattering, separable masking` or `all orders (20000 walks, seed 1)`.
pub fn model_description(m: &stfit_fit::Model) -> String {
    match (m.orders, m.walks, m.seed) {
        (stfit_fit::ScatteringOrders::Single, _, _) => {
            format!("single scattering, {} masking", m.masking.name())
        }
        (_, Some(w), Some(s)) => format!("all orders ({w} walks, seed {s})"),
        _ => "all orders".to_string(),
    }
}

/// A file-name stem for a sample: its first
/// [`MAX_SAMPLE_CHARS`](stfit_fit::files::MAX_SAMPLE_CHARS) characters (room left for a suffix
/// of [`file_stems`]), ASCII letters,
/// digits, `-`, `_` and `.` kept, anything else replaced by `_`; `sample` for an unnamed one.
pub fn file_stem(sample: &str) -> String {
    if sample.is_empty() {
        return "sample".to_string();
    }
    sample
        .chars()
        .take(stfit_fit::files::MAX_SAMPLE_CHARS)
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The file-name stems of samples called `names`, in their order: each its own
/// [`file_stem`], except that a stem already taken by an earlier sample, ignoring ASCII case
/// (one file where file names ignore case, as on macOS and Windows), gets the first of `-2`,
/// `-3`, ... appended that gives a stem no earlier sample took and no sample has as its own
/// stem, both ignoring case. The stems are distinct ignoring case, and every sample whose own
/// stem no earlier sample has keeps it.
pub fn file_stems<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let own: Vec<String> = names.into_iter().map(file_stem).collect();
    let reserved: HashSet<String> = own.iter().map(|s| s.to_ascii_lowercase()).collect();
    let mut taken: HashSet<String> = HashSet::new();
    let mut stems = Vec::with_capacity(own.len());
    for stem in own {
        if taken.insert(stem.to_ascii_lowercase()) {
            stems.push(stem);
            continue;
        }
        for k in 2u64.. {
            let candidate = format!("{stem}-{k}");
            let key = candidate.to_ascii_lowercase();
            if !reserved.contains(&key) && taken.insert(key) {
                stems.push(candidate);
                break;
            }
        }
    }
    stems
}

/// Relative difference above which a stored rmse counts as not reproduced.
const RMSE_TOLERANCE: f64 = 1e-6;

/// The points a fit uses: those of weight > 0.
fn fitted_points(sample: &stfit_fit::Sample) -> usize {
    sample.points.iter().filter(|m| m.weight > 0.0).count()
}

/// A sample split by the form of its points: `(in-plane points, general points)`, each `None`
/// when there are none (an empty sample counts as in-plane).
fn split_by_form(sample: &Sample) -> (Option<Sample>, Option<Sample>) {
    let (ip, general_part): (Vec<_>, Vec<_>) = sample
        .points
        .iter()
        .partition(|p| p.in_plane_angles().is_some());
    let part = |points: Vec<stfit_fit::Measurement>| Sample {
        name: sample.name.clone(),
        points,
    };
    match (ip.is_empty(), general_part.is_empty()) {
        (_, true) => (Some(sample.clone()), None),
        (true, false) => (None, Some(sample.clone())),
        (false, false) => (Some(part(ip)), Some(part(general_part))),
    }
}

/// Assigns each fit to its sample and panel, checking that it belongs there.
fn assign_fits<'a>(
    data: &'a Dataset,
    fits: &'a [FitResult],
) -> Result<Vec<[Option<&'a FitResult>; 4]>, ReportError> {
    let index: HashMap<&str, usize> = data
        .samples
        .iter()
        .enumerate()
        .map(|(i, s)| (s.name.as_str(), i))
        .collect();
    let mut slots = vec![[None; 4]; data.samples.len()];
    for fit in fits {
        let slot = ModelSlot::of(fit);
        let i = *index
            .get(fit.sample.as_str())
            .ok_or_else(|| ReportError::UnknownSample {
                sample: fit.sample.clone(),
                model: slot.title().to_string(),
            })?;
        let data_points = fitted_points(&data.samples[i]);
        if fit.n_points != data_points {
            return Err(ReportError::PointCount {
                sample: fit.sample.clone(),
                model: slot.title().to_string(),
                fit_points: fit.n_points,
                data_points,
            });
        }
        let cell = &mut slots[i][slot.index()];
        if cell.is_some() {
            return Err(ReportError::DuplicateFit {
                sample: fit.sample.clone(),
                model: slot.title().to_string(),
            });
        }
        *cell = Some(fit);
    }
    Ok(slots)
}

fn push_figure(
    files: &mut Vec<ReportFile>,
    stem: &str,
    fig: &impl Figure,
) -> Result<(), ReportError> {
    files.push(ReportFile {
        name: format!("{stem}.svg"),
        contents: render_svg(fig)?.into_bytes(),
    });
    files.push(ReportFile {
        name: format!("{stem}.png"),
        contents: render_png(fig)?,
    });
    Ok(())
}

/// What the random walks of [`render_report`] are ([`walk_seconds`]), for a note before a long
/// run.
pub const WALKS_DESCRIPTION: &str = "the all-orders fits' own random walks, which give the \
                                     orders >= 2 of the curves and of the model at the measured \
                                     points,";

/// Estimated wall time, in seconds, of the random walks that [`render_report`] runs to draw
/// `fits` against `data` with `opts`, for a note before a long run: the orders >= 2 term of
/// every all-orders fit at the points of its panel, curves and measured points alike (one set
/// of `walks` walks per incident direction, [`stfit_fit::Model::walk_seconds`]: a pilot run of
/// those walks, at most a sixteenth of their work), summed over the panels of every sample.
/// 0 without all-orders fits; fits that [`render_report`] refuses, or cannot evaluate, count 0.
pub fn walk_seconds(data: &Dataset, fits: &[FitResult], opts: &ReportOptions) -> f64 {
    let Ok(slots) = assign_fits(data, fits) else {
        return 0.0;
    };
    data.samples
        .iter()
        .zip(slots)
        .map(|(sample, fits)| {
            let (ip, general_part) = split_by_form(sample);
            ip.map_or(0.0, |s| SampleView::walk_seconds(&s, fits, opts))
                + general_part.map_or(0.0, |s| GeneralView::walk_seconds(&s, fits))
        })
        .sum()
}

/// Draws the report of `fits` (any subset of the four panels per sample; panels without a fit
/// show the data alone) against `data`. Every fit must name a sample of `data`, have been made
/// on its number of points of weight > 0, and be the only one of its model for that sample.
/// Points of weight 0 are drawn hollow.
pub fn render_report(
    data: &Dataset,
    fits: &[FitResult],
    opts: &ReportOptions,
) -> Result<Report, ReportError> {
    if data.samples.is_empty() {
        return Err(ReportError::NoSamples);
    }
    let slots = assign_fits(data, fits)?;
    let stems = file_stems(data.samples.iter().map(|s| s.name.as_str()));

    // In-plane samples get the Walter-form figures, general samples theirs; a sample that
    // mixes both kinds of point (files of both forms merged by name) gets both, each with its
    // own points.
    let parts: Vec<(Option<Sample>, Option<Sample>)> =
        data.samples.iter().map(split_by_form).collect();
    let mut in_plane = Vec::new();
    let mut general = Vec::new();
    let mut not_drawn: Vec<NotDrawn> = Vec::new();
    for (fits, (ip, general_part)) in slots.into_iter().zip(&parts) {
        if let Some(ip) = ip {
            in_plane.push(SampleView::new(ip, fits, opts, &mut not_drawn)?);
        }
        if let Some(general_part) = general_part {
            let mut again = Vec::new();
            general.push(GeneralView::new(
                general_part,
                fits,
                opts.y_scale,
                &mut again,
            )?);
            for n in again {
                if !not_drawn.iter().any(|m| std::ptr::eq(m.fit, n.fit)) {
                    not_drawn.push(n);
                }
            }
        }
    }
    // One palette for the incidence angles of the in-plane figures, one for the incident
    // directions of the general figures.
    let palette = AnglePalette::new(
        in_plane
            .iter()
            .flat_map(|v| v.groups.iter().map(|g| (g.theta_i_deg, 0.0))),
    );
    let general_palette = AnglePalette::new(
        general
            .iter()
            .flat_map(|v| v.incidences.iter().map(|g| (g.theta_i_deg, g.phi_i_deg))),
    );
    // (sample title, [(fit, recomputed rmse)]) of every sample, in data order, over all its
    // points (those of both figures of a mixed sample).
    let mut rmse_checks: Vec<(&str, Vec<(&FitResult, f64)>)> = Vec::new();
    for sample in &data.samples {
        let iv = in_plane.iter().find(|v| v.name == sample.name);
        let gv = general.iter().find(|v| v.name == sample.name);
        let mut checks = Vec::new();
        for slot in ModelSlot::ALL {
            let a = iv.and_then(|v| v.panels[slot.index()].as_ref());
            let b = gv.and_then(|v| v.panels[slot.index()].as_ref());
            let Some(fit) = a.map(|p| p.fit).or(b.map(|p| p.fit)) else {
                continue;
            };
            let s1 = a.map_or_else(Default::default, |p| p.sq_sum);
            let s2 = b.map_or_else(Default::default, |p| p.sq_sum);
            checks.push((fit, s1.merge(s2).rms()));
        }
        rmse_checks.push((view::sample_title(&sample.name), checks));
    }
    let mut warnings: Vec<String> = not_drawn.iter().map(NotDrawn::message).collect();
    // The stored rmse that the data do not reproduce, also listed in fits.md: its table shows
    // the stored numbers.
    let mut not_reproduced = Vec::new();
    for (title, checks) in &rmse_checks {
        for &(fit, recomputed) in checks {
            let stored = fit.rmse_sqrt_l;
            // A NaN on either side warns too.
            let gap = (recomputed - stored).abs();
            if gap.is_nan() || gap > RMSE_TOLERANCE * stored.abs().max(1e-3) {
                not_reproduced.push(format!(
                    "sample `{}`, {}: the stored rmse of the square root of the data is {} \
                     but the data and the fitted model ({}, eta {}) give {}; the fit may come \
                     from other data",
                    stfit_fit::short(title),
                    ModelSlot::of(fit).title(),
                    fmt_sig(stored, 6),
                    model_description(&fit.model),
                    fit.model.eta,
                    fmt_sig(recomputed, 6),
                ));
            }
        }
    }
    warnings.extend(not_reproduced.iter().cloned());

    let mut files = Vec::new();
    let mut figure_names: Vec<(String, Vec<(&'static str, String)>)> = Vec::new();
    let mut ndfs: Vec<(String, [Option<stfit_core::ndf::AnyNdf>; 4])> = Vec::new();
    for (sample, stem) in data.samples.iter().zip(&stems) {
        let mut names = Vec::new();
        let mut ndf = None;
        if let Some(view) = in_plane.iter().find(|v| v.name == sample.name) {
            push_figure(
                &mut files,
                &format!("{stem}-fits"),
                &SampleFigure::fits(view, &palette, opts.y_scale),
            )?;
            push_figure(
                &mut files,
                &format!("{stem}-residuals"),
                &SampleFigure::residuals(view, &palette, opts.y_scale),
            )?;
            names.push(("fits", format!("{stem}-fits.png")));
            names.push(("residuals", format!("{stem}-residuals.png")));
            ndf = Some(view.panels.clone().map(|p| p.map(|p| p.ndf)));
        }
        if let Some(view) = general.iter().find(|v| v.name == sample.name) {
            push_figure(
                &mut files,
                &format!("{stem}-plane"),
                &PlaneFigure {
                    view,
                    palette: &general_palette,
                    y_scale: opts.y_scale,
                },
            )?;
            push_figure(
                &mut files,
                &format!("{stem}-polar"),
                &PolarFigure {
                    view,
                    y_scale: opts.y_scale,
                },
            )?;
            names.push(("plane of incidence", format!("{stem}-plane.png")));
            names.push(("residual maps", format!("{stem}-polar.png")));
            ndf = ndf.or_else(|| Some(view.panels.clone().map(|p| p.map(|p| p.ndf))));
        }
        let title = view::sample_title(&sample.name).to_string();
        if let Some(ndf) = ndf {
            ndfs.push((title.clone(), ndf));
        }
        figure_names.push((title, names));
    }
    if !in_plane.is_empty() {
        let overview = OverviewFigure {
            views: &in_plane,
            palette: &palette,
            y_scale: opts.y_scale,
        };
        push_figure(&mut files, "overview", &overview)?;
    }
    push_figure(&mut files, "ndf", &NdfFigure { samples: &ndfs })?;

    // The fits table in data order.
    let by_sample: Vec<(&str, Vec<&FitResult>)> = rmse_checks
        .iter()
        .map(|(title, checks)| (*title, checks.iter().map(|c| c.0).collect()))
        .collect();
    files.push(ReportFile {
        name: "fits.md".to_string(),
        contents: with_not_reproduced(
            fits_markdown(
                &by_sample,
                &not_drawn,
                &figure_names,
                !in_plane.is_empty(),
                opts,
            ),
            &not_reproduced,
        )
        .into_bytes(),
    });
    Ok(Report { files, warnings })
}

/// `md` with a section listing `not_reproduced` (the stored rmse that the data and the fitted
/// model do not reproduce), before its list of figures.
fn with_not_reproduced(md: String, not_reproduced: &[String]) -> String {
    if not_reproduced.is_empty() {
        return md;
    }
    let mut section = String::from(
        "\n## Not reproduced\n\nThe table gives the stored rmse; the data and the fitted \
         parameters give another:\n\n",
    );
    for w in not_reproduced {
        section.push_str(&format!("- {}\n", w.replace('|', "\\|")));
    }
    match md.find("\n## Figures") {
        Some(at) => format!("{}{section}{}", &md[..at], &md[at..]),
        None => md + &section,
    }
}

/// [`render_report`], then [`Report::write_to`] `dir`.
pub fn write_report(
    data: &Dataset,
    fits: &[FitResult],
    dir: &Path,
    opts: &ReportOptions,
) -> Result<Report, ReportError> {
    let report = render_report(data, fits, opts)?;
    report.write_to(dir)?;
    Ok(report)
}
