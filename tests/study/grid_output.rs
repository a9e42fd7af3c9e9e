//! `floe grid` (floe_study::grid_output): a run's snapshots on a grid as CF
//! NetCDF, read back with the `netcdf` crate. In a doubly periodic box of
//! drifting, spinning floes that cross its edges, every record holds all
//! the ice (concentration x cell area sums to the floes' area), all their
//! volume and all their momentum (`c h u` x cell area sums to sum A h v),
//! each computed here from the run file on its own. In a pack squeezed
//! between walls, where soft contacts overlap, each cell's ice is the union
//! of the floes in it (at most the cell). With a cadence of its own, the
//! records are the snapshots it names; with a `start_time`, the time axis
//! has dates.

use std::path::{Path, PathBuf};

use crate::inherited_locks;
use crate::study_support;
use crate::union_support;
use floe_io::RunFile;
use floe_study::cadence::Cadence;
use floe_study::grid_output::{write_grid, GridArgs, FILL_VALUE};
use netcdf::AttributeValue;
use study_support::run_text;

/// Six floes drifting in a doubly periodic box (20000 s, snapshots every
/// 2000 s); tests/study/grid_xarray.rs grids it too.
const BOX: &str = include_str!("../data/grid_box.toml");

fn f64s(file: &netcdf::File, name: &str) -> Vec<f64> {
    file.variable(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .get_values::<f64, _>(..)
        .unwrap()
}

fn text(value: Option<netcdf::Result<AttributeValue>>) -> String {
    match value {
        Some(Ok(AttributeValue::Str(s))) => s,
        other => panic!("not a text attribute: {other:?}"),
    }
}

/// The box's run, in `dir`.
fn box_run(dir: &Path) -> PathBuf {
    run_text(dir, "box", BOX).unwrap()
}

#[test]
fn gridded_records_hold_all_the_ice_and_its_momentum_across_periodic_edges() {
    let _netcdf = inherited_locks::netcdf_files();
    let dir = tempfile::tempdir().unwrap();
    let h5 = box_run(dir.path());
    let nc = dir.path().join("box.nc");
    let args = GridArgs {
        run: h5.clone(),
        output: nc.clone(),
        cell_m: 450.0,
        cadence: Cadence::All,
        force: false,
    };
    write_grid(&args).unwrap();
    // Not again without --force.
    assert!(write_grid(&args).is_err());
    let bad = GridArgs {
        cell_m: 0.0,
        output: dir.path().join("x.nc"),
        ..args.clone()
    };
    assert!(write_grid(&bad)
        .unwrap_err()
        .to_string()
        .contains("--cell-m"));
    assert!(!dir.path().join("x.nc").exists());

    let data = netcdf::open(&nc).unwrap();
    // 4000 / 450 -> 9 cells of 444.4 m, 3000 / 450 -> 7 of 428.6 m.
    assert_eq!(data.dimension_len("x"), Some(9));
    assert_eq!(data.dimension_len("y"), Some(7));
    let var = |name: &str| data.variable(name).unwrap();
    let units = |name: &str| text(var(name).attribute_value("units"));
    assert_eq!(units("u"), "m s-1");
    assert_eq!(units("divergence"), "s-1");
    assert_eq!(units("stress_xx"), "N m-1");
    assert_eq!(units("x"), "m");
    // Without a start_time, seconds from the start of the run: no dates.
    assert_eq!(units("time"), "s");
    assert!(var("time").attribute("calendar").is_none());
    assert!(text(var("time").attribute_value("long_name")).contains("start of the run"));
    assert_eq!(text(var("x").attribute_value("axis")), "X");
    assert_eq!(
        text(var("concentration").attribute_value("standard_name")),
        "sea_ice_area_fraction"
    );
    assert_eq!(
        text(Some(data.attribute("Conventions").unwrap().value())),
        "CF-1.8"
    );
    assert_eq!(var("u").fill_value::<f64>().unwrap(), Some(FILL_VALUE));
    assert!(data.dimension("time").unwrap().is_unlimited());
    let cell = (4000.0 / 9.0) * (3000.0 / 7.0);

    let file = RunFile::open(&h5).unwrap();
    let floes = file.static_floes().unwrap();
    let snapshots = file.snapshot_count().unwrap();
    assert_eq!(data.dimension_len("time"), Some(snapshots));
    let time = f64s(&data, "time");
    let (conc, thick, u, v) = (
        f64s(&data, "concentration"),
        f64s(&data, "thickness"),
        f64s(&data, "u"),
        f64s(&data, "v"),
    );
    let per = 9 * 7;
    let ice: f64 = floes.area_m2.iter().sum();
    let volume: f64 = (0..floes.len())
        .map(|i| floes.area_m2[i] * floes.thickness_m[i])
        .sum();
    let mut crossed = false;
    for (k, &t) in time.iter().enumerate() {
        let snap = file.snapshot(k).unwrap();
        assert_eq!(t, snap.time_s);
        let (mut area, mut vol, mut px, mut py) = (0.0, 0.0, 0.0, 0.0);
        for c in k * per..(k + 1) * per {
            if conc[c] > 0.0 {
                let here = conc[c] * cell * thick[c];
                area += conc[c] * cell;
                vol += here;
                px += here * u[c];
                py += here * v[c];
            } else {
                assert!(u[c] > 1e36, "a cell without ice holds the fill value");
            }
        }
        // Momentum over the ice's density.
        let (qx, qy) = (0..floes.len()).fold((0.0, 0.0), |(x, y), i| {
            let w = floes.area_m2[i] * floes.thickness_m[i];
            (x + w * snap.velocity[i][0], y + w * snap.velocity[i][1])
        });
        assert!(
            (area - ice).abs() < 1e-9 * ice,
            "record {k}: {area} against {ice}"
        );
        assert!(
            (vol - volume).abs() < 1e-9 * volume,
            "record {k}: {vol} against {volume}"
        );
        assert!(
            (px - qx).abs() < 1e-9 * qx.abs().max(1.0),
            "record {k}: {px} against {qx}"
        );
        assert!(
            (py - qy).abs() < 1e-9 * qy.abs().max(1.0),
            "record {k}: {py} against {qy}"
        );
        crossed |= (0..floes.len()).any(|i| {
            let r = floes
                .local_vertices(i)
                .iter()
                .map(|p| p[0].hypot(p[1]))
                .fold(0.0, f64::max);
            let [x, y] = snap.position[i];
            x - r < 0.0 || x + r > 4000.0 || y - r < 0.0 || y + r > 3000.0
        });
    }
    assert!(crossed, "some floe lay across a periodic edge");

    // `floe render` draws the fields: one map per field and record.
    use floe_study::render::{grid_map, Snapshots};
    assert!(grid_map::is_grid_file(&nc) && !grid_map::is_grid_file(&h5));
    let maps = dir.path().join("maps");
    let mut calls = 0;
    let written = grid_map::render_grid(&nc, Snapshots::Every(5), &maps, false, &mut |_, _| {
        calls += 1
    })
    .unwrap();
    assert_eq!(calls, written.len());
    assert_eq!(
        written.len(),
        3 * 11,
        "records 0, 5, 10, eleven fields each"
    );
    assert!(written.iter().all(|p| p.exists()));
    assert!(maps.join("grid_divergence_0010.png").exists());
    assert!(
        grid_map::render_grid(&nc, Snapshots::One(5), &maps, false, &mut |_, _| {}).is_err(),
        "no overwrite"
    );
    assert!(Path::new(&nc).exists());

    // A movie of one field: a frame per record.
    use floe_study::render::movie::MovieArgs;
    let args = MovieArgs {
        path: dir.path().join("divergence.gif"),
        fps: 10.0,
        force: false,
    };
    let written = grid_map::render_grid_movie(
        &nc,
        Snapshots::Every(1),
        "divergence",
        &args,
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(written.frames, snapshots);
    let decoder = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(&written.path).unwrap())
        .unwrap();
    assert_eq!(decoder.into_iter().count(), snapshots);
    let e = grid_map::render_grid_movie(&nc, Snapshots::Every(1), "speed", &args, &mut |_, _| {})
        .unwrap_err();
    assert!(
        e.exit_code() == 2 && e.to_string().contains("concentration"),
        "{e}"
    );
}

/// `--every K` and `--interval-s T`: the records are the K-th snapshots,
/// or those nearest to the multiples of T, with the snapshots' own times.
#[test]
fn a_cadence_of_its_own_takes_the_snapshots_it_names() {
    let _netcdf = inherited_locks::netcdf_files();
    let dir = tempfile::tempdir().unwrap();
    let h5 = box_run(dir.path());
    let times = RunFile::open(&h5).unwrap().snapshot_times().unwrap();
    // Snapshots about every 2000 s (every 707 steps of 2.83 s), and the
    // final one at the run's last step, 8 s after the one before.
    assert_eq!(times.len(), 12);
    let grid = |cadence: Cadence, name: &str| -> Vec<f64> {
        let nc = dir.path().join(name);
        write_grid(&GridArgs {
            run: h5.clone(),
            output: nc.clone(),
            cell_m: 1000.0,
            cadence,
            force: false,
        })
        .unwrap();
        let data = netcdf::open(&nc).unwrap();
        let time = f64s(&data, "time");
        // Every field has one record per time.
        assert_eq!(f64s(&data, "shear").len(), time.len() * 4 * 3);
        time
    };
    assert_eq!(grid(Cadence::All, "all.nc"), times);
    assert_eq!(
        grid(Cadence::Every(3), "every3.nc"),
        [0, 3, 6, 9].map(|k| times[k])
    );
    // Nearest to 0, 5000, 10000, 15000, 20000 s (the earlier of two as
    // near, as `min_by` finds it).
    let nearest = |target: f64| {
        *times
            .iter()
            .min_by(|a, b| (*a - target).abs().total_cmp(&(*b - target).abs()))
            .unwrap()
    };
    let expected: Vec<f64> = [0.0, 5000.0, 10000.0, 15000.0, 20000.0]
        .map(nearest)
        .to_vec();
    assert_eq!(grid(Cadence::IntervalS(5000.0), "interval.nc"), expected);
    assert_eq!(
        grid(Cadence::IntervalS(6000.0), "interval6.nc"),
        [0, 3, 6, 9].map(|k| times[k]),
        "0, 6000, 12000, 18000 s"
    );
    // A bad cadence is bad input, and nothing is written.
    for (cadence, flag) in [
        (Cadence::Every(0), "--every"),
        (Cadence::IntervalS(-1.0), "--interval-s"),
    ] {
        let nc = dir.path().join("bad.nc");
        let e = write_grid(&GridArgs {
            run: h5.clone(),
            output: nc.clone(),
            cell_m: 1000.0,
            cadence,
            force: false,
        })
        .unwrap_err();
        assert!(e.to_string().contains(flag) && e.exit_code() == 2, "{e}");
        assert!(!nc.exists() && !dir.path().join("bad.nc.partial").exists());
    }
}

/// A Voronoi pack squeezed between walls 50 m inside the grid's edges (its
/// floes of one thickness): the soft contacts overlap, in pairs and in
/// threes at the floes' corners.
const SQUEEZED: &str = r#"title = "a Voronoi pack squeezed between walls"
duration_s = 900.0
seed = 7

[domain]
size_m = [3000.0, 3000.0]

[tessellation]
kind = "voronoi"
floe_scale_m = 400.0
relax_iterations = 2

[ice]
thickness_m = 1.0

[[wall]]
side = "left"
inset_m = 50.0

[[wall]]
side = "right"
inset_m = 50.0

[[wall]]
side = "bottom"
inset_m = 50.0
velocity_m_per_s = [0.0, 0.05]

[[wall]]
side = "top"
inset_m = 50.0
velocity_m_per_s = [0.0, -0.05]

[output]
snapshot_every_s = 300.0
"#;

/// Where floes overlap, a cell's concentration is the area of their union
/// in it over its area, found here on its own by vertical slabs from the
/// run file's floes: at most 1, while the floes' own areas (`c h` with
/// floes 1 m thick) add up to more than the cell. Their volume and
/// momentum are every floe's own.
#[test]
fn overlapping_floes_of_a_squeezed_pack_are_ice_once() {
    let _netcdf = inherited_locks::netcdf_files();
    let dir = tempfile::tempdir().unwrap();
    let h5 = run_text(dir.path(), "squeezed", SQUEEZED).unwrap();
    let nc = dir.path().join("squeezed.nc");
    write_grid(&GridArgs {
        run: h5.clone(),
        output: nc.clone(),
        cell_m: 250.0,
        cadence: Cadence::All,
        force: false,
    })
    .unwrap();
    let data = netcdf::open(&nc).unwrap();
    let (conc, thick, u, v) = (
        f64s(&data, "concentration"),
        f64s(&data, "thickness"),
        f64s(&data, "u"),
        f64s(&data, "v"),
    );
    let (n, cell) = (12, 250.0 * 250.0);
    let file = RunFile::open(&h5).unwrap();
    let floes = file.static_floes().unwrap();
    let free: Vec<usize> = (0..floes.len()).filter(|&i| !floes.prescribed[i]).collect();
    let (mut most_floe_area, mut most_floes_over_a_place): (f64, usize) = (0.0, 1);
    for k in 0..file.snapshot_count().unwrap() {
        let snap = file.snapshot(k).unwrap();
        let polys: Vec<Vec<[f64; 2]>> = free
            .iter()
            .map(|&i| snap.world_vertices(&floes, i))
            .collect();
        let (lo, hi) = polys
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[0]).min(p[1]), b.max(p[0]).max(p[1]))
            });
        assert!(
            lo >= 0.0 && hi <= 3000.0,
            "the floes are inside the grid: {lo} {hi}"
        );
        let record = k * n * n..(k + 1) * n * n;
        // The same floes through floe-analysis: its count of overlaps.
        let position: Vec<[f64; 2]> = free.iter().map(|&i| snap.position[i]).collect();
        let fields = floe_analysis::grid_fields::grid_fields(
            &floe_analysis::grid_fields::Grid {
                origin_m: [0.0, 0.0],
                cell_m: [250.0, 250.0],
                shape: [n, n],
            },
            &floe_analysis::grid_fields::FloeSnapshot {
                vertices: &polys,
                position: &position,
                velocity: &free.iter().map(|&i| snap.velocity[i]).collect::<Vec<_>>(),
                angular_velocity: &free
                    .iter()
                    .map(|&i| snap.angular_velocity[i])
                    .collect::<Vec<_>>(),
                thickness_m: &free
                    .iter()
                    .map(|&i| floes.thickness_m[i])
                    .collect::<Vec<_>>(),
                stress_moment_n_m: None,
            },
        )
        .unwrap();
        assert_eq!(fields.concentration, conc[record.clone()]);
        eprintln!(
            "record {k}: sets of 2, 3, ... floes with a common overlap: {:?}",
            fields.overlap_sets
        );
        most_floes_over_a_place = most_floes_over_a_place.max(fields.overlap_sets.len() + 1);
        let (mut ice, mut volume, mut px, mut py) = (0.0, 0.0, 0.0, 0.0);
        for (c, at) in record.clone().enumerate() {
            let lo = [250.0 * (c % n) as f64, 250.0 * (c / n) as f64];
            let union =
                union_support::union_area_in_box(&polys, lo, [lo[0] + 250.0, lo[1] + 250.0]);
            assert!(
                (conc[at] - union / cell).abs() < 1e-12,
                "record {k}, cell {c}: {} against {}",
                conc[at],
                union / cell
            );
            assert!(
                conc[at] <= 1.0 + 1e-12,
                "record {k}, cell {c}: {}",
                conc[at]
            );
            if conc[at] > 0.0 {
                most_floe_area = most_floe_area.max(conc[at] * thick[at]);
                ice += conc[at] * cell;
                volume += conc[at] * thick[at] * cell;
                px += conc[at] * thick[at] * cell * u[at];
                py += conc[at] * thick[at] * cell * v[at];
            }
        }
        // The floes' area minus their overlaps' area, counted once.
        let union = union_support::union_area(&polys);
        assert!(
            (ice - union).abs() < 1e-12 * union,
            "record {k}: {ice} against {union}"
        );
        let own: f64 = free
            .iter()
            .map(|&i| floes.area_m2[i] * floes.thickness_m[i])
            .sum();
        assert!(
            (volume - own).abs() < 1e-12 * own,
            "record {k}: {volume} against {own}"
        );
        let (qx, qy) = free.iter().fold((0.0, 0.0), |(x, y), &i| {
            let w = floes.area_m2[i] * floes.thickness_m[i];
            (x + w * snap.velocity[i][0], y + w * snap.velocity[i][1])
        });
        let scale = free
            .iter()
            .map(|&i| floes.area_m2[i] * snap.velocity[i][0].hypot(snap.velocity[i][1]))
            .sum::<f64>();
        assert!(
            (px - qx).abs() <= 1e-12 * scale && (py - qy).abs() <= 1e-12 * scale,
            "record {k}: ({px}, {py}) against ({qx}, {qy})"
        );
    }
    assert!(
        most_floe_area > 1.02,
        "the floes' own areas overfill a cell: {most_floe_area}"
    );
    assert!(most_floes_over_a_place >= 3, "places under three floes");
}

