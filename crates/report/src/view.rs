//! What the figures show, computed once per sample: measured points grouped by incidence
//! angle, and for every fitted model its curves and residuals in the plotted scale.

use stfit_core::Vec3;
use stfit_core::ndf::{AnyNdf, Ndf};
use stfit_fit::{FitResult, Measurement, ModelKind, Sample};

use crate::{ReportError, ReportOptions, YScale};

/// Points per model curve across the measured range of `theta_o`.
const CURVE_POINTS: usize = 401;

/// The four panels of a sample figure, in the seed paper's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ModelSlot {
    Beckmann,
    Ggx,
    /// Student-T with gamma held fixed (3 in the published comparison).
    StudentTFixed,
    /// Student-T with gamma fitted.
    StudentTFree,
}

impl ModelSlot {
    /// Every slot, in panel order.
    pub const ALL: [Self; 4] = [
        Self::Beckmann,
        Self::Ggx,
        Self::StudentTFixed,
        Self::StudentTFree,
    ];

    /// The panel a fit belongs to.
    pub fn of(fit: &FitResult) -> Self {
        match (fit.model.kind, fit.model.gamma.is_fixed()) {
            (ModelKind::Beckmann, _) => Self::Beckmann,
            (ModelKind::Ggx, _) => Self::Ggx,
            (ModelKind::StudentT, true) => Self::StudentTFixed,
            (ModelKind::StudentT, false) => Self::StudentTFree,
        }
    }

    /// The panel's position, 0 to 3.
    pub fn index(self) -> usize {
        self as usize
    }

    /// Human-readable model name for titles and tables.
    pub fn title(self) -> &'static str {
        match self {
            Self::Beckmann => "Beckmann",
            Self::Ggx => "GGX",
            Self::StudentTFixed => "Student-T, γ fixed",
            Self::StudentTFree => "Student-T, γ free",
        }
    }
}

/// A measured point in plot coordinates: `(theta_o in degrees, y)`.
pub(crate) type Point = (f64, f64);

/// The measurements of one incidence angle.
#[derive(Debug, Clone)]
pub(crate) struct AngleGroup {
    pub theta_i_deg: f64,
    /// Measured points sorted by `theta_o`, y in the report's scale.
    pub points: Vec<Point>,
    /// The measured `L` of each point (same order), for residuals.
    pub l: Vec<f64>,
    /// Whether each point was fitted: points of weight 0 are plotted hollow and left out of
    /// the rmse, as the fit leaves them out.
    pub fitted: Vec<bool>,
}

/// One fitted model of a sample, evaluated for plotting.
#[derive(Debug, Clone)]
pub(crate) struct PanelView<'a> {
    pub fit: &'a FitResult,
    pub ndf: AnyNdf,
    /// One curve per [`AngleGroup`], y in the report's scale.
    pub curves: Vec<Vec<Point>>,
    /// Measured minus model, in the report's scale, per [`AngleGroup`].
    pub residuals: Vec<Vec<Point>>,
    /// The squared residuals of `sqrt(L)` over the fitted points (weight > 0), recomputed
    /// from the data and the fitted parameters.
    pub sq_sum: SquareSum,
}

/// A sum of squares that neither overflows nor loses small terms, for the rms of residuals of
/// values up to the largest double (whose square roots' squares add up past it): kept as
/// `scale^2 * ssq` with `scale` the largest magnitude added (LAPACK's `dnrm2`). A NaN term
/// makes the rms NaN.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct SquareSum {
    scale: f64,
    ssq: f64,
    /// The number of terms.
    pub n: usize,
}

impl SquareSum {
    /// Adds `d * d`.
    pub fn add(&mut self, d: f64) {
        self.n += 1;
        let a = d.abs();
        if a.is_nan() {
            self.ssq = f64::NAN;
        } else if a > self.scale {
            self.ssq = 1.0 + self.ssq * (self.scale / a).powi(2);
            self.scale = a;
        } else if a > 0.0 {
            self.ssq += (a / self.scale).powi(2);
        }
    }

    /// The sum of both sums' terms.
    pub fn merge(self, other: Self) -> Self {
        let (big, small) = if other.scale > self.scale {
            (other, self)
        } else {
            (self, other)
        };
        let ssq = if big.scale > 0.0 {
            big.ssq + small.ssq * (small.scale / big.scale).powi(2)
        } else {
            big.ssq + small.ssq
        };
        Self {
            scale: big.scale,
            ssq,
            n: self.n + other.n,
        }
    }

