//! The GGX (Trowbridge-Reitz) NDF.

use super::{Ndf, cos2_sin2, lambda_on_sphere};
use crate::error::{ParamError, check_alpha};
use crate::math::{Vec3, safe_sqrt};
use rand::{Rng, RngExt};
use std::f64::consts::PI;

/// GGX: `D(u) = alpha^2 / (pi u^4 (alpha^2 + tan^2 theta)^2)`, Student-T with gamma = 2.
///
/// ```
/// use stfit_core::ndf::{Ggx, Ndf};
/// use stfit_core::rand::SeedableRng;
/// use stfit_core::Vec3;
///
/// let ggx = Ggx::new(0.3)?;
/// let up = Vec3::new(0.0, 0.0, 1.0);
/// // D at the pole is 1 / (pi alpha^2); nothing shadows a view from the normal.
/// assert!((ggx.d(up) - 1.0 / (std::f64::consts::PI * 0.09)).abs() < 1e-12);
/// assert_eq!(ggx.g1(up), 1.0);
/// // Visible normals face the viewer and lie on the upper hemisphere.
/// let w = Vec3::new(0.8, 0.0, 0.6);
/// let mut rng = rand_pcg::Pcg64::seed_from_u64(1);
/// let wm = ggx.sample_visible(w, &mut rng);
/// assert!(w.dot(&wm) > 0.0 && wm.z > 0.0);
/// # Ok::<(), stfit_core::ParamError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ggx {
    alpha: f64,
}

impl Ggx {
    /// A GGX NDF of roughness `alpha > 0`.
    pub fn new(alpha: f64) -> Result<Self, ParamError> {
        Ok(Self {
            alpha: check_alpha(alpha)?,
        })
    }

    /// The roughness alpha.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
}

impl Ndf for Ggx {
    /// `alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2)`, the same formula multiplied through by
    /// `cos^4` so that it stays finite (`1 / (pi alpha^2)`) at grazing normals.
    fn d(&self, wm: Vec3) -> f64 {
        let Some((u2, sin2)) = cos2_sin2(wm) else {
            return 0.0;
        };
        let a2 = self.alpha * self.alpha;
        let k = a2 * u2 + sin2;
        a2 / (PI * k * k)
    }

    /// `Lambda = (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2`.
    fn lambda(&self, w: Vec3) -> f64 {
        let a = self.alpha;
        lambda_on_sphere(w, |mu| {
            let x = a / mu;
            // (-1 + sqrt(1 + x^2)) / 2 without cancellation for small x.
            0.5 * x * x / (1.0 + (1.0 + x * x).sqrt())
        })
    }

    /// `sigma = (w.z + sqrt(w.z^2 + alpha^2 sin^2 theta)) / 2`, valid on the whole sphere.
    fn sigma(&self, w: Vec3) -> f64 {
        let c = w.z;
        let s2 = w.x * w.x + w.y * w.y;
        let r = (c * c + self.alpha * self.alpha * s2).sqrt();
        if c >= 0.0 {
            0.5 * (c + r)
        } else {
            // (r - |c|) / 2 without cancellation.
            0.5 * self.alpha * self.alpha * s2 / (r - c)
        }
    }

    /// Exact sampling by stretching to alpha = 1 and drawing from a spherical cap (Dupuy and
    /// Benyoub 2023); valid for every `w`, including below the horizon. Draws two uniforms and
    /// calls [`Ggx::sample_visible_from`].
    fn sample_visible<R: Rng + ?Sized>(&self, w: Vec3, rng: &mut R) -> Vec3 {
        let u1: f64 = rng.random();
        let u2: f64 = rng.random();
        self.sample_visible_from(w, [u1, u2])
    }
}

impl Ggx {
    /// The visible normal seen from `w` that the uniforms `u` in `[0, 1)^2` map to (pbrt-v4's
    /// `TrowbridgeReitzDistribution::Sample_wm(w, u)`, with Dupuy and Benyoub 2023's
    /// spherical cap in place of the disk): `u[0]` sets the azimuth about the stretched `w`,
    /// `u[1]` the height on the cap. Uniform `u` gives exactly the density
    /// [`Ndf::d_visible`], for every `w` on the sphere.
    ///
    /// ```
    /// use stfit_core::Vec3;
    /// use stfit_core::ndf::{Ggx, Ndf};
    ///
    /// let ggx = Ggx::new(0.3)?;
    /// let w = Vec3::new(0.6, 0.0, 0.8);
    /// let wm = ggx.sample_visible_from(w, [0.25, 0.5]);
    /// assert!((wm.norm() - 1.0).abs() < 1e-12 && wm.z > 0.0 && w.dot(&wm) > 0.0);
    /// assert!(ggx.d_visible(w, wm) > 0.0);
    /// # Ok::<(), stfit_core::ParamError>(())
    /// ```
    pub fn sample_visible_from(&self, w: Vec3, u: [f64; 2]) -> Vec3 {
        let a = self.alpha;
        let ws = Vec3::new(a * w.x, a * w.y, w.z).normalize();
        let phi = 2.0 * PI * u[0];
        let z = (1.0 - u[1]) * (1.0 + ws.z) - ws.z;
        let st = safe_sqrt(1.0 - z * z);
        let (sp, cp) = phi.sin_cos();
        let h = Vec3::new(st * cp + ws.x, st * sp + ws.y, z + ws.z);
        let m = Vec3::new(a * h.x, a * h.y, h.z.max(0.0));
        let n = m.norm();
        if n > 0.0 && m.z > 0.0 {
            m / n
        } else {
            // Measure-zero draw exactly on the cap's rim: fall back to the stretched view.
            let m = Vec3::new(a * ws.x, a * ws.y, ws.z.abs().max(f64::MIN_POSITIVE));
            m.normalize()
        }
    }
}
