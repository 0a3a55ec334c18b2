//! The report's figures: per sample a four-panel fit figure and a residual figure, an overview
//! of every sample and model, and the fitted NDFs on a log scale.

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::ReportError;
use crate::YScale;
use crate::render::{FONT, Figure};
use crate::style::{
    AnglePalette, GREY, GRID, Glyph, LegendEntry, MODEL_COLOURS, angle_legend, bold, draw_header,
    fmt_sig, text,
};
use crate::view::{ModelSlot, PanelView, SampleView, extent, ndf_at_deg};
use stfit_core::ndf::AnyNdf;

/// Sizes of one kind of panel.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Look {
    pub(crate) heading: f64,
    pub(crate) body: f64,
    pub(crate) tick: f64,
    pub(crate) title_height: u32,
    pub(crate) marker: u32,
    pub(crate) line: u32,
}

/// Panels of the four-panel figures (800 x 550 px each).
pub(crate) const LARGE: Look = Look {
    heading: 22.0,
    body: 19.0,
    tick: 17.0,
    title_height: 64,
    marker: 3,
    line: 2,
};

/// Panels of the overview (450 x 400 px each).
const SMALL: Look = Look {
    heading: 17.0,
    body: 15.0,
    tick: 14.0,
    title_height: 50,
    marker: 2,
    line: 2,
};

const HEADER_HEIGHT: u32 = 100;
const HEADER_FONT: f64 = 20.0;

/// `lo..hi` widened to multiples of `step` with at least `pad` of room.
fn padded(lo: f64, hi: f64, pad: f64, step: f64) -> (f64, f64) {
    (
        ((lo - pad) / step).floor() * step,
        ((hi + pad) / step).ceil() * step,
    )
}

/// Vertical range of a value plot: from zero (or the lowest value) to 5% above the highest,
/// at most the largest double (a linear axis of values near it had become infinite, and the
/// chart never finished).
fn value_range((lo, hi): (f64, f64)) -> (f64, f64) {
    let top = if hi > 0.0 {
        (hi * 1.05).min(f64::MAX)
    } else {
        1.0
    };
    let bottom = if lo < 0.0 {
        lo - 0.05 * (top - lo)
    } else {
        0.0
    };
    (bottom, top)
}

/// Symmetric vertical range around zero for residuals, at most half the largest double each
/// way, so that its width is finite.
fn residual_range((lo, hi): (f64, f64)) -> (f64, f64) {
    let m = lo.abs().max(hi.abs());
    let m = if m > 0.0 {
        (m * 1.1).min(f64::MAX / 2.0)
    } else {
        1.0
    };
    (-m, m)
}

/// What the models of `fits` are, for a figure title: `single-scattering fits` or `all-orders
/// fits` when every fit has those orders, else `fits`.
fn fits_phrase<'a>(fits: impl IntoIterator<Item = &'a stfit_fit::FitResult>) -> &'static str {
    let mut orders = fits.into_iter().map(|f| f.model.orders);
    let Some(first) = orders.next() else {
        return "fits";
    };
    if orders.any(|o| o != first) {
        return "fits";
    }
    match first {
        stfit_fit::ScatteringOrders::Single => "single-scattering fits",
        stfit_fit::ScatteringOrders::All => "all-orders fits",
        _ => "fits",
    }
}

/// The parameter line of a panel title.
fn params_line(p: &PanelView, with_scale: bool) -> String {
    params_text(p.fit, with_scale)
}

/// A held value as given (`3`, `2.5`) where that is short, else to 4 significant digits (a
/// hand-edited `1e15` is `1.000e15`, not 16 digits).
fn held_value(v: f64) -> String {
    let given = v.to_string();
    if given.len() <= 8 {
        given
    } else {
        fmt_sig(v, 4)
    }
}

