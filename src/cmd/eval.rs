//! `stfit eval`: the BSDF of a rough surface at direction pairs read as CSV on stdin.
//!
//! Input (`stfit_fit::pairs`): a header with the columns `wi_x,wi_y,wi_z,wo_x,wo_y,wo_z` (any
//! order; other columns are passed through), then one row per direction pair, unit vectors in
//! the local frame (z > 0 outside, index 1; z < 0 inside, index eta; `wi` toward the light).
//! Output on stdout: the same rows with a column `f_cos = f(wi, wo) |wo.z|` appended
//! (reflection or transmission by the sides of `wi` and `wo`). Single scattering of a
//! height-field NDF with dielectric facets is the closed-form BSDF of Walter et al. 2007 (a
//! Student-T NDF through its interpolated Lambda fractions,
//! [`RoughDielectric::f_cos_batch`](stfit_core::bsdf::RoughDielectric::f_cos_batch)); every
//! other case is a random-walk estimate (rows sharing a `wi` share one set of walks, seeded by
//! the direction) with a column `f_cos_stderr`.

use std::io::{BufWriter, Read, Write};
use std::path::Path;

use stfit_core::surface::Evaluation;
use stfit_core::walk::{
    DEFAULT_EVAL_WALKS, WalkCost, check_walks, defined_stderr, eval_pairs_walk_count,
    eval_pairs_with_progress, pilot_seed,
};
use stfit_fit::pairs::read_pairs;

use super::surface::{SurfaceArgs, flags};
use super::{CmdResult, MaskingArg, OrdersArg, Retired, failed, long_run, usage};

/// Arguments of `stfit eval`.
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub surface: SurfaceArgs,
    /// Masking-shadowing form [default: separable for the closed-form single scattering;
    /// the random walk's masking is height-correlated by construction, so only correlated is
    /// accepted there].
    #[arg(long, value_enum)]
    pub masking: Option<MaskingArg>,
    /// Scattering orders: single (order 1; in closed form for height-field NDFs with dielectric
    /// facets on the height-field walk), multiple (orders >= 2) or all (every order), the last
    /// two estimated by the random walk, with a column f_cos_stderr.
    #[arg(long, value_enum, default_value_t = OrdersArg::Single)]
    pub orders: OrdersArg,
    /// Random walks per distinct wi (random-walk estimates).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_EVAL_WALKS)]
    pub walks: u64,
    /// Seed of the random walks (random-walk estimates).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub retired: Retired,
}

/// Runs `stfit eval`: CSV from stdin to stdout. Invalid options are usage errors (exit status
/// 2); bad input is a failure (1), and then nothing is written.
/// `given` lists the walk flags given on the command line: they are refused where the
/// evaluation is in closed form.
pub fn run(args: &Args, given: &[String]) -> CmdResult {
    args.retired.check()?;
    check_walks(args.walks).map_err(|e| usage(format!("--walks: {e}")))?;
    let evaluation = args
        .surface
        .surface()?
        .evaluation(args.orders.into(), args.masking.map(Into::into))
        .map_err(|e| usage(flags(&e)))?;
    if let (Evaluation::Analytic(_), Some(flag)) = (&evaluation, given.first()) {
        return Err(usage(format!(
            "{flag} applies to random-walk estimates; this evaluation is in closed form"
        )));
    }
    let mut input = Vec::new();
    std::io::stdin()
        .read_to_end(&mut input)
        .map_err(|e| failed(format!("cannot read stdin: {e}")))?;
    let table = read_pairs(Path::new("<stdin>"), &input).map_err(failed)?;
    let mut out = BufWriter::new(std::io::stdout().lock());
    let written = match evaluation {
        Evaluation::Analytic(bsdf) => {
            let values = bsdf.f_cos_batch(&table.pairs);
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(failed(format!(
                    "row {}: the BSDF value is not finite",
                    k + 1
                )));
            }
            table.write_with(&mut out, &values, None)
        }
        Evaluation::Walk(walk) => {
            let all_walks = eval_pairs_walk_count(walk.as_ref(), &table.pairs, args.walks);
            let cost = WalkCost::measure_pairs(
                walk.as_ref(),
                &table.pairs,
                args.walks,
                pilot_seed(args.seed),
            );
            let bar = long_run::announce(cost, args.walks, all_walks);
            let progress = |n| {
                if let Some(bar) = &bar {
                    bar.inc(n);
                }
            };
            let est = eval_pairs_with_progress(
                walk.as_ref(),
                &table.pairs,
                args.walks,
                args.seed,
                &progress,
            );
            if let Some(bar) = bar {
                bar.finish_and_clear();
            }
            let values: Vec<f64> = est.iter().map(|e| e.mean).collect();
            let stderr: Vec<Option<f64>> = est
                .iter()
                .map(|e| defined_stderr(args.walks, e.stderr))
                .collect();
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(failed(format!(
                    "row {}: the random-walk estimate is not finite",
                    k + 1
                )));
            }
            table.write_with(&mut out, &values, Some(&stderr))
        }
    };
    match written.and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(failed(format!("writing output: {e}"))),
    }
}
