//! `floe grid` (floe_study::grid_output): a run's snapshots on a grid as CF
//! NetCDF, read back with the `netcdf3` reader. In a doubly periodic box of
//! drifting, spinning floes that cross its edges, every record holds all
//! the ice (concentration x cell area sums to the floes' area) and all the
//! momentum (the area-weighted velocity sums to sum A v, the rigid-body
//! mean), both computed here from the run file on their own.

use std::path::Path;

use floe_io::RunFile;
use floe_study::grid_output::{write_grid, GridArgs};
use floe_study::run_file::{run, Provenance, Quiet, RunArgs};
use netcdf3::{DataVector, FileReader};

const BOX: &str = r#"title = "drifting floes in a periodic box"
duration_s = 20000.0
seed = 1

[domain]
size_m = [4000.0, 3000.0]
periodic = [true, true]

[tessellation]
kind = "grid"
columns = 3
rows = 2
gap_m = 300.0

[ice]
thickness_range_m = [0.5, 2.0]
initial_velocity_m_per_s = [0.3, 0.12]

[wind]
velocity_m_per_s = [8.0, -3.0]

[output]
snapshot_every_s = 2000.0
"#;

fn f64s(v: DataVector) -> Vec<f64> {
    match v {
        DataVector::F64(x) => x,
        other => panic!("not f64: {other:?}"),
    }
}

#[test]
fn gridded_records_hold_all_the_ice_and_its_momentum_across_periodic_edges() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("box.toml");
    std::fs::write(&scenario, BOX).unwrap();
    let h5 = dir.path().join("box.h5");
    run(
        &RunArgs {
            scenario: Some(scenario),
            output: h5.clone(),
            threads: Some(1),
            force: false,
            resume: false,
            max_steps: None,
            step_limit: floe_scenario::MAX_RUN_STEPS,
            provenance: Provenance::of_this_process("test"),
            laws: floe_friction::LawRegistry::builtin(),
        },
        &Quiet,
    )
    .unwrap();
    let nc = dir.path().join("box.nc");
    let args = GridArgs {
        run: h5.clone(),
        output: nc.clone(),
        cell_m: 450.0,
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

    let mut reader = FileReader::open(&nc).unwrap();
    let data = reader.data_set();
    // 4000 / 450 -> 9 cells of 444.4 m, 3000 / 450 -> 7 of 428.6 m.
    assert_eq!(data.dim_size("x"), Some(9));
    assert_eq!(data.dim_size("y"), Some(7));
    let units = |var: &str| {
        data.get_var_attr(var, "units")
            .and_then(|a| a.get_as_string())
            .unwrap_or_default()
    };
    assert_eq!(units("u"), "m s-1");
    assert_eq!(units("divergence"), "s-1");
    assert_eq!(units("stress_xx"), "N m-1");
    let cell = (4000.0 / 9.0) * (3000.0 / 7.0);

    let file = RunFile::open(&h5).unwrap();
    let floes = file.static_floes().unwrap();
    let snapshots = file.snapshot_count().unwrap();
    assert_eq!(data.num_records(), Some(snapshots));
    let time = f64s(reader.read_var("time").unwrap());
    let (conc, u, v) = (
        f64s(reader.read_var("concentration").unwrap()),
        f64s(reader.read_var("u").unwrap()),
        f64s(reader.read_var("v").unwrap()),
    );
    let per = 9 * 7;
    let ice: f64 = floes.area_m2.iter().sum();
    let mut crossed = false;
    for (k, &t) in time.iter().enumerate() {
        let snap = file.snapshot(k).unwrap();
        assert_eq!(t, snap.time_s);
        let (mut area, mut px, mut py) = (0.0, 0.0, 0.0);
        for c in k * per..(k + 1) * per {
            if conc[c] > 0.0 {
                area += conc[c] * cell;
                px += conc[c] * cell * u[c];
                py += conc[c] * cell * v[c];
            } else {
                assert!(u[c] > 1e36, "a cell without ice holds the fill value");
            }
        }
        let (qx, qy) = (0..floes.len()).fold((0.0, 0.0), |(x, y), i| {
            (
                x + floes.area_m2[i] * snap.velocity[i][0],
                y + floes.area_m2[i] * snap.velocity[i][1],
            )
        });
        assert!(
            (area - ice).abs() < 1e-9 * ice,
            "record {k}: {area} against {ice}"
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
    assert!(grid_map::is_netcdf(&nc) && !grid_map::is_netcdf(&h5));
    let maps = dir.path().join("maps");
    let written = grid_map::render_grid(&nc, Snapshots::Every(5), &maps, false).unwrap();
    assert_eq!(
        written.len(),
        3 * 11,
        "records 0, 5, 10, eleven fields each"
    );
    assert!(written.iter().all(|p| p.exists()));
    assert!(maps.join("grid_divergence_0010.png").exists());
    assert!(
        grid_map::render_grid(&nc, Snapshots::One(5), &maps, false).is_err(),
        "no overwrite"
    );
    assert!(Path::new(&nc).exists());
}
