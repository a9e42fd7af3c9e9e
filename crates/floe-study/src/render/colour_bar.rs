//! The colour bar beside a map: the scale's colours, ticks labelled by
//! [`Ticks`], and a title with the unit (and the labels' power of ten),
//! laid out from the widths of the texts measured with the embedded font,
//! so that no label or title is cut off or runs into the bar.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::colour::ColourScale;
use crate::plot::text_width;
use crate::ticks::Ticks;

/// Font sizes of the labels and the title, pixels.
const LABEL_FONT: f64 = 13.0;
const TITLE_FONT: f64 = 14.0;
/// Height of a title line, pixels.
const TITLE_LINE: i32 = 17;
/// The bar's width, its ticks' length, the gap from tick to label, the
/// panel's inner margin, pixels.
const BAR_WIDTH: i32 = 20;
const TICK: i32 = 5;
const GAP: i32 = 4;
const PAD: i32 = 10;
/// Top of the title, and the bar's bottom above the panel's bottom (level
/// with the bottom of the map's plot area), pixels.
const TITLE_TOP: i32 = 24;
const BOTTOM: i32 = 50;
/// A title wider than this goes on two lines (name, then unit).
const TITLE_WRAP: u32 = 150;
/// Pixels per tick the bar aims at.
const PIXELS_PER_TICK: i32 = 50;

/// A text and the box it fills, in the panel's pixels (left, top, width,
/// height).
#[derive(Debug, Clone, PartialEq)]
pub struct Placed {
    /// The text.
    pub text: String,
    /// Its box: left, top, width, height.
    pub rect: (i32, i32, i32, i32),
}

/// Where everything of a colour bar goes in a panel of the height given.
#[derive(Debug, Clone, PartialEq)]
pub struct ColourBarLayout {
    /// The panel's width, pixels: wide enough for the labels and the title.
    pub width: u32,
    /// The bar: left, top, width, height.
    pub bar: (i32, i32, i32, i32),
    /// The title's lines.
    pub title: Vec<Placed>,
    /// The tick labels, bottom to top.
    pub labels: Vec<Placed>,
    /// Each label's value.
    pub values: Vec<f64>,
}

impl ColourBarLayout {
    /// The layout of the bar of `scale` titled `label` in a panel
    /// `height` pixels tall.
    pub fn new(scale: ColourScale, label: &str, height: u32) -> Self {
        let height = height as i32;
        let bar_top_guess = TITLE_TOP + 2 * TITLE_LINE + 12;
        let bar_height_guess = (height - BOTTOM - bar_top_guess).max(1);
        let target = (bar_height_guess / PIXELS_PER_TICK).clamp(2, 10) as usize;
        let ticks = Ticks::over(scale.lo, scale.hi, target);
        let title = ticks.title(label);
        let lines: Vec<String> = match title.rsplit_once(" (") {
            Some((name, unit)) if text_width(&title, TITLE_FONT) > TITLE_WRAP => {
                vec![name.to_string(), format!("({unit}")]
            }
            _ => vec![title],
        };
        let bar_top = TITLE_TOP + lines.len() as i32 * TITLE_LINE + 12;
        let bar = (PAD, bar_top, BAR_WIDTH, (height - BOTTOM - bar_top).max(1));
        let label_x = PAD + BAR_WIDTH + TICK + GAP;
        let label_height = (LABEL_FONT / 1.24).ceil() as i32 + 2;
        let labels: Vec<Placed> = ticks
            .values
            .iter()
            .zip(&ticks.labels)
            .map(|(&v, text)| {
                let y = value_row(scale, bar, v);
                Placed {
                    rect: (
                        label_x,
                        y - label_height / 2,
                        text_width(text, LABEL_FONT) as i32,
                        label_height,
                    ),
                    text: text.clone(),
                }
            })
            .collect();
        let widest_label = labels.iter().map(|l| l.rect.2).max().unwrap_or(0);
        let widths: Vec<i32> = lines
            .iter()
            .map(|l| text_width(l, TITLE_FONT) as i32)
            .collect();
        let widest_title = widths.iter().copied().max().unwrap_or(0);
        let width = (label_x + widest_label + PAD).max(widest_title + 2 * PAD);
        let title = lines
            .into_iter()
            .zip(widths)
            .enumerate()
            .map(|(i, (text, w))| Placed {
                text,
                rect: (
                    (width - w) / 2,
                    TITLE_TOP + i as i32 * TITLE_LINE,
                    w,
                    TITLE_LINE,
                ),
            })
            .collect();
        Self {
            width: width as u32,
            bar,
            title,
            labels,
            values: ticks.values,
        }
    }
}