/// A fit's parameters as a panel title states them: alpha, gamma, eta when fitted, scale and
/// the rmse.
pub(crate) fn params_text(fit: &stfit_fit::FitResult, with_scale: bool) -> String {
    let mut parts = vec![format!("α = {}", fmt_sig(fit.model.alpha, 4))];
    match fit.model.gamma {
        stfit_fit::Gamma::Fixed(g) => parts.push(format!("γ = {} (fixed)", held_value(g))),
        stfit_fit::Gamma::Free(g) => parts.push(format!("γ = {}", fmt_sig(g, 4))),
        stfit_fit::Gamma::NotApplicable => {}
    }
    if !fit.eta_fixed {
        parts.push(format!("η = {}", fmt_sig(fit.model.eta, 4)));
    }
    if with_scale {
        parts.push(format!("scale = {}", fmt_sig(fit.model.scale, 4)));
    }
    parts.push(format!(
        "rmse {} = {}",
        fit.measured.sqrt_symbol(),
        fmt_sig(fit.rmse_sqrt_l, 3)
    ));
    parts.join("    ")
}

/// Two-line panel title: bold heading, parameters below.
pub(crate) fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    heading: &str,
    detail: &str,
    look: Look,
) -> Result<(), ReportError> {
    let (w, h) = area.dim_in_pixel();
    let centre = |s: TextStyle<'static>| s.pos(Pos::new(HPos::Center, VPos::Center));
    let x = w as i32 / 2;
    area.draw_text(
        heading,
        &centre(bold(look.heading)),
        (x, (h as f64 * 0.3) as i32),
    )?;
    area.draw_text(
        detail,
        &centre(text(look.body)),
        (x, (h as f64 * 0.75) as i32),
    )?;
    Ok(())
}

/// What one fit panel plots.
enum PanelKind {
    /// Measured markers and model curves.
    Fit,
    /// Measured minus model.
    Residual,
}

/// Filled markers for fitted points, hollow ones for points of weight 0.
fn markers<'a>(
    points: &'a [(f64, f64)],
    fitted: &'a [bool],
    colour: RGBColor,
    r: u32,
) -> impl Iterator<Item = Circle<(f64, f64), u32>> + 'a {
    points.iter().zip(fitted).map(move |(&p, &f)| {
        let style = if f {
            colour.filled()
        } else {
            colour.stroke_width(1)
        };
        Circle::new(p, r, style)
    })
}

/// A chart of curves against an angle in degrees on `area`, with the report's mesh (grid lines,
/// 9 x and 7 y labels, y ticks formatted for the y span), axis descriptions and sizes of `look`.
pub(crate) fn curve_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    x_desc: &str,
    y_desc: &str,
    look: Look,
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, ReportError> {
    let mut chart = ChartBuilder::on(area)
        .margin_right((look.tick * 1.5) as u32)
        .margin_left(4)
        .margin_bottom(6)
        .x_label_area_size((look.tick * 3.2) as u32)
        .y_label_area_size((look.tick * 4.6) as u32)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .x_labels(9)
        .y_labels(7)
        .label_style((FONT, look.tick))
        .axis_desc_style((FONT, look.body))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| fmt_tick(*v, y1 - y0))
        .x_desc(x_desc)
        .y_desc(y_desc)
        .draw()?;
    Ok(chart)
}

