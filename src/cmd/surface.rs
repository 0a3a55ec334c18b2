//! The microsurface options shared by `stfit albedo` and `stfit eval`: the NDF (height-field or
//! full-sphere), the facet material and the random walk, checked together.

use super::CmdError;
use clap::ValueEnum;
use stfit_core::ParamError;
use stfit_core::Vec3;
use stfit_core::ndf::{Beckmann, Ggx, Ndf, StudentT};
use stfit_core::sphere::{Porous, SphereNdf, VonMisesFisher};
use stfit_core::walk::{
    AlbedoEstimate, ConductorFacet, DielectricFacet, Estimate, Facet, LambertianFacet,
    Microsurface, NullMicrosurface, ScatteringOrders,
};

/// The NDF family of `--ndf`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum NdfKind {
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

/// The surface options of `stfit albedo` and `stfit eval`: NDF, facet material and walk.
#[derive(Debug, Clone, clap::Args)]
pub struct SurfaceArgs {
    /// NDF family.
    #[arg(long, value_enum)]
    pub ndf: NdfKind,
    /// Roughness alpha (> 0) of a height-field NDF or of the base of --ndf porous.
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Student-T shape gamma (> 3/2); required with, and only allowed with, --ndf student-t
    /// (or --base student-t).
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
    /// perfect mirror without them) or lambertian (--reflectance). Only dielectric has a
    /// closed-form single-scattering BSDF.
    #[arg(long, value_enum, default_value_t)]
    pub facet: FacetKind,
    /// Relative index of refraction n_inside / n_outside (> 0, != 1) of dielectric facets.
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
    /// The random walk: heightfield (Heitz et al. 2016; height-field NDFs) or null (d'Eon 2023;
    /// any bounded NDF, same results on height fields, slower at low roughness; Student-T needs
    /// gamma >= 2).
    #[arg(long, value_enum, default_value_t)]
    pub walk: Walk,
}

impl SurfaceArgs {
    /// The surface options, unchecked.
    pub fn options(&self) -> Options {
        Options {
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

/// A height-field NDF family (the base of a porous NDF).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BaseKind {
    Beckmann,
    Ggx,
    #[value(name = "student-t")]
    StudentT,
}

/// The facet material of the walk.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum FacetKind {
    /// Smooth dielectric facets of index `--eta` (height-field NDFs only).
    #[default]
    Dielectric,
    /// Smooth conductor facets: Fresnel with `--n`/`--k`, else a perfect mirror.
    Conductor,
    /// Lambertian facets of albedo `--reflectance`.
    Lambertian,
}

/// The random walk.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum Walk {
    /// The height-field walk of Heitz et al. 2016 (height-field NDFs only).
    #[default]
    Heightfield,
    /// The null-scattering walk of d'Eon 2023 (any bounded NDF; Student-T needs gamma >= 2).
    Null,
}

/// A checked NDF.
#[derive(Debug, Clone, Copy)]
pub enum SurfaceNdf {
    Beckmann(Beckmann),
    Ggx(Ggx),
    StudentT(StudentT),
    Vmf(VonMisesFisher),
    Porous(PorousNdf),
}

/// A checked porous NDF with its base.
#[derive(Debug, Clone, Copy)]
pub enum PorousNdf {
    Beckmann(Porous<Beckmann>),
    Ggx(Porous<Ggx>),
    StudentT(Porous<StudentT>),
}

/// A checked facet material.
#[derive(Debug, Clone, Copy)]
pub enum SurfaceFacet {
    Dielectric(DielectricFacet),
    Conductor(ConductorFacet),
    Lambertian(LambertianFacet),
}

/// The raw options of the NDF and facet; [`Options::check`] validates them together.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// `beckmann`, `ggx`, `student-t` as a height-field family, `None` with `vmf`/`porous`.
    pub family: Option<BaseKind>,
    pub vmf: bool,
    pub porous: bool,
    pub alpha: Option<f64>,
    pub gamma: Option<f64>,
    pub kappa: Option<f64>,
    pub base: Option<BaseKind>,
    pub porosity: Option<f64>,
    pub facet: FacetKind,
    pub eta: Option<f64>,
    pub n: Option<f64>,
    pub k: Option<f64>,
    pub reflectance: Option<f64>,
    pub walk: Walk,
}

fn usage(m: impl Into<String>) -> CmdError {
    CmdError::Usage(m.into())
}

fn param(e: ParamError) -> CmdError {
    usage(e.to_string())
}

/// A parameter error prefixed by the option it came from.
fn option(name: &'static str) -> impl Fn(ParamError) -> CmdError {
    move |e| usage(format!("{name}: {e}"))
}

