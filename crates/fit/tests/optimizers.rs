//! Nelder-Mead and L-BFGS reach the same optimum, under both losses.

mod common;

use stfit_fit::fit::fit_sample;
use stfit_fit::{FitOptions, FitResult, Loss, ModelKind, ModelSpec, Optimizer};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The minimised loss of a fit, recomputed from the fitted model (weights are 1).
fn loss_of(r: &FitResult, sample: &stfit_fit::Sample, loss: Loss) -> f64 {
    let model = r.model.predict_points(&sample.points).unwrap();
    let t = |x: f64| match loss {
        Loss::Sqrt => x.sqrt(),
        Loss::Linear => x,
        Loss::Log => unreachable!("not compared here"),
    };
    sample
        .points
        .iter()
        .zip(&model)
        .map(|(p, &m)| (t(p.value) - t(m)).powi(2))
        .sum()
}

#[test]
fn nelder_mead_and_lbfgs_agree() {
    // The Walter samples when the shared folder is there; the synthetic one always.
    let mut samples = common::walter_samples("nelder_mead_and_lbfgs_agree").unwrap_or_default();
    samples.push(common::synthetic(
        &common::truth(ModelKind::StudentT, 0.25, 2.4, 1.5),
        0.03,
        7,
    ));
    let specs = [
        (ModelKind::Beckmann, None),
        (ModelKind::Ggx, None),
        (ModelKind::StudentT, Some(3.0)),
        (ModelKind::StudentT, None),
    ];
    for sample in &samples {
        for loss in [Loss::Sqrt, Loss::Linear] {
            for (kind, gamma_fixed) in specs {
                let spec = ModelSpec::new(kind, gamma_fixed).unwrap();
                let fit = |optimizer| {
                    let opts = FitOptions {
                        loss,
                        optimizer,
                        ..FitOptions::default()
                    };
                    fit_sample(sample, spec, &opts).unwrap()
                };
                let (nm, lb) = (fit(Optimizer::NelderMead), fit(Optimizer::Lbfgs));
                let (ln, ll) = (loss_of(&nm, sample, loss), loss_of(&lb, sample, loss));
                println!(
                    "{} {loss:?} {} gamma_fixed {gamma_fixed:?}: NM alpha {:.6} gamma {:?} \
                     scale {:.6} loss {ln:.10e} ({} it) | L-BFGS alpha {:.6} gamma {:?} \
                     scale {:.6} loss {ll:.10e} ({} it)",
                    sample.name,
                    kind.name(),
                    nm.model.alpha,
                    nm.model.gamma.value(),
                    nm.model.scale,
                    nm.iterations,
                    lb.model.alpha,
                    lb.model.gamma.value(),
                    lb.model.scale,
                    lb.iterations
                );
                let ctx = format!("{} {loss:?} {kind:?} {gamma_fixed:?}", sample.name);
                assert!(rel(nm.model.alpha, lb.model.alpha) < 1e-3, "{ctx}: alpha");
                assert!(rel(nm.model.scale, lb.model.scale) < 1e-3, "{ctx}: scale");
                if let (Some(a), Some(b)) = (nm.model.gamma.value(), lb.model.gamma.value()) {
                    assert!(rel(a, b) < 1e-3, "{ctx}: gamma");
                }
                assert!(rel(ln, ll) < 1e-8, "{ctx}: loss {ln} vs {ll}");
            }
        }
    }
}
