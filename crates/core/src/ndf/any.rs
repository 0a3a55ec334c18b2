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

macro_rules! dispatch {
    ($self:ident, $n:ident => $e:expr) => {
        match $self {
            AnyNdf::Beckmann($n) => $e,
            AnyNdf::Ggx($n) => $e,
            AnyNdf::StudentT($n) => $e,
        }
    };
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

    /// Runs `f` with the concrete NDF: one match, then code compiled for that NDF, whose
    /// functions inline into `f`'s loops (where `AnyNdf`'s own [`Ndf`] methods match on
    /// every call).
    ///
    /// ```
    /// use stfit_core::Vec3;
    /// use stfit_core::ndf::{AnyNdf, Ndf, StudentT, WithNdf};
    ///
    /// /// The sum of Lambda over some directions, in a loop compiled for each NDF.
    /// struct SumLambda<'a>(&'a [Vec3]);
    /// impl WithNdf for SumLambda<'_> {
    ///     type Output = f64;
    ///     fn run<N: Ndf>(self, ndf: N) -> f64 {
    ///         self.0.iter().map(|&w| ndf.lambda(w)).sum()
    ///     }
    /// }
    ///
    /// let ndf = AnyNdf::from(StudentT::new(0.3, 2.5)?);
    /// let dirs = [Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.0, 0.8, 0.6)];
    /// let sum = ndf.with(SumLambda(&dirs));
    /// assert_eq!(sum, ndf.lambda(dirs[0]) + ndf.lambda(dirs[1]));
    /// # Ok::<(), stfit_core::ParamError>(())
    /// ```
    pub fn with<F: WithNdf>(self, f: F) -> F::Output {
        dispatch!(self, n => f.run(n))
    }
}

/// A computation generic over the NDF, run on the concrete type of an [`AnyNdf`] by
/// [`AnyNdf::with`] (a closure cannot be generic, so the computation is a type).
pub trait WithNdf {
    type Output;
    /// The computation with the NDF `ndf`.
    fn run<N: Ndf>(self, ndf: N) -> Self::Output;
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

    fn sample_visible_after<R: Rng + ?Sized>(
        &self,
        w: Vec3,
        lambda_back: f64,
        rng: &mut R,
    ) -> Vec3 {
        dispatch!(self, n => n.sample_visible_after(w, lambda_back, rng))
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