/// The height-field NDF of `family` with `alpha` and `gamma`.
fn height_field(
    family: BaseKind,
    alpha: Option<f64>,
    gamma: Option<f64>,
) -> Result<SurfaceNdf, CmdError> {
    let alpha = alpha.ok_or_else(|| usage("--alpha is required for this --ndf"))?;
    Ok(match (family, gamma) {
        (BaseKind::Beckmann, None) => SurfaceNdf::Beckmann(Beckmann::new(alpha).map_err(param)?),
        (BaseKind::Ggx, None) => SurfaceNdf::Ggx(Ggx::new(alpha).map_err(param)?),
        (BaseKind::StudentT, Some(g)) => {
            SurfaceNdf::StudentT(StudentT::new(alpha, g).map_err(param)?)
        }
        (BaseKind::StudentT, None) => return Err(usage("--gamma is required for student-t")),
        (_, Some(_)) => return Err(usage("--gamma applies only to student-t")),
    })
}

impl Options {
    /// The NDF and facet these options describe, or a usage error naming the bad option.
    pub fn check(&self) -> Result<(SurfaceNdf, SurfaceFacet), CmdError> {
        let ndf = if self.vmf {
            for (set, name) in [
                (self.alpha.is_some(), "--alpha"),
                (self.gamma.is_some(), "--gamma"),
                (self.base.is_some(), "--base"),
                (self.porosity.is_some(), "--porosity"),
            ] {
                if set {
                    return Err(usage(format!("{name} does not apply to --ndf vmf")));
                }
            }
            let kappa = self
                .kappa
                .ok_or_else(|| usage("--kappa is required for --ndf vmf"))?;
            SurfaceNdf::Vmf(VonMisesFisher::new(kappa).map_err(option("--kappa"))?)
        } else if self.porous {
            if self.kappa.is_some() {
                return Err(usage("--kappa applies only to --ndf vmf"));
            }
            let base = self
                .base
                .ok_or_else(|| usage("--base is required for --ndf porous"))?;
            let p = self
                .porosity
                .ok_or_else(|| usage("--porosity is required for --ndf porous"))?;
            SurfaceNdf::Porous(match height_field(base, self.alpha, self.gamma)? {
                SurfaceNdf::Beckmann(b) => {
                    PorousNdf::Beckmann(Porous::new(b, p).map_err(option("--porosity"))?)
                }
                SurfaceNdf::Ggx(b) => {
                    PorousNdf::Ggx(Porous::new(b, p).map_err(option("--porosity"))?)
                }
                SurfaceNdf::StudentT(b) => {
                    PorousNdf::StudentT(Porous::new(b, p).map_err(option("--porosity"))?)
                }
                SurfaceNdf::Vmf(_) | SurfaceNdf::Porous(_) => {
                    return Err(usage("--base must be a height-field NDF"));
                }
            })
        } else {
            for (set, name) in [
                (self.kappa.is_some(), "--kappa"),
                (self.base.is_some(), "--base"),
                (self.porosity.is_some(), "--porosity"),
            ] {
                if set {
                    return Err(usage(format!("{name} applies only to --ndf vmf or porous")));
                }
            }
            let family = self.family.ok_or_else(|| usage("--ndf is required"))?;
            height_field(family, self.alpha, self.gamma)?
        };
        let sphere = matches!(ndf, SurfaceNdf::Vmf(_) | SurfaceNdf::Porous(_));
        if sphere && self.walk != Walk::Null {
            return Err(usage(
                "--ndf vmf and --ndf porous need --walk null (they are not height fields)",
            ));
        }
        let facet = match self.facet {
            FacetKind::Dielectric => {
                if sphere {
                    return Err(usage(
                        "--facet dielectric needs a height-field NDF; use --facet conductor or \
                         lambertian with --ndf vmf or porous",
                    ));
                }
                self.only(FacetKind::Dielectric)?;
                let eta = self
                    .eta
                    .ok_or_else(|| usage("--eta is required for --facet dielectric"))?;
                stfit_core::error::check_eta(eta).map_err(|e| usage(format!("--eta: {e}")))?;
                SurfaceFacet::Dielectric(DielectricFacet::new(eta).map_err(param)?)
            }
            FacetKind::Conductor => {
                self.only(FacetKind::Conductor)?;
                SurfaceFacet::Conductor(match (self.n, self.k) {
                    (None, None) => ConductorFacet::mirror(),
                    (Some(n), Some(k)) => {
                        ConductorFacet::fresnel(n, k).map_err(option("--n/--k"))?
                    }
                    _ => return Err(usage("--n and --k go together")),
                })
            }
            FacetKind::Lambertian => {
                self.only(FacetKind::Lambertian)?;
                let r = self
                    .reflectance
                    .ok_or_else(|| usage("--reflectance is required for --facet lambertian"))?;
                SurfaceFacet::Lambertian(LambertianFacet::new(r).map_err(option("--reflectance"))?)
            }
        };
        Ok((ndf, facet))
    }

