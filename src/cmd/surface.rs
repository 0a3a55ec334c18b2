//! The surface options shared by `stfit albedo` and `stfit eval`, parsed into the library's
//! [`SurfaceOptions`], which checks them together.

use clap::ValueEnum;
use stfit_core::surface::{FacetKind, NdfChoice, NdfFamily, Surface, SurfaceOptions, WalkKind};

use super::{CmdError, usage};

/// `--ndf`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NdfArg {
    /// Beckmann height field (--alpha).
    Beckmann,
    /// GGX height field (--alpha).
    Ggx,
    /// Student-T height field (--alpha, --gamma).
    #[value(name = "student-t")]
    StudentT,
    /// von Mises-Fisher on the whole sphere (--kappa; needs --walk null and --facet conductor
    /// or lambertian).
    Vmf,
    /// A height field (--base, --alpha, [--gamma]) blended with uniformly oriented facets
    /// (--porosity); needs --walk null and --facet conductor or lambertian.
    Porous,
}

/// `--base`: a height-field NDF family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BaseArg {
    Beckmann,
    Ggx,
    #[value(name = "student-t")]
    StudentT,
}

impl From<BaseArg> for NdfFamily {
    fn from(b: BaseArg) -> Self {
        match b {
            BaseArg::Beckmann => Self::Beckmann,
            BaseArg::Ggx => Self::Ggx,
            BaseArg::StudentT => Self::StudentT,
        }
    }
}

/// `--facet`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum FacetArg {
    /// Smooth dielectric facets of index --eta (height-field NDFs only).
    #[default]
    Dielectric,
    /// Smooth conductor facets: Fresnel with --n/--k, else a perfect mirror.
    Conductor,
    /// Lambertian facets of albedo --reflectance.
    Lambertian,
}

/// `--walk`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum WalkArg {
    /// The height-field walk of Heitz et al. 2016 (height-field NDFs only).
    #[default]
    Heightfield,
    /// The null-scattering walk of d'Eon 2023 (any bounded NDF; same results on height
    /// fields, slower at low roughness; Student-T needs gamma >= 2).
    Null,
}

/// The surface options of `stfit albedo` and `stfit eval`: NDF, facet material and walk.
#[derive(Debug, Clone, clap::Args)]
pub struct SurfaceArgs {
    /// NDF family.
    #[arg(long, value_enum)]
    pub ndf: NdfArg,
    /// Roughness alpha, in [1e-8, 100], of a height-field NDF or of the base of --ndf porous.
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Student-T shape gamma, in (3/2, 1e15], at least 1.501 where it walks; required with,
    /// and only allowed with, --ndf student-t (or --base student-t).
    #[arg(long, allow_negative_numbers = true)]
    pub gamma: Option<f64>,
    /// Concentration kappa, in [0.1, 1e4], of --ndf vmf.
    #[arg(long, allow_negative_numbers = true)]
    pub kappa: Option<f64>,
    /// Height-field base of --ndf porous.
    #[arg(long, value_enum)]
    pub base: Option<BaseArg>,
    /// Fraction of the facet area of --ndf porous that is uniformly oriented, in [0, 0.99]
    /// (--ndf porous always walks, and at 1 the walks never end).
    #[arg(long, allow_negative_numbers = true)]
    pub porosity: Option<f64>,
    /// Facet material: dielectric (height-field NDFs; --eta), conductor (--n and --k, or a
    /// perfect mirror without them) or lambertian (--reflectance). Only dielectric has a
    /// closed-form single-scattering BSDF.
    #[arg(long, value_enum, default_value_t)]
    pub facet: FacetArg,
    /// Relative index of refraction n_inside / n_outside of dielectric facets, in [0.01, 100]
    /// with |eta - 1| >= 0.005.
    #[arg(long, allow_negative_numbers = true)]
    pub eta: Option<f64>,
    /// Real part of the conductor's relative index, in [1e-3, 1e3] (with --k).
    #[arg(long, allow_negative_numbers = true)]
    pub n: Option<f64>,
    /// Imaginary part of the conductor's relative index, in [0, 1e3] (with --n).
    #[arg(long, allow_negative_numbers = true)]
    pub k: Option<f64>,
    /// Albedo of Lambertian facets, in [0, 1].
    #[arg(long, allow_negative_numbers = true)]
    pub reflectance: Option<f64>,
    /// The random walk.
    #[arg(long, value_enum, default_value_t)]
    pub walk: WalkArg,
}

impl SurfaceArgs {
    /// The checked surface, or a usage error naming the option at fault.
    pub fn surface(&self) -> Result<Surface, CmdError> {
        let options = SurfaceOptions {
            ndf: match self.ndf {
                NdfArg::Beckmann => NdfChoice::HeightField(NdfFamily::Beckmann),
                NdfArg::Ggx => NdfChoice::HeightField(NdfFamily::Ggx),
                NdfArg::StudentT => NdfChoice::HeightField(NdfFamily::StudentT),
                NdfArg::Vmf => NdfChoice::Vmf,
                NdfArg::Porous => NdfChoice::Porous,
            },
            alpha: self.alpha,
            gamma: self.gamma,
            kappa: self.kappa,
            base: self.base.map(NdfFamily::from),
            porosity: self.porosity,
            facet: match self.facet {
                FacetArg::Dielectric => FacetKind::Dielectric,
                FacetArg::Conductor => FacetKind::Conductor,
                FacetArg::Lambertian => FacetKind::Lambertian,
            },
            eta: self.eta,
            n: self.n,
            k: self.k,
            reflectance: self.reflectance,
            walk: match self.walk {
                WalkArg::Heightfield => WalkKind::HeightField,
                WalkArg::Null => WalkKind::Null,
            },
        };
        options.check().map_err(|e| usage(flags(&e)))
    }
}

/// A surface error with its parameters named as command-line flags (`--alpha`).
pub fn flags(e: &stfit_core::surface::SurfaceError) -> String {
    e.message(|p| format!("--{p}"))
}
