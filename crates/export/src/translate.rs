//! Translation of a fitted model into a renderer's BSDF by fitting that BSDF to the fitted one
//! over the sphere of directions ([`SphereSet`]), with stfit's own optimiser
//! ([`stfit_fit::optimize::minimize`], Nelder-Mead), in the fit's units `sqrt(L)`.
//!
//! The translation error is the root-mean-square difference of `sqrt(L)` over the set
//! (solid-angle weighted over outgoing directions, averaged over the incidence directions).
//! The sensitivity of each target parameter `p` is read from the curvature of the mean square
//! error `E` at the optimum, other parameters held: `E(p + d) = E0 + (s d)^2`, so `s` (in
//! `sqrt(L)` per unit of `p`) is how fast the rmse grows away from the optimum, and
//! `sqrt(0.21 E0) / s` is the change of `p` that raises the rmse by 10%.

use rayon::prelude::*;
use stfit_core::Vec3;
use stfit_fit::Optimizer;
use stfit_fit::conventions::pair_from_deg;
use stfit_fit::optimize::minimize;

use crate::directions::{SphereSet, l_of, l_per_bsdf, resolved};
use crate::target::Scatter;
use crate::{ExportError, ExportModel};
use stfit_core::bsdf::AnalyticBsdf;

/// A fit's scale as `unit root^2`, with `root` a power of 2 (so that both products are exact)
/// and `unit` within a factor 2 of 1: `sqrt(scale v) = root sqrt(unit v)` exactly, and `unit v`
/// neither overflows nor underflows where `scale v` would (a fit to data of 1e307 has a scale
/// of 1e307, and `L` at a specular peak was infinite, the rmse NaN). A scale between 0.5 and 2
/// is its own unit (`root` 1), so nothing changes for it; for any other, every result in
/// `sqrt(L)` is the same to the bit wherever the direct products were finite and normal.
pub fn split_scale(scale: f64) -> (f64, f64) {
    let m = (scale.log2() / 2.0).round().clamp(-537.0, 512.0) as i32;
    let root = f64::from_bits(((1023 + m) as u64) << 52);
    (scale / root / root, root)
}

/// The fitted model's `sqrt(L)` over a [`SphereSet`], computed once per export.
///
/// Held in units of `sqrt(L / root^2)` ([`split_scale`]); [`Reference::rmse`] and
/// [`Reference::rms`] return the fit's units `sqrt(L)`.
#[derive(Debug, Clone)]
pub struct Reference {
    set: SphereSet,
    eta: f64,
    /// The scale's `unit` ([`split_scale`]).
    scale: f64,
    /// The scale's `root` ([`split_scale`]): `sqrt(L)` is `root` times the values held.
    root: f64,
    /// `sqrt(L) / root` per incidence direction (row of the set), per outgoing direction.
    sqrt_l: Vec<Vec<f64>>,
    /// Mean square of `sqrt(L) / root`: normalises the optimiser's cost to the order of 1.
    energy: f64,
    /// Incidences whose lobes even graded directions do not resolve ([`resolved`]).
    warnings: Vec<String>,
}

impl Reference {
    /// The fitted model's values over `set`, by the library's forward model (for an all-orders
    /// fit, with the fit's own walks and seed).
    pub fn new(model: &ExportModel, set: SphereSet) -> Result<Self, ExportError> {
        let eta = model.eta();
        let pairs = set.pairs();
        let q = pairs
            .iter()
            .map(|&(wi, wo)| l_per_bsdf(wi, wo, eta))
            .collect();
        let mut values = model.forward_values(&pairs, q)?.into_iter();
        let (scale, root) = split_scale(model.scale());
        let sqrt_l = set
            .rows
            .iter()
            .map(|row| {
                values
                    .by_ref()
                    .take(row.outgoing.len())
                    .map(|v| (scale * v).max(0.0).sqrt())
                    .collect()
            })
            .collect();
        let mut r = Self {
            set,
            eta,
            scale,
            root,
            sqrt_l,
            energy: 1.0,
            warnings: Vec::new(),
        };
        r.energy = r.mean_square(|_, _| 0.0).max(f64::MIN_POSITIVE);
        Ok(r)
    }

    /// The fitted model's values over the standard set, with outgoing directions graded about
    /// the peaks for the incidences whose lobes the standard nodes do not resolve
    /// ([`resolved`], judged on the model's single scattering, whose lobes are the narrow
    /// ones).
    pub fn standard(model: &ExportModel) -> Result<Self, ExportError> {
        let single = model.single();
        let (set, warnings) = resolved(|wi, wo| single.f_cos(wi, wo), model.eta(), model.alpha());
        let mut r = Self::new(model, set)?;
        r.warnings = warnings;
        Ok(r)
    }

