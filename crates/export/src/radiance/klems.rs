//! The LBNL/Klems full angle basis and Radiance's direction conventions for it.
//!
//! From LBNL-ETA/Radiance, src/common/bsdf_m.c (`abase_list`, `fo_getvec`, `fo_getndx`,
//! `io_getohm`, `fi_/bi_/bo_getvec`):
//! - 145 patches in 9 rings with lower polar bounds 0, 5, 15, 25, 35, 45, 55, 65, 75 degrees
//!   (upper bound 90) and 1, 8, 16, 20, 24, 24, 24, 16, 12 azimuthal patches; patches are
//!   numbered ring by ring from the normal, and within a ring by azimuth, patch `k` centred on
//!   `360 k / n` degrees (`ndx = floor(n phi / 360 + 0.5) mod n`).
//! - The projected solid angle of a patch is `pi (cos^2 theta_lo - cos^2 theta_hi) / n`;
//!   `fo_getvec` draws directions inside a patch uniformly in `cos^2 theta` and azimuth, that
//!   is cosine-weighted.
//! - Incident patches are indexed by the direction the light travels, exiting patches by the
//!   direction it leaves in, each with theta from the normal of its own side and azimuth in the
//!   same tangent frame (`fi_getvec` negates x and y of the exiting vector, `bi_getvec` negates
//!   all three, `bo_getvec` negates z): straight-through transmission and mirror reflection
//!   keep the patch index.

use std::f64::consts::PI;

use stfit_core::Vec3;

/// Lower polar bound of each ring (degrees); the last ring ends at 90.
pub const THETA_LO_DEG: [f64; 9] = [0.0, 5.0, 15.0, 25.0, 35.0, 45.0, 55.0, 65.0, 75.0];
/// Patches per ring.
pub const N_PHI: [usize; 9] = [1, 8, 16, 20, 24, 24, 24, 16, 12];
/// Number of patches.
pub const N_PATCHES: usize = 145;
/// The basis name Radiance and WINDOW know it by.
pub const BASIS_NAME: &str = "LBNL/Klems Full";

/// Upper polar bound of ring `r` (degrees).
pub fn theta_hi_deg(r: usize) -> f64 {
    if r + 1 < THETA_LO_DEG.len() {
        THETA_LO_DEG[r + 1]
    } else {
        90.0
    }
}

/// `(ring, azimuthal index)` of patch `p`.
pub fn ring_of(p: usize) -> (usize, usize) {
    let mut k = p;
    for (r, &n) in N_PHI.iter().enumerate() {
        if k < n {
            return (r, k);
        }
        k -= n;
    }
    panic!("Klems patch index {p} out of range");
}

/// First patch index of ring `r`.
pub fn ring_start(r: usize) -> usize {
    N_PHI[..r].iter().sum()
}

/// Projected solid angle of patch `p` (`io_getohm`).
pub fn projected_solid_angle(p: usize) -> f64 {
    let (r, _) = ring_of(p);
    let (c0, c1) = (
        THETA_LO_DEG[r].to_radians().cos(),
        theta_hi_deg(r).to_radians().cos(),
    );
    PI * (c0 * c0 - c1 * c1) / N_PHI[r] as f64
}

/// Patch of a direction given by `cos theta >= 0` from its side's normal and azimuth
/// `(x, y)` components (`fo_getndx`); `None` for `cos theta < 0`.
pub fn patch_of(cos_theta: f64, x: f64, y: f64) -> Option<usize> {
    if !(0.0..=1.00001).contains(&cos_theta) {
        return None;
    }
    let pol = cos_theta.min(1.0).acos().to_degrees();
    let mut r = 0;
    while r + 1 < THETA_LO_DEG.len() && THETA_LO_DEG[r + 1] <= pol {
        r += 1;
    }
    let mut azi = y.atan2(x).to_degrees();
    if azi < 0.0 {
        azi += 360.0;
    }
    let n = N_PHI[r];
    let mut k = (azi / 360.0 * n as f64 + 0.5) as usize;
    if k >= n {
        k = 0;
    }
    Some(ring_start(r) + k)
}

/// A unit vector in patch `p` of the hemisphere around +z, cosine-distributed inside the patch
/// for uniform `(u1, u2)` (as `fo_getvec`).
pub fn direction_in_patch(p: usize, u1: f64, u2: f64) -> Vec3 {
    let (r, k) = ring_of(p);
    let (c0, c1) = (
        THETA_LO_DEG[r].to_radians().cos(),
        theta_hi_deg(r).to_radians().cos(),
    );
    let cos2 = (1.0 - u1) * c0 * c0 + u1 * c1 * c1;
    let c = cos2.max(0.0).sqrt();
    let s = (1.0 - cos2).max(0.0).sqrt();
    let phi = 2.0 * PI * (k as f64 + u2 - 0.5) / N_PHI[r] as f64;
    Vec3::new(s * phi.cos(), s * phi.sin(), c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The patches tile the hemisphere: their projected solid angles add to pi, and a direction
    /// drawn in a patch is found in it again.
    #[test]
    fn patches_tile_the_hemisphere_and_round_trip() {
        assert_eq!(N_PHI.iter().sum::<usize>(), N_PATCHES);
        let total: f64 = (0..N_PATCHES).map(projected_solid_angle).sum();
        assert!((total - PI).abs() < 1e-12, "{total}");
        for p in 0..N_PATCHES {
            for (u1, u2) in [(0.5, 0.5), (0.01, 0.02), (0.99, 0.97)] {
                let v = direction_in_patch(p, u1, u2);
                assert_eq!(
                    patch_of(v.z, v.x, v.y),
                    Some(p),
                    "patch {p} at ({u1}, {u2})"
                );
            }
        }
    }
}
