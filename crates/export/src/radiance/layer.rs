//! What a glazing BSDF file describes: the single rough interface, or a pane (the rough face
//! over a smooth back face at the same index), as a stochastic scattering function for light
//! arriving from either side.
//!
//! Frame: z is the normal of the rough face, its outside (air, the WINDOW "front") is z > 0.
//! For the interface the back is the glass; for the pane the back is air again, below a smooth
//! face. Directions point away from the surface; `wi` toward the light.
//!
//! Pane model: light from the front meets the rough face, which reflects it back out or
//! refracts it into the glass; inside, it crosses the slab (absorption
//! `(1 - A)^(1 / |cos theta|)` per crossing, `A` the fraction absorbed in one crossing at normal
//! incidence, 0 for a lossless pane), and the smooth face reflects it (exact Fresnel, mirror
//! direction) or refracts it out of the back; reflected light meets the rough face from inside,
//! which refracts it out of the front or reflects it down again, and so on. Every
//! inter-reflection is followed until the light leaves or is absorbed (a safety cap of
//! [`MAX_CROSSINGS`] slab crossings, far above any real path, drops and counts runaway paths).
//! Light from the back meets the smooth face first. The rough face scatters with all orders of
//! its microsurface (the random walk: a lossless pane conserves energy exactly). Lateral
//! displacement inside the slab is ignored, as in every BSDF of a thin pane.

use rand::{Rng, RngExt};
use stfit_core::Vec3;
use stfit_core::bsdf::{fresnel_dielectric, refract};
use stfit_core::ndf::AnyNdf;
use stfit_core::walk::{DielectricFacet, Microsurface, ScatteringOrders};

use crate::{ExportError, ExportModel};

/// Safety cap on slab crossings of one pane path.
pub const MAX_CROSSINGS: u32 = 100_000;

/// A stochastic scattering function: one draw of the exit direction and weight for light from
/// `wi`, or `None` when the light is absorbed (or the draw fails).
pub trait Layer: Sync {
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<(Vec3, f64)>;
    /// The layer's description for file comments.
    fn describe(&self) -> String;
}

/// The rough face of the fitted model as a random walk on its microsurface: all orders (a
/// lossless face conserves energy exactly), or only the orders >= 2 (the part of an all-orders
/// interface that no closed form gives).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughFace {
    surface: Microsurface<AnyNdf, DielectricFacet>,
}

impl RoughFace {
    /// All orders of the fitted microsurface's scattering; refuses a model whose walks are not
    /// supported ([`ExportModel::microsurface`]).
    pub fn all_orders(model: &ExportModel) -> Result<Self, ExportError> {
        Ok(Self {
            surface: model.microsurface(ScatteringOrders::All)?,
        })
    }

    /// Only the orders >= 2 of the fitted microsurface's scattering; refuses a model whose
    /// walks are not supported ([`ExportModel::microsurface`]).
    pub fn multiple_orders(model: &ExportModel) -> Result<Self, ExportError> {
        Ok(Self {
            surface: model.microsurface(ScatteringOrders::Multiple)?,
        })
    }
}

impl Layer for RoughFace {
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<(Vec3, f64)> {
        self.surface.sample_walk(wi, rng).map(|s| (s.wo, s.weight))
    }

    fn describe(&self) -> String {
        format!(
            "single rough interface, orders {} of microsurface scattering (random walk), glass (eta {}) on the back",
            self.surface.orders().name(),
            self.surface.facet().eta()
        )
    }
}

/// Checks a pane's absorption: the fraction absorbed in one crossing at normal incidence, in
/// [0, 1).
pub fn check_absorption(absorption: f64) -> Result<f64, ExportError> {
    if (0.0..1.0).contains(&absorption) {
        Ok(absorption)
    } else {
        Err(ExportError::Unsupported(format!(
            "absorption must be in [0, 1) (the fraction absorbed in one crossing at normal incidence), got {}",
            stfit_core::error::show(absorption)
        )))
    }
}

/// A pane: the rough face (front, z > 0 outside) over a smooth back face at the same index.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pane {
    face: RoughFace,
    eta: f64,
    /// Fraction absorbed in one crossing of the slab at normal incidence.
    absorption: f64,
}

impl Pane {
    /// A pane with the given rough face, relative index and absorption `A` in `[0, 1)`.
    pub fn new(face: RoughFace, eta: f64, absorption: f64) -> Result<Self, ExportError> {
        check_absorption(absorption)?;
        stfit_core::error::check_eta(eta)?;
        Ok(Self {
            face,
            eta,
            absorption,
        })
    }

    /// Transmittance of one slab crossing along a direction with cosine `c`.
    fn crossing(&self, c: f64) -> f64 {
        if self.absorption == 0.0 {
            1.0
        } else {
            (1.0 - self.absorption).powf(1.0 / c.abs())
        }
    }
}

impl Layer for Pane {
    fn scatter<R: Rng + ?Sized>(&self, wi: Vec3, rng: &mut R) -> Option<(Vec3, f64)> {
        let mut weight = 1.0;
        // The incident direction at the rough face (either side).
        let mut at_rough = if wi.z > 0.0 {
            wi
        } else {
            // From the back: the smooth face, seen from the air below (normal -z on that side).
            let f = fresnel_dielectric(-wi.z, self.eta);
            if rng.random::<f64>() < f {
                return Some((Vec3::new(-wi.x, -wi.y, wi.z), weight));
            }
            let up = refract(wi, -Vec3::z(), self.eta)?;
            weight *= self.crossing(up.z);
            -up
        };
        for _ in 0..MAX_CROSSINGS {
            let (wo, w) = self.face.scatter(at_rough, rng)?;
            weight *= w;
            if wo.z > 0.0 {
                return Some((wo, weight));
            }
            // Down through the glass to the smooth face, seen from the glass above it.
            weight *= self.crossing(wo.z);
            let f = fresnel_dielectric(-wo.z, 1.0 / self.eta);
            if rng.random::<f64>() >= f {
                let out = refract(-wo, Vec3::z(), 1.0 / self.eta)?;
                return Some((out, weight));
            }
            // Mirror reflection up, across the slab, to the rough face from inside.
            weight *= self.crossing(wo.z);
            at_rough = Vec3::new(-wo.x, -wo.y, wo.z);
        }
        None
    }

    fn describe(&self) -> String {
        format!(
            "pane: rough front face over a smooth back face at eta {}, all inter-reflections between the faces, orders {} of the rough face's microsurface scattering, absorption per normal crossing {}",
            self.eta,
            self.face.surface.orders().name(),
            self.absorption
        )
    }
}

/// Fractions of the flux from `wi` that leave on the side of the light and on the other side,
/// with their standard errors, from `n` draws of `layer` (sequential, seeded).
pub fn albedo<L: Layer>(layer: &L, wi: Vec3, n: u64, seed: u64) -> [f64; 4] {
    let mut rng = rand_pcg::Pcg64::new(u128::from(seed) << 64 | 0x5eed, 0xa02b_db6f_7e5c_3c1d);
    let (mut r, mut r2, mut t, mut t2) = (0.0, 0.0, 0.0, 0.0);
    for _ in 0..n {
        if let Some((wo, w)) = layer.scatter(wi, &mut rng) {
            if (wo.z > 0.0) == (wi.z > 0.0) {
                r += w;
                r2 += w * w;
            } else {
                t += w;
                t2 += w * w;
            }
        }
    }
    let nf = n as f64;
    let se = |s: f64, s2: f64| ((s2 / nf - (s / nf).powi(2)).max(0.0) / nf).sqrt();
    [r / nf, se(r, r2), t / nf, se(t, t2)]
}
