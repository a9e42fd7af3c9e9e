//! Writes the input files of `scenarios/nares_strait.toml`: an idealised
//! Nares Strait on the NSIDC polar stereographic plane (EPSG:3413), with
//! a storm passing over it. No downloads: everything is made here.
//!
//! Run: `cargo run --release -p floe-basin --example make_nares_strait [DIR]`
//! (default `scenarios/nares`). Writes:
//!
//! - `coast.geojson`: the two coasts (Ellesmere Island to the west,
//!   Greenland to the east) as longitude-latitude polygons, concave, with a
//!   cape on each side and a small island (Hans Island's place) in the
//!   channel; made on the plane and projected back, so the scenario's
//!   geometry is exact on the plane.
//! - `wind.nc`: an ERA5-like 10 m wind (`u10`, `v10`, eastward and
//!   northward, m/s) on a 0.25° latitude by 0.5° longitude grid, 3-hourly,
//!   `hours since 1900-01-01`: a 5 m/s down-strait background and a
//!   cyclone (Rankine vortex, 15 m/s at 60 km) crossing the strait from
//!   west to east over a day, whose winds first blow up the strait and then,
//!   behind it, down the strait at 20 m/s.
//! - `ice.nc`: ice concentration (`siconc`, fraction) and thickness
//!   (`sithick`, m) on the plane's x/y grid at 2 km: a compact pack north
//!   of the strait's mouth, open water in the channel and south of it.
//!
//! The plane frame: the strait runs along y; north of the mouth (y > 0)
//! is the Lincoln Sea side; the channel is 20 km wide, 60 km long.

#[path = "support/lon_lat_file.rs"]
mod lon_lat_file;
use lon_lat_file::lon_lat_file;

use std::path::{Path, PathBuf};

use floe_basin::MapProjection;
use floe_dem::Vec2;

/// The strait's centre on the plane: 81° N, 62.5° W.
const CENTRE_LON_LAT: (f64, f64) = (-62.5, 81.0);
/// Half the domain's width and height, km (the scenario's `[domain]`).
const HALF_WIDTH_KM: f64 = 45.0;
const HALF_HEIGHT_KM: f64 = 80.0;
/// Margin of the wind grid around the domain, km.
const WIND_MARGIN_KM: f64 = 150.0;
/// Hours of wind from 2024-03-01 00:00.
const WIND_HOURS: usize = 84;

fn km(x: f64, y: f64) -> Vec2 {
    Vec2::new(1000.0 * x, 1000.0 * y)
}

/// The west coast (Ellesmere), counter-clockwise, km from the centre: the
/// funnel from the northern basin, the channel's wall with a cape, the
/// funnel into the southern basin, closed outside the domain.
fn west_coast() -> Vec<Vec2> {
    [
        (-55.0, 85.0),
        (-55.0, -85.0),
        (-45.0, -85.0),
        (-45.0, -52.0),
        (-10.0, -40.0),
        (-10.0, -12.0),
        (-5.0, -9.0),
        (-10.0, -6.0),
        (-10.0, 20.0),
        (-45.0, 36.0),
        (-45.0, 85.0),
    ]
    .iter()
    .map(|&(x, y)| km(x, y))
    .collect()
}

/// The east coast (Greenland), counter-clockwise, with a broader cape
/// further north.
fn east_coast() -> Vec<Vec2> {
    [
        (55.0, -85.0),
        (55.0, 85.0),
        (45.0, 85.0),
        (45.0, 36.0),
        (10.0, 20.0),
        (10.0, 8.0),
        (6.0, 4.0),
        (10.0, 0.0),
        (10.0, -40.0),
        (45.0, -52.0),
        (45.0, -85.0),
    ]
    .iter()
    .map(|&(x, y)| km(x, y))
    .collect()
}

/// A small island in the channel, Hans Island's place.
fn island() -> Vec<Vec2> {
    (0..7)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 7.0;
            km(2.0 + 0.9 * a.cos(), -22.0 + 0.9 * a.sin())
        })
        .collect()
}