#[allow(clippy::too_many_arguments)]
fn draw_fit_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    view: &SampleView,
    slot: ModelSlot,
    heading: &str,
    palette: &AnglePalette,
    y_scale: YScale,
    kind: &PanelKind,
    look: Look,
    with_scale: bool,
) -> Result<(), ReportError> {
    let panel = view.panels[slot.index()].as_ref();
    let detail = panel.map_or_else(|| "not fitted".to_string(), |p| params_line(p, with_scale));
    let (title_area, plot_area) = area.split_vertically(look.title_height);
    draw_title(&title_area, heading, &detail, look)?;

    let (x0, x1) = padded(view.theta_o_range.0, view.theta_o_range.1, 2.0, 10.0);
    let (y0, y1, y_desc) = match kind {
        PanelKind::Fit => {
            let (a, b) = value_range(view.y_extent());
            (a, b, y_scale.label().to_string())
        }
        PanelKind::Residual => {
            let (a, b) = residual_range(view.residual_extent());
            (a, b, format!("{0} measured − {0} model", y_scale.label()))
        }
    };
    let mut chart = curve_chart(
        &plot_area,
        (x0, x1),
        (y0, y1),
        "θo (degrees)",
        &y_desc,
        look,
    )?;

    if let PanelKind::Residual = kind {
        chart.draw_series(LineSeries::new(
            [(x0, 0.0), (x1, 0.0)],
            GREY.stroke_width(1),
        ))?;
    }
    for (k, g) in view.groups.iter().enumerate() {
        let colour = palette.colour((g.theta_i_deg, 0.0));
        let r = look.marker;
        match kind {
            PanelKind::Fit => {
                chart.draw_series(markers(&g.points, &g.fitted, colour, r))?;
            }
            PanelKind::Residual => {
                if let Some(p) = panel {
                    let res = &p.residuals[k];
                    chart.draw_series(LineSeries::new(res.iter().copied(), colour.mix(0.5)))?;
                    chart.draw_series(markers(res, &g.fitted, colour, r))?;
                }
            }
        }
    }
    if let (PanelKind::Fit, Some(p)) = (kind, panel) {
        for (g, curve) in view.groups.iter().zip(&p.curves) {
            let style = palette.colour((g.theta_i_deg, 0.0)).stroke_width(look.line);
            chart.draw_series(LineSeries::new(curve.iter().copied(), style))?;
        }
    }
    Ok(())
}

/// The four models of one sample side by side (Figure 1 of the seed paper), or their
/// residuals.
pub(crate) struct SampleFigure<'a> {
    view: &'a SampleView<'a>,
    palette: &'a AnglePalette,
    y_scale: YScale,
    kind: PanelKind,
}

impl<'a> SampleFigure<'a> {
    pub(crate) fn fits(view: &'a SampleView<'a>, palette: &'a AnglePalette, y: YScale) -> Self {
        Self {
            view,
            palette,
            y_scale: y,
            kind: PanelKind::Fit,
        }
    }

    pub(crate) fn residuals(
        view: &'a SampleView<'a>,
        palette: &'a AnglePalette,
        y: YScale,
    ) -> Self {
        Self {
            view,
            palette,
            y_scale: y,
            kind: PanelKind::Residual,
        }
    }
}

impl Figure for SampleFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (1600, 1200)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        let (header, body) = root.split_vertically(HEADER_HEIGHT);
        let (title, legend) = match self.kind {
            PanelKind::Fit => (
                format!(
                    "{}: measured transmission and {}",
                    self.view.title(),
                    fits_phrase(self.view.panels.iter().flatten().map(|p| p.fit))
                ),
                angle_legend(self.palette, true, self.view.has_unfitted()),
            ),
            PanelKind::Residual => (
                format!(
                    "{}: residuals of the fits, measured − model",
                    self.view.title()
                ),
                angle_legend(self.palette, false, self.view.has_unfitted()),
            ),
        };
        draw_header(&header, &title, &legend, HEADER_FONT)?;
        for (area, slot) in body.split_evenly((2, 2)).iter().zip(ModelSlot::ALL) {
            let area = area.margin(0, 10, 10, 10);
            draw_fit_panel(
                &area,
                self.view,
                slot,
                slot.title(),
                self.palette,
                self.y_scale,
                &self.kind,
                LARGE,
                true,
            )?;
        }
        Ok(())
    }
}

/// Every sample (rows) against every model (columns).
pub(crate) struct OverviewFigure<'a> {
    pub views: &'a [SampleView<'a>],
    pub palette: &'a AnglePalette,
    pub y_scale: YScale,
}

