//! Figures of general samples (measurements at any pair of directions, reflection and
//! transmission, light from either side): per sample the measured and fitted BSDF along the
//! plane of incidence of each incident direction, four model panels as in the in-plane
//! figures, and polar maps of the residuals of every measured point, per incident direction and
//! model.
//!
//! Along the plane of incidence a direction `wo` is placed at its signed polar angle `x`:
//! `theta_o` when it leans away from the light (`phi_o = phi_i + 180`), `-theta_o` toward it
//! (`phi_o = phi_i`); so mirror reflection of light from outside is at `x = theta_i`,
//! straight-through transmission at `x = +-180`, reflection at `|x| < 90` and transmission
//! beyond (for light from outside).

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use stfit_core::ndf::AnyNdf;
use stfit_fit::{FitResult, Measurement, Sample, reduced_azimuth_deg};

use crate::figures::{LARGE, curve_chart, draw_title, fmt_tick};
use crate::render::Figure;
use crate::style::{AnglePalette, GREY, Glyph, LegendEntry, bold, draw_header, fmt_deg, text};
use crate::view::{
    ModelSlot, NotDrawn, SquareSum, plotted_model, sample_title, unit_predictions, walk_seconds_at,
};
use crate::{ReportError, YScale};

/// Spacing of the model curves along the plane of incidence, degrees.
const CURVE_STEP_DEG: f64 = 0.5;

/// Tolerance of "in the plane of incidence" on azimuths, degrees.
const PLANE_TOL_DEG: f64 = 1e-6;

/// The measurements of one incident direction.
#[derive(Debug, Clone)]
pub(crate) struct Incidence {
    pub theta_i_deg: f64,
    pub phi_i_deg: f64,
    /// Measured points of this incidence: `(theta_o, phi_o - phi_i)` in degrees, the value and
    /// whether it was fitted (weight > 0).
    pub points: Vec<(f64, f64, f64, bool)>,
}

impl Incidence {
    /// The label of the incident direction.
    pub(crate) fn label(&self) -> String {
        format!(
            "θi = {}, φi = {}",
            fmt_deg(self.theta_i_deg),
            fmt_deg(self.phi_i_deg)
        )
    }

    /// Points in the plane of incidence at their signed polar angle `x`, plotted value and
    /// fitted flag.
    fn plane_points(&self, y: YScale) -> Vec<((f64, f64), bool)> {
        self.points
            .iter()
            .filter_map(|&(to, dphi, v, fitted)| {
                signed_angle(to, dphi).map(|x| ((x, y.apply(v)), fitted))
            })
            .collect()
    }
}

/// The signed polar angle of a direction in the plane of incidence, or `None` out of it.
fn signed_angle(theta_o: f64, dphi: f64) -> Option<f64> {
    let d = dphi.rem_euclid(360.0);
    let near = |a: f64| (d - a).abs() < PLANE_TOL_DEG || (d - a - 360.0).abs() < PLANE_TOL_DEG;
    if theta_o == 0.0 || theta_o == 180.0 || near(180.0) {
        Some(theta_o)
    } else if near(0.0) {
        Some(-theta_o)
    } else {
        None
    }
}

/// One fitted model of a general sample, evaluated for plotting.
#[derive(Debug, Clone)]
pub(crate) struct GeneralPanel<'a> {
    pub fit: &'a FitResult,
    pub ndf: AnyNdf,
    /// Per incidence, the model along the plane of incidence `(x, y)` in the report's scale.
    pub curves: Vec<Vec<(f64, f64)>>,
    /// Per incidence and measured point (same order), measured minus model in the report's
    /// scale.
    pub residuals: Vec<Vec<f64>>,
    /// The squared residuals of the square root of the values over the fitted points,
    /// recomputed.
    pub sq_sum: SquareSum,
}

/// A general sample with everything its figures need.
#[derive(Debug, Clone)]
pub(crate) struct GeneralView<'a> {
    pub name: &'a str,
    pub incidences: Vec<Incidence>,
    pub panels: [Option<GeneralPanel<'a>>; 4],
}

