//! A map of the floes coloured by a per-floe value, with a colour bar.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::colour::ColourScale;
use super::colour_bar::{self, ColourBarLayout};
use crate::plot::{register_font, right_margin, y_label_area, TickAxis};
use floe_run::Error;

/// Grey of floes that have no value (no contacts) and of walls.
const NO_VALUE: RGBColor = RGBColor(200, 200, 200);
const WALL: RGBColor = RGBColor(110, 110, 110);
/// Grey-brown of land (`[[land]]` pieces), distinct from walls and ice.
pub const LAND: RGBColor = RGBColor(158, 134, 100);

/// What to draw.
#[derive(Debug, Clone, Copy)]
pub struct FloeMap<'a> {
    /// Caption.
    pub title: &'a str,
    /// Outlines in world coordinates, m.
    pub polygons: &'a [Vec<(f64, f64)>],
    /// The value of each floe (`None`: drawn grey).
    pub values: &'a [Option<f64>],
    /// Walls and other prescribed floes (drawn dark grey).
    pub prescribed: &'a [bool],
    /// Land pieces (prescribed too; drawn in [`LAND`], without outlines,
    /// so that the pieces read as one coast).
    pub land: &'a [bool],
    /// Value to colour.
    pub scale: ColourScale,
    /// Colour-bar title, with unit.
    pub label: &'a str,
    /// Region to show, m: `((x_min, x_max), (y_min, y_max))`.
    pub view: ((f64, f64), (f64, f64)),
}

/// Width of a map, pixels.
const WIDTH: u32 = 1400;

/// The size in pixels of a map of `view` (width, height): 1400 wide, the
/// plot as tall as the view's aspect asks (within 260 to 1400 pixels).
pub fn frame_size(view: ((f64, f64), (f64, f64))) -> (u32, u32) {
    let ((x0, x1), (y0, y1)) = view;
    let aspect = (y1 - y0) / (x1 - x0);
    let plot_height = ((WIDTH - 160) as f64 * aspect).clamp(260.0, 1400.0) as u32;
    (WIDTH, plot_height + 90)
}

/// Draws `map` into a PNG at `path`, of [`frame_size`]; axes in km.
pub fn draw(path: &Path, map: &FloeMap) -> Result<(), Error> {
    register_font();
    let root = BitMapBackend::new(path, frame_size(map.view)).into_drawing_area();
    draw_on(&root, map).map_err(|e| Error::Plot {
        path: path.to_path_buf(),
        message: e,
    })
}

/// Draws `map` into `rgb`, an image of `size` pixels (3 bytes each, rows
/// from the top), for a frame of a movie named `movie`.
pub fn draw_rgb(
    map: &FloeMap,
    size: (u32, u32),
    rgb: &mut [u8],
    movie: &Path,
) -> Result<(), Error> {
    register_font();
    let root = BitMapBackend::with_buffer(rgb, size).into_drawing_area();
    draw_on(&root, map).map_err(|e| Error::Plot {
        path: movie.to_path_buf(),
        message: e,
    })
}

