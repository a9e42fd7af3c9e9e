//! Writes the auxiliary files of the fuzz test's basin scenario
//! (`tests/data/fuzz/scenarios/basin.toml`): a 20 km square of the NSIDC
//! polar stereographic plane (EPSG:3413) near 81° N, 62° W. No downloads:
//! everything is made here, and the files are small (a few kB each).
//!
//! Run: `cargo run --release -p floe-basin --example make_fuzz_basin [DIR]`
//! (default `tests/data/fuzz/basin`). Writes:
//!
//! - `coast.geojson`: one concave island (an L, eight vertices) in the
//!   domain's lower right, as a longitude-latitude `Polygon` in a
//!   `FeatureCollection`; made on the plane and projected back.
//! - `wind.nc` (NetCDF-4, that is HDF5): an ERA5-like 10 m wind (`u10`,
//!   `v10`, eastward and northward, f32, m/s) on a 0.25° latitude by 0.5°
//!   longitude grid (latitude descending), hourly for six hours from
//!   2024-03-01 00:00 (`hours since 2024-03-01 00:00:00`): 8 m/s towards
//!   the plane's +x, turning to +y.
//! - `ssh.nc` (NetCDF-3 classic): a steady sea-surface height `zos` (m) on
//!   the plane's x/y grid at 2 km, sloping gently down towards +x, packed
//!   as `short` with `scale_factor`, `add_offset` and `_FillValue`.

#[path = "support/lon_lat_file.rs"]
mod lon_lat_file;
use lon_lat_file::lon_lat_file;

use std::path::{Path, PathBuf};

use floe_basin::MapProjection;
use floe_dem::Vec2;

/// The scenario's `[domain]`: lower-left corner and side, m.
const MIN_M: (f64, f64) = (-300_000.0, -940_000.0);
const SIDE_M: f64 = 20_000.0;
/// How far beyond the domain the files reach, m.
const MARGIN_M: f64 = 15_000.0;
/// Hours of wind from 2024-03-01 00:00.
const WIND_HOURS: usize = 6;

fn domain_point(sx: f64, sy: f64) -> Vec2 {
    Vec2::new(MIN_M.0 + sx * SIDE_M, MIN_M.1 + sy * SIDE_M)
}

/// An L-shaped island in the lower right of the domain, counter-clockwise,
/// as fractions of the domain's side.
fn island() -> Vec<Vec2> {
    [
        (0.55, 0.10),
        (0.90, 0.10),
        (0.90, 0.45),
        (0.80, 0.45),
        (0.80, 0.20),
        (0.65, 0.20),
        (0.65, 0.30),
        (0.55, 0.30),
    ]
    .iter()
    .map(|&(x, y)| domain_point(x, y))
    .collect()
}

fn write_coast(path: &Path, p: &MapProjection) {
    let mut coords: Vec<String> = island()
        .iter()
        .map(|&q| {
            let (lon, lat) = p.inverse(q).expect("inverse");
            format!("[{lon:.7}, {lat:.7}]")
        })
        .collect();
    coords.push(coords[0].clone());
    let text = format!(
        "{{\"type\": \"FeatureCollection\", \"features\": [\n  \
         {{\"type\": \"Feature\", \"properties\": {{\"name\": \"island\"}}, \
         \"geometry\": {{\"type\": \"Polygon\", \"coordinates\": [[\n    {}\n  ]]}}}}\n]}}\n",
        coords.join(",\n    ")
    );
    std::fs::write(path, text).expect("write coast");
}

/// Longitude-latitude bounds of the domain and its margin.
fn lon_lat_box(p: &MapProjection) -> ((f64, f64), (f64, f64)) {
    let mut lon = (f64::MAX, f64::MIN);
    let mut lat = (f64::MAX, f64::MIN);
    let (lo, side) = (-MARGIN_M / SIDE_M, 1.0 + 2.0 * MARGIN_M / SIDE_M);
    for k in 0..=40 {
        let s = lo + side * k as f64 / 40.0;
        for (sx, sy) in [(s, lo), (s, lo + side), (lo, s), (lo + side, s)] {
            let (a, b) = p.inverse(domain_point(sx, sy)).expect("inverse");
            lon = (lon.0.min(a), lon.1.max(a));
            lat = (lat.0.min(b), lat.1.max(b));
        }
    }
    (lon, lat)
}