impl<'a> GeneralView<'a> {
    /// The sample's name for titles; `(unnamed)` for a file without a `sample` column.
    pub(crate) fn title(&self) -> &str {
        sample_title(self.name)
    }

    /// Prepares a general sample and its fits (checked to belong to it, at most one per slot).
    pub(crate) fn new(
        sample: &'a Sample,
        fits: [Option<&'a FitResult>; 4],
        y: YScale,
        not_drawn: &mut Vec<NotDrawn<'a>>,
    ) -> Result<Self, ReportError> {
        let (incidences, members) = layout(sample)?;
        let mut panels: [Option<GeneralPanel<'a>>; 4] = Default::default();
        for (panel, fit) in panels.iter_mut().zip(fits) {
            if let Some(fit) = fit {
                *panel = NotDrawn::catch(panel_of(fit, &incidences, &members, y), fit, not_drawn)?;
            }
        }
        Ok(Self {
            name: &sample.name,
            incidences,
            panels,
        })
    }

    /// Estimated wall time, in seconds, of the random walks that [`GeneralView::new`] runs for
    /// `fits` ([`Model::walk_seconds`](stfit_fit::Model::walk_seconds) at each panel's points,
    /// summed): 0 for single-scattering fits; a fit or sample that cannot be drawn counts 0.
    pub(crate) fn walk_seconds(sample: &Sample, fits: [Option<&FitResult>; 4]) -> f64 {
        let Ok((incidences, members)) = layout(sample) else {
            return 0.0;
        };
        walk_seconds_at(fits, &panel_points(&incidences, &members))
    }
}

/// The incident directions of a general sample and, per direction (same order), its measured
/// points in the sample's own order.
type Layout<'a> = (Vec<Incidence>, Vec<Vec<&'a Measurement>>);

/// A general sample's points grouped by incident direction (ascending `theta_i`, then
/// `phi_i`); an empty sample is refused.
fn layout(sample: &Sample) -> Result<Layout<'_>, ReportError> {
    if sample.points.is_empty() {
        return Err(ReportError::EmptySample(sample.name.clone()));
    }
    let mut incidences: Vec<Incidence> = Vec::new();
    // The measured points of each incidence, in the sample's own order.
    let mut members: Vec<Vec<&Measurement>> = Vec::new();
    for p in &sample.points {
        let Some(((theta_i_deg, phi_i_deg), (theta_o_deg, phi_o_deg))) = p.spherical_angles()
        else {
            continue;
        };
        let k = match incidences
            .iter()
            .position(|g| g.theta_i_deg == theta_i_deg && g.phi_i_deg == phi_i_deg)
        {
            Some(k) => k,
            None => {
                incidences.push(Incidence {
                    theta_i_deg,
                    phi_i_deg,
                    points: Vec::new(),
                });
                members.push(Vec::new());
                incidences.len() - 1
            }
        };
        incidences[k].points.push((
            theta_o_deg,
            reduced_azimuth_deg(phi_o_deg) - reduced_azimuth_deg(phi_i_deg),
            p.value,
            p.weight > 0.0,
        ));
        members[k].push(p);
    }
    let mut order: Vec<usize> = (0..incidences.len()).collect();
    order.sort_by(|&a, &b| {
        let (ga, gb) = (&incidences[a], &incidences[b]);
        ga.theta_i_deg
            .total_cmp(&gb.theta_i_deg)
            .then(ga.phi_i_deg.total_cmp(&gb.phi_i_deg))
    });
    let incidences: Vec<Incidence> = order.iter().map(|&k| incidences[k].clone()).collect();
    let members: Vec<Vec<&Measurement>> = order.iter().map(|&k| members[k].clone()).collect();
    Ok((incidences, members))
}