    /// Estimated wall time, in seconds, of the walks of [`Reference::standard`] for `model`
    /// ([`ExportModel::forward_walk_seconds`] on the standard set's pairs; the graded rows that
    /// may replace some of them have as many walks): 0 for a single-scattering fit.
    pub fn walk_seconds(model: &ExportModel) -> Result<f64, ExportError> {
        model.forward_walk_seconds(&SphereSet::standard().pairs())
    }

    /// Warnings for the export: incidences whose lobes even graded outgoing directions do not
    /// resolve, where the translation's error is uncertain.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Mean square difference between `sqrt(L)` of `f_cos` and the reference: per incidence
    /// the weighted mean over its outgoing directions, then the mean over incidences.
    fn mean_square(&self, f_cos: impl Fn(Vec3, Vec3) -> f64 + Sync) -> f64 {
        let per_incidence: Vec<f64> = self
            .set
            .rows
            .par_iter()
            .zip(&self.sqrt_l)
            .map(|(row, refs)| {
                let total_w: f64 = row.weights.iter().sum();
                let mut s = 0.0;
                for ((&wo, &w), &r) in row.outgoing.iter().zip(&row.weights).zip(refs) {
                    let v = l_of(f_cos(row.wi, wo), row.wi, wo, self.eta, self.scale)
                        .max(0.0)
                        .sqrt();
                    s += w * (v - r) * (v - r);
                }
                s / total_w
            })
            .collect();
        per_incidence.iter().sum::<f64>() / per_incidence.len() as f64
    }

    /// Root-mean-square difference of `sqrt(L)` between `target` and the fitted model.
    pub fn rmse(&self, target: &impl Scatter) -> f64 {
        self.unit_rmse(target) * self.root
    }

    /// [`Reference::rmse`] in the units held, `sqrt(L) / root`, whose square cannot overflow.
    fn unit_rmse(&self, target: &impl Scatter) -> f64 {
        self.mean_square(|wi, wo| target.f_cos(wi, wo)).sqrt()
    }

    /// Root mean square of the fitted model's own `sqrt(L)` over the set (same weights as
    /// [`Reference::rmse`]; at least `sqrt(f64::MIN_POSITIVE)`): the scale a translation's
    /// rmse is relative to.
    pub fn rms(&self) -> f64 {
        self.energy.sqrt() * self.root
    }
}

/// Relative size of rounding: a translation whose rmse is below this times the reference's
/// rms ([`Reference::rms`]) is an exact mapping up to floating-point rounding.
pub const ROUNDING: f64 = 1e-9;

/// Whether `rmse` is rounding relative to a reference of rms `reference_rms` ([`ROUNDING`]):
/// relative, so that a fit's scale (1e-12 or 1e12: `sqrt(L)` scales with `sqrt(scale)`)
/// neither makes a real error look like rounding nor rounding look like an error.
pub fn is_rounding(rmse: f64, reference_rms: f64) -> bool {
    rmse <= ROUNDING * reference_rms
}

/// `x` with four decimals (`0.0123`), or with four significant digits in scientific notation
/// where four decimals would show none (`3.2145e-9`, an rmse of a fit at scale 1e-12) or it is
/// 1e6 or more: a small nonzero value is not printed as 0.0000.
pub fn four_digits(x: f64) -> String {
    if x == 0.0 || (5e-5..1e6).contains(&x.abs()) {
        format!("{x:.4}")
    } else {
        format!("{x:.4e}")
    }
}

/// An rmse of `sqrt(L)` as the comments print it: `0.0000` where it is rounding relative to
/// the fitted model's rms `reference_rms` ([`is_rounding`]), else [`four_digits`].
pub fn rmse_text(rmse: f64, reference_rms: f64) -> String {
    if is_rounding(rmse, reference_rms) {
        four_digits(0.0)
    } else {
        four_digits(rmse)
    }
}

/// A family of target BSDFs with parameters in the renderer's own units.
pub trait Family {
    type Bsdf: Scatter;
    /// Parameter names as the renderer spells them.
    fn names(&self) -> Vec<&'static str>;
    /// The BSDF for parameters `p` (renderer units), or an error outside their range.
    fn build(&self, p: &[f64]) -> Result<Self::Bsdf, ExportError>;
    /// Renderer parameters of unbounded search coordinates (each within its valid range).
    fn params_of(&self, x: &[f64]) -> Vec<f64>;
    /// Search coordinates of renderer parameters.
    fn search_of(&self, p: &[f64]) -> Vec<f64>;
    /// Starting points of the search, in renderer units.
    fn starts(&self) -> Vec<Vec<f64>>;
}

/// One translated parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    pub name: &'static str,
    pub value: f64,
    /// `s`: growth of the rmse (`sqrt(L)`) per unit change of the parameter at the optimum.
    pub rmse_per_unit: f64,
    /// Change of the parameter that raises the rmse by 10% (`None` where the rmse is 0 or the
    /// curvature vanishes).
    pub change_for_10pct: Option<f64>,
}

