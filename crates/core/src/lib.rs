//! stfit-core: microfacet normal distributions, Smith masking, exact visible-normal sampling,
//! single-scattering BSDFs and multiple-scattering random walks.
//!
//! Conventions (see `theory.md` of the project): the local frame has the macro-surface normal
//! along +z; the outside medium (z > 0) has index 1 and the inside medium index `eta`.
//! Directions are unit vectors pointing away from the surface. NDFs are normalised by projected
//! area: `integral D(wm) wm.z dwm = 1`. This crate does no I/O.

pub mod bsdf;
pub mod error;
pub mod math;
pub mod ndf;
pub mod quadrature;
pub mod sphere;
pub mod validate;

pub use error::ParamError;
pub use math::Vec3;
