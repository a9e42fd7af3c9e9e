//! The reproductions of issue 21 ("bad numbers and bad bytes"), one named
//! test each, through the `floe` binary: runs that go bad end with the
//! blow-up message, refused input gets one located message and exit 2,
//! nothing hangs, crashes or overwrites what the user wrote.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const FLOE: &str = env!("CARGO_BIN_EXE_floe");

/// A small walled channel of diamonds: a valid run of about 200 steps.
const SMALL: &str = r#"title = "small"
duration_s = 600.0
seed = 1

[domain]
size_m = [6000.0, 4000.0]
periodic = [true, false]

[tessellation]
kind = "diamond"
side_m = 500.0

[ice]
thickness_m = 1.0

[wind]
velocity_m_per_s = [10.0, 0.0]

[[wall]]
side = "bottom"

[[wall]]
side = "top"

[output]
snapshot_every_s = 60.0
"#;

/// Two boxes in a 3 km open domain.
const TWO_BOXES: &str = r#"title = "two boxes"
duration_s = 100.0

[domain]
size_m = [3000.0, 3000.0]

[[floe]]
box_m = [100.0, 100.0, 300.0, 300.0]
velocity_m_per_s = [1.0, 0.0]

[[floe]]
box_m = [1000.0, 1000.0, 1200.0, 1200.0]
"#;

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn floe_in(dir: &Path, args: &[&str]) -> Run {
    let Output {
        status,
        stdout,
        stderr,
    } = Command::new(FLOE)
        .args(args)
        .current_dir(dir)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("floe runs");
    Run {
        code: status.code(),
        stdout: String::from_utf8_lossy(&stdout).into(),
        stderr: String::from_utf8_lossy(&stderr).into(),
    }
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// `base` with `from` replaced by `to` (which must be there).
fn edit(base: &str, from: &str, to: &str) -> String {
    assert!(base.contains(from), "{from}");
    base.replacen(from, to, 1)
}

/// Exit 2 with one line, `error: ` then `expect_start`, containing each of
/// `expect`.
fn assert_refused(r: &Run, expect_start: &str, expect: &[&str]) {
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert_eq!(
        r.stderr.trim_end().lines().count(),
        1,
        "one line: {}",
        r.stderr
    );
    assert!(
        r.stderr.starts_with(&format!("error: {expect_start}")),
        "expected `error: {expect_start}`: {}",
        r.stderr
    );
    for e in expect {
        assert!(r.stderr.contains(e), "expected `{e}` in: {}", r.stderr);
    }
    assert!(!r.stderr.contains("panicked"), "{}", r.stderr);
}

/// Exit `code`, with `needle` in standard error.
fn assert_exit(r: &Run, code: i32, needle: &str) {
    assert_eq!(r.code, Some(code), "{}", r.stderr);
    assert!(r.stderr.contains(needle), "{}", r.stderr);
}

/// Runs scenario `text` as `s.toml` into `s.h5`.
fn run_scenario(dir: &Path, text: &str, extra: &[&str]) -> Run {
    write(dir, "s.toml", text);
    let mut args = vec!["run", "s.toml", "-o", "s.h5", "-q", "--threads", "1"];
    args.extend_from_slice(extra);
    floe_in(dir, &args)
}

/// Refused at `s.toml:LINE:COL` where `needle` starts, naming `key`.
fn assert_scenario_refused(text: &str, needle: &str, key: &str, expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let r = run_scenario(dir.path(), text, &[]);
    let start = text.find(needle).unwrap_or_else(|| panic!("{needle}"));
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let column = start - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    let mut all = vec![key];
    all.extend_from_slice(expect);
    assert_refused(&r, &format!("s.toml:{line}:{column}: "), &all);
    assert!(!dir.path().join("s.h5").exists(), "no output for bad input");
}

/// The documented blow-up: exit 1, the message last, the file readable
/// with its last good snapshot.
fn assert_blew_up(text: &str) {
    let dir = tempfile::tempdir().unwrap();
    let r = run_scenario(dir.path(), text, &[]);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    let last = r.stderr.trim_end().lines().last().unwrap_or("");
    assert!(
        last.starts_with("error: numerical blow-up at step ")
            && last.contains("try dt_s = ")
            && last.contains("last snapshot written to s.h5"),
        "{}",
        r.stderr
    );
    let info = floe_in(dir.path(), &["info", "s.h5"]);
    assert_eq!(info.code, Some(0), "{}", info.stderr);
    assert!(
        info.stdout.contains("stopped: numerical blow-up"),
        "{}",
        info.stdout
    );
}

// 1. Runs that go bad end with the blow-up message, not a crash.

#[test]
fn an_ocean_of_1e12_m_per_s_blows_up_cleanly() {
    assert_blew_up(&format!(
        "{SMALL}\n[ocean]\nvelocity_m_per_s = [-1e12, 1e12]\n"
    ));
}

#[test]
fn a_floe_at_10_km_per_s_blows_up_cleanly() {
    assert_blew_up(&edit(
        TWO_BOXES,
        "velocity_m_per_s = [1.0, 0.0]",
        "velocity_m_per_s = [10000.0, 0.0]",
    ));
}

#[test]
fn an_ocean_drag_coefficient_of_1e6_blows_up_cleanly() {
    assert_blew_up(&format!(
        "{TWO_BOXES}\n[ocean]\nvelocity_m_per_s = [0.1, 0.0]\ndrag_coefficient = 1e6\n"
    ));
}

// 2. Extra array elements are refused where they stand.

#[test]
fn arrays_of_the_wrong_length_are_refused_at_their_key() {
    let cases = [
        (
            SMALL,
            "size_m = [6000.0, 4000.0]",
            "size_m = [6000.0, 4000.0, 5.0]",
            "size_m",
        ),
        (
            SMALL,
            "size_m = [6000.0, 4000.0]",
            "size_m = [6000.0, 4000.0]\nmin_m = [0.0, 0.0, 1.0]",
            "min_m",
        ),
        (
            SMALL,
            "periodic = [true, false]",
            "periodic = [true, false, true]",
            "periodic",
        ),
        (
            SMALL,
            "velocity_m_per_s = [10.0, 0.0]",
            "velocity_m_per_s = [10.0, 0.0, 1.0]",
            "velocity_m_per_s",
        ),
        (
            TWO_BOXES,
            "box_m = [100.0, 100.0, 300.0, 300.0]",
            "box_m = [100.0, 100.0, 300.0, 300.0, 7.0]",
            "box_m",
        ),
        (
            TWO_BOXES,
            "box_m = [1000.0, 1000.0, 1200.0, 1200.0]",
            "vertices_m = [[1000.0, 1000.0, 3.0], [1200.0, 1000.0], [1100.0, 1200.0]]",
            "vertices_m",
        ),
    ];
    for (base, from, to, key) in cases {
        let text = edit(base, from, to);
        // Located at the value, after the last `key = `.
        let line = to.rsplit('\n').next().unwrap();
        let needle = &line[line.find("= ").unwrap() + 2..];
        assert_scenario_refused(&text, needle, key, &["invalid length"]);
    }
    let shear = edit(
        SMALL,
        "velocity_m_per_s = [10.0, 0.0]",
        "shear = { y_min_m = 0.0, y_max_m = 4000.0, velocity_at_y_min_m_per_s = [0.0, 0.0], velocity_at_y_max_m_per_s = [15.0, 0.0, 1.0] }",
    );
    let r = run_scenario(tempfile::tempdir().unwrap().path(), &shear, &[]);
    assert_refused(&r, "s.toml:17:112: `shear`", &["invalid length 3"]);
    let gyre = edit(
        SMALL,
        "velocity_m_per_s = [10.0, 0.0]",
        "gyre = { center_m = [3000.0, 2000.0, 0.0], core_radius_m = 500.0, max_speed_m_per_s = 1.0 }",
    );
    let r = run_scenario(tempfile::tempdir().unwrap().path(), &gyre, &[]);
    assert_refused(&r, "s.toml:17:21: `gyre`", &["invalid length 3"]);
    let range = edit(
        SMALL,
        "thickness_m = 1.0",
        "thickness_range_m = [1.0, 2.0, 3.0]",
    );
    assert_scenario_refused(
        &range,
        "[1.0, 2.0, 3.0]",
        "thickness_range_m",
        &["invalid length 3"],
    );
}

// 3. Every count of work is checked before the work starts.

#[test]
fn a_trillion_lloyd_iterations_are_refused() {
    let text = edit(
        SMALL,
        "kind = \"diamond\"\nside_m = 500.0",
        "kind = \"voronoi\"\ncount = 20\nrelax_iterations = 1000000000000",
    );
    assert_scenario_refused(
        &text,
        "1000000000000",
        "tessellation.relax_iterations",
        &["10000"],
    );
}

#[test]
fn walls_thicker_than_any_basin_are_refused() {
    let text = edit(
        SMALL,
        "side = \"bottom\"",
        "side = \"bottom\"\nthickness_m = 1e8",
    );
    assert_scenario_refused(
        &text,
        "1e8",
        "wall[0].thickness_m",
        &["thicker than the domain's larger side, 6000 m"],
    );
}

#[test]
fn a_run_of_more_steps_than_the_limit_is_refused_naming_dt_or_duration() {
    let tiny_dt = format!("dt_s = 1e-300\n{SMALL}");
    assert_scenario_refused(
        &tiny_dt,
        "1e-300",
        "dt_s",
        &["above the limit of 1e9", "--step-limit"],
    );
    let stiff = edit(
        &format!("{SMALL}\n[contact]\nyoungs_modulus_pa = 1e13\n"),
        "duration_s = 600.0",
        "duration_s = 6e7",
    );
    assert_scenario_refused(
        &stiff,
        "6e7",
        "duration_s",
        &["dt is automatic", "youngs_modulus_pa"],
    );
    let long = edit(SMALL, "duration_s = 600.0", "duration_s = 1e300");
    assert_scenario_refused(&long, "1e300", "duration_s", &["1e300 s"]);
    // The limit is the user's to raise: 1e-3 s steps over 600 s are 6e5.
    let dir = tempfile::tempdir().unwrap();
    let fine = format!("dt_s = 1e-3\n{SMALL}");
    let r = run_scenario(dir.path(), &fine, &["--step-limit", "1e5"]);
    assert_refused(
        &r,
        "s.toml:1:8: `dt_s`",
        &["600000 steps", "above the limit of 100000"],
    );
    let r = run_scenario(
        dir.path(),
        &fine,
        &["--step-limit", "1e6", "--max-steps", "3"],
    );
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}

#[test]
fn a_hundred_thousand_threads_are_refused() {
    let text = format!("threads = 100000\n{SMALL}");
    assert_scenario_refused(&text, "100000", "threads", &["from 1 to 1024"]);
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", SMALL);
    let r = floe_in(
        dir.path(),
        &["run", "s.toml", "-o", "s.h5", "--threads", "100000"],
    );
    assert_refused(&r, "--threads 100000", &["1024"]);
    let r = floe_in(
        dir.path(),
        &[
            "sweep",
            "s.toml",
            "--set",
            "seed=1,2",
            "-o",
            "sw",
            "--threads",
            "100000",
        ],
    );
    assert_refused(&r, "--threads 100000", &["1024"]);
    assert!(
        !dir.path().join("sw").exists(),
        "nothing written before the check"
    );
}

#[test]
fn slider_tests_longer_than_the_step_limit_are_refused_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 3] = [
        (
            &["slider", "hold", "--preset", "lab", "--hold", "1e12"],
            "--hold 1e12",
        ),
        (
            &[
                "slider", "hold", "--preset", "lab", "--hold", "1", "--dt", "1e-300",
            ],
            "--hold 1 at --dt 1e-300",
        ),
        (
            &[
                "slider", "step", "--preset", "tank", "--from", "1e-3", "--to", "1e-300",
            ],
            "--from 0.001 --to 1e-300",
        ),
    ];
    for (args, start) in cases {
        let r = floe_in(dir.path(), args);
        assert_refused(&r, start, &["above the limit of 1e9", "--step-limit"]);
    }
    let long = "[apparatus]\npreset = \"lab\"\n\n[law]\nkind = \"rate-state\"\n\n[[segment]]\nvelocity_m_per_s = 1e-4\nduration_s = 1e12\n";
    write(dir.path(), "p.toml", long);
    let r = floe_in(dir.path(), &["slider", "run", "p.toml", "--out", "o"]);
    assert_refused(&r, "p.toml:9:14: ", &["--step-limit"]);
    let fine = long
        .replace("1e12", "2")
        .replace("preset = \"lab\"", "preset = \"lab\"\ndt_s = 1e-300");
    write(dir.path(), "p.toml", &fine);
    let r = floe_in(dir.path(), &["slider", "run", "p.toml", "--out", "o"]);
    assert_refused(&r, "p.toml:3:8: ", &["dt_s", "--step-limit"]);
}

