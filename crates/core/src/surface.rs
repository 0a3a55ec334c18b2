//! A microsurface described at run time: its NDF (a height field or a full-sphere NDF), the
//! material of its facets and the random walk that evaluates it, with the rules for which go
//! together. A front end (the command line, a Python binding) fills [`SurfaceOptions`] from
//! what its user gave, [`SurfaceOptions::check`] validates them together, and the checked
//! [`Surface`] yields its Monte Carlo estimators as one object, [`Surface::estimator`], or its
//! closed-form single-scattering BSDF where one exists, [`Surface::analytic`].
//!
//! ```
//! use stfit_core::surface::{FacetKind, NdfChoice, NdfFamily, SurfaceOptions, WalkKind};
//! use stfit_core::walk::ScatteringOrders;
//! use stfit_core::Vec3;
//!
//! let options = SurfaceOptions {
//!     alpha: Some(0.4),
//!     gamma: Some(3.0),
//!     eta: Some(1.5),
//!     ..SurfaceOptions::new(NdfChoice::HeightField(NdfFamily::StudentT))
//! };
//! let surface = options.check()?;
//! let walks = surface.estimator(ScatteringOrders::Multiple)?;
//! let albedo = walks.albedo(Vec3::new(0.0, 0.0, 1.0), 10_000, 1);
//! assert!(albedo.reflectance + albedo.transmittance < 0.2);
//! # Ok::<(), stfit_core::surface::SurfaceError>(())
//! ```

use std::fmt;

use crate::ParamError;
use crate::bsdf::{Masking, RoughDielectric};
use crate::ndf::{AnyNdf, Beckmann, Ggx, Ndf, StudentT};
use crate::sphere::{HeightField, Porous, SphereNdf, VonMisesFisher};
use crate::walk::{
    ConductorFacet, DielectricFacet, Estimator, Facet, LambertianFacet, Microsurface,
    NullMicrosurface, ScatteringOrders,
};

/// A height-field NDF family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NdfFamily {
    Beckmann,
    Ggx,
    StudentT,
}

impl NdfFamily {
    /// `beckmann`, `ggx` or `student-t`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Beckmann => "beckmann",
            Self::Ggx => "ggx",
            Self::StudentT => "student-t",
        }
    }

    /// The NDF of this family with roughness `alpha` and, for Student-T only, shape `gamma`.
    pub fn ndf(self, alpha: f64, gamma: Option<f64>) -> Result<AnyNdf, SurfaceError> {
        let param = |p: &'static str| {
            move |e: ParamError| SurfaceError::Param {
                param: p,
                source: e,
            }
        };
        Ok(match (self, gamma) {
            (Self::Beckmann, None) => Beckmann::new(alpha).map_err(param("alpha"))?.into(),
            (Self::Ggx, None) => Ggx::new(alpha).map_err(param("alpha"))?.into(),
            (Self::StudentT, Some(g)) => StudentT::new(alpha, g)
                .map_err(|e| match e {
                    ParamError::Gamma(_) => SurfaceError::Param {
                        param: "gamma",
                        source: e,
                    },
                    ParamError::NonFinite { name, .. } => SurfaceError::Param {
                        param: name,
                        source: e,
                    },
                    _ => SurfaceError::Param {
                        param: "alpha",
                        source: e,
                    },
                })?
                .into(),
            (Self::StudentT, None) => {
                return Err(SurfaceError::Missing {
                    param: "gamma",
                    context: "student-t",
                });
            }
            (_, Some(_)) => {
                return Err(SurfaceError::NotApplicable {
                    param: "gamma",
                    context: "student-t",
                });
            }
        })
    }
}

/// The NDF of a surface: a height-field family, a von Mises-Fisher lobe on the sphere, or a
/// porous blend of a height field with uniformly oriented facets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NdfChoice {
    /// Beckmann, GGX or Student-T (`alpha`, and `gamma` for Student-T).
    HeightField(NdfFamily),
    /// von Mises-Fisher on the whole sphere (`kappa`); needs the null walk.
    Vmf,
    /// A height field (`base`, `alpha`, `gamma`) blended with uniformly oriented facets
    /// (`porosity`); needs the null walk.
    Porous,
}

/// The material of the facets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum FacetKind {
    /// Smooth dielectric facets of relative index `eta` (height-field NDFs only).
    #[default]
    Dielectric,
    /// Smooth conductor facets: Fresnel with `n` and `k`, else a perfect mirror.
    Conductor,
    /// Lambertian facets of albedo `reflectance`.
    Lambertian,
}

