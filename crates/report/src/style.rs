//! Colours, number formats and the shared figure header (title and legend).

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, RGBColor};

use crate::ReportError;
use crate::render::FONT;

/// Okabe-Ito colours (distinguishable with the common colour-vision deficiencies), without its
/// yellow, which is too light on white.
const OKABE_ITO: [RGBColor; 7] = [
    RGBColor(0x00, 0x72, 0xB2),
    RGBColor(0xE6, 0x9F, 0x00),
    RGBColor(0x00, 0x9E, 0x73),
    RGBColor(0xD5, 0x5E, 0x00),
    RGBColor(0xCC, 0x79, 0xA7),
    RGBColor(0x56, 0xB4, 0xE9),
    RGBColor(0x00, 0x00, 0x00),
];

/// Neutral grey for legend entries that explain marker and line.
pub(crate) const GREY: RGBColor = RGBColor(0x55, 0x55, 0x55);
/// Grid lines.
pub(crate) const GRID: RGBColor = RGBColor(0xE2, 0xE2, 0xE2);

/// One colour per incident direction, fixed for a whole report: the `k`-th incident direction
/// `(theta_i, phi_i)` of the dataset, in ascending order, gets the `k`-th colour in every
/// figure and panel. In-plane figures key their incidences by `(theta_i, 0)`; the figures of
/// general samples have their own palette, so that two incidences at the same `theta_i` and
/// other azimuths get different colours.
#[derive(Debug, Clone)]
pub(crate) struct AnglePalette {
    angles: Vec<(f64, f64)>,
}

impl AnglePalette {
    pub(crate) fn new(angles: impl Iterator<Item = (f64, f64)>) -> Self {
        let mut angles: Vec<(f64, f64)> = angles.collect();
        angles.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        angles.dedup();
        Self { angles }
    }

    pub(crate) fn colour(&self, incidence: (f64, f64)) -> RGBColor {
        let k = self
            .angles
            .iter()
            .position(|&a| a == incidence)
            .unwrap_or(0);
        OKABE_ITO[k % OKABE_ITO.len()]
    }

    pub(crate) fn angles(&self) -> &[(f64, f64)] {
        &self.angles
    }
}

/// Colour of each model slot in the NDF figure.
pub(crate) const MODEL_COLOURS: [RGBColor; 4] = [
    RGBColor(0x00, 0x00, 0x00),
    OKABE_ITO[3],
    OKABE_ITO[0],
    OKABE_ITO[2],
];

/// `x` with `sig` significant digits, in plain notation for moderate magnitudes. The magnitude
/// is that of `x` rounded to those digits, so that 9.99996 to 4 digits is `10.00`, not `10.000`.
pub fn fmt_sig(x: f64, sig: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".to_string();
    }
    let rounded = format!("{x:.*e}", sig.saturating_sub(1));
    let mag: i32 = rounded
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .expect("Rust writes an exponent in {:e}");
    if (-5..6).contains(&mag) {
        let decimals = (sig as i32 - 1 - mag).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        rounded
    }
}

/// An angle in degrees without a trailing `.0` for whole degrees.
pub(crate) fn fmt_deg(x: f64) -> String {
    if x == x.round() && x.abs() < 1e6 {
        format!("{}°", x as i64)
    } else {
        format!("{}°", fmt_sig(x, 4))
    }
}

pub(crate) fn text(size: f64) -> TextStyle<'static> {
    (FONT, size).into_font().color(&BLACK)
}

pub(crate) fn bold(size: f64) -> TextStyle<'static> {
    // `FontDesc::style` keeps the regular glyphs: the bold face must be chosen on creation.
    (FONT, size, FontStyle::Bold).into_font().color(&BLACK)
}

/// How a legend entry is drawn.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Glyph {
    Marker,
    HollowMarker,
    Line,
    MarkerAndLine,
}

/// One legend entry.
#[derive(Debug, Clone)]
pub(crate) struct LegendEntry {
    pub colour: RGBColor,
    pub glyph: Glyph,
    pub label: String,
}