/// The pixel row of value `v` on the bar (its top is `hi`).
fn value_row(scale: ColourScale, bar: (i32, i32, i32, i32), v: f64) -> i32 {
    let (_, top, _, h) = bar;
    let t = (v - scale.lo) / (scale.hi - scale.lo);
    top + ((1.0 - t) * (h - 1) as f64).round() as i32
}

/// Draws the bar of `scale` as `layout` places it on `area`.
pub(crate) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    scale: ColourScale,
    layout: &ColourBarLayout,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (x, top, w, h) = layout.bar;
    // One row of pixels at a time (a filled rectangle's far corner is
    // outside it), each the colour of its middle value.
    for row in 0..h {
        let t = 1.0 - (row as f64 + 0.5) / h as f64;
        let colour = scale.colour(scale.lo + t * (scale.hi - scale.lo));
        area.draw(&Rectangle::new(
            [(x, top + row), (x + w, top + row + 1)],
            colour.filled(),
        ))
        .map_err(err)?;
    }
    area.draw(&Rectangle::new(
        [(x, top), (x + w - 1, top + h - 1)],
        BLACK.stroke_width(1),
    ))
    .map_err(err)?;
    let label_style = TextStyle::from(("sans-serif", LABEL_FONT).into_font())
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (label, &v) in layout.labels.iter().zip(&layout.values) {
        let y = value_row(scale, layout.bar, v);
        area.draw(&PathElement::new(
            vec![(x + w - 1, y), (x + w - 1 + TICK, y)],
            BLACK.stroke_width(1),
        ))
        .map_err(err)?;
        area.draw_text(&label.text, &label_style, (label.rect.0, y))
            .map_err(err)?;
    }
    let title_style = TextStyle::from(("sans-serif", TITLE_FONT).into_font())
        .pos(Pos::new(HPos::Left, VPos::Top));
    for line in &layout.title {
        area.draw_text(&line.text, &title_style, (line.rect.0, line.rect.1))
            .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn overlap(a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)) -> bool {
        a.0 < b.0 + b.2 && b.0 < a.0 + a.2 && a.1 < b.1 + b.3 && b.1 < a.1 + a.3
    }

    #[test]
    fn labels_and_title_fit_in_the_panel_without_touching_the_bar_or_each_other() {
        let titles = [
            "shear (s-1)",
            "concentration (1)",
            "theta (mean over contacts)",
            "total_deformation (s-1)",
            "pressure (kN/m)",
        ];
        let mut ranges = vec![
            (2.390250834193666e-7, 3.35551725156712e-5),
            (0.8520923443704952, 1.001588188852965),
            (-2168.5846023321637, -46.96698538788321),
            (1000.001, 1000.002),
            (-1.5e9, 2.5e9),
        ];
        for e in -15..=15 {
            let x = 10f64.powi(e);
            ranges.push((0.13 * x, 7.7 * x));
            ranges.push((-3.3 * x, 3.3 * x));
        }
        for (lo, hi) in ranges {
            for (k, &title) in titles.iter().enumerate() {
                let scale = ColourScale {
                    lo,
                    hi,
                    diverging: k % 2 == 1,
                };
                for height in [350, 710, 1490] {
                    let l = ColourBarLayout::new(scale, title, height);
                    let why = format!("[{lo:e}, {hi:e}] {title} in {height}: {l:?}");
                    let panel = (0, 0, l.width as i32, height as i32);
                    let inside = |r: (i32, i32, i32, i32)| {
                        r.0 >= 0 && r.1 >= 0 && r.0 + r.2 <= panel.2 && r.1 + r.3 <= panel.3
                    };
                    assert!(l.labels.len() >= 2, "{why}");
                    for (i, a) in l.labels.iter().enumerate() {
                        assert!(inside(a.rect), "{why}");
                        assert!(a.rect.0 > l.bar.0 + l.bar.2 + TICK, "{why}");
                        for b in &l.labels[i + 1..] {
                            assert!(!overlap(a.rect, b.rect), "{why}");
                            assert_ne!(a.text, b.text, "{why}");
                        }
                        for t in &l.title {
                            assert!(!overlap(a.rect, t.rect), "{why}");
                        }
                    }
                    for t in &l.title {
                        assert!(inside(t.rect), "{why}");
                        assert!(t.rect.1 + t.rect.3 <= l.bar.1, "{why}");
                    }
                    if lo >= 0.0 {
                        assert!(l.values.iter().all(|&v| v >= 0.0), "{why}");
                        assert!(l.labels.iter().all(|p| !p.text.starts_with('-')), "{why}");
                    }
                }
            }
        }
    }
}
