//! Height-field NDFs seen as bounded NDFs on the whole sphere (zero below the horizon).
//!
//! Each bound is the exact supremum of `D` over `x = tan^2 theta_m >= 0`, with a relative
//! margin of 1e-12 against rounding.

use super::SphereNdf;
use crate::math::Vec3;
use crate::ndf::{Beckmann, Ggx, Ndf, StudentT};

/// A height-field NDF ([`Ndf`]) seen as an NDF on the whole sphere ([`SphereNdf`]): `D` above
/// the horizon, zero below, with the exact projected area of the height field ([`Ndf::sigma`],
/// which the quadrature of [`SphereNdf`] reproduces). It is how the null-scattering walk and
/// [`Porous`](super::Porous) take Beckmann, GGX and Student-T.
///
/// ```
/// use stfit_core::ndf::Ggx;
/// use stfit_core::sphere::{HeightField, SphereNdf};
///
/// let hf = HeightField(Ggx::new(0.5)?);
/// assert!(hf.is_height_field());
/// assert_eq!(hf.d_cos(-0.1), 0.0);
/// assert!(hf.majorant() >= hf.d_cos(1.0));
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeightField<N>(pub N);

const MARGIN: f64 = 1.0 + 1e-12;

/// `D` at `tan^2 theta_m = x` through the height-field NDF's own evaluation.
fn d_at_tan2(ndf: &impl Ndf, x: f64) -> f64 {
    let u = 1.0 / (1.0 + x).sqrt();
    ndf.d(Vec3::new((1.0 - u * u).max(0.0).sqrt(), 0.0, u))
}

/// `D(u)` on the sphere: the height-field NDF above the horizon, zero below.
fn d_cos_height_field(ndf: &impl Ndf, u: f64) -> f64 {
    if u <= 0.0 {
        return 0.0;
    }
    ndf.d(Vec3::new((1.0 - u * u).max(0.0).sqrt(), 0.0, u))
}

impl SphereNdf for HeightField<Beckmann> {
    fn d_cos(&self, u: f64) -> f64 {
        d_cos_height_field(&self.0, u)
    }

    /// `D` is proportional to `exp(-x/alpha^2) (1+x)^2`, largest at `x = max(0, 2 alpha^2 - 1)`.
    fn majorant(&self) -> f64 {
        let a2 = self.0.alpha() * self.0.alpha();
        MARGIN * d_at_tan2(&self.0, (2.0 * a2 - 1.0).max(0.0))
    }

    fn is_height_field(&self) -> bool {
        true
    }

    /// The height field's closed form.
    fn sigma(&self, w: Vec3) -> f64 {
        self.0.sigma(w)
    }

    fn angular_width(&self) -> f64 {
        self.0.alpha().atan()
    }
}

impl SphereNdf for HeightField<Ggx> {
    /// `alpha^2 / (pi (alpha^2 u^2 + 1 - u^2)^2)` above the horizon: no square root, as the
    /// null-scattering walk evaluates it at every tentative collision.
    #[inline]
    fn d_cos(&self, u: f64) -> f64 {
        if u <= 0.0 {
            return 0.0;
        }
        let a2 = self.0.alpha() * self.0.alpha();
        let k = 1.0 + (a2 - 1.0) * u * u;
        a2 / (std::f64::consts::PI * k * k)
    }

    /// `D` is proportional to `((1+x)/(alpha^2+x))^2`: largest at `x = 0` for `alpha <= 1`,
    /// else approached at grazing, where it tends to `alpha^2 / pi`.
    fn majorant(&self) -> f64 {
        let a2 = self.0.alpha() * self.0.alpha();
        MARGIN * (1.0 / (std::f64::consts::PI * a2)).max(a2 / std::f64::consts::PI)
    }

    fn is_height_field(&self) -> bool {
        true
    }

    /// The height field's closed form.
    fn sigma(&self, w: Vec3) -> f64 {
        self.0.sigma(w)
    }

    fn angular_width(&self) -> f64 {
        self.0.alpha().atan()
    }
}

impl SphereNdf for HeightField<StudentT> {
    fn d_cos(&self, u: f64) -> f64 {
        d_cos_height_field(&self.0, u)
    }

    /// `D` is proportional to `(1+x)^2 / (A+x)^g` with `A = alpha^2 (g-1)`. For `g > 2` it is
    /// largest at `x = max(0, (2A - g)/(g - 2))`; `g = 2` is GGX. For `g < 2`, `D` grows without
    /// bound toward the horizon and no majorant exists: the bound is `+inf`, which the null
    /// walk rejects.
    fn majorant(&self) -> f64 {
        let g = self.0.gamma();
        let a2 = self.0.alpha() * self.0.alpha();
        if g < 2.0 {
            return f64::INFINITY;
        }
        if g == 2.0 {
            return MARGIN * (1.0 / (std::f64::consts::PI * a2)).max(a2 / std::f64::consts::PI);
        }
        let big_a = a2 * (g - 1.0);
        let x = ((2.0 * big_a - g) / (g - 2.0)).max(0.0);
        MARGIN * d_at_tan2(&self.0, x)
    }

    fn is_height_field(&self) -> bool {
        true
    }

    /// The height field's closed form.
    fn sigma(&self, w: Vec3) -> f64 {
        self.0.sigma(w)
    }

    fn angular_width(&self) -> f64 {
        self.0.alpha().atan()
    }
}
