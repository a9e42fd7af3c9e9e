//! Gridded forcing read from CF NetCDF (issue 22, item 1), end to end
//! through `floe run`:
//! - a wind file on the model plane's x/y grid, uniform in space and
//!   piecewise linear in time, drives the floes exactly as the same wind
//!   given as a `time_series` (two independent ways to one forcing);
//! - a longitude-latitude file on EPSG:3413 of a wind that is uniform on
//!   the plane, written as east/north components from the geometry of the
//!   polar stereographic plane, comes back uniform, with an error that falls
//!   as the square of the file's spacing (bilinear sampling);
//! - a sea-surface height sloping at `s` accelerates a floe at `−g s`;
//! - the run file records each input's path and SHA-256, and a resume with
//!   a changed file is refused;
//! - a file that misses a variable, the run's times or the domain, or
//!   that has missing values under a floe at the start, ends in one message
//!   located at the key naming the file, with exit code 2, before the run
//!   starts; a floe that drifts off the grid during the run stops it, as a
//!   blow-up does, with exit code 1 and the message located at the key;
//! - a value beyond what the field can be on Earth (a 1e30 m/s wind) is
//!   refused when its slice is read, wherever it lies.

use std::path::Path;

use floe_basin::MapProjection;
use floe_io::RunFile;
use floe_run::run_file::{run, Quiet, RunArgs};

use crate::study_support;
use study_support::{run_args, run_text};

/// One variable to write: name, CF attributes and value at (x, y, t).
struct Var<'a> {
    name: &'a str,
    standard_name: &'a str,
    units: &'a str,
    value: &'a dyn Fn(f64, f64, f64) -> f64,
}

/// A CF file with axes `x`/`y` (metres, or lon/lat degrees when
/// `geographic`), an optional time axis in hours since 2024-03-01.
fn write_nc(
    path: &Path,
    xs: &[f64],
    ys: &[f64],
    hours: Option<&[f64]>,
    geographic: bool,
    vars: &[Var<'_>],
) {
    let mut f = netcdf::create(path).unwrap();
    let (xn, yn) = if geographic {
        ("lon", "lat")
    } else {
        ("x", "y")
    };
    f.add_dimension(yn, ys.len()).unwrap();
    f.add_dimension(xn, xs.len()).unwrap();
    let mut dims = vec![yn, xn];
    if let Some(h) = hours {
        f.add_dimension("time", h.len()).unwrap();
        dims.insert(0, "time");
        let mut t = f.add_variable::<f64>("time", &["time"]).unwrap();
        t.put_attribute("units", "hours since 2024-03-01 00:00:00")
            .unwrap();
        t.put_attribute("calendar", "proleptic_gregorian").unwrap();
        t.put_values(h, ..).unwrap();
    }
    for (name, values, geo_units, sn) in [
        (
            xn,
            xs,
            "degrees_east",
            if geographic {
                "longitude"
            } else {
                "projection_x_coordinate"
            },
        ),
        (
            yn,
            ys,
            "degrees_north",
            if geographic {
                "latitude"
            } else {
                "projection_y_coordinate"
            },
        ),
    ] {
        let mut c = f.add_variable::<f64>(name, &[name]).unwrap();
        c.put_attribute("units", if geographic { geo_units } else { "m" })
            .unwrap();
        c.put_attribute("standard_name", sn).unwrap();
        c.put_values(values, ..).unwrap();
    }
    let times = hours.map_or(vec![0.0], |h| h.to_vec());
    for v in vars {
        let mut data = Vec::new();
        for &t in &times {
            for &y in ys {
                for &x in xs {
                    data.push((v.value)(x, y, t * 3600.0) as f32);
                }
            }
        }
        let mut var = f.add_variable::<f32>(v.name, &dims).unwrap();
        var.put_attribute("standard_name", v.standard_name).unwrap();
        var.put_attribute("units", v.units).unwrap();
        var.put_attribute("_FillValue", 1e20f32).unwrap();
        var.put_values(&data, ..).unwrap();
    }
}

fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| a + (b - a) * k as f64 / (n - 1) as f64)
        .collect()
}

