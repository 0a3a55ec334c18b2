//! Tables of fits: the text table the command line prints ([`fits_table`]) and `fits.md`, the
//! markdown table of a report ([`fits_markdown`]). Both use [`fmt_sig`] for every number.

use std::fmt::Write;

use stfit_fit::{FitResult, FitWarning, Gamma, Measured};

use crate::style::fmt_sig;
use crate::view::{ModelSlot, NotDrawn};
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

/// The eta of a fit: `1.51 (fixed)` when held, else with its error.
fn eta_cell(fit: &FitResult, digits: usize) -> String {
    if fit.eta_fixed {
        format!("{} (fixed)", fmt_sig(fit.model.eta, digits))
    } else {
        with_error(fit.model.eta, fit.eta_stderr, digits)
    }
}

/// The scale of a fit: `1 (fixed)` when held, else with its error.
fn scale_cell(fit: &FitResult, digits: usize) -> String {
    if fit.scale_fixed {
        format!("{} (fixed)", fmt_sig(fit.model.scale, digits))
    } else {
        with_error(fit.model.scale, fit.scale_stderr, digits)
    }
}

/// What the fits' points measure together, for a column header: `sqrt(L)` when every fit's
/// points give `L`, and so on.
fn rmse_header<'a>(fits: impl IntoIterator<Item = &'a FitResult>) -> String {
    let mut measured: Option<Measured> = None;
    for f in fits {
        measured = Some(match measured {
            None => f.measured,
            Some(m) if m == f.measured => m,
            Some(_) => Measured::Both,
        });
    }
    format!("rmse {}", measured.unwrap_or_default().sqrt_label())
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

/// A fit's warnings as short codes for a table cell: `at-bound(alpha)`, `singular`,
/// `few-points`, `kink(eta)`, `tir-onset(eta)`, comma-separated; empty for an unflagged fit.
pub fn warning_codes(fit: &FitResult) -> String {
    fit.warnings
        .iter()
        .map(|w| match w {
            FitWarning::AtBound { parameter, .. } => format!("at-bound({parameter})"),
            FitWarning::SingularCurvature => "singular".to_string(),
            FitWarning::FewInformativePoints { .. } => "few-points".to_string(),
            FitWarning::NotDifferentiable { parameter } => format!("kink({parameter})"),
            FitWarning::TotalReflectionOnset { .. } => "tir-onset(eta)".to_string(),
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// The readable text table of fits, one row per sample and model, columns aligned: sample,
/// model, alpha, gamma, eta (when any fit fitted it), scale (each with its standard error, or
/// marked fixed), the rmse of the square root of what was measured (`sqrt(L)` or
/// `sqrt(BSDF)`) and the number of points; when any fit is flagged, a last column `warnings`
/// with its [`warning_codes`] (and `-` for the others).
pub fn fits_table(fits: &[FitResult]) -> String {
    let flagged = fits.iter().any(FitResult::flagged);
    // An eta column when any fit fitted it.
    let eta = fits.iter().any(|f| !f.eta_fixed);
    let mut header: Vec<String> = ["sample", "model", "alpha", "gamma"]
        .map(String::from)
        .to_vec();
    if eta {
        header.push("eta".into());
    }
    header.extend(["scale".to_string(), rmse_header(fits), "n".to_string()]);
    if flagged {
        header.push("warnings".into());
    }
    let rows: Vec<Vec<String>> = fits
        .iter()
        .map(|f| {
            let mut row = vec![
                sample_cell(&f.sample),
                f.model.kind.name().into(),
                with_error(f.model.alpha, f.alpha_stderr, 5),
                gamma_cell(f, 5),
            ];
            if eta {
                row.push(eta_cell(f, 5));
            }
            row.extend([
                scale_cell(f, 5),
                fmt_sig(f.rmse_sqrt_l, 4),
                f.n_points.to_string(),
            ]);
            if flagged {
                let codes = warning_codes(f);
                row.push(if codes.is_empty() { "-".into() } else { codes });
            }
            row
        })
        .collect();
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let count = header.iter().position(|h| h == "n").unwrap_or(0);
    let mut text = String::new();
    for row in std::iter::once(&header).chain(&rows) {
        let mut line = String::new();
        for (i, (cell, &w)) in row.iter().zip(&widths).enumerate() {
            if i > 0 {
                line.push_str("  ");
            }
            // The count column is right-aligned, the others left-aligned. Padded by hand:
            // a `{:w$}` width must fit in a u16, and a sample name may be longer.
            let pad = " ".repeat(w.saturating_sub(cell.chars().count()));
            if i == count {
                line.push_str(&pad);
                line.push_str(cell);
            } else {
                line.push_str(cell);
                line.push_str(&pad);
            }
        }
        text.push_str(line.trim_end());
        text.push('\n');
    }
    text
}

/// The markdown of `fits.md`: one table row per fit, grouped by sample in data order and by
/// model in panel order, each naming the model actually fitted (orders, masking, eta); the
/// lowest rmse of each sample in bold; `not_drawn` are listed under their own heading.
/// `figures` lists, per sample, its name and its figures
/// as `(what, file)`; `overview` says whether the report has an overview figure (whether it
/// has in-plane samples, whose panels' y axis the text then states).
pub fn fits_markdown(
    samples: &[(&str, Vec<&FitResult>)],
    not_drawn: &[NotDrawn<'_>],
    figures: &[(String, Vec<(&str, String)>)],
    overview: bool,
    opts: &ReportOptions,
) -> String {
    let mut md = String::new();
    md.push_str("# Fits\n\n");
    let all = || samples.iter().flat_map(|(_, fits)| fits.iter().copied());
    let measured = all().fold(None, |acc: Option<Measured>, f| match acc {
        None => Some(f.measured),
        Some(m) if m == f.measured => Some(m),
        Some(_) => Some(Measured::Both),
    });
    let model = match measured.unwrap_or_default() {
        Measured::L => {
            "Rough-dielectric BTDF (Walter et al. 2007): `L = scale * f_t * cos(theta_i) / eta^2`"
        }
        Measured::Bsdf => {
            "Rough-dielectric BSDF (Walter et al. 2007, reflection and transmission): \
             `bsdf = scale * f`"
        }
        Measured::Both => {
            "Rough-dielectric BSDF (Walter et al. 2007): `L = scale * f_t * cos(theta_i) / \
             eta^2` for in-plane points, `bsdf = scale * f` for general ones"
        }
    };
    let rmse_header = rmse_header(all());
    // Only in-plane samples have the panels whose y axis --y-axis chooses.
    let y_axis = if overview {
        format!(
            " Figures of in-plane data plot {}.",
            match opts.y_scale {
                YScale::Sqrt => "sqrt(L)",
                YScale::Linear => "L",
            }
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        md,
        "{model}, each fit with the model and loss it was fitted with. {} is over the points of \
         weight > 0 (the fitted points); ± gives standard errors; the lowest rmse of each sample \
         is in bold; ⚠ marks a fit that cannot be trusted as it stands (see Warnings).{y_axis}\n",
        rmse_header,
    );
    let _ = writeln!(
        md,
        "| sample | model | fitted with | alpha | gamma | eta | scale | {rmse_header} | points | \
         iterations |"
    );
    md.push_str("|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
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
                "| {} | {} | {}, {} loss | {} | {} | {} | {} | {} | {} | {} |",
                sample_cell(name).replace('|', "\\|"),
                if fit.flagged() {
                    format!("⚠ {}", ModelSlot::of(fit).title())
                } else {
                    ModelSlot::of(fit).title().to_string()
                },
                model_description(&fit.model),
                fit.loss.name(),
                with_error(fit.model.alpha, fit.alpha_stderr, 4),
                gamma_cell(fit, 4),
                eta_cell(fit, 4),
                scale_cell(fit, 4),
                rmse,
                fit.n_points,
                fit.iterations
            );
        }
    }
    let flagged: Vec<&FitResult> = all().filter(|f| f.flagged()).collect();
    if !flagged.is_empty() {
        md.push_str("\n## Warnings\n\n");
        for fit in flagged {
            for w in &fit.warnings {
                let _ = writeln!(
                    md,
                    "- {}: {w}",
                    sample_cell(&fit.label()).replace('|', "\\|")
                );
            }
        }
    }
    if !not_drawn.is_empty() {
        md.push_str("\n## Not drawn\n\n");
        for n in not_drawn {
            let _ = writeln!(
                md,
                "- {}: the stored fit is not valid or its model cannot be evaluated ({}); the panel \
                 shows the data alone",
                sample_cell(&n.fit.label()).replace('|', "\\|"),
                n.reason.replace('|', "\\|")
            );
        }
    }
    md.push_str("\n## Figures\n\n");
    if overview {
        md.push_str("- [All samples and models](overview.png)\n");
    }
    md.push_str("- [Fitted NDFs](ndf.png)\n");
    for (name, files) in figures {
        let links: Vec<String> = files
            .iter()
            .map(|(what, file)| format!("[{what}]({file})"))
            .collect();
        let _ = writeln!(md, "- {name}: {}", links.join(", "));
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
            multiple_term: None,
            rmse_sqrt_l: 0.004_123_4,
            n_points: 300,
            alpha_stderr: Some(0.001_234),
            gamma_stderr: matches!(gamma, Gamma::Free(_)).then_some(0.081),
            scale_stderr: None,
            iterations: 42,
            data: None,
            warnings: Vec::new(),
            stfit_version: "0".into(),
            eta_fixed: true,
            scale_fixed: false,
            log_floor: None,
            eta_stderr: None,
            measured: Measured::L,
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

    /// A sample name wider than any format width (65,535) is padded, not a panic, and the
    /// columns after it stay aligned.
    #[test]
    fn a_sample_name_of_any_length_is_aligned() {
        let mut long = result(ModelKind::Ggx, Gamma::NotApplicable);
        long.sample = "x".repeat(70_000);
        let text = fits_table(&[long, result(ModelKind::Ggx, Gamma::NotApplicable)]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        let col = |l: &str| l.find("ggx").or_else(|| l.find("model"));
        assert_eq!(col(lines[0]), Some(70_002));
        assert!(lines.iter().all(|l| col(l) == col(lines[0])));
    }
}