    /// An error if an option of another facet material is set.
    fn only(&self, facet: FacetKind) -> Result<(), CmdError> {
        for (set, name, owner) in [
            (self.eta.is_some(), "--eta", FacetKind::Dielectric),
            (self.n.is_some(), "--n", FacetKind::Conductor),
            (self.k.is_some(), "--k", FacetKind::Conductor),
            (
                self.reflectance.is_some(),
                "--reflectance",
                FacetKind::Lambertian,
            ),
        ] {
            if set && owner != facet {
                let owner = owner.to_possible_value().expect("no skipped variants");
                return Err(usage(format!(
                    "{name} applies only to --facet {}",
                    owner.get_name()
                )));
            }
        }
        Ok(())
    }
}

/// The batch estimators of a random walk, behind one object type for the command line.
pub trait Estimators: Sync {
    /// See [`Microsurface::eval_many`].
    fn eval_many(&self, wi: Vec3, wos: &[Vec3], walks: u64, seed: u64) -> Vec<Estimate>;
    /// See [`Microsurface::albedo_with_progress`].
    fn albedo_with_progress(
        &self,
        wi: Vec3,
        walks: u64,
        seed: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) -> AlbedoEstimate;
}

macro_rules! impl_estimators {
    ($ty:ident, $bound:path) => {
        impl<N: $bound, F: Facet> Estimators for $ty<N, F> {
            fn eval_many(&self, wi: Vec3, wos: &[Vec3], walks: u64, seed: u64) -> Vec<Estimate> {
                $ty::eval_many(self, wi, wos, walks, seed)
            }
            fn albedo_with_progress(
                &self,
                wi: Vec3,
                walks: u64,
                seed: u64,
                progress: &(dyn Fn(u64) + Sync),
            ) -> AlbedoEstimate {
                $ty::albedo_with_progress(self, wi, walks, seed, progress)
            }
        }
    };
}
impl_estimators!(Microsurface, Ndf);
impl_estimators!(NullMicrosurface, SphereNdf);

/// The walk over a checked NDF and facet.
pub fn walker(
    ndf: SurfaceNdf,
    facet: SurfaceFacet,
    walk: Walk,
    orders: ScatteringOrders,
) -> Result<Box<dyn Estimators>, CmdError> {
    match facet {
        SurfaceFacet::Dielectric(f) => with_facet(ndf, f, walk, orders),
        SurfaceFacet::Conductor(f) => with_facet(ndf, f, walk, orders),
        SurfaceFacet::Lambertian(f) => with_facet(ndf, f, walk, orders),
    }
}

fn with_facet<F: Facet + 'static>(
    ndf: SurfaceNdf,
    facet: F,
    walk: Walk,
    orders: ScatteringOrders,
) -> Result<Box<dyn Estimators>, CmdError> {
    fn hf<N: Ndf + SphereNdf + 'static, F: Facet + 'static>(
        ndf: N,
        facet: F,
        walk: Walk,
        orders: ScatteringOrders,
    ) -> Result<Box<dyn Estimators>, CmdError> {
        Ok(match walk {
            Walk::Heightfield => Box::new(Microsurface::new(ndf, facet).with_orders(orders)),
            Walk::Null => null(ndf, facet, orders)?,
        })
    }
    fn null<S: SphereNdf + 'static, F: Facet + 'static>(
        ndf: S,
        facet: F,
        orders: ScatteringOrders,
    ) -> Result<Box<dyn Estimators>, CmdError> {
        Ok(Box::new(
            NullMicrosurface::new(ndf, facet)
                .map_err(param)?
                .with_orders(orders),
        ))
    }
    match ndf {
        SurfaceNdf::Beckmann(n) => hf(n, facet, walk, orders),
        SurfaceNdf::Ggx(n) => hf(n, facet, walk, orders),
        SurfaceNdf::StudentT(n) => hf(n, facet, walk, orders),
        SurfaceNdf::Vmf(n) => null(n, facet, orders),
        SurfaceNdf::Porous(PorousNdf::Beckmann(n)) => null(n, facet, orders),
        SurfaceNdf::Porous(PorousNdf::Ggx(n)) => null(n, facet, orders),
        SurfaceNdf::Porous(PorousNdf::StudentT(n)) => null(n, facet, orders),
    }
}