fn write_coast(path: &Path, p: &MapProjection, centre: Vec2) {
    let features: Vec<serde_json::Value> = [
        ("Ellesmere Island", west_coast()),
        ("Greenland", east_coast()),
        ("island", island()),
    ]
    .iter()
    .map(|(name, ring)| {
        let mut coords: Vec<[f64; 2]> = ring
            .iter()
            .map(|&q| {
                let (lon, lat) = p.inverse(centre + q).expect("inverse");
                [lon, lat]
            })
            .collect();
        coords.push(coords[0]);
        serde_json::json!({
            "type": "Feature",
            "properties": { "name": name },
            "geometry": { "type": "Polygon", "coordinates": [coords] }
        })
    })
    .collect();
    let doc = serde_json::json!({ "type": "FeatureCollection", "features": features });
    std::fs::write(path, serde_json::to_string_pretty(&doc).expect("json")).expect("write coast");
}

/// The wind on the plane (m/s) at `q` (m from the centre) and hour `h`.
fn wind_on_plane(q: Vec2, h: f64) -> Vec2 {
    let background = Vec2::new(0.0, -5.0);
    // The cyclone's centre crosses y = 0 from x = -300 km to +300 km
    // between hours 24 and 48.
    let centre = Vec2::new(-300e3 + 600e3 * (h - 24.0) / 24.0, 0.0);
    let r = q - centre;
    let d = r.length().max(1.0);
    let (radius, peak) = (60e3, 15.0);
    let speed = if d < radius {
        peak * d / radius
    } else {
        peak * radius / d
    };
    // Counter-clockwise (a Northern Hemisphere low).
    background + speed * Vec2::new(-r.y, r.x) / d
}