const PACK: &str = r#"duration_s = 7200.0
seed = 3
start_time = "2024-03-01 00:00:00"
dt_s = 2.0

[domain]
min_m = [0.0, 0.0]
size_m = [20000.0, 12000.0]

[tessellation]
kind = "grid"
columns = 4
rows = 3
gap_m = 800.0

[ice]
thickness_m = 1.0

[output]
snapshot_every_s = 1800.0
"#;

/// The wind of the x/y file: uniform, linear in time between the hours.
fn wind_at(t_s: f64) -> [f64; 2] {
    let h = t_s / 3600.0;
    if h <= 1.0 {
        [10.0 - 4.0 * h, 2.0 + 3.0 * h]
    } else {
        [6.0 + 2.0 * (h - 1.0), 5.0 - 6.0 * (h - 1.0)]
    }
}

fn last_snapshot(path: &Path) -> floe_io::Snapshot {
    let f = RunFile::open(path).unwrap();
    let n = f.snapshot_count().unwrap();
    f.snapshot(n - 1).unwrap()
}

#[test]
fn a_gridded_wind_drives_the_floes_as_the_same_wind_given_as_a_time_series() {
    let dir = tempfile::tempdir().unwrap();
    let nc = dir.path().join("wind.nc");
    write_nc(
        &nc,
        &linspace(-2000.0, 22000.0, 13),
        &linspace(-1000.0, 13000.0, 8),
        Some(&[0.0, 1.0, 2.0]),
        false,
        &[
            Var {
                name: "u",
                standard_name: "x_wind",
                units: "m s-1",
                value: &|_, _, t| wind_at(t)[0],
            },
            Var {
                name: "v",
                standard_name: "y_wind",
                units: "m s-1",
                value: &|_, _, t| wind_at(t)[1],
            },
        ],
    );
    let gridded = run_text(
        dir.path(),
        "gridded",
        &format!("{PACK}\n[wind]\nfile = \"wind.nc\"\nvariables = [\"u\", \"v\"]\n"),
    )
    .unwrap();
    let series = run_text(
        dir.path(),
        "series",
        &format!(
            "{PACK}\n[wind]\ntime_series = {{ times_s = [0.0, 3600.0, 7200.0], velocities_m_per_s = [[10.0, 2.0], [6.0, 5.0], [8.0, -1.0]] }}\n"
        ),
    )
    .unwrap();
    let (a, b) = (last_snapshot(&gridded), last_snapshot(&series));
    assert_eq!(a.position.len(), 12);
    let mut moved = 0.0f64;
    for (p, q) in a.position.iter().zip(&b.position) {
        // f32 storage of the file's values: 1e-7 relative in the wind.
        assert!(
            (p[0] - q[0]).abs() < 1e-3 && (p[1] - q[1]).abs() < 1e-3,
            "{p:?} {q:?}"
        );
        moved = moved.max(q[0]);
    }
    assert!(moved > 3000.0, "the wind moved the floes ({moved} m)");
    // The provenance holds the file and its checksum.
    let meta = RunFile::open(&gridded).unwrap().metadata().unwrap();
    assert_eq!(meta.inputs.len(), 1);
    assert_eq!(meta.inputs[0].role, "wind");
    assert_eq!(
        meta.inputs[0].sha256,
        floe_basin::checksum::sha256_file(&nc).unwrap()
    );
    // Two threads give the same file content.
    let scenario = dir.path().join("gridded.toml");
    let two = dir.path().join("two.h5");
    run(&run_args(&scenario, &two, 2), &Quiet).unwrap();
    let (c, d) = (last_snapshot(&gridded), last_snapshot(&two));
    assert_eq!(format!("{:?}", c.position), format!("{:?}", d.position));
}