impl FacetKind {
    /// `dielectric`, `conductor` or `lambertian`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Dielectric => "dielectric",
            Self::Conductor => "conductor",
            Self::Lambertian => "lambertian",
        }
    }
}

/// The random walk.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum WalkKind {
    /// The height-field walk of Heitz et al. 2016 (height-field NDFs only).
    #[default]
    HeightField,
    /// The null-scattering walk of d'Eon 2023 (any bounded NDF; Student-T needs gamma >= 2).
    Null,
}

/// A surface's options as a front end gathers them, every parameter optional: which apply
/// depends on the NDF and the facet, and [`SurfaceOptions::check`] says what is missing or
/// does not apply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceOptions {
    pub ndf: NdfChoice,
    /// Roughness (> 0) of a height-field NDF or of the base of a porous one.
    pub alpha: Option<f64>,
    /// Student-T shape (> 3/2).
    pub gamma: Option<f64>,
    /// vMF concentration.
    pub kappa: Option<f64>,
    /// Height-field base of a porous NDF.
    pub base: Option<NdfFamily>,
    /// Uniformly oriented fraction of a porous NDF's facet area, in [0, 1].
    pub porosity: Option<f64>,
    pub facet: FacetKind,
    /// Relative index of refraction `n_inside / n_outside` of dielectric facets.
    pub eta: Option<f64>,
    /// Complex index `n + i k` of conductor facets (both or neither).
    pub n: Option<f64>,
    pub k: Option<f64>,
    /// Albedo of Lambertian facets, in [0, 1].
    pub reflectance: Option<f64>,
    pub walk: WalkKind,
}

impl SurfaceOptions {
    /// Options for `ndf` with dielectric facets, the height-field walk and nothing else set.
    pub fn new(ndf: NdfChoice) -> Self {
        Self {
            ndf,
            alpha: None,
            gamma: None,
            kappa: None,
            base: None,
            porosity: None,
            facet: FacetKind::Dielectric,
            eta: None,
            n: None,
            k: None,
            reflectance: None,
            walk: WalkKind::HeightField,
        }
    }

    /// The surface these options describe, or the first problem, naming the parameter.
    pub fn check(&self) -> Result<Surface, SurfaceError> {
        let ndf = self.check_ndf()?;
        let sphere = matches!(ndf, SurfaceNdf::Vmf(_) | SurfaceNdf::Porous(_));
        if sphere && self.walk != WalkKind::Null {
            return Err(SurfaceError::Incompatible {
                param: "walk",
                message: "vmf and porous NDFs are not height fields: they need {param} null",
            });
        }
        let facet = match self.facet {
            FacetKind::Dielectric => {
                if sphere {
                    return Err(SurfaceError::Incompatible {
                        param: "facet",
                        message: "dielectric facets need a height-field NDF; use {param} \
                                  conductor or lambertian with vmf or porous NDFs",
                    });
                }
                self.only(FacetKind::Dielectric)?;
                let eta = self.eta.ok_or(SurfaceError::Missing {
                    param: "eta",
                    context: "dielectric facets",
                })?;
                SurfaceFacet::Dielectric(DielectricFacet::new(eta).map_err(param("eta"))?)
            }
            FacetKind::Conductor => {
                self.only(FacetKind::Conductor)?;
                SurfaceFacet::Conductor(match (self.n, self.k) {
                    (None, None) => ConductorFacet::mirror(),
                    (Some(n), Some(k)) => ConductorFacet::fresnel(n, k).map_err(|e| {
                        let p = if matches!(
                            &e,
                            ParamError::OutOfRange { name: "k", .. }
                                | ParamError::NonFinite { name: "k", .. }
                        ) {
                            "k"
                        } else {
                            "n"
                        };
                        SurfaceError::Param {
                            param: p,
                            source: e,
                        }
                    })?,
                    (Some(_), None) => {
                        return Err(SurfaceError::Missing {
                            param: "k",
                            context: "a conductor with n (n and k go together)",
                        });
                    }
                    (None, Some(_)) => {
                        return Err(SurfaceError::Missing {
                            param: "n",
                            context: "a conductor with k (n and k go together)",
                        });
                    }
                })
            }
            FacetKind::Lambertian => {
                self.only(FacetKind::Lambertian)?;
                let r = self.reflectance.ok_or(SurfaceError::Missing {
                    param: "reflectance",
                    context: "lambertian facets",
                })?;
                SurfaceFacet::Lambertian(LambertianFacet::new(r).map_err(param("reflectance"))?)
            }
        };
        Ok(Surface {
            ndf,
            facet,
            walk: self.walk,
        })
    }

