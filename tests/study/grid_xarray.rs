//! The xarray example of docs/output.md runs against a file of `floe grid`
//! and finds its coordinates, units and fill values; with a `start_time`,
//! xarray (or netCDF4 without it) decodes the time axis into the dates
//! Python's own calendar arithmetic gives. Each test starts python while
//! no other test has a NetCDF file open (`inherited_locks`).

use std::path::Path;
use std::process::Command;

use floe_io::RunFile;

use crate::inherited_locks;
use crate::study_support;
use floe_study::cadence::Cadence;
use floe_study::grid_output::{write_grid, GridArgs};
use study_support::run_text;

/// Whether python3 imports `module`.
fn has(module: &str) -> bool {
    Command::new("python3")
        .args(["-c", &format!("import {module}")])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs `script` in python3 in `dir`: its standard output, after checking
/// that it succeeded.
fn python(script: &str, dir: &Path) -> String {
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .current_dir(dir)
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}{stderr}");
    stdout.into_owned()
}

/// The xarray example of docs/output.md opens a gridded-fields file with
/// its coordinates and units (skipped, with a note, where python3 lacks
/// xarray or both of its NetCDF-4 engines, netCDF4 and h5netcdf).
#[test]
fn xarray_opens_the_file_as_docs_output_md_shows() {
    let _programs = inherited_locks::starting_programs();
    if !has("xarray") || !(has("netCDF4") || has("h5netcdf")) {
        eprintln!("skipped: python3 without xarray, or without netCDF4 and h5netcdf (pip install h5netcdf)");
        return;
    }
    let doc = include_str!("../../docs/output.md");
    let at = doc.rfind("```python\n").expect("a python block") + "```python\n".len();
    let example = &doc[at..at + doc[at..].find("```").expect("its end")];
    let dir = tempfile::tempdir().unwrap();
    let h5 = run_text(dir.path(), "box", include_str!("../data/grid_box.toml")).unwrap();
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
    let stdout = python(&format!("{example}{check}"), dir.path());
    assert!(stdout.trim_end().ends_with("m s-1"), "{stdout}");
}

/// With `start_time` 2024-02-28 23:00 UTC, the records of the first
/// 20000 s fall on 28 and 29 February (2024 is a leap year): xarray
/// decodes the time axis to those dates, as does netCDF4's `num2date`
/// where xarray is missing (skipped, with a note, without either).
#[test]
fn python_decodes_the_time_axis_into_dates() {
    let _programs = inherited_locks::starting_programs();
    let decoder = if has("xarray") && (has("netCDF4") || has("h5netcdf")) {
        "import xarray as xr\n\
         ds = xr.open_dataset('fields.nc')\n\
         got = [datetime.datetime(1970, 1, 1) + datetime.timedelta(microseconds=int(t) // 1000)\n\
                for t in ds.time.values.astype('datetime64[ns]').astype('int64')]\n"
    } else if has("netCDF4") {
        "import netCDF4\n\
         with netCDF4.Dataset('fields.nc') as ds:\n\
         \x20   t = ds['time']\n\
         \x20   got = list(netCDF4.num2date(t[:], t.units, t.calendar,\n\
         \x20       only_use_cftime_datetimes=False, only_use_python_datetimes=True))\n"
    } else {
        eprintln!("skipped: python3 without xarray and netCDF4 (pip install xarray netCDF4)");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let scenario = include_str!("../data/grid_box.toml").replace(
        "seed = 1\n",
        "seed = 1\nstart_time = \"2024-02-28 23:00:00\"\n",
    );
    let h5 = run_text(dir.path(), "box", &scenario).unwrap();
    write_grid(&GridArgs {
        run: h5.clone(),
        output: dir.path().join("fields.nc"),
        cell_m: 1000.0,
        cadence: Cadence::All,
        force: false,
    })
    .unwrap();
    let seconds: Vec<String> = RunFile::open(&h5)
        .unwrap()
        .snapshot_times()
        .unwrap()
        .iter()
        .map(|t| format!("{t:?}"))
        .collect();
    let script = format!(
        "import datetime\n{decoder}\
         start = datetime.datetime(2024, 2, 28, 23)\n\
         want = [start + datetime.timedelta(seconds=s) for s in [{}]]\n\
         assert len(got) == len(want), (got, want)\n\
         for g, w in zip(got, want):\n\
         \x20   assert abs((g - w).total_seconds()) < 1e-3, (g, w)\n\
         assert want[-1].day == 29 and want[0].day == 28\n\
         print(got[0], got[-1])\n",
        seconds.join(", ")
    );
    let stdout = python(&script, dir.path());
    assert!(stdout.contains("2024-02-29"), "{stdout}");
}
