//! `stfit albedo`: fractions of the incident flux that a rough dielectric reflects and transmits,
//! by the height-field random walk.

use super::{CmdError, CmdResult, print_stdout};
use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use stfit_core::Vec3;
use stfit_core::math::radians;
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT};
use stfit_core::sphere::SphereNdf;
use stfit_core::walk::{
    AlbedoEstimate, DielectricFacet, Microsurface, NullMicrosurface, ScatteringOrders,
};

/// The NDF family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NdfKind {
    Beckmann,
    Ggx,
    StudentT,
}

/// Scattering orders to count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Scattering {
    /// Paths that scatter exactly once.
    Single,
    /// Paths that scatter two or more times.
    Multiple,
    /// Every path.
    All,
}

impl From<Scattering> for ScatteringOrders {
    fn from(s: Scattering) -> Self {
        match s {
            Scattering::Single => Self::Single,
            Scattering::Multiple => Self::Multiple,
            Scattering::All => Self::All,
        }
    }
}

/// The random walk.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Walk {
    /// The height-field walk of Heitz et al. 2016.
    Heightfield,
    /// The null-scattering walk of d'Eon 2023 (same results; slower at low roughness; Student-T
    /// needs gamma >= 2).
    Null,
}

/// Arguments of `stfit albedo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// NDF family.
    #[arg(long, value_enum)]
    pub ndf: NdfKind,
    /// Roughness alpha (> 0).
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Student-T shape gamma (> 3/2); required for student-t, rejected otherwise.
    #[arg(long, allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// Relative index n_inside / n_outside (> 0, != 1).
    #[arg(long, allow_negative_numbers = true)]
    pub eta: f64,
    /// Incidence angle in degrees from the outward normal, in [0, 180] except 90; above 90 the
    /// light comes from inside.
    #[arg(long = "theta-i", allow_negative_numbers = true)]
    pub theta_i: f64,
    /// Scattering orders to count.
    #[arg(long, value_enum, default_value_t = Scattering::All)]
    pub scattering: Scattering,
    /// The random walk.
    #[arg(long, value_enum, default_value_t = Walk::Heightfield)]
    pub walk: Walk,
    /// Number of walks.
    #[arg(long, default_value_t = 1_000_000)]
    pub samples: u64,
    /// Seed of the random numbers.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `stfit albedo`. Invalid arguments are usage errors (exit status 2).
pub fn run(args: &Args) -> CmdResult {
    let usage = |m: String| CmdError::Usage(m);
    let theta = args.theta_i;
    if !theta.is_finite() || !(0.0..=180.0).contains(&theta) || theta == 90.0 {
        return Err(usage(format!(
            "--theta-i must be in [0, 180] and not 90, got {theta}"
        )));
    }
    if args.samples == 0 {
        return Err(usage("--samples must be at least 1".into()));
    }
    let param = |e: stfit_core::ParamError| usage(e.to_string());
    let t = radians(theta);
    let wi = Vec3::new(-t.sin(), 0.0, t.cos());
    let facet = DielectricFacet::new(args.eta).map_err(param)?;
    let result = match (args.ndf, args.gamma) {
        (NdfKind::Beckmann, None) => {
            estimate(Beckmann::new(args.alpha).map_err(param)?, facet, wi, args)
        }
        (NdfKind::Ggx, None) => estimate(Ggx::new(args.alpha).map_err(param)?, facet, wi, args),
        (NdfKind::StudentT, Some(g)) => estimate(
            StudentT::new(args.alpha, g).map_err(param)?,
            facet,
            wi,
            args,
        ),
        (NdfKind::StudentT, None) => {
            return Err(usage("--gamma is required for student-t".into()));
        }
        (_, Some(_)) => return Err(usage("--gamma applies only to student-t".into())),
    }
    .map_err(param)?;
    print_stdout(&format_result(args, &result))
}

/// Runs the walks, with a progress bar when both output streams are terminals.
fn estimate<N: Ndf + SphereNdf>(
    ndf: N,
    facet: DielectricFacet,
    wi: Vec3,
    args: &Args,
) -> Result<AlbedoEstimate, stfit_core::ParamError> {
    let orders = ScatteringOrders::from(args.scattering);
    let show = !args.json
        && std::io::stdout().is_terminal()
        && std::io::stderr().is_terminal()
        && args.samples >= 1_000_000;
    let bar = show.then(|| {
        let bar = ProgressBar::new(args.samples);
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} walks, eta {eta}") {
            bar.set_style(style);
        }
        bar
    });
    let progress = |n| {
        if let Some(bar) = &bar {
            bar.inc(n);
        }
    };
    let (n, seed) = (args.samples, args.seed);
    let result = match args.walk {
        Walk::Heightfield => Microsurface::new(ndf, facet)
            .with_orders(orders)
            .albedo_with_progress(wi, n, seed, &progress),
        Walk::Null => NullMicrosurface::new(ndf, facet)?
            .with_orders(orders)
            .albedo_with_progress(wi, n, seed, &progress),
    };
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    Ok(result)
}

/// The report: one JSON object with `--json`, else a few aligned lines.
fn format_result(args: &Args, a: &AlbedoEstimate) -> String {
    if args.json {
        let v = serde_json::json!({
            "reflectance": a.reflectance,
            "transmittance": a.transmittance,
            "reflectance_stderr": a.reflectance_stderr,
            "transmittance_stderr": a.transmittance_stderr,
            "mean_bounces": a.mean_bounces,
            "truncated": a.truncated,
            "samples": a.walks,
            "seed": args.seed,
        });
        return format!("{v}\n");
    }
    let mut text = format!(
        "reflectance    {:.6} +- {:.6}\ntransmittance  {:.6} +- {:.6}\nmean bounces   {:.4}\nwalks          {}\n",
        a.reflectance,
        a.reflectance_stderr,
        a.transmittance,
        a.transmittance_stderr,
        a.mean_bounces,
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