impl Figure for OverviewFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (1800, HEADER_HEIGHT + 400 * self.views.len() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        let (header, body) = root.split_vertically(HEADER_HEIGHT);
        let fits = self
            .views
            .iter()
            .flat_map(|v| v.panels.iter().flatten().map(|p| p.fit));
        draw_header(
            &header,
            &format!(
                "All samples: measured transmission and {}",
                fits_phrase(fits)
            ),
            &angle_legend(
                self.palette,
                true,
                self.views.iter().any(SampleView::has_unfitted),
            ),
            HEADER_FONT,
        )?;
        let cells = body.split_evenly((self.views.len(), ModelSlot::ALL.len()));
        for (row, view) in cells.chunks(ModelSlot::ALL.len()).zip(self.views) {
            for (area, slot) in row.iter().zip(ModelSlot::ALL) {
                let area = area.margin(0, 8, 6, 6);
                let heading = format!("{} · {}", view.title(), slot.title());
                draw_fit_panel(
                    &area,
                    view,
                    slot,
                    &heading,
                    self.palette,
                    self.y_scale,
                    &PanelKind::Fit,
                    SMALL,
                    false,
                )?;
            }
        }
        Ok(())
    }
}

/// A linear-axis tick: `v` rounded to a thousandth of the axis span and printed in its
/// shortest form, so ticks read `0.2`, `0`, `1.5` (never `-0.0` or `0.30000000000000004`).
pub fn fmt_tick(v: f64, span: f64) -> String {
    if !(v.is_finite() && span.is_finite() && span > 0.0) {
        return format!("{v}");
    }
    let k = 3 - span.log10().floor() as i32;
    let r = if k >= 0 {
        let m = 10f64.powi(k.min(22));
        (v * m).round() / m
    } else {
        let m = 10f64.powi((-k).min(22));
        (v / m).round() * m
    };
    if r == 0.0 {
        "0".to_string()
    } else {
        format!("{r}")
    }
}

/// A log-axis tick: plain for 0.01 to 1000, else `1e-5` style.
fn fmt_power_of_ten(v: f64) -> String {
    let e = v.log10().round();
    if (v / 10f64.powf(e) - 1.0).abs() > 1e-9 {
        return fmt_sig(v, 2);
    }
    match e as i32 {
        k @ 0..=3 => format!("1{}", "0".repeat(k as usize)),
        k @ -2..=-1 => format!("0.{}1", "0".repeat((-k - 1) as usize)),
        k => format!("1e{k}"),
    }
}

/// Points per NDF curve over `0..NDF_MAX_DEG`.
const NDF_POINTS: usize = 357;
/// Largest facet angle plotted, degrees (D is evaluated up to here, the axis ends at 90).
const NDF_MAX_DEG: f64 = 89.0;
/// Decades shown below the largest D of a panel.
const NDF_DECADES: f64 = 7.0;

/// Splits a polyline into the pieces with `y >= floor`, cutting each crossing where the
/// segment meets the floor (interpolated in `ln y`), so that nothing is drawn below a log
/// axis.
pub fn clip_below(points: &[(f64, f64)], floor: f64) -> Vec<Vec<(f64, f64)>> {
    let cross = |a: (f64, f64), b: (f64, f64)| {
        let (la, lb, lf) = (
            a.1.max(f64::MIN_POSITIVE).ln(),
            b.1.max(f64::MIN_POSITIVE).ln(),
            floor.ln(),
        );
        let t = ((lf - la) / (lb - la)).clamp(0.0, 1.0);
        (a.0 + t * (b.0 - a.0), floor)
    };
    let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    for (i, &p) in points.iter().enumerate() {
        let inside = p.1 >= floor;
        let prev = i.checked_sub(1).map(|j| points[j]);
        match (prev.map(|q| q.1 >= floor), inside) {
            (Some(false), true) => current.push(cross(prev.expect("checked"), p)),
            (Some(true), false) => {
                current.push(cross(prev.expect("checked"), p));
                pieces.push(std::mem::take(&mut current));
            }
            _ => {}
        }
        if inside {
            current.push(p);
        }
    }
    if !current.is_empty() {
        pieces.push(current);
    }
    pieces
}

/// The fitted NDFs `D(theta_m)` of every sample on a log scale: per sample its title and the
/// NDFs of its four panels.
pub(crate) struct NdfFigure<'a> {
    pub samples: &'a [(String, [Option<AnyNdf>; 4])],
}