// 4. A closed or full standard output.

/// A small completed run in `dir`/s.h5.
fn small_run(dir: &Path) {
    let r = run_scenario(dir, SMALL, &["--max-steps", "20"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}

/// Runs `floe args` with its stdout a pipe closed before anything is read.
fn to_closed_pipe(dir: &Path, args: &[&str]) -> Option<i32> {
    let mut child = Command::new(FLOE)
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    out.status.code()
}

#[test]
fn output_to_a_closed_pipe_ends_quietly() {
    let dir = tempfile::tempdir().unwrap();
    small_run(dir.path());
    for args in [
        &["info", "s.h5"][..],
        &[
            "slider", "hold", "--preset", "lab", "--hold", "10", "--json",
        ],
        &[
            "slider", "step", "--preset", "lab", "--from", "1e-4", "--to", "1e-3",
        ],
        &["--help"],
    ] {
        let code = to_closed_pipe(dir.path(), args);
        assert!(matches!(code, Some(0) | Some(141)), "{args:?}: {code:?}");
    }
}

#[test]
fn output_to_a_full_device_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    small_run(dir.path());
    let full = std::fs::File::create("/dev/full").unwrap();
    let out = Command::new(FLOE)
        .args(["info", "s.h5"])
        .current_dir(dir.path())
        .stdout(full)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: cannot write to standard output"),
        "{stderr}"
    );
}

