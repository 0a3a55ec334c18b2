//! In-memory measurements: one or more named samples of measured points, each with the angles
//! its file gave, the measured value and a least-squares weight.

use std::path::PathBuf;
use stfit_core::error::show;

use serde::{Deserialize, Serialize};

use stfit_core::Vec3;

use crate::conventions::{
    THETA_I_RANGE, THETA_O_RANGE, THETA_RANGE, pair_from_deg, spherical_from_deg, theta_i_in_range,
    theta_in_range, theta_o_in_range,
};

/// Text from a file or the command line as a message shows it: control characters escaped
/// (so that the message stays on one line) and, past 60 characters, cut with the total length
/// given, so that a huge field is not echoed whole.
pub fn short(text: &str) -> String {
    const MAX: usize = 60;
    let mut out = String::new();
    for (shown, c) in text.chars().enumerate() {
        if shown == MAX {
            out.push_str(&format!("... ({} characters)", text.chars().count()));
            return out;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// The angles of a measurement as its file gave them, in degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Angles {
    /// An in-plane file (the Walter et al. 2007 form, [`crate::conventions`]): light from the
    /// air at `theta_i` in [0, 90), `theta_o` the transmitted direction inside the glass in
    /// (90, 270), 180 straight through. The value is `L`.
    InPlane { theta_i_deg: f64, theta_o_deg: f64 },
    /// A general file: spherical coordinates of `wi` (toward the light) and `wo` (toward the
    /// detector) in the surface frame, `theta` from the outside normal in [0, 180] (90
    /// excluded; above 90 is inside the glass), `phi` any finite azimuth. The value is the
    /// BSDF `f(wi, wo)`.
    Spherical {
        theta_i_deg: f64,
        phi_i_deg: f64,
        theta_o_deg: f64,
        phi_o_deg: f64,
    },
}

/// What a measured value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// `L = scale f_t(wi, wo) cos(theta_i) / eta^2` of an in-plane file.
    L,
    /// `scale f(wi, wo)`, the BSDF in 1/sr (Walter et al. 2007's radiance convention).
    Bsdf,
}

impl Quantity {
    /// The value's name in files and messages: `L` or `bsdf`.
    pub fn name(self) -> &'static str {
        match self {
            Self::L => "L",
            Self::Bsdf => "bsdf",
        }
    }
}

/// What the points of a sample measure: one quantity, or both (a sample merged from in-plane
/// and general files). Recorded with every fit so that its rmse can be named.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub enum Measured {
    /// Every point gives `L` (in-plane files).
    #[default]
    #[serde(rename = "L")]
    L,
    /// Every point gives the BSDF (general and pab-opto files).
    #[serde(rename = "bsdf")]
    Bsdf,
    /// Some points give `L`, others the BSDF.
    #[serde(rename = "L+bsdf")]
    Both,
}

impl Measured {
    /// The square root the rmse is of, in plain text: `sqrt(L)`, `sqrt(BSDF)` or
    /// `sqrt(L or BSDF)`.
    pub fn sqrt_label(self) -> &'static str {
        match self {
            Self::L => "sqrt(L)",
            Self::Bsdf => "sqrt(BSDF)",
            Self::Both => "sqrt(L or BSDF)",
        }
    }

    /// The same with a radical sign, for figures: `√L`, `√BSDF` or `√(L or BSDF)`.
    pub fn sqrt_symbol(self) -> &'static str {
        match self {
            Self::L => "√L",
            Self::Bsdf => "√BSDF",
            Self::Both => "√(L or BSDF)",
        }
    }

    /// What points of `quantities` measure together (`L` for none).
    pub fn of(quantities: impl IntoIterator<Item = Quantity>) -> Self {
        let (mut l, mut bsdf) = (false, false);
        for q in quantities {
            match q {
                Quantity::L => l = true,
                Quantity::Bsdf => bsdf = true,
            }
        }
        match (l, bsdf) {
            (_, false) => Self::L,
            (false, true) => Self::Bsdf,
            (true, true) => Self::Both,
        }
    }
}

/// One measured point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    /// The angles as the file gave them; they fix the directions and the quantity.
    pub angles: Angles,
    /// The measured value: `L` for an in-plane point (a `sqrt_L` column is squared on load),
    /// the BSDF for a general point.
    pub value: f64,
    /// Least-squares weight (1 when the file has no `weight` column).
    pub weight: f64,
}

impl Measurement {
    /// An in-plane point: incidence `theta_i_deg`, transmitted direction `theta_o_deg` inside
    /// the glass, measured `l`.
    pub fn in_plane(theta_i_deg: f64, theta_o_deg: f64, l: f64, weight: f64) -> Self {
        Self {
            angles: Angles::InPlane {
                theta_i_deg,
                theta_o_deg,
            },
            value: l,
            weight,
        }
    }