/// A uniform plane wind `w` as east/north components at (lon, lat) on
/// EPSG:3413: north points to the pole (the plane's origin), east is north
/// turned clockwise. Geometry only, not the reader's finite differences.
fn east_north_components(p: &MapProjection, lon: f64, lat: f64, w: [f64; 2]) -> [f64; 2] {
    let q = p.forward(lon, lat).unwrap();
    let north = -q / q.length();
    let east = [north.y, -north.x];
    [
        w[0] * east[0] + w[1] * east[1],
        w[0] * north.x + w[1] * north.y,
    ]
}

/// Largest error of the wind the floes of a Nares-like domain feel from a
/// lon/lat file of spacing `step_deg`, against the uniform plane wind.
fn lonlat_wind_error(dir: &Path, step_deg: f64) -> f64 {
    let p = MapProjection::parse("EPSG:3413").unwrap();
    let w = [6.0, -9.0];
    let lons: Vec<f64> = (0..)
        .map(|k| -80.0 + k as f64 * step_deg)
        .take_while(|&l| l <= -50.0)
        .collect();
    let lats: Vec<f64> = (0..)
        .map(|k| 76.0 + k as f64 * step_deg)
        .take_while(|&l| l <= 84.0)
        .collect();
    let name = format!("w{}", (1.0 / step_deg).round());
    let nc = dir.join(format!("{name}.nc"));
    let (pu, pv) = (p.clone(), p.clone());
    write_nc(
        &nc,
        &lons,
        &lats,
        None,
        true,
        &[
            Var {
                name: "u10",
                standard_name: "eastward_wind",
                units: "m s-1",
                value: &move |lon, lat, _| east_north_components(&pu, lon, lat, w)[0],
            },
            Var {
                name: "v10",
                standard_name: "northward_wind",
                units: "m s-1",
                value: &move |lon, lat, _| east_north_components(&pv, lon, lat, w)[1],
            },
        ],
    );
    // Floes near 80.5° N, 65° W (Nares Strait), at rest, held by nothing:
    // after one step their velocity is along the wind stress, so along w.
    let c = p.forward(-65.0, 80.5).unwrap();
    let text = format!(
        "duration_s = 10.0\nseed = 1\ndt_s = 1.0\n[map]\nprojection = \"EPSG:3413\"\n\
         [domain]\nmin_m = [{}, {}]\nsize_m = [40000.0, 40000.0]\n\
         [tessellation]\nkind = \"grid\"\ncolumns = 5\nrows = 5\ngap_m = 2000.0\n\
         [ice]\nthickness_m = 1.0\n[ocean]\ndrag_coefficient = 0.0\n\
         [wind]\nfile = \"{name}.nc\"\nvariables = [\"u10\", \"v10\"]\n[output]\nsnapshot_every_s = 10.0\n",
        c.x - 20000.0,
        c.y - 20000.0
    );
    let out = run_text(dir, &name, &text).unwrap();
    // The same floes under the uniform wind itself.
    let uniform = text.replace(
        &format!("file = \"{name}.nc\"\nvariables = [\"u10\", \"v10\"]"),
        &format!("velocity_m_per_s = [{}, {}]", w[0], w[1]),
    );
    let reference = run_text(dir, &format!("{name}_uniform"), &uniform).unwrap();
    let (s, r) = (last_snapshot(&out), last_snapshot(&reference));
    let mut worst = 0.0f64;
    for (v, u) in s.velocity.iter().zip(&r.velocity) {
        let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
        worst = worst.max((dx * dx + dy * dy).sqrt() / (u[0] * u[0] + u[1] * u[1]).sqrt());
    }
    worst
}

#[test]
fn a_lonlat_wind_on_epsg_3413_comes_back_uniform_and_converges_at_second_order() {
    let dir = tempfile::tempdir().unwrap();
    let coarse = lonlat_wind_error(dir.path(), 0.5);
    let fine = lonlat_wind_error(dir.path(), 0.25);
    // Relative error of the floes' velocity (∝ |U| U): east/north
    // components interpolated linearly in longitude shrink the vector by
    // about h²/8 (h the spacing in radians): second order.
    eprintln!("lon/lat wind, relative velocity error: 0.5° {coarse:.3e}, 0.25° {fine:.3e}");
    assert!(coarse < 1e-4, "coarse {coarse}");
    assert!(fine < coarse / 3.0, "coarse {coarse}, fine {fine}");
}