fn write_wind(path: &Path, p: &MapProjection, centre: Vec2) {
    // Longitude-latitude box around the domain plus margin.
    let (hw, hh) = (
        HALF_WIDTH_KM + WIND_MARGIN_KM,
        HALF_HEIGHT_KM + WIND_MARGIN_KM,
    );
    let mut lon = (f64::MAX, f64::MIN);
    let mut lat = (f64::MAX, f64::MIN);
    for k in 0..=40 {
        let s = k as f64 / 40.0;
        for q in [
            km(-hw + 2.0 * hw * s, -hh),
            km(-hw + 2.0 * hw * s, hh),
            km(-hw, -hh + 2.0 * hh * s),
            km(hw, -hh + 2.0 * hh * s),
        ] {
            let (lo, la) = p.inverse(centre + q).expect("inverse");
            lon = (lon.0.min(lo), lon.1.max(lo));
            lat = (lat.0.min(la), lat.1.max(la));
        }
    }
    let (dlon, dlat) = (0.5, 0.25);
    let lons: Vec<f64> = {
        let a = (lon.0 / dlon).floor() * dlon;
        (0..)
            .map(|k| a + k as f64 * dlon)
            .take_while(|&x| x <= lon.1 + dlon)
            .collect()
    };
    // ERA5 order: latitude descending.
    let lats: Vec<f64> = {
        let b = (lat.1 / dlat).ceil() * dlat;
        (0..)
            .map(|k| b - k as f64 * dlat)
            .take_while(|&y| y >= lat.0 - dlat)
            .collect()
    };
    let hours: Vec<f64> = (0..=WIND_HOURS).step_by(3).map(|h| h as f64).collect();
    // 2024-03-01 00:00 is 1,088,400 h after 1900-01-01.
    let era5_hours: Vec<f64> = hours.iter().map(|h| 1_088_400.0 + h).collect();
    let mut f = lon_lat_file(
        path,
        "idealised storm over Nares Strait (floe: make_nares_strait)",
        ("hours since 1900-01-01 00:00:00.0", &era5_hours),
        &lats,
        &lons,
    );
    let (mut u, mut v) = (Vec::new(), Vec::new());
    for &h in &hours {
        for &la in &lats {
            for &lo in &lons {
                let q = p.forward(lo, la).expect("forward") - centre;
                let w = wind_on_plane(q, h);
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
        var.put_attribute(
            "long_name",
            format!(
                "10 metre {} wind component",
                if name == "u10" { "U" } else { "V" }
            ),
        )
        .unwrap();
        var.put_values(data, ..).unwrap();
    }
}

fn write_ice(path: &Path, centre: Vec2) {
    let step = 2000.0;
    let nx = (2.0 * HALF_WIDTH_KM * 1000.0 / step) as usize + 3;
    let ny = (2.0 * HALF_HEIGHT_KM * 1000.0 / step) as usize + 3;
    let xs: Vec<f64> = (0..nx)
        .map(|i| centre.x - HALF_WIDTH_KM * 1000.0 + (i as f64 - 1.0) * step)
        .collect();
    let ys: Vec<f64> = (0..ny)
        .map(|j| centre.y - HALF_HEIGHT_KM * 1000.0 + (j as f64 - 1.0) * step)
        .collect();
    let mut f = netcdf::create(path).expect("create ice");
    f.add_attribute("Conventions", "CF-1.8").unwrap();
    f.add_attribute(
        "title",
        "idealised ice north of Nares Strait (floe: make_nares_strait)",
    )
    .unwrap();
    f.add_dimension("y", ny).unwrap();
    f.add_dimension("x", nx).unwrap();
    for (name, values, sn) in [
        ("x", &xs, "projection_x_coordinate"),
        ("y", &ys, "projection_y_coordinate"),
    ] {
        let mut c = f.add_variable::<f64>(name, &[name]).unwrap();
        c.put_attribute("units", "m").unwrap();
        c.put_attribute("standard_name", sn).unwrap();
        c.put_values(values, ..).unwrap();
    }
    let (mut conc, mut thick) = (Vec::new(), Vec::new());
    for &y in &ys {
        for &x in &xs {
            let (qx, qy) = ((x - centre.x) / 1000.0, (y - centre.y) / 1000.0);
            // A compact pack north of y = 22 km (the funnel and the basin).
            let c = if qy > 22.0 { 0.95 } else { 0.0 };
            conc.push(c as f32);
            // Thicker ice to the north and along the coasts: 1.2 to 2.4 m.
            thick.push((1.2 + 0.02 * (qy - 22.0).max(0.0) + 0.01 * qx.abs()) as f32);
        }
    }
    for (name, data, sn, units) in [
        ("siconc", &conc, "sea_ice_area_fraction", "1"),
        ("sithick", &thick, "sea_ice_thickness", "m"),
    ] {
        let mut var = f.add_variable::<f32>(name, &["y", "x"]).unwrap();
        var.put_attribute("units", units).unwrap();
        var.put_attribute("standard_name", sn).unwrap();
        var.put_values(data, ..).unwrap();
    }
}

fn main() {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "scenarios/nares".into()),
    );
    std::fs::create_dir_all(&dir).expect("make the directory");
    let p = MapProjection::parse("EPSG:3413").expect("EPSG:3413");
    let centre = p
        .forward(CENTRE_LON_LAT.0, CENTRE_LON_LAT.1)
        .expect("centre");
    write_coast(&dir.join("coast.geojson"), &p, centre);
    write_wind(&dir.join("wind.nc"), &p, centre);
    write_ice(&dir.join("ice.nc"), centre);
    println!(
        "wrote {}/coast.geojson, wind.nc, ice.nc; domain min_m = [{:.1}, {:.1}], size_m = [{:.1}, {:.1}]",
        dir.display(),
        centre.x - HALF_WIDTH_KM * 1000.0,
        centre.y - HALF_HEIGHT_KM * 1000.0,
        2.0 * HALF_WIDTH_KM * 1000.0,
        2.0 * HALF_HEIGHT_KM * 1000.0
    );
}
