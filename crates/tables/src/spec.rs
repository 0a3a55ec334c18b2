//! What a table holds: the surface, the NDF family, the masking, the scattering orders and the
//! axes, with the order of its cells.
//!
//! Cells are ordered by side, then gamma, then eta, then mu, with alpha varying fastest: cell
//! `(s, g, z, y, x)` has index `(((s * G + g) * Z + z) * Y + y) * X + x` for axes of lengths
//! `G` (gamma), `Z` (eta), `Y` (mu) and `X` (alpha). A *line* is the cells of one
//! `(side, gamma, eta, alpha)`: all cosines, and the cosine-weighted average.

use crate::error::SpecError;
use crate::grid::{Axis, cycles_ior, cycles_mu, cycles_roughness};
use crate::single::{Interface, TableMasking};
use serde::{Deserialize, Serialize};
use stfit_core::Vec3;
use stfit_core::error::show;
use stfit_core::walk::{ConductorFacet, DielectricFacet, ScatteringOrders};

/// The NDF family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    Beckmann,
    Ggx,
    StudentT,
}

impl Family {
    /// The name used on the command line and in CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Beckmann => "beckmann",
            Self::Ggx => "ggx",
            Self::StudentT => "student-t",
        }
    }

    /// The name used in C identifiers.
    pub fn c_name(self) -> &'static str {
        match self {
            Self::StudentT => "student_t",
            other => other.name(),
        }
    }
}

/// The facet material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Surface {
    /// A dielectric interface; the eta axis gives `n_inside / n_outside > 1`.
    Dielectric,
    /// A conductor of complex index `n + i k` relative to the outside medium (exact unpolarised
    /// Fresnel reflectance).
    Conductor { n: f64, k: f64 },
    /// Facets that reflect everything (`F = 1`): the table renderers' energy compensation for
    /// metals is built on (Kulla and Conty 2017; Cycles' `ggx_E`).
    Mirror,
}

impl Surface {
    /// The name used in CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Dielectric => "dielectric",
            Self::Conductor { .. } => "conductor",
            Self::Mirror => "mirror",
        }
    }
}

/// Where the light comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// From the outside medium (air), `wi.z > 0`.
    Outside,
    /// From inside the dielectric, `wi.z < 0` (Cycles' `inv` tables).
    Inside,
}

impl Side {
    /// The name used on the command line and in CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Outside => "outside",
            Self::Inside => "inside",
        }
    }
}

/// Supported roughness range.
pub const ALPHA_RANGE: (f64, f64) = (1e-8, 4.0);
/// Supported Student-T shape range.
pub const GAMMA_RANGE: (f64, f64) = (1.6, 40.0);
/// Supported range of the cosine of incidence.
pub const MU_RANGE: (f64, f64) = (1e-4, 1.0);
/// Supported relative index range, `eta > 1` (open below).
pub const ETA_RANGE: (f64, f64) = (1.0, 100.0);
/// Supported range of a conductor's `n`; `k` is in `[0, CONDUCTOR_RANGE.1]`.
pub const CONDUCTOR_RANGE: (f64, f64) = (stfit_core::error::CONDUCTOR_N_MIN, 100.0);
/// Largest number of cells of a table (2^24, 64^4): the results are held in memory and the
/// file is written at once, about 100 bytes per cell in memory and 250 in a CSV file, and
/// single scattering alone takes 1 to 4 ms of CPU time per cell. Axes of up to
/// [`crate::grid::MAX_NODES`] nodes each could otherwise ask for 2^37 lines (an allocation of
/// a terabyte, which aborted the process).
pub const MAX_CELLS: usize = 1 << 24;
/// Largest number of walks per cell: the walks' own rule ([`stfit_core::walk::check_walks`]).
pub use stfit_core::walk::MAX_WALKS;

/// A table to compute.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableSpec {
    pub family: Family,
    pub surface: Surface,
    /// The masking of the tabulated single-scattering albedo `E_ss`.
    pub masking: TableMasking,
    /// `Single`: `E_ss` only; `Multiple`: also orders >= 2 by random walks; `All`: also all
    /// orders (`E_ss` with height-correlated masking plus the walks' orders >= 2).
    #[serde(with = "orders_name")]
    pub orders: ScatteringOrders,
    /// The sides, in order (outside before inside).
    pub sides: Vec<Side>,
    pub alpha: Axis,
    /// Student-T only.
    pub gamma: Option<Axis>,
    /// Dielectrics only.
    pub eta: Option<Axis>,
    pub mu: Axis,
    /// Walks per cell (orders >= 2).
    pub walks: u64,
    /// Seed of the walks; every cell uses the same random numbers (common random numbers).
    pub seed: u64,
}

/// The position of a line: indices into the sides and the gamma, eta and alpha axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Line {
    pub side: usize,
    pub gamma: usize,
    pub eta: usize,
    pub alpha: usize,
}