// 5. An output that is the input.

#[test]
fn a_run_never_overwrites_its_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = write(dir.path(), "s.toml", SMALL);
    std::os::unix::fs::symlink(&scenario, dir.path().join("link.h5")).unwrap();
    for (output, force) in [
        ("s.toml", true),
        ("s.toml", false),
        ("link.h5", true),
        ("./s.toml", true),
    ] {
        let mut args = vec!["run", "s.toml", "-o", output, "-q"];
        if force {
            args.push("--force");
        }
        let r = floe_in(dir.path(), &args);
        assert_eq!(r.code, Some(2), "{output}: {}", r.stderr);
        assert!(r.stderr.trim_end().lines().count() == 1, "{}", r.stderr);
        assert_eq!(
            std::fs::read_to_string(&scenario).unwrap(),
            SMALL,
            "{output}"
        );
    }
}

// 6. Files that are not UTF-8 text.

#[test]
fn files_that_are_not_text_are_located_and_recognised() {
    let dir = tempfile::tempdir().unwrap();
    small_run(dir.path());
    let mut latin1 = b"# caf\xe9\n".to_vec();
    latin1.extend_from_slice(SMALL.as_bytes());
    std::fs::write(dir.path().join("latin1.toml"), latin1).unwrap();
    let utf16: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(SMALL.encode_utf16().flat_map(u16::to_le_bytes))
        .collect();
    std::fs::write(dir.path().join("utf16.toml"), utf16).unwrap();
    std::fs::write(
        dir.path().join("gz.toml"),
        [0x1f, 0x8b, 0x08, 0x00, 0xff, 0x00],
    )
    .unwrap();
    std::fs::copy(dir.path().join("s.h5"), dir.path().join("h5.toml")).unwrap();
    let cases = [
        ("latin1.toml", "latin1.toml:1:6: ", "Latin-1"),
        ("utf16.toml", "utf16.toml:1:1: ", "UTF-16"),
        ("gz.toml", "gz.toml:1:1: ", "gzip"),
        ("h5.toml", "h5.toml:1:1: ", "floe info"),
    ];
    for (file, start, hint) in cases {
        let r = floe_in(dir.path(), &["run", file, "-o", "x.h5"]);
        assert_refused(&r, start, &[hint]);
        let r = floe_in(dir.path(), &["slider", "run", file, "--out", "o"]);
        assert_refused(&r, start, &[hint]);
    }
}