impl NdfFigure<'_> {
    fn grid(&self) -> (usize, usize, u32) {
        let n = self.samples.len().max(1);
        let cols = n.min(3);
        let width = match cols {
            1 => 1100,
            2 => 820,
            _ => 640,
        };
        (n.div_ceil(cols), cols, width)
    }
}

impl Figure for NdfFigure<'_> {
    fn size(&self) -> (u32, u32) {
        let (rows, cols, width) = self.grid();
        (width * cols as u32, HEADER_HEIGHT + 560 * rows as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        let (header, body) = root.split_vertically(HEADER_HEIGHT);
        let legend: Vec<LegendEntry> = ModelSlot::ALL
            .iter()
            .map(|s| LegendEntry {
                colour: MODEL_COLOURS[s.index()],
                glyph: Glyph::Line,
                label: s.title().to_string(),
            })
            .collect();
        draw_header(&header, "Fitted NDFs D(θm)", &legend, HEADER_FONT)?;
        let (rows, cols, _) = self.grid();
        for (area, (title, ndfs)) in body.split_evenly((rows, cols)).iter().zip(self.samples) {
            draw_ndf_panel(&area.margin(0, 10, 10, 10), title, ndfs)?;
        }
        Ok(())
    }
}

fn draw_ndf_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    ndfs: &[Option<AnyNdf>; 4],
) -> Result<(), ReportError> {
    let look = LARGE;
    let curves: Vec<(ModelSlot, Vec<(f64, f64)>)> = ModelSlot::ALL
        .iter()
        .filter_map(|&s| ndfs[s.index()].as_ref().map(|ndf| (s, ndf)))
        .map(|(s, ndf)| {
            let pts = (0..NDF_POINTS)
                .map(|k| {
                    let t = NDF_MAX_DEG * k as f64 / (NDF_POINTS - 1) as f64;
                    (t, ndf_at_deg(ndf, t))
                })
                .collect();
            (s, pts)
        })
        .collect();
    let (_, top) = extent(curves.iter().flat_map(|(_, c)| c.iter().map(|p| p.1)));
    let top = if top > 0.0 { top } else { 1.0 };
    let y1 = 10f64.powf((top.log10() + 0.05).ceil());
    let y0 = y1 / 10f64.powf(NDF_DECADES);

    let (title_area, plot_area) = area.split_vertically(look.title_height / 2 + 8);
    let (w, h) = title_area.dim_in_pixel();
    title_area.draw_text(
        title,
        &bold(look.heading).pos(Pos::new(HPos::Center, VPos::Center)),
        (w as i32 / 2, h as i32 / 2),
    )?;
    let mut chart = ChartBuilder::on(&plot_area)
        .margin_right((look.tick * 1.5) as u32)
        .margin_bottom(6)
        .x_label_area_size((look.tick * 3.2) as u32)
        .y_label_area_size((look.tick * 4.6) as u32)
        .build_cartesian_2d(0.0..90.0, (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .x_labels(10)
        .label_style((FONT, look.tick))
        .axis_desc_style((FONT, look.body))
        .x_desc("θm (degrees)")
        .y_desc("D(θm)")
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| fmt_power_of_ten(*v))
        .draw()?;
    for (slot, pts) in &curves {
        let style = MODEL_COLOURS[slot.index()].stroke_width(look.line);
        for piece in clip_below(pts, y0) {
            chart.draw_series(LineSeries::new(piece, style))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A held gamma reads as given when short (`3`, `2.5`); a hand-edited huge one is cut to
    /// four significant digits instead of printing 16.
    #[test]
    fn held_values_read_as_given_unless_long() {
        assert_eq!(held_value(3.0), "3");
        assert_eq!(held_value(2.5), "2.5");
        assert_eq!(held_value(1e15), fmt_sig(1e15, 4));
        assert!(held_value(1e15).len() < 10, "{}", held_value(1e15));
    }
}