/// The signed polar angles `x` of the points of a model curve along the plane of incidence,
/// every [`CURVE_STEP_DEG`] across (-180, 180), grazing directions (`|x|` = 90) left out.
fn curve_xs() -> Vec<f64> {
    (0..)
        .map(|k| -180.0 + CURVE_STEP_DEG * (k as f64 + 0.5))
        .take_while(|&x| x < 180.0)
        .filter(|x: &f64| x.abs() != 90.0)
        .collect()
}

/// The points at which a panel evaluates its model, in one batch (for an all-orders model,
/// one set of walks per incident direction): the curve of every incidence ([`curve_xs`]),
/// then the measured points of every incidence.
fn panel_points(incidences: &[Incidence], members: &[Vec<&Measurement>]) -> Vec<Measurement> {
    let xs = curve_xs();
    let mut points = Vec::new();
    for g in incidences {
        points.extend(xs.iter().map(|&x| {
            let phi = g.phi_i_deg + if x >= 0.0 { 180.0 } else { 0.0 };
            Measurement::spherical((g.theta_i_deg, g.phi_i_deg), (x.abs(), phi), 0.0, 1.0)
        }));
    }
    for m in members {
        points.extend(m.iter().map(|p| **p));
    }
    points
}

fn panel_of<'a>(
    fit: &'a FitResult,
    incidences: &[Incidence],
    members: &[Vec<&Measurement>],
    y: YScale,
) -> Result<GeneralPanel<'a>, ReportError> {
    let ndf = crate::view::drawable_ndf(fit)?;
    let invalid = |e| ReportError::invalid_fit(fit, e);
    let xs = curve_xs();
    let values = unit_predictions(fit, &panel_points(incidences, members)).map_err(invalid)?;
    let scale = fit.model.scale;
    let (curve_values, point_values) = values.split_at(xs.len() * incidences.len());
    let curves = curve_values
        .chunks(xs.len())
        .map(|c| {
            xs.iter()
                .zip(c)
                .map(|(&x, &v)| (x, plotted_model(y, scale, v)))
                .collect()
        })
        .collect();
    let mut residuals = Vec::with_capacity(incidences.len());
    let mut sq_sum = SquareSum::default();
    let mut at = 0;
    for g in incidences {
        let mut res = Vec::with_capacity(g.points.len());
        for &(_, _, v, fitted) in &g.points {
            let unit = point_values[at];
            at += 1;
            res.push(y.apply(v) - plotted_model(y, scale, unit));
            if fitted {
                sq_sum.add(YScale::Sqrt.apply(v) - plotted_model(YScale::Sqrt, scale, unit));
            }
        }
        residuals.push(res);
    }
    Ok(GeneralPanel {
        fit,
        ndf,
        curves,
        residuals,
        sq_sum,
    })
}

/// The four model panels of a general sample along the plane of incidence.
pub(crate) struct PlaneFigure<'a> {
    pub view: &'a GeneralView<'a>,
    pub palette: &'a AnglePalette,
    pub y_scale: YScale,
}

impl Figure for PlaneFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (1600, 1200)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        let (header, body) = root.split_vertically(100);
        let mut legend = vec![
            LegendEntry {
                colour: GREY,
                glyph: Glyph::Marker,
                label: "measured in the plane of incidence".into(),
            },
            LegendEntry {
                colour: GREY,
                glyph: Glyph::Line,
                label: "model".into(),
            },
        ];
        legend.extend(self.view.incidences.iter().map(|g| LegendEntry {
            colour: self.palette.colour((g.theta_i_deg, g.phi_i_deg)),
            glyph: Glyph::MarkerAndLine,
            label: g.label(),
        }));
        let title = format!(
            "{}: BSDF along the plane of incidence (|x| < 90 outside the glass, above the surface)",
            self.view.title()
        );
        draw_header(&header, &title, &legend, 20.0)?;
        let extent = plane_extent(self.view, self.y_scale);
        for (area, slot) in body.split_evenly((2, 2)).iter().zip(ModelSlot::ALL) {
            self.panel(&area.margin(0, 10, 10, 10), slot, extent)?;
        }
        Ok(())
    }
}

