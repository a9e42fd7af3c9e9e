//! The xarray example of docs/output.md runs against a file of `floe grid`
//! and finds its coordinates, units and fill values. A test binary of its
//! own: it starts python, which would inherit the open files (and their
//! HDF5 file locks) of NetCDF files other tests of the same process were
//! writing at that moment, and lock them for python's lifetime.

use std::process::Command;

use floe_study::cadence::Cadence;
use floe_study::grid_output::{write_grid, GridArgs};
#[path = "study_support/mod.rs"]
mod study_support;
use study_support::run_text;

/// The xarray example of docs/output.md opens a gridded-fields file with
/// its coordinates and units (skipped, with a note, where python3 lacks
/// xarray or both of its NetCDF-4 engines, netCDF4 and h5netcdf).
#[test]
fn xarray_opens_the_file_as_docs_output_md_shows() {
    let has = |module: &str| {
        Command::new("python3")
            .args(["-c", &format!("import {module}")])
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if !has("xarray") || !(has("netCDF4") || has("h5netcdf")) {
        eprintln!("skipped: python3 without xarray, or without netCDF4 and h5netcdf (pip install h5netcdf)");
        return;
    }
    let doc = include_str!("../docs/output.md");
    let at = doc.rfind("```python\n").expect("a python block") + "```python\n".len();
    let example = &doc[at..at + doc[at..].find("```").expect("its end")];
    let dir = tempfile::tempdir().unwrap();
    let h5 = run_text(dir.path(), "box", include_str!("data/grid_box.toml")).unwrap();
    let nc = dir.path().join("fields.nc");
    write_grid(&GridArgs {
        run: h5,
        output: nc.clone(),
        cell_m: 250.0,
        cadence: Cadence::IntervalS(10000.0),
        force: false,
    })
    .unwrap();
    let check = "\nassert list(ds.concentration.dims) == ['time', 'y', 'x']\n\
                 assert ds.x.attrs['units'] == 'm' and ds.time.attrs['units'] == 's'\n\
                 assert len(ds.time) == 3, ds.time\n\
                 assert ds.u.isnull().any() and ds.u.encoding['_FillValue'] > 9e36\n";
    let out = Command::new("python3")
        .arg("-c")
        .arg(format!("{example}{check}"))
        .current_dir(dir.path())
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(stdout.trim_end().ends_with("m s-1"), "{stdout}");
}