/// With the scenario's `start_time`, the time axis is seconds since that
/// date in the proleptic Gregorian calendar, as CF readers decode dates
/// from (tests/study/grid_xarray.rs decodes them with Python).
#[test]
fn a_start_time_makes_the_time_axis_dates() {
    let _netcdf = inherited_locks::netcdf_files();
    let dir = tempfile::tempdir().unwrap();
    let dated = BOX.replace(
        "seed = 1\n",
        "seed = 1\nstart_time = \"2024-02-28T23:00Z\"\n",
    );
    assert_ne!(dated, BOX);
    let h5 = run_text(dir.path(), "dated", &dated).unwrap();
    let nc = dir.path().join("dated.nc");
    write_grid(&GridArgs {
        run: h5.clone(),
        output: nc.clone(),
        cell_m: 1000.0,
        cadence: Cadence::All,
        force: false,
    })
    .unwrap();
    let data = netcdf::open(&nc).unwrap();
    let time = data.variable("time").unwrap();
    let attr = |name: &str| text(time.attribute_value(name));
    assert_eq!(attr("units"), "seconds since 2024-02-28 23:00:00");
    assert_eq!(attr("calendar"), "proleptic_gregorian");
    assert_eq!(attr("standard_name"), "time");
    assert_eq!(attr("axis"), "T");
    assert_eq!(
        f64s(&data, "time"),
        RunFile::open(&h5).unwrap().snapshot_times().unwrap()
    );
}