/// Largest plotted value of the plane figure's points and curves.
fn plane_extent(view: &GeneralView, y: YScale) -> f64 {
    let data = view
        .incidences
        .iter()
        .flat_map(|g| g.plane_points(y).into_iter().map(|(p, _)| p.1));
    let curves = view
        .panels
        .iter()
        .flatten()
        .flat_map(|p| p.curves.iter().flatten().map(|c| c.1));
    data.chain(curves)
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max)
}

impl PlaneFigure<'_> {
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        slot: ModelSlot,
        top: f64,
    ) -> Result<(), ReportError> {
        let panel = self.view.panels[slot.index()].as_ref();
        let (title_area, plot_area) = area.split_vertically(LARGE.title_height);
        let detail = panel.map_or_else(
            || "not fitted".to_string(),
            |p| crate::figures::params_text(p.fit, true),
        );
        draw_title(&title_area, slot.title(), &detail, LARGE)?;
        // At most the largest double: an infinite axis never finished drawing.
        let y1 = if top > 0.0 {
            (top * 1.05).min(f64::MAX)
        } else {
            1.0
        };
        let y_desc = match self.y_scale {
            YScale::Sqrt => "√BSDF",
            YScale::Linear => "BSDF",
        };
        let mut chart = curve_chart(
            &plot_area,
            (-180.0, 180.0),
            (0.0, y1),
            "signed θo in the plane of incidence (degrees)",
            y_desc,
            LARGE,
        )?;
        for x in [-90.0, 90.0] {
            chart.draw_series(LineSeries::new([(x, 0.0), (x, y1)], GREY.stroke_width(1)))?;
        }
        for (k, g) in self.view.incidences.iter().enumerate() {
            let colour = self.palette.colour((g.theta_i_deg, g.phi_i_deg));
            chart.draw_series(g.plane_points(self.y_scale).into_iter().map(|(p, f)| {
                let style = if f {
                    colour.filled()
                } else {
                    colour.stroke_width(1)
                };
                Circle::new(p, 3, style)
            }))?;
            if let Some(p) = panel {
                // Three pieces, broken at the horizon (x = +-90), where no light leaves.
                type Region = fn(f64) -> bool;
                let regions: [Region; 3] = [|x| x < -90.0, |x| x.abs() < 90.0, |x| x > 90.0];
                for region in regions {
                    let piece = p.curves[k].iter().filter(|c| region(c.0)).copied();
                    chart.draw_series(LineSeries::new(piece, colour.stroke_width(2)))?;
                }
            }
        }
        Ok(())
    }
}

/// Polar maps of the residuals of every measured point: rows are incident directions, columns
/// models; each cell shows the hemisphere on the light's side (left) and the other (right),
/// looked at from outside along each hemisphere's pole, radius proportional to the angle from
/// it, azimuth `phi_o - phi_i` counter-clockwise from the right.
pub(crate) struct PolarFigure<'a> {
    pub view: &'a GeneralView<'a>,
    pub y_scale: YScale,
}

impl PolarFigure<'_> {
    /// The largest absolute residual, the colour scale's end.
    fn limit(&self) -> f64 {
        let m = self
            .view
            .panels
            .iter()
            .flatten()
            .flat_map(|p| p.residuals.iter().flatten())
            .filter(|r| r.is_finite())
            .fold(0.0, |m: f64, r| m.max(r.abs()));
        if m > 0.0 { m } else { 1.0 }
    }
}

/// Diverging colour of `t` in [-1, 1]: blue (model above the measurement), white, red.
fn diverging(t: f64) -> RGBColor {
    let t = t.clamp(-1.0, 1.0);
    let mix = |a: f64, b: f64, s: f64| (a + (b - a) * s).round() as u8;
    let (end, s) = if t >= 0.0 {
        ((178.0, 24.0, 43.0), t)
    } else {
        ((33.0, 102.0, 172.0), -t)
    };
    RGBColor(
        mix(247.0, end.0, s),
        mix(247.0, end.1, s),
        mix(247.0, end.2, s),
    )
}

