//! stfit-core: microfacet normal distributions, Smith masking, exact visible-normal sampling,
//! single-scattering BSDFs and multiple-scattering random walks.
//!
//! Conventions (see `theory.md` of the project): the local frame has the macro-surface normal
//! along +z; the outside medium (z > 0) has index 1 and the inside medium index `eta`.
//! Directions are unit vectors pointing away from the surface, `wi` toward the light. NDFs are
//! normalised by projected area: `integral D(wm) wm.z dwm = 1`. BSDF values follow Walter et
//! al. 2007 ([`bsdf`] states the convention exactly). This crate does no I/O.
//!
//! - [`ndf`]: the [`Ndf`](ndf::Ndf) trait and Beckmann, GGX, Student-T;
//! - [`bsdf`]: the [`Bsdf`](bsdf::Bsdf) trait, rough and smooth dielectrics and conductors;
//! - [`walk`]: the height-field and null-scattering random walks (themselves BSDFs), and the
//!   [`Estimator`](walk::Estimator) trait of their Monte Carlo estimates;
//! - [`sphere`]: NDFs on the whole sphere (von Mises-Fisher, porous blends);
//! - [`surface`]: a surface described at run time, for front ends.
//!
//! `rand` and `nalgebra` are re-exported, so that callers use the versions this crate uses.

pub mod bsdf;
pub mod error;
pub mod math;
pub mod ndf;
pub mod quadrature;
pub mod sphere;
pub mod surface;
pub mod walk;

pub use error::ParamError;
pub use math::Vec3;
pub use walk::ScatteringOrders;
pub use {nalgebra, rand};
