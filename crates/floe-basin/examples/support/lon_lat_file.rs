//! The head of an ERA5-like CF NetCDF file, shared by the examples that
//! make input files: a time axis and latitude/longitude axes, to which the
//! caller adds its fields on (time, latitude, longitude).

use std::path::Path;

/// A new CF-1.8 file at `path` titled `title`, with a `time` axis (values
/// `times` in `time_units`, Gregorian) and `latitude`/`longitude` axes.
pub fn lon_lat_file(
    path: &Path,
    title: &str,
    (time_units, times): (&str, &[f64]),
    lats: &[f64],
    lons: &[f64],
) -> netcdf::FileMut {
    let mut f = netcdf::create(path).expect("create the file");
    f.add_attribute("Conventions", "CF-1.8").unwrap();
    f.add_attribute("title", title).unwrap();
    f.add_dimension("time", times.len()).unwrap();
    f.add_dimension("latitude", lats.len()).unwrap();
    f.add_dimension("longitude", lons.len()).unwrap();
    let mut t = f.add_variable::<f64>("time", &["time"]).unwrap();
    t.put_attribute("units", time_units).unwrap();
    t.put_attribute("calendar", "gregorian").unwrap();
    t.put_attribute("standard_name", "time").unwrap();
    t.put_values(times, ..).unwrap();
    for (name, values, units, sn) in [
        ("latitude", lats, "degrees_north", "latitude"),
        ("longitude", lons, "degrees_east", "longitude"),
    ] {
        let mut c = f.add_variable::<f64>(name, &[name]).unwrap();
        c.put_attribute("units", units).unwrap();
        c.put_attribute("standard_name", sn).unwrap();
        c.put_values(values, ..).unwrap();
    }
    f
}