    fn check_ndf(&self) -> Result<SurfaceNdf, SurfaceError> {
        let unused = |set: bool, param: &'static str, context: &'static str| {
            if set {
                Err(SurfaceError::NotApplicable { param, context })
            } else {
                Ok(())
            }
        };
        match self.ndf {
            NdfChoice::Vmf => {
                const VMF: &str = "porous or height-field NDFs, not vmf";
                unused(self.alpha.is_some(), "alpha", VMF)?;
                unused(self.gamma.is_some(), "gamma", VMF)?;
                unused(self.base.is_some(), "base", "porous NDFs")?;
                unused(self.porosity.is_some(), "porosity", "porous NDFs")?;
                let kappa = self.kappa.ok_or(SurfaceError::Missing {
                    param: "kappa",
                    context: "vmf",
                })?;
                Ok(SurfaceNdf::Vmf(
                    VonMisesFisher::new(kappa).map_err(param("kappa"))?,
                ))
            }
            NdfChoice::Porous => {
                unused(self.kappa.is_some(), "kappa", "vmf")?;
                let base = self.base.ok_or(SurfaceError::Missing {
                    param: "base",
                    context: "porous",
                })?;
                let p = self.porosity.ok_or(SurfaceError::Missing {
                    param: "porosity",
                    context: "porous",
                })?;
                let alpha = self.alpha.ok_or(SurfaceError::Missing {
                    param: "alpha",
                    context: "porous",
                })?;
                let porous = |e| SurfaceError::Param {
                    param: "porosity",
                    source: e,
                };
                Ok(SurfaceNdf::Porous(match base.ndf(alpha, self.gamma)? {
                    AnyNdf::Beckmann(b) => {
                        PorousNdf::Beckmann(Porous::new(HeightField(b), p).map_err(porous)?)
                    }
                    AnyNdf::Ggx(b) => {
                        PorousNdf::Ggx(Porous::new(HeightField(b), p).map_err(porous)?)
                    }
                    AnyNdf::StudentT(b) => {
                        PorousNdf::StudentT(Porous::new(HeightField(b), p).map_err(porous)?)
                    }
                }))
            }
            NdfChoice::HeightField(family) => {
                unused(self.kappa.is_some(), "kappa", "vmf")?;
                unused(self.base.is_some(), "base", "porous NDFs")?;
                unused(self.porosity.is_some(), "porosity", "porous NDFs")?;
                let alpha = self.alpha.ok_or(SurfaceError::Missing {
                    param: "alpha",
                    context: family.name(),
                })?;
                Ok(SurfaceNdf::HeightField(family.ndf(alpha, self.gamma)?))
            }
        }
    }

    /// An error if a parameter of another facet material is set.
    fn only(&self, facet: FacetKind) -> Result<(), SurfaceError> {
        for (set, param, owner) in [
            (self.eta.is_some(), "eta", FacetKind::Dielectric),
            (self.n.is_some(), "n", FacetKind::Conductor),
            (self.k.is_some(), "k", FacetKind::Conductor),
            (
                self.reflectance.is_some(),
                "reflectance",
                FacetKind::Lambertian,
            ),
        ] {
            if set && owner != facet {
                return Err(SurfaceError::NotApplicable {
                    param,
                    context: match owner {
                        FacetKind::Dielectric => "dielectric facets",
                        FacetKind::Conductor => "conductor facets",
                        FacetKind::Lambertian => "lambertian facets",
                    },
                });
            }
        }
        Ok(())
    }
}

fn param(p: &'static str) -> impl Fn(ParamError) -> SurfaceError {
    move |e| SurfaceError::Param {
        param: p,
        source: e,
    }
}

/// How a surface's BSDF is evaluated (see [`Surface::evaluation`]).
// The analytic variant holds a Student-T NDF inline (see `AnyNdf`).
#[allow(clippy::large_enum_variant)]
pub enum Evaluation {
    /// The closed-form single-scattering BSDF.
    Analytic(RoughDielectric<AnyNdf>),
    /// Monte Carlo estimates of the random walk, with standard errors.
    Walk(Box<dyn Estimator>),
}