/// A translation: target parameters, their sensitivity and the error.
#[derive(Debug, Clone, PartialEq)]
pub struct Translation {
    pub params: Vec<Parameter>,
    /// rmse of `sqrt(L)` over the sphere of directions (fit units).
    pub rmse: f64,
    /// rmse of `sqrt(L)` over the measurement grid of the data (light from air at 0, 30, 60,
    /// 80 degrees, transmitted 106 to 254 degrees in steps of 2, in the plane of incidence):
    /// the translation's error where the fit was made, comparable with the fit's own rmse.
    pub rmse_measured_grid: f64,
    /// True when the parameters are an exact mapping of the fitted NDF (no optimisation).
    pub exact_ndf: bool,
    /// Optimiser iterations (0 for an exact mapping).
    pub iterations: u64,
    /// Root mean square of the fitted model's `sqrt(L)` over the sphere of directions
    /// ([`Reference::rms`]): what `rmse` is relative to.
    pub reference_rms: f64,
}

impl Translation {
    /// The value of parameter `name`.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.params.iter().find(|p| p.name == name).map(|p| p.value)
    }

    /// A one-line summary for comments.
    pub fn summary(&self) -> String {
        let how = if self.exact_ndf {
            "NDF mapped exactly; error from the renderer's masking term"
        } else {
            "fitted over the sphere of directions (Nelder-Mead)"
        };
        format!(
            "{how}; rmse sqrt(L): {} over the sphere of directions, {} over the measurement grid",
            rmse_text(self.rmse, self.reference_rms),
            rmse_text(self.rmse_measured_grid, self.reference_rms)
        )
    }

    /// Whether the rmse is rounding relative to the fitted model's own values
    /// ([`is_rounding`]).
    pub fn exact_to_rounding(&self) -> bool {
        is_rounding(self.rmse, self.reference_rms)
    }

    /// One line per parameter: value, rmse growth per unit and the change for +10% rmse (none
    /// where the mapping's rmse is rounding ([`Translation::exact_to_rounding`]): 10% of it
    /// means nothing).
    pub fn sensitivity_lines(&self) -> Vec<String> {
        self.params
            .iter()
            .map(|p| {
                let ten = match p.change_for_10pct {
                    _ if self.exact_to_rounding() => {
                        "- (the mapping is exact to rounding)".to_string()
                    }
                    Some(d) => format!("{d:.3e}"),
                    None => "-".to_string(),
                };
                format!(
                    "{} = {:.6}: rmse grows {:.3e} sqrt(L) per unit; change for +10% rmse {}",
                    p.name, p.value, p.rmse_per_unit, ten
                )
            })
            .collect()
    }
}

/// The measurement grid of the data (see [`Translation::rmse_measured_grid`]).
pub fn measured_grid() -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for ti in [0.0, 30.0, 60.0, 80.0] {
        for k in 0..75 {
            v.push((ti, 106.0 + 2.0 * k as f64));
        }
    }
    v
}

/// rmse of `sqrt(L)` between `target` and the fitted model over `grid` (`(theta_i,
/// theta_o)` in degrees, data convention), the fitted model by [`stfit_fit::Model::predict`].
pub fn grid_rmse(
    model: &ExportModel,
    target: &impl Scatter,
    grid: &[(f64, f64)],
) -> Result<f64, ExportError> {
    // In units of sqrt(L) / root (split_scale), as the reference.
    let (scale, root) = split_scale(model.scale());
    let unit_model = stfit_fit::Model {
        scale,
        ..model.model
    };
    let fitted = unit_model.predict(grid)?;
    let s: f64 = grid
        .iter()
        .zip(&fitted)
        .map(|(&(ti, to), &l)| {
            let (wi, wo) = pair_from_deg(ti, to);
            let t = l_of(target.f_cos(wi, wo), wi, wo, model.eta(), scale);
            (l.max(0.0).sqrt() - t.max(0.0).sqrt()).powi(2)
        })
        .sum();
    Ok((s / grid.len().max(1) as f64).sqrt() * root)
}

