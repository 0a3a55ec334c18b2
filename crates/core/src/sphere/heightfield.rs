//! Height-field NDFs seen as bounded NDFs on the whole sphere (zero below the horizon).
//!
//! Each bound is the exact supremum of `D` over `x = tan^2 theta_m >= 0`, with a relative
//! margin of 1e-12 against rounding.

use super::SphereNdf;
use crate::math::Vec3;
use crate::ndf::{Beckmann, Ggx, Ndf, StudentT};

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

impl SphereNdf for Beckmann {
    fn d_cos(&self, u: f64) -> f64 {
        d_cos_height_field(self, u)
    }

    /// `D` is proportional to `exp(-x/alpha^2) (1+x)^2`, largest at `x = max(0, 2 alpha^2 - 1)`.
    fn bound(&self) -> f64 {
        let a2 = self.alpha() * self.alpha();
        MARGIN * d_at_tan2(self, (2.0 * a2 - 1.0).max(0.0))
    }

    fn height_field(&self) -> bool {
        true
    }

    fn angular_width(&self) -> f64 {
        self.alpha().atan()
    }
}

impl SphereNdf for Ggx {
    /// `alpha^2 / (pi (alpha^2 u^2 + 1 - u^2)^2)` above the horizon: no square root, as the
    /// null-scattering walk evaluates it at every tentative collision.
    #[inline]
    fn d_cos(&self, u: f64) -> f64 {
        if u <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha() * self.alpha();
        let k = 1.0 + (a2 - 1.0) * u * u;
        a2 / (std::f64::consts::PI * k * k)
    }

    /// `D` is proportional to `((1+x)/(alpha^2+x))^2`: largest at `x = 0` for `alpha <= 1`,
    /// else approached at grazing, where it tends to `alpha^2 / pi`.
    fn bound(&self) -> f64 {
        let a2 = self.alpha() * self.alpha();
        MARGIN * (1.0 / (std::f64::consts::PI * a2)).max(a2 / std::f64::consts::PI)
    }

    fn height_field(&self) -> bool {
        true
    }

    fn angular_width(&self) -> f64 {
        self.alpha().atan()
    }
}

impl SphereNdf for StudentT {
    fn d_cos(&self, u: f64) -> f64 {
        d_cos_height_field(self, u)
    }

    /// `D` is proportional to `(1+x)^2 / (A+x)^g` with `A = alpha^2 (g-1)`. For `g > 2` it is
    /// largest at `x = max(0, (2A - g)/(g - 2))`; `g = 2` is GGX. For `g < 2`, `D` grows without
    /// bound toward the horizon and no majorant exists: the bound is `+inf`, which the null
    /// walk rejects.
    fn bound(&self) -> f64 {
        let g = self.gamma();
        let a2 = self.alpha() * self.alpha();
        if g < 2.0 {
            return f64::INFINITY;
        }
        if g == 2.0 {
            return MARGIN * (1.0 / (std::f64::consts::PI * a2)).max(a2 / std::f64::consts::PI);
        }
        let big_a = a2 * (g - 1.0);
        let x = ((2.0 * big_a - g) / (g - 2.0)).max(0.0);
        MARGIN * d_at_tan2(self, x)
    }

    fn height_field(&self) -> bool {
        true
    }

    fn angular_width(&self) -> f64 {
        self.alpha().atan()
    }
}
