//! Run-time choice among the height-field NDFs, for command lines and fitting.

use super::{Beckmann, Ggx, Ndf, StudentT};
use crate::math::Vec3;
use rand::Rng;

/// One of the height-field NDFs, chosen at run time. Hot loops should prefer the concrete
/// types; this enum dispatches with a match.
// StudentT carries the coefficient tables of its Lambda's continued fractions (768 bytes):
// built once per NDF and read in the hot loops, so kept inline rather than boxed.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyNdf {
    Beckmann(Beckmann),
    Ggx(Ggx),
    StudentT(StudentT),
}

impl AnyNdf {
    /// The roughness alpha.
    pub fn alpha(&self) -> f64 {
        match self {
            Self::Beckmann(n) => n.alpha(),
            Self::Ggx(n) => n.alpha(),
            Self::StudentT(n) => n.alpha(),
        }
    }

    /// The Student-T shape gamma, `None` for Beckmann and GGX.
    pub fn gamma(&self) -> Option<f64> {
        match self {
            Self::StudentT(n) => Some(n.gamma()),
            _ => None,
        }
    }
}

macro_rules! dispatch {
    ($self:ident, $n:ident => $e:expr) => {
        match $self {
            AnyNdf::Beckmann($n) => $e,
            AnyNdf::Ggx($n) => $e,
            AnyNdf::StudentT($n) => $e,
        }
    };
}

impl Ndf for AnyNdf {
    fn d(&self, wm: Vec3) -> f64 {
        dispatch!(self, n => n.d(wm))
    }
    fn lambda(&self, w: Vec3) -> f64 {
        dispatch!(self, n => n.lambda(w))
    }
    fn sigma(&self, w: Vec3) -> f64 {
        dispatch!(self, n => n.sigma(w))
    }
    fn sample_visible<R: Rng + ?Sized>(&self, w: Vec3, rng: &mut R) -> Vec3 {
        dispatch!(self, n => n.sample_visible(w, rng))
    }
}

impl From<Beckmann> for AnyNdf {
    fn from(n: Beckmann) -> Self {
        Self::Beckmann(n)
    }
}
impl From<Ggx> for AnyNdf {
    fn from(n: Ggx) -> Self {
        Self::Ggx(n)
    }
}
impl From<StudentT> for AnyNdf {
    fn from(n: StudentT) -> Self {
        Self::StudentT(n)
    }
}