/// Draws a figure title and, below it, a one-line legend, both centred, into `area`.
pub(crate) fn draw_header<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    legend: &[LegendEntry],
    font_size: f64,
) -> Result<(), ReportError> {
    let (w, h) = area.dim_in_pixel();
    let title_style = bold(font_size * 1.25).pos(Pos::new(HPos::Center, VPos::Center));
    let title_y = (h as f64 * 0.3) as i32;
    area.draw_text(title, &title_style, (w as i32 / 2, title_y))?;

    let label_style = text(font_size).pos(Pos::new(HPos::Left, VPos::Center));
    let glyph_w = (font_size * 1.8) as i32;
    let gap = (font_size * 0.4) as i32;
    let spacing = (font_size * 1.6) as i32;
    let widths = legend
        .iter()
        .map(|e| {
            let (tw, _) = area.estimate_text_size(&e.label, &label_style)?;
            Ok(glyph_w + gap + tw as i32)
        })
        .collect::<Result<Vec<_>, ReportError>>()?;
    let total: i32 = widths.iter().sum::<i32>() + spacing * (widths.len() as i32 - 1).max(0);
    let y = (h as f64 * 0.75) as i32;
    let mut x = (w as i32 - total) / 2;
    let r = (font_size * 0.3).round() as i32;
    for (e, width) in legend.iter().zip(widths) {
        let mid = x + glyph_w / 2;
        let line = e.colour.stroke_width(3);
        match e.glyph {
            Glyph::Marker => area.draw(&Circle::new((mid, y), r, e.colour.filled()))?,
            Glyph::HollowMarker => {
                area.draw(&Circle::new((mid, y), r, e.colour.stroke_width(2)))?
            }
            Glyph::Line => area.draw(&PathElement::new(vec![(x, y), (x + glyph_w, y)], line))?,
            Glyph::MarkerAndLine => {
                area.draw(&PathElement::new(vec![(x, y), (x + glyph_w, y)], line))?;
                area.draw(&Circle::new((mid, y), r, e.colour.filled()))?;
            }
        }
        area.draw_text(&e.label, &label_style, (x + glyph_w + gap, y))?;
        x += width + spacing;
    }
    Ok(())
}

/// Legend of the fit and residual figures: what markers and lines mean, and the colour of
/// each incidence angle; `unfitted` adds the hollow marker of points of weight 0.
pub(crate) fn angle_legend(
    palette: &AnglePalette,
    lines: bool,
    unfitted: bool,
) -> Vec<LegendEntry> {
    let mut entries = vec![LegendEntry {
        colour: GREY,
        glyph: Glyph::Marker,
        label: "measured".into(),
    }];
    if unfitted {
        entries.push(LegendEntry {
            colour: GREY,
            glyph: Glyph::HollowMarker,
            label: "weight 0, not fitted".into(),
        });
    }
    if lines {
        entries.push(LegendEntry {
            colour: GREY,
            glyph: Glyph::Line,
            label: "model".into(),
        });
    }
    entries.extend(palette.angles().iter().map(|&a| LegendEntry {
        colour: palette.colour(a),
        glyph: if lines {
            Glyph::MarkerAndLine
        } else {
            Glyph::Marker
        },
        label: format!("θi = {}", fmt_deg(a.0)),
    }));
    entries
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Significant digits are counted after rounding: a value just below a power of ten that
    /// rounds up to it has no extra digit.
    #[test]
    fn fmt_sig_counts_digits_after_rounding() {
        assert_eq!(fmt_sig(9.99996, 4), "10.00");
        assert_eq!(fmt_sig(0.099996, 2), "0.10");
        assert_eq!(fmt_sig(0.2001, 4), "0.2001");
        assert_eq!(fmt_sig(1234.5, 2), "1234");
        assert_eq!(fmt_sig(-0.00012345, 3), "-0.000123");
        assert_eq!(fmt_sig(999_999.7, 3), "1.00e6");
        assert_eq!(fmt_sig(1.5e-7, 2), "1.5e-7");
    }
}