    /// The root mean square of the terms, 0 for none.
    pub fn rms(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.scale * (self.ssq / self.n as f64).sqrt()
        }
    }
}

/// The model value `scale * unit` (`unit` the model at scale 1) in the plotted scale `y`,
/// computed so that a value near or past the largest double does not overflow: on the square
/// root axis `sqrt(scale) sqrt(unit)`, always finite; on the linear axis `scale * unit`, a
/// value past the largest double being drawn at it (above the top of the chart).
pub(crate) fn plotted_model(y: YScale, scale: f64, unit: f64) -> f64 {
    match y {
        YScale::Sqrt => scale.sqrt() * YScale::Sqrt.apply(unit),
        YScale::Linear => (scale * unit).clamp(-f64::MAX, f64::MAX),
    }
}

/// The model of `fit` at `points` at scale 1 (the fitted scale is applied by
/// [`plotted_model`]): a fit of values near the largest double, whose model at points between
/// the measured ones can exceed it, is still drawn.
pub(crate) fn unit_predictions(
    fit: &FitResult,
    points: &[Measurement],
) -> Result<Vec<f64>, stfit_fit::FitError> {
    let unit = stfit_fit::Model {
        scale: 1.0,
        ..fit.model
    };
    unit.predict_points(points)
}

/// A sample with everything its figures need.
#[derive(Debug, Clone)]
pub(crate) struct SampleView<'a> {
    pub name: &'a str,
    pub groups: Vec<AngleGroup>,
    /// Range of `theta_o` covered by the measurements, degrees.
    pub theta_o_range: (f64, f64),
    pub panels: [Option<PanelView<'a>>; 4],
}

impl YScale {
    /// The plotted value of an `L`: `sqrt(L)` (signed, so negative measured values stay
    /// visible) or `L` itself.
    pub fn apply(self, l: f64) -> f64 {
        match self {
            Self::Sqrt => l.signum() * l.abs().sqrt(),
            Self::Linear => l,
        }
    }

    /// Axis label of the plotted quantity.
    pub(crate) fn label(self) -> &'static str {
        match self {
            Self::Sqrt => "√L",
            Self::Linear => "L",
        }
    }
}

/// Groups a sample's points by incidence angle (ascending) and sorts each group by `theta_o`.
fn angle_groups(sample: &Sample, y: YScale) -> Vec<AngleGroup> {
    let mut points: Vec<_> = sample
        .points
        .iter()
        .filter_map(|m| m.in_plane_angles().map(|(ti, to)| (ti, to, m)))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut groups: Vec<AngleGroup> = Vec::new();
    for (theta_i_deg, theta_o_deg, m) in points {
        if groups.last().is_none_or(|g| g.theta_i_deg != theta_i_deg) {
            groups.push(AngleGroup {
                theta_i_deg,
                points: Vec::new(),
                l: Vec::new(),
                fitted: Vec::new(),
            });
        }
        let g = groups.last_mut().expect("a group was just pushed");
        g.points.push((theta_o_deg, y.apply(m.value)));
        g.l.push(m.value);
        g.fitted.push(m.weight > 0.0);
    }
    groups
}

