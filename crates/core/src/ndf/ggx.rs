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
    #[inline]
    fn d(&self, wm: Vec3) -> f64 {
        let Some((u2, sin2)) = cos2_sin2(wm) else {
            return 0.0;
        };
        let a2 = self.alpha * self.alpha;
        let k = a2 * u2 + sin2;
        a2 / (PI * k * k)
    }

    /// `Lambda = (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2`, written with the stretched length
    /// `r = sqrt(w.z^2 + alpha^2 sin^2 theta)` as `alpha^2 sin^2 / (2 |w.z| (r + |w.z|))`: one
    /// square root and one division, no cancellation, and `+inf` at the horizon. Below the
    /// horizon `Lambda(-w) = -1 - Lambda(w)`.
    #[inline]
    fn lambda(&self, w: Vec3) -> f64 {
        let a2 = self.alpha * self.alpha;
        lambda_on_sphere(w, |c, s2| {
            let t = a2 * s2;
            0.5 * t / (c * ((c * c + t).sqrt() + c))
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
    /// Benyoub 2023); valid for every `w`, including below the horizon. The cap is drawn in
    /// units of the stretched length `l = |(alpha w.x, alpha w.y, w.z)|`, so the stretched
    /// direction is never normalised, and without trigonometry: a point `(x1, x2)` uniform in
    /// the unit disk (by rejection from its square, 4/pi tries on average) has a uniform
    /// azimuth and an independent uniform `s = x1^2 + x2^2`, which places the point's height
    /// `z = 1 - (1 + w_s.z) s` uniformly on the cap (Marsaglia 1972); its horizontal part is
    /// `(x1, x2) sqrt((1 - z^2) / s)`.
    #[inline(always)]
    fn sample_visible<R: Rng + ?Sized>(&self, w: Vec3, rng: &mut R) -> Vec3 {
        let (x1, x2, s) = unit_disk(rng);
        self.cap_normal(w, self.stretched_length(w), x1, x2, s)
    }

    /// The stretched length `|(alpha w.x, alpha w.y, w.z)|` is `-w.z (1 + 2 Lambda(-w))` on the
    /// whole sphere (`Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2` above the horizon, and
    /// `Lambda(-v) = -1 - Lambda(v)`): a product in place of a square root where `Lambda(-w)`
    /// is known, except at the horizon.
    #[inline(always)]
    fn sample_visible_after<R: Rng + ?Sized>(
        &self,
        w: Vec3,
        lambda_back: f64,
        rng: &mut R,
    ) -> Vec3 {
        let (x1, x2, s) = unit_disk(rng);
        let l = -w.z * (1.0 + 2.0 * lambda_back);
        let l = if l.is_finite() && l > 0.0 {
            l
        } else {
            self.stretched_length(w)
        };
        self.cap_normal(w, l, x1, x2, s)
    }
}

/// A uniform point `(x1, x2)` of the unit disk by rejection from the square, and `x1^2 + x2^2`.
#[inline]
fn unit_disk<R: Rng + ?Sized>(rng: &mut R) -> (f64, f64, f64) {
    loop {
        let x1 = 2.0 * rng.random::<f64>() - 1.0;
        let x2 = 2.0 * rng.random::<f64>() - 1.0;
        let s = x1 * x1 + x2 * x2;
        if s < 1.0 {
            return (x1, x2, s);
        }
    }
}

impl Ggx {
    /// The visible normal seen from `w` that the uniforms `u` in `[0, 1)^2` map to (pbrt-v4's
    /// `TrowbridgeReitzDistribution::Sample_wm(w, u)`, with Dupuy and Benyoub 2023's
    /// spherical cap in place of the disk): `u[0]` sets the azimuth about the stretched `w`,
    /// `u[1]` the height on the cap. Uniform `u` gives exactly the density
    /// [`Ndf::d_visible`], for every `w` on the sphere. [`Ndf::sample_visible`] draws the
    /// same cap point from a uniform point of the unit disk instead, without trigonometry,
    /// so the two do not map a generator's numbers to the same normals.
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
        let (sp, cp) = (2.0 * PI * u[0]).sin_cos();
        let r = u[1].sqrt();
        self.cap_normal(w, self.stretched_length(w), r * cp, r * sp, u[1])
    }

    /// `|(alpha w.x, alpha w.y, w.z)|`, the length of `w` stretched to roughness 1.
    #[inline]
    fn stretched_length(&self, w: Vec3) -> f64 {
        let a = self.alpha;
        (a * a * (w.x * w.x + w.y * w.y) + w.z * w.z).sqrt()
    }

    /// The visible normal seen from `w` for the point `(x1, x2)` of the unit disk with
    /// `s = x1^2 + x2^2`: its azimuth is the azimuth about the stretched direction
    /// `w_s = (alpha w.x, alpha w.y, w.z)` and `s` the uniform that places the height
    /// `z = 1 - (1 + w_s.z) s` on the spherical cap (Dupuy and Benyoub 2023; Marsaglia 1972
    /// for the disk's `s`). The cap is formed in units of the stretched length
    /// `l = |w_s|`, so `w_s` is never normalised: `l (1 - z) = p = s (l + w_s.z)` and
    /// `l^2 (1 - z^2) / s = (l + w_s.z) (2 l - p)`, without cancellation near the cap's pole.
    /// The cap point plus `w_s` is unstretched to the normal. One square root and one
    /// division besides `l`, which the caller gives ([`Ggx::stretched_length`]). Below the
    /// horizon `q = l + w_s.z` is the difference of nearly equal numbers at small alpha; it is
    /// taken as `(w_s.x^2 + w_s.y^2) / (l - w_s.z)` there (`l^2 = |w_s|^2`), and the point's
    /// height plus `w_s.z` as `q (1 - s)`, so that the normal stays visible from `w` down to
    /// alpha 1e-8.
    #[inline]
    fn cap_normal(&self, w: Vec3, l: f64, x1: f64, x2: f64, s: f64) -> Vec3 {
        let a = self.alpha;
        let ws = Vec3::new(a * w.x, a * w.y, w.z);
        let q = if ws.z >= 0.0 {
            l + ws.z
        } else {
            (ws.x * ws.x + ws.y * ws.y) / (l - ws.z)
        };
        let p = s * q;
        let r = safe_sqrt(q * (2.0 * l - p));
        let h = Vec3::new(r * x1 + ws.x, r * x2 + ws.y, q * (1.0 - s));
        let m = Vec3::new(a * h.x, a * h.y, h.z.max(0.0));
        let n2 = m.norm_squared();
        if n2 > 0.0 && m.z > 0.0 {
            m * (1.0 / n2.sqrt())
        } else {
            // Measure-zero draw exactly on the cap's rim: fall back to the stretched view.
            let m = Vec3::new(a * ws.x, a * ws.y, ws.z.abs().max(f64::MIN_POSITIVE));
            m.normalize()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::spherical_direction;
    use rand::SeedableRng;
    use rand_pcg::Pcg64;
    use std::f64::consts::FRAC_PI_2;

    /// Given `Lambda(-w)`, the walk's sampler draws the normal `sample_visible` draws from the
    /// same random numbers, to a few ulps, from near-vertical to near-grazing `w` on both
    /// sides, where the stretched length comes from Lambda instead of a square root.
    #[test]
    fn sampling_after_lambda_matches_sample_visible() {
        for alpha in [0.01, 0.45, 3.0] {
            let ggx = Ggx::new(alpha).unwrap();
            for theta in [
                1e-6,
                0.3,
                1.2,
                FRAC_PI_2 - 1e-4,
                FRAC_PI_2 + 1e-4,
                2.5,
                std::f64::consts::PI - 1e-6,
            ] {
                let w = spherical_direction(theta, 0.7);
                let (mut a, mut b) = (Pcg64::seed_from_u64(5), Pcg64::seed_from_u64(5));
                for _ in 0..100 {
                    let m = ggx.sample_visible(w, &mut a);
                    let n = ggx.sample_visible_after(w, ggx.lambda(-w), &mut b);
                    assert!(
                        (m - n).norm() < 1e-13,
                        "alpha {alpha} theta {theta}: {m:?} {n:?}"
                    );
                }
            }
        }
    }

    /// Seen from below the horizon at tiny roughness the visible normals are nearly
    /// perpendicular to `w`; every drawn normal is still visible (`w.wm > 0`, `wm.z > 0`),
    /// from just below the horizon to 179 degrees, for alpha down to 1e-8.
    #[test]
    fn normals_seen_from_below_at_tiny_alpha_are_visible() {
        let mut rng = Pcg64::seed_from_u64(17);
        for alpha in [1e-8, 1e-6, 1e-3, 0.3] {
            let ggx = Ggx::new(alpha).unwrap();
            for deg in [90.5f64, 100.0, 120.0, 135.0, 150.0, 170.0, 179.0] {
                let w = spherical_direction(deg.to_radians(), 0.7);
                for _ in 0..2000 {
                    for m in [
                        ggx.sample_visible(w, &mut rng),
                        ggx.sample_visible_after(w, ggx.lambda(-w), &mut rng),
                    ] {
                        assert!(
                            w.dot(&m) > 0.0 && m.z > 0.0 && (m.norm() - 1.0).abs() < 1e-12,
                            "alpha {alpha}, {deg} degrees: {m:?}"
                        );
                    }
                }
            }
        }
    }
}