// 7. Messages name the key the user wrote, where it is, in short numbers.

#[test]
fn a_grid_of_a_trillion_columns_blames_columns() {
    let text = edit(
        SMALL,
        "kind = \"diamond\"\nside_m = 500.0",
        "kind = \"grid\"\ncolumns = 1000000000000\nrows = 2\ngap_m = 10.0",
    );
    assert_scenario_refused(&text, "1000000000000", "tessellation.columns", &[]);
}

#[test]
fn a_voronoi_count_above_the_cap_points_at_count() {
    let text = edit(
        SMALL,
        "kind = \"diamond\"\nside_m = 500.0",
        "kind = \"voronoi\"\ncount = 100000000000",
    );
    assert_scenario_refused(&text, "100000000000", "tessellation.count", &["10000000"]);
}

#[test]
fn absurd_thickness_is_blamed_on_its_key() {
    let text = edit(SMALL, "thickness_m = 1.0", "thickness_mean_m = 1e300");
    assert_scenario_refused(
        &text,
        "1e300",
        "ice.thickness_mean_m",
        &["1e300 m", "10000 m"],
    );
}

#[test]
fn a_key_of_fifty_thousand_parts_is_located_and_clipped() {
    let key = vec!["a"; 50_000].join(".");
    let text = format!("{SMALL}{key} = 1\n");
    let dir = tempfile::tempdir().unwrap();
    let r = run_scenario(dir.path(), &text, &[]);
    let line = SMALL.lines().count() + 1;
    assert_refused(&r, &format!("s.toml:{line}:1: "), &["nested too deep"]);
    assert!(r.stderr.len() < 1000, "{} bytes", r.stderr.len());
}