/// A sample's points grouped by incidence angle ([`angle_groups`]) and the range of `theta_o`
/// they cover, in degrees; an empty sample is refused.
fn layout(sample: &Sample, y: YScale) -> Result<(Vec<AngleGroup>, (f64, f64)), ReportError> {
    if sample.points.is_empty() {
        return Err(ReportError::EmptySample(sample.name.clone()));
    }
    let groups = angle_groups(sample, y);
    let range = groups
        .iter()
        .flat_map(|g| g.points.iter().map(|p| p.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
    Ok((groups, range))
}

/// The `theta_o` of a curve's point `k` of [`CURVE_POINTS`], evenly across `(x0, x1)`.
fn curve_x((x0, x1): (f64, f64), k: usize) -> f64 {
    x0 + (x1 - x0) * k as f64 / (CURVE_POINTS - 1) as f64
}

/// The points at which a panel evaluates its model, in one batch (for an all-orders model,
/// one set of walks per incidence angle): per [`AngleGroup`], [`CURVE_POINTS`] points of its
/// curve evenly across `(x0, x1)`, then its measured points.
fn panel_points(groups: &[AngleGroup], range: (f64, f64)) -> Vec<Measurement> {
    let mut points = Vec::new();
    for g in groups {
        points.extend(
            (0..CURVE_POINTS)
                .map(|k| Measurement::in_plane(g.theta_i_deg, curve_x(range, k), 0.0, 1.0)),
        );
        points.extend(
            g.points
                .iter()
                .map(|&(x, _)| Measurement::in_plane(g.theta_i_deg, x, 0.0, 1.0)),
        );
    }
    points
}

/// The summed [`Model::walk_seconds`](stfit_fit::Model::walk_seconds) of a sample's `fits`
/// at the points of their panel: 0 for single-scattering fits and for a fit the points refuse.
pub(crate) fn walk_seconds_at(fits: [Option<&FitResult>; 4], points: &[Measurement]) -> f64 {
    fits.iter()
        .flatten()
        .map(|f| f.model.walk_seconds(points).unwrap_or(0.0))
        .sum()
}

fn panel_view<'a>(
    fit: &'a FitResult,
    groups: &[AngleGroup],
    range: (f64, f64),
    opts: &ReportOptions,
) -> Result<PanelView<'a>, ReportError> {
    let ndf = drawable_ndf(fit)?;
    let invalid = |e| ReportError::invalid_fit(fit, e);
    let points = panel_points(groups, range);
    let unit = unit_predictions(fit, &points).map_err(invalid)?;
    let scale = fit.model.scale;
    let y = opts.y_scale;
    let mut curves = Vec::with_capacity(groups.len());
    let mut residuals = Vec::with_capacity(groups.len());
    let mut sq_sum = SquareSum::default();
    let mut at = 0;
    for g in groups {
        let curve = (0..CURVE_POINTS)
            .map(|k| (curve_x(range, k), plotted_model(y, scale, unit[at + k])))
            .collect();
        at += CURVE_POINTS;
        let mut res = Vec::with_capacity(g.points.len());
        for ((&(x, y_meas), &l_meas), &fitted) in g.points.iter().zip(&g.l).zip(&g.fitted) {
            let unit_model = unit[at];
            at += 1;
            res.push((x, y_meas - plotted_model(y, scale, unit_model)));
            if fitted {
                sq_sum.add(
                    YScale::Sqrt.apply(l_meas) - plotted_model(YScale::Sqrt, scale, unit_model),
                );
            }
        }
        curves.push(curve);
        residuals.push(res);
    }
    Ok(PanelView {
        fit,
        ndf,
        curves,
        residuals,
        sq_sum,
    })
}

/// The NDF of `fit`, for drawing its panel: refused ([`ReportError::invalid_fit`]) when its
/// record is not one a fit writes ([`FitResult::check`]) or its model cannot be evaluated.
pub(crate) fn drawable_ndf(fit: &FitResult) -> Result<AnyNdf, ReportError> {
    fit.check().map_err(|e| ReportError::invalid_fit(fit, e))?;
    fit.model
        .ndf()
        .map_err(|e| ReportError::invalid_fit(fit, e))
}

/// A stored fit whose model cannot be evaluated (parameters outside the supported ranges, say,
/// in a hand-edited fits file), or whose record is not one a fit writes (a number outside its
/// documented range, such as a negative standard error, [`FitResult::check`]): the report names
/// it in its warnings and in `fits.md`, draws its panel with the data alone and leaves it out of
/// the table.
#[derive(Debug, Clone)]
pub struct NotDrawn<'a> {
    pub fit: &'a FitResult,
    /// Why the fit is not valid or its model cannot be evaluated.
    pub reason: String,
}