impl Figure for PolarFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (1600, 130 + 250 * self.view.incidences.len().max(1) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        let (header, body) = root.split_vertically(130);
        let limit = self.limit();
        let what = match self.y_scale {
            YScale::Sqrt => "√BSDF",
            YScale::Linear => "BSDF",
        };
        let title = format!(
            "{}: residuals, {what} measured − model, of every measured point",
            self.view.title()
        );
        let (w, _) = header.dim_in_pixel();
        header.draw_text(
            &title,
            &bold(25.0).pos(Pos::new(HPos::Center, VPos::Center)),
            (w as i32 / 2, 30),
        )?;
        // The colour bar.
        let (x0, x1, yb) = (w as i32 / 2 - 300, w as i32 / 2 + 300, 70);
        for k in 0..600 {
            let t = 2.0 * k as f64 / 599.0 - 1.0;
            header.draw(&Rectangle::new(
                [(x0 + k, yb), (x0 + k + 1, yb + 18)],
                diverging(t).filled(),
            ))?;
        }
        let label = text(17.0).pos(Pos::new(HPos::Center, VPos::Top));
        for (x, v) in [(x0, -limit), ((x0 + x1) / 2, 0.0), (x1, limit)] {
            header.draw_text(&fmt_tick(v, 2.0 * limit), &label, (x, yb + 22))?;
        }
        header.draw_text(
            "left disk: the light's side; right: the other side",
            &text(17.0).pos(Pos::new(HPos::Left, VPos::Center)),
            (x1 + 30, yb + 9),
        )?;
        let rows = self.view.incidences.len().max(1);
        let cells = body.split_evenly((rows, ModelSlot::ALL.len()));
        for (r, g) in self.view.incidences.iter().enumerate() {
            for (c, slot) in ModelSlot::ALL.iter().enumerate() {
                let cell = &cells[r * ModelSlot::ALL.len() + c];
                let panel = self.view.panels[slot.index()].as_ref();
                draw_polar_cell(cell, g, panel.map(|p| &p.residuals[r][..]), slot, limit)?;
            }
        }
        Ok(())
    }
}

fn draw_polar_cell<DB: DrawingBackend>(
    cell: &DrawingArea<DB, Shift>,
    g: &Incidence,
    residuals: Option<&[f64]>,
    slot: &ModelSlot,
    limit: f64,
) -> Result<(), ReportError> {
    let (title, disks) = cell.split_vertically(40);
    let (w, _) = title.dim_in_pixel();
    title.draw_text(
        &format!("{} · {}", slot.title(), g.label()),
        &text(15.0).pos(Pos::new(HPos::Center, VPos::Center)),
        (w as i32 / 2, 20),
    )?;
    let halves = disks.split_evenly((1, 2));
    let light_outside = g.theta_i_deg < 90.0;
    for (side, area) in halves.iter().enumerate() {
        let (aw, ah) = area.dim_in_pixel();
        let radius = (aw.min(ah) as f64 / 2.0 - 8.0).max(10.0);
        let centre = (aw as i32 / 2, ah as i32 / 2);
        area.draw(&Circle::new(centre, radius as i32, GREY.stroke_width(1)))?;
        let Some(residuals) = residuals else {
            continue;
        };
        for (&(to, dphi, _, fitted), &res) in g.points.iter().zip(residuals) {
            let outside = to < 90.0;
            // The light's side is the left disk.
            if (outside == light_outside) != (side == 0) {
                continue;
            }
            let from_pole = if outside { to } else { 180.0 - to };
            let (s, c) = dphi.to_radians().sin_cos();
            let r = radius * from_pole / 90.0;
            let p = (centre.0 + (r * c) as i32, centre.1 - (r * s) as i32);
            let colour = diverging(res / limit);
            area.draw(&Circle::new(p, 5, colour.filled()))?;
            if !fitted {
                area.draw(&Circle::new(p, 5, GREY.stroke_width(1)))?;
            }
        }
    }
    Ok(())
}