#[test]
fn a_float_where_a_count_goes_is_located() {
    let text = format!("threads = 1e12\n{SMALL}");
    assert_scenario_refused(&text, "1e12", "threads", &["expected an integer"]);
}

#[test]
fn huge_numbers_are_quoted_short() {
    let text = edit(
        SMALL,
        "size_m = [6000.0, 4000.0]",
        "size_m = [1e300, -1e300]",
    );
    assert_scenario_refused(&text, "[1e300", "domain.size_m", &["1e300"]);
    let dir = tempfile::tempdir().unwrap();
    let r = run_scenario(dir.path(), &text, &[]);
    assert!(!r.stderr.contains("0000000000"), "{}", r.stderr);
}

// 8. Readers of a running file: tests/cli/run.rs
//    (`floe_info_reads_a_file_while_a_run_writes_it`).

// 9. Every flag is checked before any work.

#[test]
fn bad_compare_flags_are_refused_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", SMALL);
    for (flag, value) in [
        ("--profile-bins", "0"),
        ("--slip-jump", "0"),
        ("--slip-jump", "1"),
        ("--slip-jump", "nan"),
        ("--slip-min-rate", "nan"),
        ("--slip-min-rate", "-1"),
        ("--reference-slip-speed", "inf"),
        ("--amontons-mu", "-0.5"),
    ] {
        let arg = format!("{flag}={value}");
        let r = floe_in(dir.path(), &["compare", "s.toml", "-o", "cmp", &arg]);
        assert_refused(&r, &format!("invalid value '{value}' for '{flag}"), &[]);
        assert!(
            !dir.path().join("cmp").exists(),
            "{flag} {value}: nothing written"
        );
    }
}

// 10. A sweep key given twice.

#[test]
fn a_sweep_key_set_twice_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", SMALL);
    let r = floe_in(
        dir.path(),
        &[
            "sweep",
            "s.toml",
            "--set",
            "duration_s=10.0",
            "--set",
            "duration_s=20.0",
            "-o",
            "sw",
        ],
    );
    assert_refused(
        &r,
        "--set duration_s: set twice",
        &["--set duration_s=10.0,20.0"],
    );
    let r = floe_in(
        dir.path(),
        &[
            "sweep",
            "s.toml",
            "--set",
            "wind.velocity_m_per_s=[1.0,0.0]",
            "--set",
            "wind={}",
            "-o",
            "sw",
        ],
    );
    assert_refused(&r, "--set wind: overlaps --set wind.velocity_m_per_s", &[]);
    assert!(!dir.path().join("sw").exists());
}

// 11. Resuming an edited file, a run that died, a full disk.