fn write_wind(path: &Path, p: &MapProjection) {
    let (lon, lat) = lon_lat_box(p);
    let (dlon, dlat) = (0.5, 0.25);
    let lons: Vec<f64> = {
        let a = (lon.0 / dlon).floor() * dlon;
        (0..)
            .map(|k| a + k as f64 * dlon)
            .take_while(|&x| x <= lon.1 + dlon)
            .collect()
    };
    let lats: Vec<f64> = {
        let b = (lat.1 / dlat).ceil() * dlat;
        (0..)
            .map(|k| b - k as f64 * dlat)
            .take_while(|&y| y >= lat.0 - dlat)
            .collect()
    };
    let hours: Vec<f64> = (0..=WIND_HOURS).map(|h| h as f64).collect();
    let mut f = lon_lat_file(
        path,
        "fuzz basin wind (floe: make_fuzz_basin)",
        ("hours since 2024-03-01 00:00:00", &hours),
        &lats,
        &lons,
    );
    let (mut u, mut v) = (Vec::new(), Vec::new());
    for &h in &hours {
        // 8 m/s towards +x on the plane, turning to +y over the six hours.
        let a = std::f64::consts::FRAC_PI_2 * h / WIND_HOURS as f64;
        let w = 8.0 * Vec2::new(a.cos(), a.sin());
        for &la in &lats {
            for &lo in &lons {
                let (east, north) = p.east_north(lo, la).expect("directions");
                u.push(w.dot(east) as f32);
                v.push(w.dot(north) as f32);
            }
        }
    }
    for (name, data, sn) in [("u10", &u, "eastward_wind"), ("v10", &v, "northward_wind")] {
        let mut var = f
            .add_variable::<f32>(name, &["time", "latitude", "longitude"])
            .unwrap();
        var.put_attribute("units", "m s**-1").unwrap();
        var.put_attribute("standard_name", sn).unwrap();
        var.put_values(data, ..).unwrap();
    }
}

fn write_ssh(path: &Path) {
    let step = 2000.0;
    let n = ((SIDE_M + 2.0 * MARGIN_M) / step) as usize + 1;
    let xs: Vec<f64> = (0..n)
        .map(|i| MIN_M.0 - MARGIN_M + i as f64 * step)
        .collect();
    let ys: Vec<f64> = (0..n)
        .map(|j| MIN_M.1 - MARGIN_M + j as f64 * step)
        .collect();
    let mut f = netcdf::create_with(path, netcdf::Options::empty()).expect("create ssh");
    f.add_attribute("Conventions", "CF-1.8").unwrap();
    f.add_attribute(
        "title",
        "fuzz basin sea-surface height (floe: make_fuzz_basin)",
    )
    .unwrap();
    f.add_dimension("y", n).unwrap();
    f.add_dimension("x", n).unwrap();
    // A classic file: define everything, then write the values.
    for (name, sn) in [
        ("x", "projection_x_coordinate"),
        ("y", "projection_y_coordinate"),
    ] {
        let mut c = f.add_variable::<f64>(name, &[name]).unwrap();
        c.put_attribute("units", "m").unwrap();
        c.put_attribute("standard_name", sn).unwrap();
    }
    let (scale, offset, fill) = (1e-4f32, 0.1f32, -32767i16);
    let mut zos = Vec::new();
    for _ in &ys {
        for &x in &xs {
            // Down towards +x at 1e-7 (2 mm over the domain and margins).
            let eta = -1e-7 * (x - MIN_M.0);
            zos.push(((eta - offset as f64) / scale as f64).round() as i16);
        }
    }
    let mut var = f.add_variable::<i16>("zos", &["y", "x"]).unwrap();
    var.put_attribute("units", "m").unwrap();
    var.put_attribute("standard_name", "sea_surface_height_above_geoid")
        .unwrap();
    var.put_attribute("scale_factor", scale).unwrap();
    var.put_attribute("add_offset", offset).unwrap();
    var.put_attribute("_FillValue", fill).unwrap();
    f.enddef().unwrap();
    f.variable_mut("zos").unwrap().put_values(&zos, ..).unwrap();
    for (name, values) in [("x", &xs), ("y", &ys)] {
        f.variable_mut(name)
            .unwrap()
            .put_values(values, ..)
            .unwrap();
    }
}

fn main() {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "tests/data/fuzz/basin".into()),
    );
    std::fs::create_dir_all(&dir).expect("make the directory");
    let p = MapProjection::parse("EPSG:3413").expect("EPSG:3413");
    write_coast(&dir.join("coast.geojson"), &p);
    write_wind(&dir.join("wind.nc"), &p);
    write_ssh(&dir.join("ssh.nc"));
    println!(
        "wrote {}/coast.geojson, wind.nc, ssh.nc; domain min_m = [{:.1}, {:.1}], size_m = [{SIDE_M:.1}, {SIDE_M:.1}]",
        dir.display(),
        MIN_M.0,
        MIN_M.1,
    );
}