impl TableSpec {
    /// What the random walks of a table (or shard) of this specification are, for a note
    /// before a long run.
    pub fn walks_description(&self) -> String {
        format!("the random walks of the table ({} per cell)", self.walks)
    }

    /// The nodes of Blender Cycles' tables (`src/app/cycles_precompute.cpp`): for a dielectric
    /// the 16 x 16 x 16 nodes of `ggx_glass_E` and `ggx_glass_inv_E`, both sides
    /// ([`cycles_roughness`], [`cycles_mu`], [`cycles_ior`]); for a conductor or mirror the
    /// 32 x 32 nodes of `ggx_E`.
    pub fn cycles(
        family: Family,
        surface: Surface,
        masking: TableMasking,
        orders: ScatteringOrders,
        gamma: Option<Axis>,
    ) -> Self {
        let (n, sides, eta) = match surface {
            Surface::Dielectric => (16, vec![Side::Outside, Side::Inside], Some(cycles_ior(16))),
            _ => (32, vec![Side::Outside], None),
        };
        Self {
            family,
            surface,
            masking,
            orders,
            sides,
            alpha: cycles_roughness(n),
            gamma,
            eta,
            mu: cycles_mu(n),
            walks: 100_000,
            seed: 1,
        }
    }

    /// Checks the specification against the supported ranges and the options that go together.
    pub fn check(&self) -> Result<(), SpecError> {
        let invalid = |m: &str| Err(SpecError::Invalid(m.into()));
        self.alpha
            .check_range("alpha", ALPHA_RANGE.0, false, ALPHA_RANGE.1)?;
        self.mu.check_range("mu", MU_RANGE.0, false, MU_RANGE.1)?;
        match (self.family, &self.gamma) {
            (Family::StudentT, Some(g)) => {
                g.check_range("gamma", GAMMA_RANGE.0, false, GAMMA_RANGE.1)?
            }
            (Family::StudentT, None) => return invalid("student-t needs a gamma axis"),
            (_, Some(_)) => return invalid("a gamma axis applies only to student-t"),
            _ => {}
        }
        match (self.surface, &self.eta) {
            (Surface::Dielectric, Some(e)) => {
                e.check_range("eta", ETA_RANGE.0, true, ETA_RANGE.1)?
            }
            (Surface::Dielectric, None) => return invalid("a dielectric needs an eta axis"),
            (_, Some(_)) => return invalid("an eta axis applies only to a dielectric"),
            _ => {}
        }
        self.check_walked_eta()?;
        if let Surface::Conductor { n, k } = self.surface {
            let (lo, hi) = CONDUCTOR_RANGE;
            if !((lo..=hi).contains(&n) && (0.0..=hi).contains(&k)) {
                return Err(SpecError::Invalid(format!(
                    "conductor index n = {}, k = {} is outside the supported range of tables: \
                     n in [{lo}, {hi}], k in [0, {hi}]",
                    show(n),
                    show(k)
                )));
            }
        }
        if self.sides.is_empty() || !self.sides.windows(2).all(|w| w[0] < w[1]) {
            return invalid("sides must be outside, inside, or outside then inside");
        }
        let shape = self.shape();
        if shape
            .iter()
            .try_fold(1usize, |n, &len| n.checked_mul(len))
            .is_none_or(|cells| cells > MAX_CELLS)
        {
            return Err(SpecError::Invalid(format!(
                "the table has {} cells (sides x gamma x eta x mu x alpha = {}), more than the \
                 {MAX_CELLS} a table may have: use fewer nodes",
                shape.iter().map(|&n| n as f64).product::<f64>(),
                shape.map(|n| n.to_string()).join(" x ")
            )));
        }
        if self.surface != Surface::Dielectric && self.sides != [Side::Outside] {
            return invalid("conductors and mirrors are two-sided: tabulate side outside only");
        }
        if self.orders != ScatteringOrders::Single
            && stfit_core::walk::check_walks(self.walks).is_err()
        {
            return Err(SpecError::Invalid(format!(
                "walks per cell must be in [1, {MAX_WALKS}], got {}",
                self.walks
            )));
        }
        Ok(())
    }

    /// With walks (orders >= 2), checks every eta against the walks' own rule
    /// ([`DielectricFacet::new`]: `|eta - 1| >= stfit_core::error::ETA_NEAR_ONE`), so that a
    /// table they cannot compute is refused before any work.
    fn check_walked_eta(&self) -> Result<(), SpecError> {
        let Some(eta) = self.eta.as_ref().filter(|_| self.walks_needed()) else {
            return Ok(());
        };
        for &v in &eta.values {
            DielectricFacet::new(v).map_err(|e| SpecError::Axis {
                axis: "eta",
                message: format!(
                    "value {} cannot be walked (orders multiple and all need random walks): {e}",
                    show(v)
                ),
            })?;
        }
        Ok(())
    }