#[test]
fn a_stored_scenario_edited_after_the_start_is_refused_on_resume() {
    let dir = tempfile::tempdir().unwrap();
    let r = run_scenario(dir.path(), SMALL, &["--max-steps", "10"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    // Replace /parameters/scenario_toml with another scenario, as h5py would.
    let file = hdf5::File::open_rw(dir.path().join("s.h5")).unwrap();
    let g = file.group("parameters").unwrap();
    g.unlink("scenario_toml").unwrap();
    let other: hdf5::types::VarLenUnicode = edit(SMALL, "seed = 1", "seed = 2").parse().unwrap();
    g.new_dataset::<hdf5::types::VarLenUnicode>()
        .create("scenario_toml")
        .unwrap()
        .write_scalar(&other)
        .unwrap();
    drop((g, file));
    let r = floe_in(dir.path(), &["run", "--resume", "-o", "s.h5", "-q"]);
    assert_exit(&r, 1, "was changed after the run began");
}

#[test]
fn a_run_whose_process_died_is_reported_as_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let long = edit(SMALL, "duration_s = 600.0", "duration_s = 6e6").replace(
        "snapshot_every_s = 60.0",
        "snapshot_every_s = 6e4\ncheckpoint_every_s = 600.0",
    );
    write(dir.path(), "s.toml", &long);
    let mut child = Command::new(FLOE)
        .args(["run", "s.toml", "-o", "s.h5", "-q", "--threads", "1"])
        .current_dir(dir.path())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Wait for the first checkpoint, then kill as a second Ctrl-C would.
    let h5 = dir.path().join("s.h5");
    let waited = std::time::Instant::now();
    while !floe_in(dir.path(), &["info", "s.h5"])
        .stdout
        .contains("checkpoint   step")
    {
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        assert!(waited.elapsed().as_secs() < 120, "no checkpoint");
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let info = floe_in(dir.path(), &["info", "s.h5"]);
    assert!(
        info.stdout.contains("that process is gone"),
        "{}",
        info.stdout
    );
    // The suggested command, as printed (and a step budget after it).
    let start = info
        .stdout
        .find("`floe run --resume s.h5`")
        .expect("how to resume");
    let said = &info.stdout[start + 6..start + 6 + "run --resume s.h5".len()];
    let mut args: Vec<&str> = said.split_whitespace().collect();
    args.extend(["-q", "--max-steps", "5"]);
    let r = floe_in(dir.path(), &args);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert!(h5.exists());
}

/// What the run file at `path` holds (snapshots, contacts, observables),
/// printed exactly (`{:?}` of an f64 round-trips).
fn output_of(path: &Path) -> String {
    let run = floe_io::RunFile::open(path).unwrap();
    let mut out = String::new();
    for k in 0..run.snapshot_count().unwrap() {
        out += &format!(
            "{:?}\n{:?}\n",
            run.snapshot(k).unwrap(),
            run.contacts(k).unwrap()
        );
    }
    for name in run.observable_names().unwrap() {
        out += &format!("{name} {:?}\n", run.observable(&name).unwrap());
    }
    out
}

#[test]
fn a_file_size_limit_mid_run_is_one_line_and_the_run_resumes_bitwise() {
    let dir = tempfile::tempdir().unwrap();
    let long = edit(SMALL, "duration_s = 600.0", "duration_s = 20000.0").replace(
        "snapshot_every_s = 60.0",
        "snapshot_every_s = 20.0\ncheckpoint_every_s = 600.0",
    );
    write(dir.path(), "s.toml", &long);
    // `ulimit -f` (512-byte blocks) stops the file at 3 MB, a third of the
    // way: floe ignores SIGXFSZ, so the write fails with EFBIG as a full
    // disk fails with ENOSPC.
    let out = Command::new("sh")
        .args([
            "-c",
            &format!("ulimit -f 6000; exec {FLOE} run s.toml -o s.h5 -q --threads 1"),
        ])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    let last = stderr.trim_end().lines().last().unwrap();
    assert!(
        last.starts_with("error: s.h5: File too large (errno 27)")
            && last.contains("floe run --resume -o s.h5"),
        "{stderr}"
    );
    let info = floe_in(dir.path(), &["info", "s.h5"]);
    assert_eq!(
        info.code,
        Some(0),
        "the stopped file stays readable: {}",
        info.stderr
    );
    let r = floe_in(dir.path(), &["run", "--resume", "-o", "s.h5", "-q"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let r = floe_in(
        dir.path(),
        &["run", "s.toml", "-o", "clean.h5", "-q", "--threads", "1"],
    );
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let resumed = output_of(&dir.path().join("s.h5"));
    let clean = output_of(&dir.path().join("clean.h5"));
    assert!(clean.len() > 100_000, "{} bytes", clean.len());
    assert!(
        resumed == clean,
        "the resumed run's output differs from an uninterrupted one"
    );
}

// Found by tests/cli/fuzz.rs.

#[test]
fn a_wall_faster_than_any_basin_is_refused_at_its_velocity() {
    // Across the non-periodic y axis: 1e12 m/s over 600 s is beyond 100
    // domain sizes (the wall would be built that long).
    for v in ["1e12", "1e300"] {
        let text = edit(
            SMALL,
            "side = \"top\"",
            &format!("side = \"top\"\nvelocity_m_per_s = [0.1, {v}]"),
        );
        let needle = format!("[0.1, {v}]");
        let most = "more than 100 domain sizes (600000 m)";
        assert_scenario_refused(&text, &needle, "wall[1].velocity_m_per_s", &[most]);
    }
    // Along the periodic x axis a wall wraps: a year at 4 m/s is fine.
    let year = edit(SMALL, "duration_s = 600.0", "duration_s = 3.156e7").replace(
        "side = \"top\"",
        "side = \"top\"\nvelocity_m_per_s = [4.0, 0.0]",
    );
    let dir = tempfile::tempdir().unwrap();
    let r = run_scenario(dir.path(), &year, &["--max-steps", "2"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}

#[test]
fn slider_loads_speeds_and_steps_beyond_meaning_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &[
                "slider",
                "hold",
                "--preset",
                "lab",
                "--hold",
                "1",
                "--normal-load",
                "1e-300",
            ],
            "--normal-load",
        ),
        (
            &[
                "slider", "step", "--preset", "lab", "--from", "1e-4", "--to", "1e300",
            ],
            "--to",
        ),
        (
            &["slider", "hold", "--preset", "lab", "--dt", "1e300"],
            "--dt",
        ),
        (&["slider", "hold", "--preset", "lab", "--dt", "-1"], "--dt"),
    ];
    for (args, flag) in cases {
        let r = floe_in(dir.path(), args);
        assert_refused(&r, "invalid value", &[flag]);
    }
    let fast = "[apparatus]\npreset = \"lab\"\n\n[law]\nkind = \"rate-state\"\n\n[[segment]]\nvelocity_m_per_s = 1e300\nduration_s = 2\n";
    write(dir.path(), "p.toml", fast);
    let r = floe_in(dir.path(), &["slider", "run", "p.toml", "--out", "o"]);
    assert_refused(
        &r,
        "p.toml:8:20: `segment[0].velocity_m_per_s`",
        &["in [-100, 100] m/s"],
    );
}

#[test]
fn compare_checks_threads_and_the_matched_mu_before_writing_anything() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", SMALL);
    let r = floe_in(
        dir.path(),
        &["compare", "s.toml", "-o", "c", "--threads", "0", "-q"],
    );
    assert_refused(&r, "--threads must be at least 1", &[]);
    let r = floe_in(
        dir.path(),
        &[
            "compare",
            "s.toml",
            "-o",
            "c",
            "--reference-slip-speed",
            "1e-300",
            "-q",
        ],
    );
    assert_refused(
        &r,
        "--reference-slip-speed 1e-300",
        &["mu = 49.78", "--amontons-mu"],
    );
    let r = floe_in(
        dir.path(),
        &[
            "compare",
            "s.toml",
            "-o",
            "c",
            "--amontons-mu",
            "0.5",
            "--reference-slip-speed",
            "0.05",
        ],
    );
    assert_refused(
        &r,
        "the argument '--amontons-mu <MU>' cannot be used with",
        &[],
    );
    assert!(!dir.path().join("c").exists(), "nothing written");
}

#[test]
fn info_on_a_directory_or_a_missing_file_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let r = floe_in(dir.path(), &["info", "."]);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert_eq!(
        r.stderr.trim_end(),
        "error: .: is a directory, not a run file"
    );
    let r = floe_in(dir.path(), &["info", "missing.h5"]);
    assert_eq!(r.stderr.trim_end(), "error: missing.h5: no such file");
}

#[test]
fn friction_coefficients_and_prescribed_speeds_beyond_meaning_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let rate = "[apparatus]\npreset = \"lab\"\n\n[law]\nkind = \"rate-state\"\nmu0 = -1e300\n\n[[segment]]\nvelocity_m_per_s = 1e-4\nduration_s = 2\n";
    write(dir.path(), "p.toml", rate);
    let r = floe_in(dir.path(), &["slider", "run", "p.toml", "--out", "o"]);
    assert_refused(&r, "p.toml:6:7: `law.mu0`", &[">= 0 and <= 10"]);
    let pushed = edit(
        TWO_BOXES,
        "box_m = [1000.0, 1000.0, 1200.0, 1200.0]",
        "box_m = [1000.0, 1000.0, 1200.0, 1200.0]\nprescribed = true\nvelocity_m_per_s = [-1e300, 0.0]",
    );
    let most = "more than 100 domain sizes (300000 m)";
    assert_scenario_refused(&pushed, "[-1e300", "floe[1].velocity_m_per_s", &[most]);
}