#[test]
fn a_sloping_sea_surface_accelerates_a_floe_down_the_slope_at_g_s() {
    let dir = tempfile::tempdir().unwrap();
    let slope = 2e-6;
    write_nc(
        &dir.path().join("ssh.nc"),
        &linspace(-1000.0, 21000.0, 12),
        &linspace(-1000.0, 13000.0, 8),
        None,
        false,
        &[Var {
            name: "zos",
            standard_name: "sea_surface_height_above_geoid",
            units: "m",
            value: &|x, _, _| slope * x,
        }],
    );
    let text = PACK
        .replace("duration_s = 7200.0", "duration_s = 600.0")
        .replace("snapshot_every_s = 1800.0", "snapshot_every_s = 600.0")
        + "\n[ocean]\ndrag_coefficient = 0.0\nrotational_drag = false\n\
           sea_surface_height = { variable = \"zos\", file = \"ssh.nc\" }\n";
    let out = run_text(dir.path(), "ssh", &text).unwrap();
    let s = last_snapshot(&out);
    let want = -9.80665 * slope * 600.0;
    for v in &s.velocity {
        assert!(
            (v[0] - want).abs() < 1e-6 * want.abs(),
            "{} vs {want}",
            v[0]
        );
        assert!(v[1].abs() < 1e-12);
    }
}

fn error_of(dir: &Path, name: &str, text: &str) -> (u8, String) {
    let e = run_text(dir, name, text).unwrap_err();
    (e.exit_code(), e.to_string())
}

#[test]
fn files_that_do_not_fit_the_run_end_in_one_message_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let w = |x: f64, _y: f64, _t: f64| 0.05 * x / 1000.0;
    // Covers the domain for two hours; v has a hole at one node.
    let hole = |x: f64, y: f64, _t: f64| {
        if (x - 10000.0).abs() < 1.0 && (y - 6000.0).abs() < 1.0 {
            1e20
        } else {
            0.0
        }
    };
    write_nc(
        &d.join("w.nc"),
        &linspace(-2000.0, 22000.0, 13),
        &linspace(-2000.0, 14000.0, 9),
        Some(&[0.0, 2.0]),
        false,
        &[
            Var {
                name: "u",
                standard_name: "x_wind",
                units: "m s-1",
                value: &w,
            },
            Var {
                name: "v",
                standard_name: "y_wind",
                units: "m s-1",
                value: &|_, _, _| 0.0,
            },
            Var {
                name: "vh",
                standard_name: "y_wind",
                units: "m s-1",
                value: &hole,
            },
        ],
    );
    let wind = |vars: &str| format!("{PACK}\n[wind]\nfile = \"w.nc\"\nvariables = {vars}\n");
    let (code, msg) = error_of(d, "novar", &wind("[\"u\", \"nope\"]"));
    assert_eq!(code, 2);
    assert!(
        msg.contains("novar.toml:")
            && msg.contains("wind.file")
            && msg.contains("w.nc")
            && msg.contains("no variable \"nope\""),
        "{msg}"
    );
    // Three hours asked of a two-hour file.
    let (code, msg) = error_of(
        d,
        "short",
        &wind("[\"u\", \"v\"]").replace("duration_s = 7200.0", "duration_s = 10800.0"),
    );
    assert_eq!(code, 2);
    assert!(
        msg.contains("short.toml:")
            && msg.contains("wind.file")
            && msg.contains("w.nc")
            && msg.contains("cover"),
        "{msg}"
    );
    // A domain wider than the grid.
    let (code, msg) = error_of(
        d,
        "wide",
        &wind("[\"u\", \"v\"]")
            .replace("size_m = [20000.0, 12000.0]", "size_m = [30000.0, 12000.0]"),
    );
    assert_eq!(code, 2);
    assert!(
        msg.contains("wide.toml:") && msg.contains("w.nc") && msg.contains("covers the domain"),
        "{msg}"
    );
    // A floe over the hole (the floe grid puts centres at 10 km, 6 km? the
    // hole's cells are refused wherever a floe sits in them).
    let (code, msg) = error_of(
        d,
        "hole",
        &wind("[\"u\", \"vh\"]").replace("columns = 4\nrows = 3", "columns = 5\nrows = 5"),
    );
    assert_eq!(code, 2);
    assert!(
        msg.contains("hole.toml:")
            && msg.contains("wind.file")
            && msg.contains("w.nc")
            && msg.contains("missing values"),
        "{msg}"
    );
    // No start_time for a file with dates.
    let (code, msg) = error_of(
        d,
        "nostart",
        &wind("[\"u\", \"v\"]").replace("start_time = \"2024-03-01 00:00:00\"\n", ""),
    );
    assert_eq!(code, 2);
    assert!(msg.contains("start_time"), "{msg}");
    // lon/lat needs [map]; a file that is not NetCDF.
    std::fs::write(d.join("junk.nc"), "not netcdf").unwrap();
    let (code, msg) = error_of(
        d,
        "junk",
        &format!("{PACK}\n[wind]\nfile = \"junk.nc\"\nvariables = [\"u\", \"v\"]\n"),
    );
    assert_eq!(code, 2);
    assert!(msg.contains("junk.nc") && msg.contains("NetCDF"), "{msg}");
}

