//! Small geometric helpers: the vector type, orthonormal frames, spherical coordinates.

use std::f64::consts::PI;

/// A 3-vector of `f64`; directions are unit vectors pointing away from the surface.
pub type Vec3 = nalgebra::Vector3<f64>;

/// An orthonormal frame whose third axis is a given unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// Builds a frame around the unit vector `n` (Duff et al. 2017, branchless, continuous
    /// except across `n.z = 0`).
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1f64.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { s, t, n }
    }

    /// Expresses the world vector `v` in this frame.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(&self.s), v.dot(&self.t), v.dot(&self.n))
    }

    /// Expresses the local vector `v` in world coordinates.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// The unit vector with polar angle `theta` from +z and azimuth `phi` (radians).
#[inline]
pub fn spherical_direction(theta: f64, phi: f64) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

/// `w` scaled to unit length when its squared norm is off 1 by more than rounding
/// (`|w.w - 1| > 4 eps`), else `w` itself, bit for bit: for directions accepted within a tolerance of unit
/// length (1e-6, as a CSV with 6 decimals gives them), whose excess norm would otherwise tilt
/// half vectors (by 0.79 of an alpha-1e-8 lobe at grazing reflection) and shift cosines. `w`
/// must be finite and nonzero.
#[inline]
pub fn to_unit(w: Vec3) -> Vec3 {
    let n2 = w.norm_squared();
    if (n2 - 1.0).abs() > 4.0 * f64::EPSILON {
        w / n2.sqrt()
    } else {
        w
    }
}

/// `sqrt(max(0, x))`: guards square roots of quantities that are >= 0 up to rounding.
#[inline]
pub fn safe_sqrt(x: f64) -> f64 {
    x.max(0.0).sqrt()
}

/// `(cos theta, sin theta)` of a direction measured from +z, with sin >= 0.
#[inline]
pub fn cos_sin_theta(w: Vec3) -> (f64, f64) {
    (w.z, (w.x * w.x + w.y * w.y).sqrt())
}

/// Degrees to radians.
#[inline]
pub fn radians(deg: f64) -> f64 {
    deg * PI / 180.0
}
