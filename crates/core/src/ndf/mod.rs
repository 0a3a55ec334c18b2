//! Isotropic height-field normal distribution functions (NDFs) and their Smith functions.
//!
//! Every NDF is normalised by projected area, `integral D(wm) wm.z dwm = 1`, and defined for
//! `wm.z > 0` (zero below). The Smith `Lambda` is extended to the whole sphere so that the
//! projected area obeys `sigma(w) = w.z (1 + Lambda(w))` for every direction; this gives
//! `Lambda(-w) = -1 - Lambda(w)` and, below the horizon, `sigma(w) = |w.z| Lambda(-w)`
//! (Heitz et al. 2016).

mod any;
mod beckmann;
mod ggx;
pub mod special;
mod student_t;

pub use any::{AnyNdf, WithNdf};
pub use beckmann::Beckmann;
pub use ggx::Ggx;
pub use student_t::{StudentT, TabulatedStudentT};

use crate::math::Vec3;
use rand::Rng;

/// An isotropic microfacet normal distribution with Smith masking and exact sampling of its
/// distribution of visible normals.
pub trait Ndf: Clone + Send + Sync {
    /// `D(wm)`, normalised by projected area; zero for `wm.z <= 0` (and below 1.5e-162, where
    /// `wm.z^2` underflows). `wm` must be unit length.
    fn d(&self, wm: Vec3) -> f64;

    /// Smith `Lambda(w)` for any unit `w` on the sphere, extended below the horizon by
    /// `Lambda(-w) = -1 - Lambda(w)`; `+inf` (`-inf`) exactly at the horizon from above (below).
    fn lambda(&self, w: Vec3) -> f64;

    /// Projected area of the microsurface seen from `w`: `integral max(0, w.wm) D(wm) dwm`.
    /// Equals `w.z (1 + Lambda(w))` above the horizon and `|w.z| Lambda(-w)` below it; finite
    /// and positive at the horizon itself.
    fn sigma(&self, w: Vec3) -> f64;

    /// Draws a microfacet normal from the distribution of normals visible from `w`,
    /// [`Ndf::d_visible`], for any `w` on the sphere with `sigma(w) > 0`.
    /// The result is a unit vector with `w.wm > 0` and `wm.z > 0`. Where `sigma(w) = 0` (no
    /// normal is visible: straight below, or far below the horizon where the tail of `D`
    /// underflows) it is a unit vector with `wm.z > 0` that may not be visible: where such `w`
    /// can occur, check `w.wm > 0` (Beckmann's sampler still finds visible normals where
    /// `sigma` has underflowed, so `sigma(w) = 0` alone is too strict a test).
    fn sample_visible<R: Rng + ?Sized>(&self, w: Vec3, rng: &mut R) -> Vec3;

    /// [`Ndf::sample_visible`] from `w` given `lambda_back = Lambda(-w)`, which a random walk has
    /// computed for the flight that ends seen from `w`: NDFs whose sampler shares work with
    /// Lambda take it from there (GGX's stretched length). The same normal for the same random
    /// numbers, to rounding.
    #[inline]
    fn sample_visible_after<R: Rng + ?Sized>(
        &self,
        w: Vec3,
        lambda_back: f64,
        rng: &mut R,
    ) -> Vec3 {
        let _ = lambda_back;
        self.sample_visible(w, rng)
    }

    /// Smith masking `G1(w) = 1 / (1 + Lambda(w'))` of a direction by the surface on its own
    /// side: `w'` is `w` mirrored to the upper hemisphere (so a direction inside a dielectric is
    /// masked by the mirrored surface, as in Walter et al. 2007). The local facet condition
    /// `w.wm / w.z > 0` is the caller's to check.
    fn g1(&self, w: Vec3) -> f64 {
        let up = Vec3::new(w.x, w.y, w.z.abs());
        1.0 / (1.0 + self.lambda(up))
    }

    /// Density of visible normals, `D_w(wm) = max(0, w.wm) D(wm) / sigma(w)`, per unit solid
    /// angle of `wm`.
    fn d_visible(&self, w: Vec3, wm: Vec3) -> f64 {
        let cos = w.dot(&wm);
        if cos <= 0.0 {
            return 0.0;
        }
        let sigma = self.sigma(w);
        if sigma > 0.0 {
            cos * self.d(wm) / sigma
        } else {
            0.0
        }
    }
}

/// `(cos^2 theta, sin^2 theta)` of a facet normal, or `None` for `wm.z <= 0` and where
/// `cos^2` underflows (`wm.z < 1.5e-162`; the NDFs are taken as 0 there, which drops a mass
/// below 1e-30 even for the most heavy-tailed Student-T). NDFs combine the two so that
/// nothing overflows or meets `0 * inf` near the horizon.
#[inline]
pub(crate) fn cos2_sin2(wm: Vec3) -> Option<(f64, f64)> {
    let u2 = wm.z * wm.z;
    if wm.z <= 0.0 || u2 == 0.0 {
        return None;
    }
    Some((u2, (wm.x * wm.x + wm.y * wm.y).min(1.0)))
}

/// Extends a Lambda defined for upward directions to the whole sphere by `Lambda(-w) = -1 -
/// Lambda(w)`: `lambda_up(|w.z|, sin^2 theta)` is called off the pole and the horizon (0 at
/// the upward pole, `+inf` at the horizon).
#[inline]
pub(crate) fn lambda_on_sphere(w: Vec3, lambda_up: impl Fn(f64, f64) -> f64) -> f64 {
    let s2 = w.x * w.x + w.y * w.y;
    if s2 == 0.0 {
        return if w.z > 0.0 { 0.0 } else { -1.0 };
    }
    if w.z == 0.0 {
        return f64::INFINITY;
    }
    let l = lambda_up(w.z.abs(), s2);
    if w.z > 0.0 { l } else { -1.0 - l }
}