// Found in review.

#[test]
fn a_closed_stderr_does_not_stop_a_run() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", SMALL);
    let mut child = Command::new(FLOE)
        .args(["run", "s.toml", "-o", "s.h5", "--threads", "1"])
        .current_dir(dir.path())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stderr.take());
    assert_eq!(child.wait().unwrap().code(), Some(0));
    let info = floe_in(dir.path(), &["info", "s.h5"]);
    assert!(
        info.stdout.contains("status       completed"),
        "{}",
        info.stdout
    );
}

#[test]
fn force_never_replaces_what_is_not_a_regular_file() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", SMALL);
    let fifo = dir.path().join("fifo");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    std::fs::create_dir(dir.path().join("d")).unwrap();
    for output in ["fifo", "d"] {
        let r = floe_in(
            dir.path(),
            &["run", "s.toml", "-o", output, "--force", "-q"],
        );
        assert_refused(
            &r,
            &format!("-o {output}: exists and is not a regular file"),
            &[],
        );
    }
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    let r = floe_in(
        dir.path(),
        &["run", "s.toml", "-o", "x.h5", "--max-steps", "0"],
    );
    assert_refused(&r, "invalid value '0' for '--max-steps", &[">= 1"]);
}

#[test]
fn compare_and_sweep_build_the_scenario_before_writing_anything() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "s.toml", &format!("dt_s = 10.0\n{SMALL}"));
    let r = floe_in(dir.path(), &["compare", "s.toml", "-o", "c", "-q"]);
    assert_refused(&r, "s.toml:1:8: `dt_s`", &["above the stable limit"]);
    assert!(!dir.path().join("c").exists());
    write(dir.path(), "s.toml", SMALL);
    let r = floe_in(
        dir.path(),
        &["sweep", "s.toml", "--set", "dt_s=0.1,10.0", "-o", "sw"],
    );
    assert_refused(&r, "s.toml with dt_s=10.0:", &["above the stable limit"]);
    assert!(!dir.path().join("sw").exists());
    let r = floe_in(
        dir.path(),
        &[
            "compare",
            "s.toml",
            "-o",
            "c",
            "--laws",
            "rate",
            "--amontons-mu",
            "0.5",
        ],
    );
    assert_refused(&r, "--amontons-mu applies to the amontons law", &[]);
    let r = floe_in(
        dir.path(),
        &["compare", "s.toml", "-o", "c", "--step-limit", "10", "-q"],
    );
    assert_refused(&r, "s.toml:2:14: `duration_s`", &["above the limit of 10"]);
}

#[test]
fn a_youngs_modulus_outside_what_contacts_can_be_is_refused() {
    for e in ["1e-300", "1e300"] {
        let text = format!("{SMALL}\n[contact]\nyoungs_modulus_pa = {e}\n");
        assert_scenario_refused(&text, e, "contact.youngs_modulus_pa", &["[1000, 1e13] Pa"]);
    }
}