/// A wind of 1e30 m/s at one file node, far from every floe (the domain's
/// corner), at hour `bad_hour` of a file of hours 0, 1 and 2.
fn wind_with_a_wild_value(path: &Path, bad_hour: f64) {
    let wild = move |x: f64, y: f64, t: f64| {
        if x < -1000.0 && y < -1000.0 && (t - bad_hour * 3600.0).abs() < 1.0 {
            1e30
        } else {
            5.0
        }
    };
    write_nc(
        path,
        &linspace(-2000.0, 22000.0, 13),
        &linspace(-2000.0, 14000.0, 9),
        Some(&[0.0, 1.0, 2.0]),
        false,
        &[
            Var {
                name: "u",
                standard_name: "x_wind",
                units: "m s-1",
                value: &wild,
            },
            Var {
                name: "v",
                standard_name: "y_wind",
                units: "m s-1",
                value: &|_, _, _| 0.0,
            },
        ],
    );
}

#[test]
fn a_wind_beyond_any_on_earth_is_refused_when_read_naming_the_file_variable_and_limit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scenario =
        |file: &str| format!("{PACK}\n[wind]\nfile = \"{file}\"\nvariables = [\"u\", \"v\"]\n");
    // In the first slice: refused before the run starts.
    wind_with_a_wild_value(&d.join("first.nc"), 0.0);
    let (code, msg) = error_of(d, "first", &scenario("first.nc"));
    assert_eq!(code, 2, "{msg}");
    for part in [
        "first.toml:",
        "wind.file",
        "first.nc",
        "variable \"u\"",
        "1e30 m/s",
        "150 m/s",
        "time index 0",
    ] {
        assert!(msg.contains(part), "`{part}` in {msg}");
    }
    // In the last slice: the run stops when it reads it (hour 1), with its
    // checkpoint, instead of running on a field no floe happens to sample.
    wind_with_a_wild_value(&d.join("later.nc"), 2.0);
    let (code, msg) = error_of(d, "later", &scenario("later.nc"));
    assert_eq!(code, 1, "{msg}");
    for part in ["later.toml:", "wind.file", "1e30 m/s", "time index 2"] {
        assert!(msg.contains(part), "`{part}` in {msg}");
    }
    let f = RunFile::open(&d.join("later.h5")).unwrap();
    assert!(f.snapshot_count().unwrap() >= 2, "it ran until the read");
}

