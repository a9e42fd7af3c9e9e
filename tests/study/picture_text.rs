//! The text of floe's pictures, read back from the pixels drawn. The
//! colour bar of a map (floe_study::render::floe_map): the tick labels
//! stand clear of the bar and its tick marks (no glyph runs into them),
//! and the title and labels lie whole inside the bar's panel (none cut at
//! the image's edge or written over the map); three bars that went wrong:
//! the demo's gridded shear rates (2e-7 to 3e-5 /s), its concentration
//! (0.85 to 1), and theta (a diverging scale with a long title). A plot
//! (floe_study::plot): the last x label, centred on the plot's right
//! edge, is not cut by the image's edge.

use std::path::Path;

use floe_study::plot::{panels, Axes, Line};
use floe_study::render::colour::ColourScale;
use floe_study::render::floe_map::{draw_rgb, frame_size, FloeMap};

/// A map of 20 x 10 cells of 1 km, coloured by `values(i, j)`.
fn draw(label: &str, diverging: bool, value: impl Fn(usize, usize) -> f64) -> Image {
    let mut polygons = Vec::new();
    let mut values = Vec::new();
    for j in 0..10 {
        for i in 0..20 {
            let (x, y) = (i as f64 * 1000.0, j as f64 * 1000.0);
            polygons.push(vec![
                (x, y),
                (x + 1000.0, y),
                (x + 1000.0, y + 1000.0),
                (x, y + 1000.0),
            ]);
            values.push(Some(value(i, j)));
        }
    }
    let flags = vec![false; polygons.len()];
    let view = ((0.0, 20_000.0), (0.0, 10_000.0));
    let map = FloeMap {
        title: "fields.nc: a field",
        polygons: &polygons,
        values: &values,
        prescribed: &flags,
        land: &flags,
        scale: ColourScale::fit(values.iter().flatten().copied(), diverging),
        label,
        view,
    };
    let (width, height) = frame_size(view);
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    draw_rgb(&map, (width, height), &mut rgb, Path::new("test.gif")).unwrap();
    Image { width, height, rgb }
}

struct Image {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Image {
    fn at(&self, x: u32, y: u32) -> [u8; 3] {
        let k = 3 * (y as usize * self.width as usize + x as usize);
        [self.rgb[k], self.rgb[k + 1], self.rgb[k + 2]]
    }

    /// A pixel of a colour scale: saturated.
    fn colourful(&self, x: u32, y: u32) -> bool {
        let p = self.at(x, y);
        p.iter().max().unwrap() - p.iter().min().unwrap() > 25
    }

    /// A pixel of black text or lines (anti-aliased edges included): grey
    /// and darker than light grey.
    fn ink(&self, x: u32, y: u32) -> bool {
        let p = self.at(x, y);
        let spread = p.iter().max().unwrap() - p.iter().min().unwrap();
        spread < 40 && p.iter().map(|&c| c as u32).sum::<u32>() < 3 * 170
    }
}

/// The bar (its coloured columns' left and right, its coloured rows' top
/// and bottom) and the right edge of the map's coloured cells.
struct Found {
    bar: (u32, u32, u32, u32),
    map_right: u32,
}

fn find(img: &Image) -> Found {
    // Columns mostly of scale colours, from the right: the bar, then the map.
    let tall = |x: u32| (0..img.height).filter(|&y| img.colourful(x, y)).count() as u32;
    let coloured: Vec<bool> = (0..img.width).map(|x| tall(x) > img.height / 2).collect();
    let right = (0..img.width)
        .rev()
        .find(|&x| coloured[x as usize])
        .unwrap();
    let left = (0..=right).rev().find(|&x| !coloured[x as usize]).unwrap() + 1;
    let map_right = (0..left).rev().find(|&x| coloured[x as usize]).unwrap();
    let middle = (left + right) / 2;
    let top = (0..img.height).find(|&y| img.colourful(middle, y)).unwrap();
    let bottom = (0..img.height)
        .rev()
        .find(|&y| img.colourful(middle, y))
        .unwrap();
    Found {
        bar: (left, right, top, bottom),
        map_right,
    }
}

/// The 8-connected components of ink within `x >= x0`, as bounding boxes
/// (left, right, top, bottom).
fn ink_components(img: &Image, x0: u32) -> Vec<(u32, u32, u32, u32)> {
    let (w, h) = (img.width as usize, img.height as usize);
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    for y in 0..h {
        for x in x0 as usize..w {
            if seen[y * w + x] || !img.ink(x as u32, y as u32) {
                continue;
            }
            let mut stack = vec![(x, y)];
            seen[y * w + x] = true;
            let mut b = (x as u32, x as u32, y as u32, y as u32);
            while let Some((px, py)) = stack.pop() {
                b = (
                    b.0.min(px as u32),
                    b.1.max(px as u32),
                    b.2.min(py as u32),
                    b.3.max(py as u32),
                );
                for dy in -1i64..=1 {
                    for dx in -1i64..=1 {
                        let (nx, ny) = (px as i64 + dx, py as i64 + dy);
                        if nx < x0 as i64 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                            continue;
                        }
                        let (nx, ny) = (nx as usize, ny as usize);
                        if !seen[ny * w + nx] && img.ink(nx as u32, ny as u32) {
                            seen[ny * w + nx] = true;
                            stack.push((nx, ny));
                        }
                    }
                }
            }
            out.push(b);
        }
    }
    out
}

