//! `floe render` draws land (`[[land]]` pieces, marked in the run file)
//! filled in the land colour, distinct from walls and ice; and a run file
//! without the land marker (older files) reads as having no land.

use crate::study_support;
use floe_io::RunFile;
use floe_study::render::floe_map::LAND;
use floe_study::render::{render, ColourBy, Snapshots};
use study_support::run_text;

/// Land east of x = 7 km with a notch, over the whole height of the view.
const COAST: &str = r#"{"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
  "coordinates": [[[7000, -2000], [14000, -2000], [14000, 12000], [7000, 12000],
                   [7000, 6000], [8500, 5000], [7000, 4000], [7000, -2000]]]}}"#;

const SCENARIO: &str = r#"duration_s = 60.0

[domain]
size_m = [10000.0, 10000.0]

[tessellation]
kind = "diamond"
side_m = 800.0

[[wall]]
side = "bottom"

[ice]
initial_velocity_m_per_s = [0.5, 0.0]

[[land]]
file = "coast.geojson"
coordinates = "xy"

[output]
snapshot_every_s = 30.0
"#;

#[test]
fn render_draws_land_in_the_land_colour() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("coast.geojson"), COAST).unwrap();
    let h5 = run_text(dir.path(), "coast", SCENARIO).unwrap();
    let floes = RunFile::open(&h5).unwrap().static_floes().unwrap();
    let land = floes.land.iter().filter(|&&l| l).count();
    let walls = floes
        .prescribed
        .iter()
        .zip(&floes.land)
        .filter(|(&p, &l)| p && !l)
        .count();
    assert!(
        land > 10 && walls > 0,
        "{land} land pieces, {walls} wall pieces"
    );
    assert!(floes
        .land
        .iter()
        .zip(&floes.prescribed)
        .all(|(&l, &p)| !l || p));

    let out = dir.path().join("pictures");
    let files = render(&h5, Snapshots::One(-1), ColourBy::Speed, &out, false).unwrap();
    let png = std::fs::File::open(&files[0]).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(png))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let (w, h) = (info.width as usize, info.height as usize);
    let channels = info.line_size / w;
    let pixel = |x: usize, y: usize| {
        let k = y * info.line_size + x * channels;
        (buf[k], buf[k + 1], buf[k + 2])
    };
    let land_rgb = (LAND.0, LAND.1, LAND.2);
    // The plot spans x from about pixel 70 to 1240 for the view from -400
    // m to 10,400 m: x = 9.5 km (on land at every height) is near pixel
    // 1100, x = 2 km (ice) near 290. Middle row.
    let x_of = |m: f64| (70.0 + (m + 400.0) / 10_800.0 * 1170.0).round() as usize;
    let row = h / 2;
    assert_eq!(pixel(x_of(9500.0), row), land_rgb, "a pixel on land");
    assert_ne!(pixel(x_of(2000.0), row), land_rgb, "a pixel on the ice");
    let land_pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| pixel(x, y) == land_rgb)
        .count();
    // The land covers about a quarter of the plot.
    assert!(
        land_pixels > w * h / 10,
        "{land_pixels} land pixels of {}",
        w * h
    );
}