/// Draws `map` on `root`: the floes on the left, the colour bar on the right.
fn draw_on<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, map: &FloeMap) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let ((x0, x1), (y0, y1)) = map.view;
    let (width, height) = root.dim_in_pixel();
    root.fill(&WHITE).map_err(err)?;
    let bar = ColourBarLayout::new(map.scale, map.label, height);
    let (left, right) = root.split_horizontally(width.saturating_sub(bar.width));
    let km = 1e-3;
    let (plot_width, plot_height) = left.dim_in_pixel();
    let (xr, xt) = TickAxis::over(x0 * km, x1 * km, (plot_width / 100).max(2) as usize);
    let (yr, yt) = TickAxis::over(y0 * km, y1 * km, (plot_height / 60).max(2) as usize);
    let mut chart = ChartBuilder::on(&left)
        .caption(map.title, ("sans-serif", 20))
        .margin(10)
        .margin_right(right_margin(&xt, 10))
        .x_label_area_size(40)
        .y_label_area_size(y_label_area(&yt))
        .build_cartesian_2d(xr, yr)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(xt.title("x (km)"))
        .y_desc(yt.title("y (km)"))
        .x_label_formatter(&|v| xt.label_of(*v))
        .y_label_formatter(&|v| yt.label_of(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let inside = |&(x, y): &(f64, f64)| x >= x0 && x <= x1 && y >= y0 && y <= y1;
    let fills = map.polygons.iter().enumerate().filter_map(|(i, poly)| {
        // plotters does not clip to the plot area: clip every outline to
        // it (walls and land reach beyond the view; clamping the vertices
        // instead would distort a piece that crosses a corner).
        let clipped = clip_to_view(poly, map.view);
        if clipped.len() < 3 {
            return None;
        }
        let colour = if map.land[i] {
            LAND
        } else if map.prescribed[i] {
            WALL
        } else {
            map.values[i].map_or(NO_VALUE, |v| map.scale.colour(v))
        };
        let pts: Vec<(f64, f64)> = clipped.iter().map(|&(x, y)| (x * km, y * km)).collect();
        Some(Polygon::new(pts, colour.filled()))
    });
    chart.draw_series(fills).map_err(err)?;
    // Land pieces' edges in the land colour: the fills alone leave
    // hairline seams between pieces that share an edge.
    let seams = map
        .polygons
        .iter()
        .zip(map.land)
        .filter(|(_, &land)| land)
        .filter_map(|(poly, _)| {
            let mut pts: Vec<(f64, f64)> = clip_to_view(poly, map.view)
                .iter()
                .map(|&(x, y)| (x * km, y * km))
                .collect();
            let first = *pts.first()?;
            pts.push(first);
            Some(PathElement::new(pts, LAND.stroke_width(1)))
        });
    chart.draw_series(seams).map_err(err)?;
    // Outlines only when floes are big enough on screen to show them.
    let bodies = map.land.iter().filter(|&&l| !l).count();
    let pixels_per_floe = (width as f64 - 220.0) / (bodies as f64).sqrt().max(1.0);
    if pixels_per_floe > 6.0 {
        let outlines = map
            .polygons
            .iter()
            .zip(map.land)
            .filter(|(p, &land)| !land && p.iter().any(inside))
            .map(|(poly, _)| {
                let mut pts: Vec<(f64, f64)> = poly
                    .iter()
                    .map(|&(x, y)| (x.clamp(x0, x1) * km, y.clamp(y0, y1) * km))
                    .collect();
                pts.push(pts[0]);
                PathElement::new(pts, BLACK.mix(0.35).stroke_width(1))
            });
        chart.draw_series(outlines).map_err(err)?;
    }
    colour_bar::draw(&right, map.scale, &bar)?;
    root.present().map_err(err)
}

/// The convex outline `poly` clipped to the rectangle `view` (one
/// Sutherland-Hodgman pass per side).
fn clip_to_view(
    poly: &[(f64, f64)],
    ((x0, x1), (y0, y1)): ((f64, f64), (f64, f64)),
) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = poly.to_vec();
    // Each side as (coordinate index, bound, keep at or above the bound).
    for (axis, bound, above) in [(0, x0, true), (0, x1, false), (1, y0, true), (1, y1, false)] {
        let value = |p: (f64, f64)| if axis == 0 { p.0 } else { p.1 };
        let keep = |p: (f64, f64)| {
            if above {
                value(p) >= bound
            } else {
                value(p) <= bound
            }
        };
        let n = out.len();
        let mut next = Vec::with_capacity(n + 2);
        for k in 0..n {
            let (p, q) = (out[k], out[(k + 1) % n]);
            if keep(p) {
                next.push(p);
            }
            if keep(p) != keep(q) {
                let t = (bound - value(p)) / (value(q) - value(p));
                next.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
            }
        }
        out = next;
        if out.len() < 3 {
            break;
        }
    }
    out
}