/// Sensitivity of each parameter at `p` (see the module docs), from the mean square error `e0`
/// at `p` in the reference's units ([`Reference::unit_rmse`] squared).
fn sensitivity<F: Family>(
    family: &F,
    reference: &Reference,
    p: &[f64],
    e0: f64,
) -> Result<Vec<Parameter>, ExportError> {
    let names = family.names();
    let mut out = Vec::with_capacity(p.len());
    for k in 0..p.len() {
        let h = 1e-3 * p[k].abs().max(1e-2);
        let mut e = [0.0; 2];
        for (j, sign) in [1.0, -1.0].into_iter().enumerate() {
            let mut q = p.to_vec();
            q[k] += sign * h;
            // Stay inside the renderer's range: a one-sided difference at a bound.
            let q = family.params_of(&family.search_of(&q));
            e[j] = reference.unit_rmse(&family.build(&q)?).powi(2);
        }
        let curv = ((e[0] + e[1] - 2.0 * e0) / (h * h)).max(0.0);
        let s = (0.5 * curv).sqrt();
        out.push(Parameter {
            name: names[k],
            value: p[k],
            rmse_per_unit: s * reference.root,
            change_for_10pct: (e0 > 0.0 && s > 0.0).then(|| (0.21 * e0).sqrt() / s),
        });
    }
    Ok(out)
}

/// Evaluates fixed target parameters (an exact NDF mapping): error and sensitivity.
pub fn evaluate<F: Family>(
    family: &F,
    model: &ExportModel,
    reference: &Reference,
    p: &[f64],
) -> Result<Translation, ExportError> {
    let bsdf = family.build(p)?;
    let unit_rmse = reference.unit_rmse(&bsdf);
    Ok(Translation {
        params: sensitivity(family, reference, p, unit_rmse * unit_rmse)?,
        rmse: unit_rmse * reference.root,
        rmse_measured_grid: grid_rmse(model, &bsdf, &measured_grid())?,
        exact_ndf: true,
        iterations: 0,
        reference_rms: reference.rms(),
    })
}

/// Fits the family to the fitted model over the sphere of directions, adding a warning to
/// `warnings` for each parameter that ends on a bound of its range.
pub fn fit<F: Family>(
    family: &F,
    model: &ExportModel,
    reference: &Reference,
    warnings: &mut Vec<String>,
) -> Result<Translation, ExportError> {
    let cost = |x: &[f64]| {
        let p = family.params_of(x);
        family.build(&p).map_or(f64::INFINITY, |b| {
            reference.unit_rmse(&b).powi(2) / reference.energy
        })
    };
    let mut best: Option<stfit_fit::optimize::Minimum> = None;
    let mut iterations = 0;
    let mut last_err = None;
    for start in family.starts() {
        match minimize(cost, &family.search_of(&start), Optimizer::NelderMead) {
            Ok(m) => {
                iterations += m.iterations;
                if best.as_ref().is_none_or(|b| m.cost < b.cost) {
                    best = Some(m);
                }
            }
            Err(e) => last_err = Some(e.to_string()),
        }
    }
    let best = best.ok_or_else(|| {
        ExportError::Optimizer(last_err.unwrap_or_else(|| "no starting point".into()))
    })?;
    let p = family.params_of(&best.x);
    for (k, name) in family.names().into_iter().enumerate() {
        if at_search_bound(family, &best.x, k) {
            warnings.push(format!(
                "{name} {:.6} ended on a bound of its range: the renderer's BSDF nearest the \
                 fitted one may need a value beyond it; the translation's error is as stated",
                p[k]
            ));
        }
    }
    let bsdf = family.build(&p)?;
    let unit_rmse = reference.unit_rmse(&bsdf);
    Ok(Translation {
        params: sensitivity(family, reference, &p, unit_rmse * unit_rmse)?,
        rmse: unit_rmse * reference.root,
        rmse_measured_grid: grid_rmse(model, &bsdf, &measured_grid())?,
        exact_ndf: false,
        iterations,
        reference_rms: reference.rms(),
    })
}

/// Whether parameter `k` at search coordinates `x` is held on a bound of its range: a step of
/// the coordinate outward, either way, leaves the parameter where it is (the families' maps
/// clamp their coordinates to the range searched).
fn at_search_bound<F: Family>(family: &F, x: &[f64], k: usize) -> bool {
    let at = family.params_of(x)[k];
    [-1.0, 1.0].into_iter().any(|d| {
        let mut y = x.to_vec();
        y[k] += d * 1e-6 * (1.0 + x[k].abs());
        family.params_of(&y)[k] == at
    })
}

/// `ln` mapping of a positive parameter bounded to `[lo, hi]`.
pub fn log_coord(p: f64, lo: f64, hi: f64) -> f64 {
    p.clamp(lo, hi).ln()
}

/// Inverse of [`log_coord`].
pub fn from_log_coord(x: f64, lo: f64, hi: f64) -> f64 {
    x.clamp(lo.ln(), hi.ln()).exp()
}

/// Logistic mapping of a parameter in `(0, 1)`.
pub fn unit_coord(p: f64) -> f64 {
    let p = p.clamp(1e-9, 1.0 - 1e-9);
    (p / (1.0 - p)).ln()
}

/// Inverse of [`unit_coord`].
pub fn from_unit_coord(x: f64) -> f64 {
    1.0 / (1.0 + (-x).exp())
}
