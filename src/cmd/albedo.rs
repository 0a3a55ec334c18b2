//! `stfit albedo`: fractions of the incident flux that a rough surface reflects and transmits,
//! by the height-field or the null-scattering random walk.

use super::surface::{self, BaseKind, Estimators, FacetKind, Walk};
use super::{CmdError, CmdResult, print_stdout};
use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use stfit_core::Vec3;
use stfit_core::math::radians;
use stfit_core::walk::{AlbedoEstimate, ScatteringOrders};

/// The NDF family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NdfKind {
    /// Beckmann height field (--alpha).
    Beckmann,
    /// GGX height field (--alpha).
    Ggx,
    /// Student-T height field (--alpha, --gamma).
    StudentT,
    /// von Mises-Fisher on the whole sphere (--kappa; needs --walk null and a conductor or
    /// Lambertian facet).
    Vmf,
    /// A height field (--base, --alpha, [--gamma]) blended with uniformly oriented facets
    /// (--porosity); needs --walk null and a conductor or Lambertian facet.
    Porous,
}

impl NdfKind {
    /// The height-field family, if this is one.
    pub fn family(self) -> Option<BaseKind> {
        match self {
            Self::Beckmann => Some(BaseKind::Beckmann),
            Self::Ggx => Some(BaseKind::Ggx),
            Self::StudentT => Some(BaseKind::StudentT),
            Self::Vmf | Self::Porous => None,
        }
    }
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

/// Arguments of `stfit albedo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// NDF family.
    #[arg(long, value_enum)]
    pub ndf: NdfKind,
    /// Roughness alpha (> 0) of a height-field NDF or of the base of --ndf porous.
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Student-T shape gamma (> 3/2); required for student-t, rejected otherwise.
    #[arg(long, allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// Concentration kappa (> 0) of --ndf vmf.
    #[arg(long, allow_negative_numbers = true)]
    pub kappa: Option<f64>,
    /// Height-field base of --ndf porous.
    #[arg(long, value_enum)]
    pub base: Option<BaseKind>,
    /// Fraction of the facet area of --ndf porous that is uniformly oriented, in [0, 1].
    #[arg(long, allow_negative_numbers = true)]
    pub porosity: Option<f64>,
    /// Facet material: dielectric (height-field NDFs; --eta), conductor (--n and --k, or a
    /// perfect mirror without them) or lambertian (--reflectance).
    #[arg(long, value_enum, default_value_t)]
    pub facet: FacetKind,
    /// Relative index n_inside / n_outside (> 0, != 1) of dielectric facets.
    #[arg(long, allow_negative_numbers = true)]
    pub eta: Option<f64>,
    /// Real part of the conductor's relative index (with --k).
    #[arg(long, allow_negative_numbers = true)]
    pub n: Option<f64>,
    /// Imaginary part of the conductor's relative index (with --n).
    #[arg(long, allow_negative_numbers = true)]
    pub k: Option<f64>,
    /// Albedo of Lambertian facets, in [0, 1].
    #[arg(long, allow_negative_numbers = true)]
    pub reflectance: Option<f64>,
    /// Incidence angle in degrees from the outward normal, in [0, 180] except 90; above 90 the
    /// light comes from inside.
    #[arg(long = "theta-i", allow_negative_numbers = true)]
    pub theta_i: f64,
    /// Scattering orders to count.
    #[arg(long, value_enum, default_value_t = Scattering::All)]
    pub scattering: Scattering,
    /// The random walk: heightfield (Heitz et al. 2016; height-field NDFs) or null (d'Eon 2023;
    /// any bounded NDF, same results on height fields, slower at low roughness; Student-T needs
    /// gamma >= 2).
    #[arg(long, value_enum, default_value_t)]
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
    let t = radians(theta);
    let wi = Vec3::new(-t.sin(), 0.0, t.cos());
    let (ndf, facet) = args.surface().check()?;
    let walk = surface::walker(ndf, facet, args.walk, args.scattering.into())?;
    let result = estimate(walk.as_ref(), wi, args);
    print_stdout(&format_result(args, &result))
}

impl Args {
    /// The surface options, unchecked.
    fn surface(&self) -> surface::Options {
        surface::Options {
            family: self.ndf.family(),
            vmf: self.ndf == NdfKind::Vmf,
            porous: self.ndf == NdfKind::Porous,
            alpha: self.alpha,
            gamma: self.gamma,
            kappa: self.kappa,
            base: self.base,
            porosity: self.porosity,
            facet: self.facet,
            eta: self.eta,
            n: self.n,
            k: self.k,
            reflectance: self.reflectance,
            walk: self.walk,
        }
    }
}

/// Runs the walks, with a progress bar when both output streams are terminals.
fn estimate(walk: &dyn Estimators, wi: Vec3, args: &Args) -> AlbedoEstimate {
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
    let result = walk.albedo_with_progress(wi, args.samples, args.seed, &progress);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    result
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