    /// The lengths of the axes in cell order: sides, gamma, eta, mu, alpha (1 for an axis that
    /// does not apply).
    pub fn shape(&self) -> [usize; 5] {
        [
            self.sides.len(),
            self.gamma.as_ref().map_or(1, Axis::len),
            self.eta.as_ref().map_or(1, Axis::len),
            self.mu.len(),
            self.alpha.len(),
        ]
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.shape().iter().product()
    }

    /// Number of lines: cells of one (side, gamma, eta, alpha).
    pub fn lines(&self) -> usize {
        let [s, g, z, _, x] = self.shape();
        s * g * z * x
    }

    /// The position of line `i` (lines are ordered like cells, without the mu axis).
    pub fn line(&self, i: usize) -> Line {
        let [_, g, z, _, x] = self.shape();
        Line {
            alpha: i % x,
            eta: (i / x) % z,
            gamma: (i / (x * z)) % g,
            side: i / (x * z * g),
        }
    }

    /// The index of the cell of line `line` at cosine index `mu`.
    pub fn cell_index(&self, line: Line, mu: usize) -> usize {
        let [_, g, z, y, x] = self.shape();
        (((line.side * g + line.gamma) * z + line.eta) * y + mu) * x + line.alpha
    }

    /// Whether walks are run (orders >= 2 are asked for).
    pub fn walks_needed(&self) -> bool {
        self.orders != ScatteringOrders::Single
    }

    /// The Student-T shape of a line (2 for GGX, `None` for Beckmann).
    pub fn gamma_value(&self, line: Line) -> Option<f64> {
        match self.family {
            Family::StudentT => self.gamma.as_ref().map(|g| g.values[line.gamma]),
            Family::Ggx => Some(2.0),
            Family::Beckmann => None,
        }
    }

    /// The relative index `n_inside / n_outside` of a line (dielectrics).
    pub fn eta_value(&self, line: Line) -> Option<f64> {
        self.eta.as_ref().map(|e| e.values[line.eta])
    }

    /// What the facets do with light arriving on the line's side, in the frame where the light
    /// comes from above.
    pub fn interface(&self, line: Line) -> Result<Interface, SpecError> {
        Ok(match self.surface {
            Surface::Dielectric => {
                let eta = self
                    .eta_value(line)
                    .ok_or_else(|| SpecError::Invalid("a dielectric needs an eta axis".into()))?;
                Interface::Dielectric {
                    eta_rel: match self.sides[line.side] {
                        Side::Outside => eta,
                        Side::Inside => 1.0 / eta,
                    },
                }
            }
            Surface::Conductor { .. } | Surface::Mirror => Interface::Conductor(self.conductor()?),
        })
    }

    /// The facets of a conductor or mirror surface.
    pub fn conductor(&self) -> Result<ConductorFacet, SpecError> {
        match self.surface {
            Surface::Conductor { n, k } => ConductorFacet::fresnel(n, k)
                .map_err(|e| SpecError::Invalid(format!("conductor index: {e}"))),
            _ => Ok(ConductorFacet::mirror()),
        }
    }

    /// The direction toward the light for a line's side and cosine `mu` (in the xz-plane).
    pub fn wi(&self, line: Line, mu: f64) -> Vec3 {
        let s = (1.0 - mu * mu).max(0.0).sqrt();
        match self.sides[line.side] {
            Side::Outside => Vec3::new(s, 0.0, mu),
            Side::Inside => Vec3::new(s, 0.0, -mu),
        }
    }
}

/// `ScatteringOrders` by name in files: `single`, `multiple`, `all`.
mod orders_name {
    use serde::{Deserialize, Deserializer, Serializer};
    use stfit_core::walk::ScatteringOrders;

    pub fn serialize<S: Serializer>(o: &ScatteringOrders, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(super::orders_str(*o))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<ScatteringOrders, D::Error> {
        let name = String::deserialize(d)?;
        super::parse_orders(&name).map_err(serde::de::Error::custom)
    }
}

/// The name of a choice of scattering orders: `single`, `multiple` or `all`.
pub fn orders_str(o: ScatteringOrders) -> &'static str {
    match o {
        ScatteringOrders::Single => "single",
        ScatteringOrders::Multiple => "multiple",
        ScatteringOrders::All => "all",
    }
}

/// The scattering orders named `single`, `multiple` or `all`.
pub fn parse_orders(name: &str) -> Result<ScatteringOrders, String> {
    match name {
        "single" => Ok(ScatteringOrders::Single),
        "multiple" => Ok(ScatteringOrders::Multiple),
        "all" => Ok(ScatteringOrders::All),
        other => Err(format!(
            "unknown orders '{other}' (expected single, multiple or all)"
        )),
    }
}
