//! Bad input gets one clear message naming file, line and key, exit code 2,
//! and never a panic or a backtrace.

use std::path::Path;
use std::process::Command;

fn floe(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_floe"))
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("floe runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

const GOOD: &str = "[apparatus]\npreset = \"lab\"\n\n[law]\nkind = \"rate-state\"\n\n[[segment]]\nvelocity_m_per_s = 1e-4\nduration_s = 2\n";

/// Runs `floe slider run` on a protocol and checks the one-line error.
fn refused(protocol: &str, expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, protocol).unwrap();
    let out = dir.path().join("out");
    let (code, err) = floe(&[
        "slider",
        "run",
        &path.to_string_lossy(),
        "--out",
        &out.to_string_lossy(),
    ]);
    assert_one_clear_error(code, &err, 2);
    for e in expect {
        assert!(err.contains(e), "expected `{e}` in: {err}");
    }
    assert!(
        !out.join("series.csv").exists(),
        "nothing is written for bad input"
    );
}

fn assert_one_clear_error(code: i32, err: &str, expected_code: i32) {
    assert_eq!(code, expected_code, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    assert!(
        !err.contains("panicked") && !err.contains("backtrace"),
        "{err}"
    );
}

#[test]
fn the_good_protocol_runs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("good.toml");
    std::fs::write(&path, GOOD).unwrap();
    let (code, err) = floe(&[
        "slider",
        "run",
        &path.to_string_lossy(),
        "--out",
        &dir.path().join("o").to_string_lossy(),
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn unknown_keys_are_refused_with_their_location() {
    refused(
        &GOOD.replace(
            "kind = \"rate-state\"",
            "kind = \"rate-state\"\nmu_zero = 0.8",
        ),
        &[
            "bad.toml:6:1",
            "`law.mu_zero`",
            "unknown key `mu_zero`",
            "`mu0`",
        ],
    );
    refused(
        &GOOD.replace("duration_s = 2", "duration_s = 2\nspeed = 3"),
        &["bad.toml:10:1", "unknown field `speed`"],
    );
    refused(
        &format!("{GOOD}\n[extra]\nx = 1\n"),
        &["unknown field `extra`"],
    );
}

#[test]
fn negative_durations_are_refused() {
    refused(
        &GOOD.replace("duration_s = 2", "duration_s = -5"),
        &["bad.toml:9:14", "`segment[0].duration_s`", "> 0", "-5"],
    );
}

#[test]
fn zero_or_negative_stiffness_and_load_are_refused() {
    refused(
        &GOOD.replace("preset = \"lab\"", "stiffness_n_per_m = 0"),
        &["bad.toml:2:21", "`apparatus.stiffness_n_per_m`"],
    );
    refused(
        &GOOD.replace("preset = \"lab\"", "normal_load_n = -2000"),
        &["bad.toml:2:17", "`apparatus.normal_load_n`"],
    );
}

#[test]
fn non_finite_numbers_are_refused() {
    refused(
        &GOOD.replace("velocity_m_per_s = 1e-4", "velocity_m_per_s = nan"),
        &["bad.toml:8", "`segment[0].velocity_m_per_s`", "finite"],
    );
    refused(
        &GOOD.replace("kind = \"rate-state\"", "kind = \"rate-state\"\na = inf"),
        &["bad.toml:6:5", "`law.a`", "finite"],
    );
}

#[test]
fn wrong_types_syntax_and_structure_are_refused() {
    refused(
        &GOOD.replace("duration_s = 2", "duration_s = \"two\""),
        &["bad.toml:9:14", "`duration_s`", "expected f64"],
    );
    refused(&GOOD.replace("[law]", "[law"), &["bad.toml:4"]);
    refused(
        "[apparatus]\npreset = \"lab\"\n",
        &["bad.toml:1:1", "[[segment]]"],
    );
    refused(
        &GOOD.replace(
            "velocity_m_per_s = 1e-4",
            "velocity_m_per_s = 1e-4\nramp_m_per_s = [1e-4, 1e-3]",
        ),
        &["bad.toml:7", "`segment[0]`", "exactly one"],
    );
    refused(
        &GOOD.replace("velocity_m_per_s = 1e-4", "ramp_m_per_s = [1e-4]"),
        &["bad.toml:8", "[from, to]"],
    );
}

#[test]
fn values_that_do_not_fit_the_law_are_refused() {
    refused(
        &GOOD.replace("kind = \"rate-state\"", "kind = \"rate-state\"\nmu = 0.5"),
        &["bad.toml:6:1", "`law.mu`", "does not apply"],
    );
    refused(
        &GOOD.replace("kind = \"rate-state\"", "kind = \"coulomb\""),
        &["bad.toml:5:8", "`law.kind`", "amontons"],
    );
    refused(
        &GOOD.replace("preset = \"lab\"", "preset = \"arctic\""),
        &["bad.toml:2:10", "`apparatus.preset`"],
    );
    refused(
        &GOOD.replace("kind = \"rate-state\"", "kind = \"amontons\""),
        &["needs `mu`"],
    );
    refused(
        &GOOD.replace(
            "kind = \"rate-state\"",
            "kind = \"rate-state\"\nform = \"exact\"",
        ),
        &["`law.form`"],
    );
}

fn fit_refused(csv: &str, expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data.csv");
    std::fs::write(&data, csv).unwrap();
    let protocol = dir.path().join("p.toml");
    std::fs::write(&protocol, GOOD).unwrap();
    let (code, err) = floe(&[
        "slider",
        "fit",
        &data.to_string_lossy(),
        "--protocol",
        &protocol.to_string_lossy(),
    ]);
    assert_one_clear_error(code, &err, 2);
    for e in expect {
        assert!(err.contains(e), "expected `{e}` in: {err}");
    }
}

#[test]
fn measured_data_with_missing_columns_or_bad_numbers_is_refused() {
    fit_refused(
        "t_s,friction\n0,0.7\n1,0.7\n2,0.7\n",
        &["data.csv:1:", "`mu`", "missing column", "friction"],
    );
    fit_refused("time,mu\n0,0.7\n", &["data.csv:1:", "time column"]);
    fit_refused(
        "t_s,mu\n0,0.7\n1,abc\n2,0.7\n",
        &["data.csv:3:", "`mu`", "`abc`"],
    );
    fit_refused("t_s,mu\n0,0.7\n1,NaN\n2,0.7\n", &["data.csv:3:", "finite"]);
    fit_refused(
        "t_s,mu\n0,0.7\n1,0.7\n0.5,0.7\n",
        &["data.csv:4:", "`t_s`", "must increase"],
    );
    fit_refused(
        "t_s,mu\n0,0.7\n1,0.7\n30,0.7\n",
        &["beyond the end of the protocol"],
    );
}

#[test]
fn bad_flags_and_missing_files_get_one_message() {
    let (code, err) = floe(&["slider", "hold", "--preset", "lab", "--hold", "0"]);
    assert_one_clear_error(code, &err, 2);
    let (code, err) = floe(&[
        "slider", "step", "--preset", "lab", "--from", "1e-4", "--to", "-1", "--json",
    ]);
    assert_one_clear_error(code, &err, 2);
    let (code, err) = floe(&[
        "slider",
        "hold",
        "--preset",
        "lab",
        "--hold",
        "1",
        "--normal-load",
        "0",
    ]);
    assert_one_clear_error(code, &err, 2);
    assert!(err.contains("--normal-load"), "{err}");
    // A file that is not there is bad input: exit 2, the path named.
    let (code, err) = floe(&["slider", "run", "/nonexistent/p.toml", "--out", "/tmp/x"]);
    assert_one_clear_error(code, &err, 2);
    assert!(err.contains("/nonexistent/p.toml"), "{err}");
    assert!(Path::new("/tmp").exists());
}

#[test]
fn bad_decomposition_flags_get_one_message_naming_the_flag() {
    for (flag, value) in [
        ("--halo-skin", "0"),
        ("--halo-skin", "nan"),
        ("--rebalance-threshold", "-0.1"),
        ("--rebalance-threshold", "inf"),
        ("--rebalance-threshold", "x"),
    ] {
        let (code, err) = floe(&["run", "s.toml", "-o", "o.h5", &format!("{flag}={value}")]);
        assert_one_clear_error(code, &err, 2);
        assert!(err.contains(flag) && err.contains("fraction > 0"), "{err}");
    }
}

#[test]
fn rheology_flags_and_scenarios_that_are_not_cells_get_one_message() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out = out.to_string_lossy();
    let shipped = |name: &str| {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios")
            .join(name)
            .to_string_lossy()
            .into_owned()
    };
    let cell = shipped("shear_cell.toml");
    for (args, expect) in [
        (vec!["--speeds", "0.1,-2"], "--speeds -2"),
        (vec!["--speeds", "0.1,nan"], "--speeds"),
        (vec!["--speeds", "0.1,0.1,0.2"], "twice"),
        (vec!["--strain", "0"], "--strain"),
        (vec!["--snapshots", "1"], "--snapshots"),
        (vec!["--transient", "1"], "--transient"),
        (vec!["--laws", "amontons,nope"], "nope"),
    ] {
        let mut all = vec!["rheology", cell.as_str(), "-o", &out];
        all.extend(args);
        let (code, err) = floe(&all);
        assert_one_clear_error(code, &err, 2);
        assert!(err.contains(expect), "expected `{expect}` in: {err}");
    }
    let (code, err) = floe(&["rheology", &shipped("demo.toml"), "-o", &out]);
    assert_one_clear_error(code, &err, 2);
    assert!(err.contains("not a shear cell"), "{err}");
    assert!(!dir.path().join("out").exists(), "nothing written");
}

/// Four floes on a grid, 21 steps at the automatic time step.
const GRID: &str = "duration_s = 100.0\n\n[domain]\nsize_m = [4000.0, 4000.0]\n\n\
                    [tessellation]\nkind = \"grid\"\ncolumns = 2\nrows = 2\ngap_m = 100.0\n";

/// Runs `floe run` on scenario `text` (with `extra` flags) and checks the
/// one-line error, exit 2, that nothing was written, and that it starts
/// with `bad.toml:LINE:COL` of `needle`'s first occurrence plus `offset`.
fn run_refused(text: &str, extra: &[&str], (needle, offset): (&str, usize), expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let out = dir.path().join("out.h5");
    let mut args = vec![
        "run".to_string(),
        path.to_string_lossy().into_owned(),
        "-o".into(),
        out.to_string_lossy().into_owned(),
        "-q".into(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = floe(&args);
    assert_one_clear_error(code, &err, 2);
    let start = text.find(needle).unwrap_or_else(|| panic!("{needle}")) + offset;
    let line = text[..start].matches('\n').count() + 1;
    let column = start - text[..start].rfind('\n').map_or(0, |i| i + 1) + 1;
    let place = format!("error: {}:{line}:{column}: ", path.display());
    assert!(err.starts_with(&place), "expected {place}: {err}");
    for e in expect {
        assert!(err.contains(e), "expected `{e}` in: {err}");
    }
    assert!(!out.exists(), "nothing is written for bad input");
}

#[test]
fn a_run_refuses_a_bad_dt_fraction_at_its_key() {
    let with = |line: &str| {
        GRID.replacen(
            "duration_s = 100.0\n",
            &format!("duration_s = 100.0\n{line}\n"),
            1,
        )
    };
    for bad in ["0.0", "1.25", "-1.0"] {
        let line = format!("dt_fraction = {bad}");
        run_refused(&with(&line), &[], (&line, 14), &["`dt_fraction`", "(0, 1]"]);
    }
    run_refused(
        &with("dt_s = 1.0\ndt_fraction = 0.5"),
        &[],
        ("dt_fraction = 0.5", 14),
        &["`dt_fraction`", "not both"],
    );
}

#[test]
fn a_run_refuses_bad_output_windows_at_their_keys() {
    let with = |window: &str| format!("{GRID}\n[[output.window]]\n{window}\n");
    run_refused(
        &with("from_s = 50.0\nto_s = 40.0\nobservables_every_s = 0.1"),
        &[],
        ("to_s = 40.0", 7),
        &["`output.window[0].to_s`", "after from_s = 50 s"],
    );
    run_refused(
        &with("from_s = 50.0\nto_s = 140.0\nobservables_every_s = 0.1"),
        &[],
        ("to_s = 140.0", 7),
        &["`output.window[0].to_s`", "[0, 100] s"],
    );
    run_refused(
        &with("from_s = 50.0\nto_s = 60.0"),
        &[],
        ("[[output.window]]", 0),
        &[
            "`output.window[0]`",
            "snapshot_every_s",
            "observables_every_s",
        ],
    );
    // Every step of the run, twice: more outputs than the step limit allows.
    let every_step = "[[output.window]]\nfrom_s = 0.0\nto_s = 100.0\nsnapshot_every_s = 1e-9\n\n";
    run_refused(
        &format!("{GRID}\n{}", every_step.repeat(2)),
        &["--step-limit", "30"],
        ("[[output.window]]", every_step.len()),
        &["`output.window[1]`", "44 snapshots", "--step-limit"],
    );
}

#[test]
fn grid_info_and_render_refuse_missing_or_foreign_files_and_grid_a_bad_cell_size() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f.nc");
    let out = out.to_string_lossy();
    let (code, err) = floe(&[
        "grid",
        "/nonexistent/run.h5",
        "-o",
        &out,
        "--cell-m",
        "1000",
    ]);
    assert_one_clear_error(code, &err, 2);
    assert!(err.contains("/nonexistent/run.h5"), "{err}");
    for bad in ["0", "-5", "nan"] {
        let (code, err) = floe(&["grid", "/nonexistent/run.h5", "-o", &out, "--cell-m", bad]);
        assert_one_clear_error(code, &err, 2);
        assert!(err.contains("--cell-m"), "{err}");
    }
    // The cadence flags likewise, before the run file is looked at.
    for (flags, named) in [
        (&["--every", "0"][..], "--every"),
        (&["--interval-s", "0"], "--interval-s"),
        (&["--interval-s", "-5"], "--interval-s"),
        (&["--interval-s", "inf"], "--interval-s"),
        (&["--every", "2", "--interval-s", "60"], "--interval-s"),
    ] {
        let mut args = vec![
            "grid",
            "/nonexistent/run.h5",
            "-o",
            &out,
            "--cell-m",
            "1000",
        ];
        args.extend_from_slice(flags);
        let (code, err) = floe(&args);
        assert_one_clear_error(code, &err, 2);
        assert!(err.contains(named), "{flags:?}: {err}");
    }
    assert!(!dir.path().join("f.nc").exists());
    // The other readers of run files say the same: a missing file, or one
    // that is not a floe run file, is bad input.
    let text = dir.path().join("notes.txt");
    std::fs::write(&text, "not a run").unwrap();
    for file in ["/nonexistent/run.h5", &text.to_string_lossy()] {
        for args in [vec!["info", file], vec!["render", file, "-o", &out]] {
            let (code, err) = floe(&args);
            assert_one_clear_error(code, &err, 2);
            assert!(err.contains(file), "{err}");
        }
    }
}

#[test]
fn a_run_refuses_a_missing_ice_grid_and_a_bad_size_distribution_at_their_keys() {
    let ice = format!(
        "{GRID}\n[ice]\nconcentration_grid = {{ file = \"siconc.nc\", variable = \"siconc\" }}\n"
    );
    run_refused(
        &ice,
        &[],
        ("{ file", 0),
        &["`ice.concentration_grid`", "siconc.nc", "no such file"],
    );
    let fsd = GRID.replacen(
        "kind = \"grid\"\ncolumns = 2\nrows = 2\ngap_m = 100.0",
        "kind = \"voronoi\"\nsize_distribution = { kind = \"power_law\", exponent = 2.0, min_m = 500.0, max_m = 400.0 }",
        1,
    );
    run_refused(
        &fsd,
        &[],
        ("400.0", 0),
        &["`tessellation.size_distribution.max_m`", "above min_m"],
    );
}

#[test]
fn bad_land_files_stop_floe_run_with_one_located_message() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("coast.toml");
    let base = "duration_s = 10.0\n\n[domain]\nsize_m = [4000.0, 4000.0]\n\n\
                [tessellation]\nkind = \"grid\"\ncolumns = 2\nrows = 2\n\n\
                [[land]]\nfile = \"coast.geojson\"\ncoordinates = \"xy\"\n";
    std::fs::write(&scenario, base).unwrap();
    let out = dir.path().join("run.h5");
    let run = || {
        floe(&[
            "run",
            &scenario.to_string_lossy(),
            "-o",
            &out.to_string_lossy(),
            "--quiet",
        ])
    };
    // Missing: relative to the scenario's directory, named.
    let (code, err) = run();
    assert_one_clear_error(code, &err, 2);
    assert!(
        err.contains("coast.toml:12:8")
            && err.contains("land[0].file")
            && err.contains("coast.geojson"),
        "{err}"
    );
    // Bad geometry.
    std::fs::write(
        dir.path().join("coast.geojson"),
        r#"{"type": "Polygon", "coordinates": [[[0, 0], [10, 10], [10, 0], [0, 10], [0, 0]]]}"#,
    )
    .unwrap();
    let (code, err) = run();
    assert_one_clear_error(code, &err, 2);
    assert!(err.contains("not simple"), "{err}");
    assert!(!out.exists(), "nothing is written for bad input");
    // Good land runs, and the run file marks it.
    std::fs::write(
        dir.path().join("coast.geojson"),
        r#"{"type": "Polygon", "coordinates": [[[3000, -500], [4500, -500], [4500, 4500], [3000, 4500], [3000, -500]]]}"#,
    )
    .unwrap();
    let (code, err) = run();
    assert_eq!(code, 0, "{err}");
    assert!(out.exists());
}

#[test]
fn export_refuses_missing_or_foreign_files_and_needs_a_format() {
    let dir = tempfile::tempdir().unwrap();
    let (code, err) = floe(&["export", "/nonexistent/run.h5", "--xdmf"]);
    assert_one_clear_error(code, &err, 2);
    assert!(err.contains("/nonexistent/run.h5"), "{err}");
    let text = dir.path().join("text.h5");
    std::fs::write(&text, "not a run file").unwrap();
    let (code, err) = floe(&["export", &text.to_string_lossy(), "--xdmf"]);
    assert_one_clear_error(code, &err, 2);
    assert!(err.contains("not an HDF5 file"), "{err}");
    // Without a format flag there is nothing to write: clap names --xdmf.
    let (code, err) = floe(&["export", &text.to_string_lossy()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--xdmf"), "{err}");
    assert!(!dir.path().join("text.xdmf").exists());
}