/// The checks on one map's colour bar.
fn check(name: &str, img: &Image) {
    let f = find(img);
    let (_, bar_right, bar_top, bar_bottom) = f.bar;
    // Right of the bar's own edge line (one column) and level with the
    // bar, the ink is tick marks (a row or two tall), perhaps an axis line
    // (a column or two wide), and text standing apart from both: nothing
    // both wide and tall may reach the first few columns by the bar.
    let beside = bar_right + 2;
    for c in ink_components(img, beside) {
        let (left, right, top, bottom) = c;
        let (w, h) = (right - left + 1, bottom - top + 1);
        let level_with_bar = bottom + 2 >= bar_top && top <= bar_bottom + 2;
        if level_with_bar && left <= beside + 6 {
            assert!(
                w <= 2 || h <= 2,
                "{name}: ink {c:?} runs from the bar's tick marks into text (bar {:?})",
                f.bar
            );
        }
        // Nothing cut at the image's edges.
        assert!(right < img.width - 1, "{name}: {c:?} cut at the right edge");
        assert!(
            top > 0 && bottom < img.height - 1,
            "{name}: {c:?} cut at the top or bottom"
        );
    }
    // The panel's text (title included) lies right of the map's cells:
    // none of it runs into the map from the panel.
    let panel = f.map_right + 2;
    for c in ink_components(img, panel) {
        if c.2 > img.height - 45 {
            continue; // the map's x-axis title and labels, below the plot
        }
        assert!(
            c.0 > panel,
            "{name}: ink {c:?} crosses into the map (its cells end at x = {})",
            f.map_right
        );
    }
}

#[test]
fn colour_bar_labels_and_titles_are_whole_and_clear_of_the_bar() {
    let wave = |i: usize, j: usize| ((i * 7 + j * 3) % 23) as f64 / 22.0;
    let shear = draw("shear (s-1)", false, |i, j| {
        2.390250834193666e-7 + (3.35551725156712e-5 - 2.390250834193666e-7) * wave(i, j)
    });
    check("shear", &shear);
    let concentration = draw("concentration (1)", false, |i, j| {
        0.8520923443704952 + 0.1494957 * wave(i, j)
    });
    check("concentration", &concentration);
    let theta = draw("theta (mean over contacts)", true, |i, j| {
        -2.6 + 2.9 * wave(i, j)
    });
    check("theta", &theta);
}

#[test]
fn the_last_x_label_of_a_plot_is_not_cut_at_the_image_edge() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plot.png");
    // x from -5 to 10 s: the last label, 10.0, sits on the right edge.
    let line: Vec<(f64, f64)> = (0..=150)
        .map(|k| (-5.0 + 0.1 * k as f64, (0.1 * k as f64).sin()))
        .collect();
    let axes = Axes {
        title: "a hold",
        x: "time from the end of the hold (s)",
        y: "mu",
    };
    panels(&path, &[(axes, vec![Line::new("", line)])]).unwrap();
    let decoder = png::Decoder::new(std::fs::File::open(&path).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let img = Image {
        width: info.width,
        height: info.height,
        rgb: buf[..info.buffer_size()].to_vec(),
    };
    // Text in the last columns is a glyph the edge cut.
    for x in img.width - 2..img.width {
        for y in 0..img.height {
            assert!(!img.ink(x, y), "ink at ({x}, {y}), the image's edge");
        }
    }
}
