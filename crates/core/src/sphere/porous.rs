//! A porous surface: a height-field NDF blended with the uniform sphere.

use super::{SphereNdf, total_area};
use crate::error::{ParamError, finite};
use std::f64::consts::PI;

/// A blend of a height-field NDF with uniformly oriented facets (grains or pores):
/// `D(u) = (1 - P) D_hf(u) + P A / (4 pi)` with `A = integral D_hf dwm` the height field's total
/// facet area, so the porosity `P` in [0, 1] is the fraction of all facet area that is
/// uniformly oriented. `P = 0` is the height field itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Porous<N> {
    base: N,
    porosity: f64,
    /// `P A / (4 pi)`, the uniform part of D.
    uniform: f64,
}

impl<N: SphereNdf> Porous<N> {
    /// Blends `base` with the uniform sphere at porosity `P` in [0, 1] (a random walk needs
    /// `P <= 0.99`: at 1 no facet area faces up on average and walks never end).
    pub fn new(base: N, porosity: f64) -> Result<Self, ParamError> {
        let porosity = finite("porosity", porosity)?;
        if !(0.0..=1.0).contains(&porosity) {
            return Err(ParamError::OutOfRange {
                name: "porosity",
                value: porosity,
                expected: "porosity must be in [0, 1]",
            });
        }
        let area = total_area(|u| base.d_cos(u), base.angular_width());
        Ok(Self {
            base,
            porosity,
            uniform: porosity * area / (4.0 * PI),
        })
    }

    /// The height-field part.
    pub fn base(&self) -> &N {
        &self.base
    }

    /// The porosity P.
    pub fn porosity(&self) -> f64 {
        self.porosity
    }
}

impl<N: SphereNdf> SphereNdf for Porous<N> {
    fn d_cos(&self, u: f64) -> f64 {
        (1.0 - self.porosity) * self.base.d_cos(u) + self.uniform
    }

    fn majorant(&self) -> f64 {
        (1.0 - self.porosity) * self.base.majorant() + self.uniform
    }

    fn angular_width(&self) -> f64 {
        self.base.angular_width()
    }
}
