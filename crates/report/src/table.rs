//! `fits.md`: every fit of the report as a markdown table.

use std::fmt::Write;

use stfit_fit::FitResult;

use crate::style::fmt_sig;
use crate::view::ModelSlot;
use crate::{ReportOptions, YScale};

/// `value ± stderr`, or the value alone when the error is not finite.
fn with_error(value: f64, stderr: f64) -> String {
    if stderr.is_finite() {
        format!("{} ± {}", fmt_sig(value, 4), fmt_sig(stderr, 2))
    } else {
        fmt_sig(value, 4)
    }
}

fn gamma_cell(fit: &FitResult) -> String {
    match (fit.gamma, fit.gamma_fixed) {
        (None, _) => "–".to_string(),
        (Some(g), true) => format!("{g} (fixed)"),
        (Some(g), false) => with_error(g, fit.gamma_stderr.unwrap_or(f64::NAN)),
    }
}

/// The markdown of `fits.md`: one table row per fit, grouped by sample in data order and by
/// model in panel order; the lowest rmse of each sample in bold. `figures` lists, per sample,
/// `(sample name, fit figure file, residual figure file)`.
pub fn fits_markdown(
    samples: &[(&str, Vec<&FitResult>)],
    figures: &[(String, String, String)],
    opts: &ReportOptions,
) -> String {
    let mut md = String::new();
    md.push_str("# Fits\n\n");
    let masking = match opts.masking {
        stfit_core::bsdf::Masking::Separable => "separable",
        stfit_core::bsdf::Masking::Correlated => "height-correlated",
    };
    let _ = writeln!(
        md,
        "Single-scattering rough-dielectric BTDF (Walter et al. 2007), eta = {}, {masking} \
         masking: `L = scale * f_t * cos(theta_i) / eta^2`. rmse is of sqrt(L) over the points \
         of weight > 0 (the fitted points); ± gives standard errors; the lowest rmse of each \
         sample is in bold. Figures plot {}.\n",
        opts.eta,
        match opts.y_scale {
            YScale::Sqrt => "sqrt(L)",
            YScale::Linear => "L",
        }
    );
    md.push_str(
        "| sample | model | alpha | gamma | scale | rmse sqrt(L) | points | iterations |\n",
    );
    md.push_str("|---|---|---:|---:|---:|---:|---:|---:|\n");
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
                "| {} | {} | {} | {} | {} | {} | {} | {} |",
                name,
                ModelSlot::of(fit).title(),
                with_error(fit.alpha, fit.alpha_stderr),
                gamma_cell(fit),
                with_error(fit.scale, fit.scale_stderr),
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