/// A wind file whose grid covers the PACK domain with 400 m to spare; in
/// an open domain its 30 m/s wind blows the floes off it within two hours.
/// Returns the scenario text.
fn gale(d: &Path) -> String {
    write_nc(
        &d.join("gale.nc"),
        &linspace(-1200.0, 20400.0, 13),
        &linspace(-1000.0, 13000.0, 8),
        None,
        false,
        &[
            Var {
                name: "u",
                standard_name: "x_wind",
                units: "m s-1",
                value: &|_, _, _| 30.0,
            },
            Var {
                name: "v",
                standard_name: "y_wind",
                units: "m s-1",
                value: &|_, _, _| 0.0,
            },
        ],
    );
    format!("{PACK}\n[wind]\nfile = \"gale.nc\"\nvariables = [\"u\", \"v\"]\n").replace(
        "[output]\nsnapshot_every_s = 1800.0",
        "[output]\nsnapshot_every_s = 600.0\ncheckpoint_every_s = 600.0",
    )
}

#[test]
fn a_floe_blown_off_the_grid_stops_the_run_with_its_checkpoint_intact_and_resume_checks_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = gale(d);
    let (code, msg) = error_of(d, "gale", &text);
    assert_eq!(code, 1, "{msg}");
    assert!(
        msg.contains("gale.toml:")
            && msg.contains("wind.file")
            && msg.contains("gale.nc")
            && msg.contains("outside the grid")
            && msg.contains("checkpoint"),
        "{msg}"
    );
    // The file stays a valid run whose checkpoint is resumable; changing
    // the forcing file since the run began is refused.
    let out = d.join("gale.h5");
    let f = RunFile::open(&out).unwrap();
    assert!(f.snapshot_count().unwrap() >= 1);
    drop(f);
    write_nc(
        &d.join("gale.nc"),
        &linspace(-1200.0, 20400.0, 13),
        &linspace(-1000.0, 13000.0, 8),
        None,
        false,
        &[
            Var {
                name: "u",
                standard_name: "x_wind",
                units: "m s-1",
                value: &|_, _, _| 0.0,
            },
            Var {
                name: "v",
                standard_name: "y_wind",
                units: "m s-1",
                value: &|_, _, _| 0.0,
            },
        ],
    );
    let resume = RunArgs {
        scenario: None,
        resume: true,
        force: false,
        ..run_args(&d.join("gale.toml"), &out, 1)
    };
    let e = run(&resume, &Quiet).unwrap_err();
    assert_eq!(e.exit_code(), 2);
    assert!(e.to_string().contains("changed since the run began"), "{e}");
}

/// Over two processes (threads standing for MPI ranks) the run stops at
/// the same step, with the same message in the file's status, the same
/// exit code and the same last checkpoint as one process.
#[test]
fn over_two_processes_a_floe_blown_off_the_grid_ends_the_run_as_in_one() {
    use floe_parallel::{Settings, ThreadComm};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scenario = d.join("gale.toml");
    std::fs::write(&scenario, gale(d)).unwrap();
    let one = run(&run_args(&scenario, &d.join("one.h5"), 1), &Quiet).unwrap_err();
    assert_eq!(one.exit_code(), 1, "{one}");
    let codes = ThreadComm::run(2, |comm| {
        let args = run_args(&scenario, &d.join("two.h5"), 1);
        floe_run::run_parallel::run_parallel(&args, &Quiet, &comm, Settings::default())
            .unwrap_err()
            .exit_code()
    });
    assert_eq!(codes, [1, 1]);
    let (a, b) = (
        RunFile::open(&d.join("one.h5")).unwrap(),
        RunFile::open(&d.join("two.h5")).unwrap(),
    );
    let status = a.status().unwrap();
    assert!(status.contains("outside the grid"), "{status}");
    assert_eq!(status, b.status().unwrap());
    assert_eq!(
        format!("{:?}", a.checkpoint_state(|| None).unwrap()),
        format!("{:?}", b.checkpoint_state(|| None).unwrap())
    );
}