/// Why surface options do not describe a surface.
#[derive(Debug, Clone, PartialEq)]
pub enum SurfaceError {
    /// A parameter the surface needs is not given.
    Missing {
        param: &'static str,
        context: &'static str,
    },
    /// A parameter is given that this surface does not have.
    NotApplicable {
        param: &'static str,
        context: &'static str,
    },
    /// A parameter is out of its range.
    Param {
        param: &'static str,
        source: ParamError,
    },
    /// A combination of NDF, facet and walk that does not exist; `message` names the
    /// parameter that would fix it as `{param}`.
    Incompatible {
        param: &'static str,
        message: &'static str,
    },
    /// A masking the random walk cannot have.
    Masking(crate::walk::MaskingError),
}

impl SurfaceError {
    /// The parameter the error is about, if one.
    pub fn param(&self) -> Option<&'static str> {
        match self {
            Self::Missing { param, .. }
            | Self::NotApplicable { param, .. }
            | Self::Param { param, .. }
            | Self::Incompatible { param, .. } => Some(param),
            Self::Masking(_) => Some("masking"),
        }
    }

    /// The message with each parameter named by `name(param)` (a command line writes `--alpha`,
    /// a Python binding `alpha=`).
    pub fn message(&self, name: impl Fn(&str) -> String) -> String {
        match self {
            Self::Missing { param, context } => {
                format!("{} is required for {context}", name(param))
            }
            Self::NotApplicable { param, context } => {
                format!("{} applies only to {context}", name(param))
            }
            Self::Param { param, source } => format!("{}: {source}", name(param)),
            Self::Incompatible { param, message } => message.replace("{param}", &name(param)),
            Self::Masking(e) => format!("{}: {e}", name("masking")),
        }
    }
}

impl fmt::Display for SurfaceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message(|p| format!("`{p}`")))
    }
}

impl std::error::Error for SurfaceError {}

/// A checked NDF.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SurfaceNdf {
    HeightField(AnyNdf),
    Vmf(VonMisesFisher),
    Porous(PorousNdf),
}

/// A checked porous NDF with its base.
// The Student-T variant holds its NDF inline (see `AnyNdf`).
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PorousNdf {
    Beckmann(Porous<HeightField<Beckmann>>),
    Ggx(Porous<HeightField<Ggx>>),
    StudentT(Porous<HeightField<StudentT>>),
}

/// A checked facet material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SurfaceFacet {
    Dielectric(DielectricFacet),
    Conductor(ConductorFacet),
    Lambertian(LambertianFacet),
}

/// A surface whose NDF, facets and walk go together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    pub ndf: SurfaceNdf,
    pub facet: SurfaceFacet,
    pub walk: WalkKind,
}

impl Surface {
    /// The surface's random walk restricted to `orders`, as one estimator object. Fails for a
    /// Student-T shape below [`GAMMA_WALK_MIN`](crate::error::GAMMA_WALK_MIN) (walks whose
    /// length diverges at 3/2) and for a null walk on an NDF without a finite majorant
    /// (Student-T with gamma < 2).
    pub fn estimator(&self, orders: ScatteringOrders) -> Result<Box<dyn Estimator>, SurfaceError> {
        if let Some(g) = self.student_t_gamma() {
            crate::error::check_walk_gamma(g).map_err(param("gamma"))?;
        }
        if let Some(p) = self.porosity().filter(|&p| p > 0.99) {
            return Err(SurfaceError::Param {
                param: "porosity",
                source: ParamError::OutOfRange {
                    name: "porosity",
                    value: p,
                    expected: "random walks need porosity in [0, 0.99]: at 1 they never end",
                },
            });
        }
        match self.facet {
            SurfaceFacet::Dielectric(f) => with_facet(self.ndf, f, self.walk, orders),
            SurfaceFacet::Conductor(f) => with_facet(self.ndf, f, self.walk, orders),
            SurfaceFacet::Lambertian(f) => with_facet(self.ndf, f, self.walk, orders),
        }
    }

    /// The porosity of a porous NDF.
    fn porosity(&self) -> Option<f64> {
        match self.ndf {
            SurfaceNdf::Porous(PorousNdf::Beckmann(p)) => Some(p.porosity()),
            SurfaceNdf::Porous(PorousNdf::Ggx(p)) => Some(p.porosity()),
            SurfaceNdf::Porous(PorousNdf::StudentT(p)) => Some(p.porosity()),
            _ => None,
        }
    }