impl<'a> NotDrawn<'a> {
    /// The panel of `fit`, or `None` with `fit` added to `not_drawn` when its model cannot be
    /// evaluated; other errors pass through.
    pub(crate) fn catch<P>(
        panel: Result<P, ReportError>,
        fit: &'a FitResult,
        not_drawn: &mut Vec<NotDrawn<'a>>,
    ) -> Result<Option<P>, ReportError> {
        match panel {
            Ok(p) => Ok(Some(p)),
            Err(ReportError::InvalidFit { reason, .. }) => {
                not_drawn.push(NotDrawn { fit, reason });
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }

    /// The warning of the report: the fit, why, and what was left out.
    pub fn message(&self) -> String {
        format!(
            "{}: the stored fit is not valid or its model cannot be evaluated ({}); its curves are \
             not drawn and it is left out of the table",
            self.fit.label(),
            self.reason
        )
    }
}

/// A sample's name for titles: `(unnamed)` for a file without a `sample` column.
pub(crate) fn sample_title(name: &str) -> &str {
    if name.is_empty() { "(unnamed)" } else { name }
}

impl<'a> SampleView<'a> {
    /// The sample's name for titles; `(unnamed)` for a file without a `sample` column.
    pub(crate) fn title(&self) -> &str {
        sample_title(self.name)
    }

    /// Prepares a sample and its fits (already checked to belong to it, at most one per slot).
    pub(crate) fn new(
        sample: &'a Sample,
        fits: [Option<&'a FitResult>; 4],
        opts: &ReportOptions,
        not_drawn: &mut Vec<NotDrawn<'a>>,
    ) -> Result<Self, ReportError> {
        let (groups, range) = layout(sample, opts.y_scale)?;
        let mut panels: [Option<PanelView<'a>>; 4] = Default::default();
        for (panel, fit) in panels.iter_mut().zip(fits) {
            if let Some(fit) = fit {
                *panel = NotDrawn::catch(panel_view(fit, &groups, range, opts), fit, not_drawn)?;
            }
        }
        Ok(Self {
            name: &sample.name,
            groups,
            theta_o_range: range,
            panels,
        })
    }

    /// Estimated wall time, in seconds, of the random walks that [`SampleView::new`] runs for
    /// `fits` ([`Model::walk_seconds`](stfit_fit::Model::walk_seconds) at each panel's points,
    /// summed): 0 for single-scattering fits; a fit or sample that cannot be drawn counts 0.
    pub(crate) fn walk_seconds(
        sample: &Sample,
        fits: [Option<&FitResult>; 4],
        opts: &ReportOptions,
    ) -> f64 {
        let Ok((groups, range)) = layout(sample, opts.y_scale) else {
            return 0.0;
        };
        walk_seconds_at(fits, &panel_points(&groups, range))
    }

    /// Whether any point has weight 0 (drawn hollow, not fitted).
    pub(crate) fn has_unfitted(&self) -> bool {
        self.groups.iter().any(|g| g.fitted.contains(&false))
    }

    /// Smallest and largest plotted value of data and model curves.
    pub(crate) fn y_extent(&self) -> (f64, f64) {
        let data = self.groups.iter().flat_map(|g| g.points.iter());
        let curves = self
            .panels
            .iter()
            .flatten()
            .flat_map(|p| p.curves.iter().flatten());
        extent(data.chain(curves).map(|p| p.1))
    }

    /// Smallest and largest residual over every panel.
    pub(crate) fn residual_extent(&self) -> (f64, f64) {
        extent(
            self.panels
                .iter()
                .flatten()
                .flat_map(|p| p.residuals.iter().flatten())
                .map(|p| p.1),
        )
    }
}

/// Finite minimum and maximum, `(0, 0)` when there are none.
pub(crate) fn extent(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo <= hi { (lo, hi) } else { (0.0, 0.0) }
}

/// `D(theta_m)` of an NDF for a facet tilted by `theta_m_deg` degrees.
pub(crate) fn ndf_at_deg(ndf: &AnyNdf, theta_m_deg: f64) -> f64 {
    let t = theta_m_deg.to_radians();
    ndf.d(Vec3::new(t.sin(), 0.0, t.cos()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Squares past the largest double, and squares too small to survive a fixed rescaling,
    /// sum to the rms they have.
    #[test]
    fn square_sums_neither_overflow_nor_lose_small_terms() {
        let mut big = SquareSum::default();
        for d in [3e154, -4e154, 0.0] {
            big.add(d);
        }
        let expected = (25.0f64 / 3.0).sqrt() * 1e154;
        assert!((big.rms() / expected - 1.0).abs() < 1e-15, "{}", big.rms());
        let mut small = SquareSum::default();
        for d in [3e-170, 4e-170] {
            small.add(d);
        }
        assert!((small.rms() / (12.5f64.sqrt() * 1e-170) - 1.0).abs() < 1e-15);
        let all = big.merge(small);
        assert_eq!(all.n, 5);
        assert!((all.rms() / ((25.0f64 / 5.0).sqrt() * 1e154) - 1.0).abs() < 1e-15);
        assert_eq!(SquareSum::default().merge(small), small);
        assert_eq!(SquareSum::default().rms(), 0.0);
        let mut nan = big;
        nan.add(f64::NAN);
        assert!(nan.rms().is_nan());
    }

    /// The plotted model of a value past the largest double is finite on both axes.
    #[test]
    fn plotted_models_do_not_overflow() {
        let v = plotted_model(YScale::Sqrt, 1e307, 30.0);
        assert!(
            (v / (1e307f64.sqrt() * 30f64.sqrt()) - 1.0).abs() < 1e-15,
            "{v}"
        );
        assert_eq!(plotted_model(YScale::Linear, 1e307, 30.0), f64::MAX);
        assert_eq!(plotted_model(YScale::Linear, 2.0, 3.0), 6.0);
    }
}