    /// A general point: spherical angles of `wi` and `wo`, measured BSDF `bsdf`.
    pub fn spherical(
        (theta_i_deg, phi_i_deg): (f64, f64),
        (theta_o_deg, phi_o_deg): (f64, f64),
        bsdf: f64,
        weight: f64,
    ) -> Self {
        Self {
            angles: Angles::Spherical {
                theta_i_deg,
                phi_i_deg,
                theta_o_deg,
                phi_o_deg,
            },
            value: bsdf,
            weight,
        }
    }

    /// The unit directions `(wi, wo)` in the surface frame.
    pub fn directions(&self) -> (Vec3, Vec3) {
        match self.angles {
            Angles::InPlane {
                theta_i_deg,
                theta_o_deg,
            } => pair_from_deg(theta_i_deg, theta_o_deg),
            Angles::Spherical {
                theta_i_deg,
                phi_i_deg,
                theta_o_deg,
                phi_o_deg,
            } => (
                spherical_from_deg(theta_i_deg, phi_i_deg),
                spherical_from_deg(theta_o_deg, phi_o_deg),
            ),
        }
    }

    /// Checks the angles against their file form's domain (`data-format.md`): an in-plane
    /// `theta_i` in [0, 90) and `theta_o` in (90, 270); general polar angles in [0, 180] but not
    /// 90, finite azimuths.
    pub fn check_angles(&self) -> Result<(), String> {
        let bad = |name: &str, value: f64, range: &str| {
            Err(format!(
                "{name} must be in {range} degrees, got {}",
                show(value)
            ))
        };
        match self.angles {
            Angles::InPlane {
                theta_i_deg,
                theta_o_deg,
            } => {
                if !theta_i_in_range(theta_i_deg) {
                    return bad("theta_i", theta_i_deg, THETA_I_RANGE);
                }
                if !theta_o_in_range(theta_o_deg) {
                    return bad("theta_o", theta_o_deg, THETA_O_RANGE);
                }
            }
            Angles::Spherical {
                theta_i_deg,
                phi_i_deg,
                theta_o_deg,
                phi_o_deg,
            } => {
                for (name, theta) in [("theta_i", theta_i_deg), ("theta_o", theta_o_deg)] {
                    if !theta_in_range(theta) {
                        return bad(name, theta, THETA_RANGE);
                    }
                }
                for (name, phi) in [("phi_i", phi_i_deg), ("phi_o", phi_o_deg)] {
                    if !phi.is_finite() {
                        return Err(format!("{name} must be finite, got {phi}"));
                    }
                }
            }
        }
        Ok(())
    }

    /// What [`Measurement::value`] is.
    pub fn quantity(&self) -> Quantity {
        match self.angles {
            Angles::InPlane { .. } => Quantity::L,
            Angles::Spherical { .. } => Quantity::Bsdf,
        }
    }

    /// The polar angle of `wi` from the outside normal as the file gave it, degrees: the same
    /// quantity in both file forms.
    pub fn theta_i_deg(&self) -> f64 {
        match self.angles {
            Angles::InPlane { theta_i_deg, .. } | Angles::Spherical { theta_i_deg, .. } => {
                theta_i_deg
            }
        }
    }

    /// The in-plane angles `(theta_i_deg, theta_o_deg)`, if this is an in-plane point.
    pub fn in_plane_angles(&self) -> Option<(f64, f64)> {
        match self.angles {
            Angles::InPlane {
                theta_i_deg,
                theta_o_deg,
            } => Some((theta_i_deg, theta_o_deg)),
            Angles::Spherical { .. } => None,
        }
    }

    /// The spherical angles `((theta_i_deg, phi_i_deg), (theta_o_deg, phi_o_deg))`, if this is
    /// a general point.
    pub fn spherical_angles(&self) -> Option<((f64, f64), (f64, f64))> {
        match self.angles {
            Angles::Spherical {
                theta_i_deg,
                phi_i_deg,
                theta_o_deg,
                phi_o_deg,
            } => Some(((theta_i_deg, phi_i_deg), (theta_o_deg, phi_o_deg))),
            Angles::InPlane { .. } => None,
        }
    }
}

/// The measurements of one physical sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// The sample's name (empty when the file has no `sample` column).
    pub name: String,
    pub points: Vec<Measurement>,
}

impl Sample {
    /// What the sample's points measure.
    pub fn measured(&self) -> Measured {
        Measured::of(self.points.iter().map(Measurement::quantity))
    }

    /// Whether every point is in-plane (the Walter form).
    pub fn is_in_plane(&self) -> bool {
        self.points
            .iter()
            .all(|p| matches!(p.angles, Angles::InPlane { .. }))
    }
}

/// Every sample read from one file (or several), in order of first appearance.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    /// Where the data came from, for messages (the file, or the first of several).
    pub source: PathBuf,
    pub samples: Vec<Sample>,
}
