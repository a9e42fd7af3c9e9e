//! Writing small CF NetCDF grids for the tests of ice from gridded fields:
//! projected x/y axes in metres (CF `projection_x_coordinate`,
//! `projection_y_coordinate`), an optional time axis, and one field with a
//! `_FillValue` where the function gives NaN (land).
#![allow(dead_code)]

use std::path::Path;

/// The fill value written where a field is NaN.
pub const FILL: f64 = -9999.0;

/// A field to write.
pub struct Grid<'a> {
    /// Node coordinates along x, m.
    pub x: Vec<f64>,
    /// Node coordinates along y, m.
    pub y: Vec<f64>,
    /// Records of a time axis (`hours since 2024-01-01`), or none.
    pub times: Option<usize>,
    /// The variable's name.
    pub variable: &'a str,
    /// Its `units` attribute, if any.
    pub units: Option<&'a str>,
}

/// Nodes from `start` every `step` metres, `count` of them.
pub fn axis(start: f64, step: f64, count: usize) -> Vec<f64> {
    (0..count).map(|k| start + k as f64 * step).collect()
}

impl Grid<'_> {
    /// Writes the file at `path` with the values `value(x, y, record)`.
    pub fn write(&self, path: &Path, value: impl Fn(f64, f64, usize) -> f64) {
        let mut file = netcdf::create(path).expect("create the NetCDF file");
        file.add_dimension("x", self.x.len()).unwrap();
        file.add_dimension("y", self.y.len()).unwrap();
        let mut dims = Vec::new();
        if let Some(n) = self.times {
            file.add_dimension("time", n).unwrap();
            let mut t = file.add_variable::<f64>("time", &["time"]).unwrap();
            t.put_attribute("units", "hours since 2024-01-01 00:00:00")
                .unwrap();
            t.put_attribute("standard_name", "time").unwrap();
            t.put_attribute("calendar", "standard").unwrap();
            let hours: Vec<f64> = (0..n).map(|k| 6.0 * k as f64).collect();
            t.put_values(&hours, ..).unwrap();
            dims.push("time");
        }
        dims.extend(["y", "x"]);
        for (name, values, standard) in [
            ("x", &self.x, "projection_x_coordinate"),
            ("y", &self.y, "projection_y_coordinate"),
        ] {
            let mut v = file.add_variable::<f64>(name, &[name]).unwrap();
            v.put_attribute("units", "m").unwrap();
            v.put_attribute("standard_name", standard).unwrap();
            v.put_values(values, ..).unwrap();
        }
        let mut v = file.add_variable::<f64>(self.variable, &dims).unwrap();
        v.put_attribute("_FillValue", FILL).unwrap();
        if let Some(u) = self.units {
            v.put_attribute("units", u).unwrap();
        }
        let records = self.times.unwrap_or(1);
        let mut data = Vec::with_capacity(records * self.x.len() * self.y.len());
        for t in 0..records {
            for &y in &self.y {
                for &x in &self.x {
                    let z = value(x, y, t);
                    data.push(if z.is_nan() { FILL } else { z });
                }
            }
        }
        v.put_values(&data, ..).unwrap();
    }
}