    /// The Student-T shape of the surface's NDF or of its porous base, if it has one.
    fn student_t_gamma(&self) -> Option<f64> {
        match self.ndf {
            SurfaceNdf::HeightField(AnyNdf::StudentT(n)) => Some(n.gamma()),
            SurfaceNdf::Porous(PorousNdf::StudentT(p)) => Some(p.base().0.gamma()),
            _ => None,
        }
    }

    /// How this surface's BSDF is evaluated for `orders`: in closed form (Walter et al. 2007)
    /// for single scattering of a height-field NDF with dielectric facets on the height-field
    /// walk, with `masking` (separable unless given); otherwise by the random walk, whose
    /// masking is height-correlated by construction (`masking`, if given, must be
    /// correlated).
    pub fn evaluation(
        &self,
        orders: ScatteringOrders,
        masking: Option<Masking>,
    ) -> Result<Evaluation, SurfaceError> {
        if orders == ScatteringOrders::Single && self.walk == WalkKind::HeightField {
            let masking = orders.masking(masking).map_err(SurfaceError::Masking)?;
            if let Some(bsdf) = self.analytic(masking) {
                return Ok(Evaluation::Analytic(bsdf));
            }
        }
        ScatteringOrders::All
            .masking(masking)
            .map_err(|_| SurfaceError::Masking(crate::walk::MaskingError { orders }))?;
        Ok(Evaluation::Walk(self.estimator(orders)?))
    }

    /// The closed-form single-scattering BSDF (Walter et al. 2007) of a height-field NDF with
    /// dielectric facets, with the given masking; `None` for other surfaces, which only the
    /// walks evaluate.
    pub fn analytic(&self, masking: Masking) -> Option<RoughDielectric<AnyNdf>> {
        match (self.ndf, self.facet) {
            (SurfaceNdf::HeightField(ndf), SurfaceFacet::Dielectric(f)) => {
                RoughDielectric::new(ndf, f.eta(), masking).ok()
            }
            _ => None,
        }
    }
}

fn with_facet<F: Facet + 'static>(
    ndf: SurfaceNdf,
    facet: F,
    walk: WalkKind,
    orders: ScatteringOrders,
) -> Result<Box<dyn Estimator>, SurfaceError> {
    fn height_field<N: Ndf + 'static, F: Facet + 'static>(
        ndf: N,
        facet: F,
        walk: WalkKind,
        orders: ScatteringOrders,
    ) -> Result<Box<dyn Estimator>, SurfaceError>
    where
        HeightField<N>: SphereNdf,
    {
        Ok(match walk {
            WalkKind::HeightField => Box::new(Microsurface::new(ndf, facet).with_orders(orders)),
            WalkKind::Null => null(HeightField(ndf), facet, orders)?,
        })
    }
    fn null<S: SphereNdf + 'static, F: Facet + 'static>(
        ndf: S,
        facet: F,
        orders: ScatteringOrders,
    ) -> Result<Box<dyn Estimator>, SurfaceError> {
        // The majorant is infinite for a Student-T gamma below 2, too large for a small alpha
        // (vmf's kappa range keeps its peak below the limit).
        let walk = NullMicrosurface::new(ndf, facet).map_err(|e| {
            let param = match e {
                ParamError::OutOfRange { value, .. } if value.is_finite() => "alpha",
                _ => "gamma",
            };
            SurfaceError::Param { param, source: e }
        })?;
        Ok(Box::new(walk.with_orders(orders)))
    }
    match ndf {
        SurfaceNdf::HeightField(AnyNdf::Beckmann(n)) => height_field(n, facet, walk, orders),
        SurfaceNdf::HeightField(AnyNdf::Ggx(n)) => height_field(n, facet, walk, orders),
        SurfaceNdf::HeightField(AnyNdf::StudentT(n)) => height_field(n, facet, walk, orders),
        SurfaceNdf::Vmf(n) => null(n, facet, orders),
        SurfaceNdf::Porous(PorousNdf::Beckmann(n)) => null(n, facet, orders),
        SurfaceNdf::Porous(PorousNdf::Ggx(n)) => null(n, facet, orders),
        SurfaceNdf::Porous(PorousNdf::StudentT(n)) => null(n, facet, orders),
    }
}
