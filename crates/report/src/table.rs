//! Tables of fits: the text table the command line prints ([`fits_table`]) and `fits.md`, the
//! markdown table of a report ([`fits_markdown`]). Both use [`fmt_sig`] for every number.

use std::fmt::Write;

use stfit_fit::{FitResult, Gamma};

use crate::style::fmt_sig;
use crate::view::ModelSlot;
use crate::{ReportOptions, YScale, model_description};

/// `value ± stderr` with `digits` significant digits of the value and two of the error, or the
/// value alone when the error is undefined.
fn with_error(value: f64, stderr: Option<f64>, digits: usize) -> String {
    match stderr {
        Some(se) => format!("{} ± {}", fmt_sig(value, digits), fmt_sig(se, 2)),
        None => fmt_sig(value, digits),
    }
}

/// The gamma of a fit: `-` when not applicable, `3 (fixed)` when held, else with its error.
fn gamma_cell(fit: &FitResult, digits: usize) -> String {
    match fit.model.gamma {
        Gamma::NotApplicable => "-".to_string(),
        Gamma::Fixed(g) => format!("{} (fixed)", fmt_sig(g, digits)),
        Gamma::Free(g) => with_error(g, fit.gamma_stderr, digits),
    }
}

/// A sample name for a table cell: `-` when empty, control characters escaped, so that a row
/// stays on one line whatever the name holds.
fn sample_cell(name: &str) -> String {
    if name.is_empty() {
        return "-".to_string();
    }
    name.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_default().collect()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// The readable text table of fits, one row per sample and model, columns aligned: sample,
/// model, alpha, gamma, scale (each with its standard error), rmse of `sqrt(L)` and the number
/// of points.
pub fn fits_table(fits: &[FitResult]) -> String {
    let header = [
        "sample",
        "model",
        "alpha",
        "gamma",
        "scale",
        "rmse sqrt(L)",
        "n",
    ]
    .map(String::from);
    let rows: Vec<[String; 7]> = fits
        .iter()
        .map(|f| {
            [
                sample_cell(&f.sample),
                f.model.kind.name().into(),
                with_error(f.model.alpha, f.alpha_stderr, 5),
                gamma_cell(f, 5),
                with_error(f.model.scale, f.scale_stderr, 5),
                fmt_sig(f.rmse_sqrt_l, 4),
                f.n_points.to_string(),
            ]
        })
        .collect();
    let mut widths = header.clone().map(|h| h.chars().count());
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut text = String::new();
    for row in std::iter::once(&header).chain(&rows) {
        let mut line = String::new();
        for (i, (cell, &w)) in row.iter().zip(&widths).enumerate() {
            if i > 0 {
                line.push_str("  ");
            }
            // The count column is right-aligned, the others left-aligned.
            if i == row.len() - 1 {
                let _ = write!(line, "{cell:>w$}");
            } else {
                let _ = write!(line, "{cell:<w$}");
            }
        }
        text.push_str(line.trim_end());
        text.push('\n');
    }
    text
}

/// The markdown of `fits.md`: one table row per fit, grouped by sample in data order and by
/// model in panel order, each naming the model actually fitted (orders, masking, eta); the
/// lowest rmse of each sample in bold. `figures` lists, per sample,
/// `(sample name, fit figure file, residual figure file)`.
pub fn fits_markdown(
    samples: &[(&str, Vec<&FitResult>)],
    figures: &[(String, String, String)],
    opts: &ReportOptions,
) -> String {
    let mut md = String::new();
    md.push_str("# Fits\n\n");
    let _ = writeln!(
        md,
        "Rough-dielectric BTDF (Walter et al. 2007): `L = scale * f_t * cos(theta_i) / eta^2`, \
         each fit with the model it was fitted with. rmse is of sqrt(L) over the points of \
         weight > 0 (the fitted points); ± gives standard errors; the lowest rmse of each sample \
         is in bold. Figures plot {}.\n",
        match opts.y_scale {
            YScale::Sqrt => "sqrt(L)",
            YScale::Linear => "L",
        }
    );
    md.push_str(
        "| sample | model | fitted with | alpha | gamma | scale | rmse sqrt(L) | points | \
         iterations |\n",
    );
    md.push_str("|---|---|---|---:|---:|---:|---:|---:|---:|\n");
    for (name, fits) in samples {
        let best = fits
            .iter()
            .map(|f| f.rmse_sqrt_l)
            .filter(|r| r.is_finite())
            .fold(f64::INFINITY, f64::min);
        for fit in fits {
            let rmse = fmt_sig(fit.rmse_sqrt_l, 4);
            let rmse = if fit.rmse_sqrt_l == best {
                format!("**{rmse}**")
            } else {
                rmse
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                sample_cell(name).replace('|', "\\|"),
                ModelSlot::of(fit).title(),
                model_description(&fit.model),
                with_error(fit.model.alpha, fit.alpha_stderr, 4),
                gamma_cell(fit, 4),
                with_error(fit.model.scale, fit.scale_stderr, 4),
                rmse,
                fit.n_points,
                fit.iterations
            );
        }
    }
    md.push_str("\n## Figures\n\n");
    md.push_str("- [All samples and models](overview.png)\n- [Fitted NDFs](ndf.png)\n");
    for (name, fit_png, residual_png) in figures {
        let _ = writeln!(
            md,
            "- {name}: [fits]({fit_png}), [residuals]({residual_png})"
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;
    use stfit_fit::{Loss, Model, ModelKind, Optimizer};

    fn result(kind: ModelKind, gamma: Gamma) -> FitResult {
        FitResult {
            sample: "frosted".into(),
            model: Model::single(kind, 0.201_234_5, gamma, 1.234_567),
            loss: Loss::Sqrt,
            optimizer: Optimizer::NelderMead,
            rmse_sqrt_l: 0.004_123_4,
            n_points: 300,
            alpha_stderr: Some(0.001_234),
            gamma_stderr: matches!(gamma, Gamma::Free(_)).then_some(0.081),
            scale_stderr: None,
            iterations: 42,
            data: None,
            stfit_version: "0".into(),
        }
    }

    /// One header and one aligned row per fit; fixed gamma marked, undefined errors left out.
    #[test]
    fn table_has_a_header_and_aligned_rows() {
        let fits = [
            result(ModelKind::Ggx, Gamma::NotApplicable),
            result(ModelKind::StudentT, Gamma::Fixed(3.0)),
            result(ModelKind::StudentT, Gamma::Free(2.95)),
        ];
        let text = fits_table(&fits);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[0].starts_with("sample   model      alpha"));
        assert!(lines[0].ends_with("rmse sqrt(L)    n"));
        assert!(lines[1].contains("0.20123 ± 0.0012"));
        assert!(lines[1].contains("1.2346 "));
        assert!(!lines[1].contains('?'));
        assert!(lines[1].contains("  -  "));
        assert!(lines[2].contains("3.0000 (fixed)"));
        assert!(lines[3].contains("2.9500 ± 0.081"));
        assert!(
            lines
                .iter()
                .skip(1)
                .all(|l| l.ends_with("0.004123      300"))
        );
        let col = |l: &str| l.find("alpha").or_else(|| l.find("0.20123"));
        assert!(lines.iter().all(|l| col(l) == col(lines[0])));
    }

    /// A sample name with line breaks and tabs stays on its row.
    #[test]
    fn control_characters_are_escaped() {
        let mut fit = result(ModelKind::Ggx, Gamma::NotApplicable);
        fit.sample = "a\nb\tc".into();
        let text = fits_table(&[fit]);
        assert_eq!(text.lines().count(), 2);
        assert!(text.contains("a\\nb\\tc"));
    }
}
