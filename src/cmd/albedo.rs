//! `stfit albedo`: fractions of the incident flux that a rough surface reflects and transmits,
//! by the height-field or the null-scattering random walk.

use super::surface::{SurfaceArgs, flags};
use super::{CmdResult, OrdersArg, Retired, long_run, print_stdout, usage};
use stfit_core::Vec3;
use stfit_core::math::radians;
use stfit_core::walk::{
    AlbedoEstimate, DEFAULT_ALBEDO_WALKS, Estimator, SideError, WalkCost, check_walks, pilot_seed,
};

/// Arguments of `stfit albedo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub surface: SurfaceArgs,
    /// Incidence angle in degrees from the outward normal, in [0, 180] except 90; above 90 the
    /// light comes from inside.
    #[arg(long = "theta-i", allow_negative_numbers = true)]
    pub theta_i: f64,
    /// Scattering orders to count: single (order 1), multiple (orders >= 2) or all.
    #[arg(long, value_enum, default_value_t = OrdersArg::All)]
    pub orders: OrdersArg,
    /// Number of random walks.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_ALBEDO_WALKS)]
    pub walks: u64,
    /// Seed of the random numbers.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub retired: Retired,
}

/// Runs `stfit albedo`. Invalid arguments are usage errors (exit status 2).
pub fn run(args: &Args) -> CmdResult {
    args.retired.check()?;
    let theta = args.theta_i;
    if !theta.is_finite() || !(0.0..=180.0).contains(&theta) || theta == 90.0 {
        return Err(usage(format!(
            "--theta-i must be in [0, 180] and not 90, got {}",
            stfit_core::error::show(theta)
        )));
    }
    check_walks(args.walks).map_err(|e| usage(format!("--walks: {e}")))?;
    let t = radians(theta);
    let wi = Vec3::new(-t.sin(), 0.0, t.cos());
    let walk = args
        .surface
        .surface()?
        .estimator(args.orders.into())
        .map_err(|e| usage(flags(&e)))?;
    let result = estimate(walk.as_ref(), wi, args);
    print_stdout(&format_result(args, &result))
}

/// Runs the walks, announcing a long run and drawing a progress bar on a terminal
/// ([`long_run::announce`]).
fn estimate(walk: &dyn Estimator, wi: Vec3, args: &Args) -> AlbedoEstimate {
    let cost = WalkCost::measure(walk, wi, args.walks, pilot_seed(args.seed));
    let bar = long_run::announce(cost, args.walks, args.walks);
    let progress = |n| {
        if let Some(bar) = &bar {
            bar.inc(n);
        }
    };
    let result = walk.albedo_with_progress(wi, args.walks, args.seed, &progress);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    result
}

/// The report: one JSON object with `--json`, else a few aligned lines. A side that no walk
/// reached has no standard error (null) but a one-sided 95% upper bound
/// (`*_upper_bound`, null for a side that walks reached).
fn format_result(args: &Args, a: &AlbedoEstimate) -> String {
    let (r_err, t_err) = (a.reflectance_error(), a.transmittance_error());
    if args.json {
        let v = serde_json::json!({
            "reflectance": a.reflectance,
            "transmittance": a.transmittance,
            "reflectance_stderr": r_err.stderr(),
            "transmittance_stderr": t_err.stderr(),
            "reflectance_upper_bound": r_err.upper_bound(),
            "transmittance_upper_bound": t_err.upper_bound(),
            "mean_bounces": a.mean_bounces,
            "truncated": a.truncated,
            "walks": a.walks,
            "seed": args.seed,
        });
        return format!("{v}\n");
    }
    let pm = |e: SideError| match e {
        SideError::Stderr(se) => format!(" +- {se:.6}"),
        SideError::UpperBound(b) => format!(" (no walk; below {b:.3e} at 95%)"),
        SideError::Undefined => String::new(),
    };
    let bounces = match a.mean_bounces {
        Some(b) => format!("{b:.4}"),
        None => "- (no walk left within the orders)".to_owned(),
    };
    let mut text = format!(
        "reflectance    {:.6}{}\ntransmittance  {:.6}{}\nmean bounces   {bounces}\nwalks          {}\n",
        a.reflectance,
        pm(r_err),
        a.transmittance,
        pm(t_err),
        a.walks
    );
    if a.truncated > 0.0 {
        text += &format!(
            "truncated      {:.3e} of the flux (walks past the safety cap)\n",
            a.truncated
        );
    }
    text
}
