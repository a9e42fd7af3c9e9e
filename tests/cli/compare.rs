//! `floe compare` and `floe sweep` end to end on a small channel: the
//! variants differ in exactly what they should, the matched Amontons mu is
//! the rate-and-state steady state, the report and figures are written, a
//! parallel sweep gives the same files as runs made one by one, and an
//! emitted sweep is gathered.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use floe_friction::law::FrictionLaw;
use floe_friction::params::RateStateParams;
use floe_friction::rate_state::RateState;
use floe_friction::{Form, StateLaw};
use floe_io::RunFile;

const SMALL: &str = include_str!("../data/run_small.toml");

fn floe(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_floe"))
        .args(args)
        .output()
        .expect("floe runs")
}

fn ok(args: &[&str]) -> String {
    let out = floe(args);
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(0), "floe {args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    String::from_utf8_lossy(&out.stdout).to_string()
}

fn setup() -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("small.toml");
    std::fs::write(&scenario, SMALL).unwrap();
    let s = scenario.display().to_string();
    (dir, s)
}

fn table_without_friction(text: &str) -> toml::Table {
    let mut t: toml::Table = text.parse().unwrap();
    t.remove("friction");
    t
}

fn friction(file: &Path) -> toml::Table {
    let text = RunFile::open(file)
        .unwrap()
        .metadata()
        .unwrap()
        .scenario_toml;
    let t: toml::Table = text.parse().unwrap();
    t["friction"].as_table().unwrap().clone()
}

fn is_png(p: &Path) -> bool {
    std::fs::read(p).is_ok_and(|b| b.starts_with(b"\x89PNG\r\n\x1a\n"))
}

#[test]
fn compare_runs_the_same_ice_under_each_law() {
    let (dir, scenario) = setup();
    let out = dir.path().join("cmp");
    let o = out.display().to_string();
    ok(&[
        "compare",
        &scenario,
        "-o",
        &o,
        "--quiet",
        "--reference-slip-speed",
        "0.003",
    ]);

    // Only the friction table differs, and the initial floes are the same.
    let first = RunFile::open(&out.join("rate-state.h5")).unwrap();
    let base = table_without_friction(&first.metadata().unwrap().scenario_toml);
    let start = first.snapshot(0).unwrap();
    for law in ["amontons", "rate"] {
        let f = RunFile::open(&out.join(format!("{law}.h5"))).unwrap();
        assert_eq!(
            table_without_friction(&f.metadata().unwrap().scenario_toml),
            base,
            "{law}"
        );
        assert_eq!(f.snapshot(0).unwrap().position, start.position, "{law}");
        assert_eq!(f.status().unwrap(), "completed");
    }
    // ... and the laws did make a difference.
    let n = first.snapshot_count().unwrap();
    let end = first.snapshot(n - 1).unwrap();
    let other = RunFile::open(&out.join("amontons.h5"))
        .unwrap()
        .snapshot(n - 1)
        .unwrap();
    assert_ne!(end.position, other.position);

    // Amontons' mu: the rate-and-state steady state at 3 mm/s, computed here
    // from the law's definition (regularised form, the scenario's default).
    let reference = RateState {
        params: RateStateParams::lishman_2011_tank(),
        form: Form::Regularized,
        state_law: StateLaw::Slip,
    };
    let p = reference.params;
    let q = (0.003f64 / p.v_star_m_per_s).ln();
    let theta = -p.b * q;
    let by_hand = p.a * (0.5 * (q + (p.mu0 + theta) / p.a).exp()).asinh();
    assert!((reference.mu_steady(0.003) - by_hand).abs() < 1e-12);
    let mu = friction(&out.join("amontons.h5"))["mu"].as_float().unwrap();
    assert!((mu - by_hand).abs() < 1e-12, "{mu} against {by_hand}");
    let rate = friction(&out.join("rate.h5"));
    assert_eq!(rate["law"].as_str(), Some("rate"));
    assert!((rate["c1"].as_float().unwrap() - (p.a - p.b)).abs() < 1e-15);

    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for expected in [
        "| amontons |",
        "| rate |",
        "| rate-state |",
        "histories.png",
        "0.003 m/s",
    ] {
        assert!(
            report.contains(expected),
            "`{expected}` in report:\n{report}"
        );
    }
    // The report shows C1 = A - B to six significant digits (no
    // floating-point noise); the variant's scenario file keeps it exact.
    let c1 = p.a - p.b;
    let shown = format!("c1 = {}", (c1 * 1e6).round() / 1e6);
    assert!(
        report.contains(&format!("{shown}\n")),
        "`{shown}` in report:\n{report}"
    );
    let file: toml::Table = std::fs::read_to_string(out.join("rate.toml"))
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(file["friction"]["c1"].as_float(), Some(c1));
    for png in ["histories.png", "profile.png", "slip_events.png"] {
        assert!(is_png(&out.join(png)), "{png}");
    }
    let maps: Vec<PathBuf> = std::fs::read_dir(out.join("rate-state"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("floes_speed")
        })
        .collect();
    assert_eq!(maps.len(), 1);
    assert!(is_png(&maps[0]));

    // Again without --force: refused, nothing touched.
    let before = std::fs::read(out.join("report.md")).unwrap();
    let again = floe(&["compare", &scenario, "-o", &o, "--quiet"]);
    assert_eq!(again.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
    assert_eq!(std::fs::read(out.join("report.md")).unwrap(), before);
}

#[test]
fn compare_refuses_bad_options_clearly() {
    let (dir, scenario) = setup();
    let o = dir.path().join("x").display().to_string();
    for (args, expected) in [
        (vec!["--laws", "amontons,coulomb"], "coulomb"),
        (vec!["--laws", "rate,rate"], "twice"),
        (vec!["--reference-slip-speed=-1"], "reference-slip-speed"),
    ] {
        let mut all = vec!["compare", scenario.as_str(), "-o", o.as_str()];
        all.extend(args);
        let out = floe(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(expected), "`{expected}` in {err}");
        assert!(!err.contains("panicked"));
    }
}

#[test]
fn a_parallel_sweep_equals_runs_made_one_by_one() {
    let (dir, scenario) = setup();
    let out = dir.path().join("sweep");
    let o = out.display().to_string();
    let stdout = ok(&[
        "sweep",
        &scenario,
        "--set",
        "friction.a=0.30,0.34",
        "--set",
        "seed=3,4",
        "-o",
        &o,
        "--threads",
        "2",
    ]);
    assert!(stdout.contains("results.csv"), "{stdout}");
    let mut rows = csv::Reader::from_path(out.join("results.csv")).unwrap();
    let header = rows.headers().unwrap().clone();
    assert_eq!(&header[0], "variant");
    assert_eq!(&header[1], "friction.a");
    assert_eq!(&header[2], "seed");
    let rows: Vec<csv::StringRecord> = rows.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 4);
    assert_eq!((&rows[1][1], &rows[1][2]), ("0.30", "4"));
    for r in &rows {
        assert_eq!(&r[3], "completed", "{r:?}");
    }
    // results.csv is data: every digit. Variant 2's frictional dissipation
    // is its run's last observable, in MJ.
    let column = header
        .iter()
        .position(|h| h == "friction_dissipation_mj")
        .unwrap();
    let dissipation = RunFile::open(&out.join("variant_002.h5"))
        .unwrap()
        .observable("friction_dissipation")
        .unwrap();
    let last = *dissipation.value.last().unwrap();
    assert_eq!(rows[1][column].parse::<f64>().unwrap(), last * 1e-6);
    // results.md is for reading: the same number to four significant digits.
    let md = std::fs::read_to_string(out.join("results.md")).unwrap();
    let row = md
        .lines()
        .find(|l| l.starts_with("| variant_002 |"))
        .unwrap();
    let shown = row.split('|').map(str::trim).nth(column + 1).unwrap();
    let mantissa = shown.split('e').next().unwrap();
    let digits = mantissa
        .trim_start_matches(['-', '0', '.'])
        .replace('.', "");
    assert!(digits.len() <= 4, "{shown}");
    let relative = (shown.parse::<f64>().unwrap() / (last * 1e-6) - 1.0).abs();
    assert!(relative < 5e-4, "{shown} for {}", last * 1e-6);
    // variant_002: a = 0.30, seed = 4, as its scenario says.
    let text = std::fs::read_to_string(out.join("variant_002.toml")).unwrap();
    let t: toml::Table = text.parse().unwrap();
    assert_eq!(t["friction"]["a"].as_float(), Some(0.30));
    assert_eq!(t["seed"].as_integer(), Some(4));
    // The same variant run alone on two threads: bitwise the same states.
    let alone = dir.path().join("alone.h5");
    ok(&[
        "run",
        &out.join("variant_002.toml").display().to_string(),
        "-o",
        &alone.display().to_string(),
        "--threads",
        "2",
        "--quiet",
    ]);
    let (a, b) = (
        RunFile::open(&alone).unwrap(),
        RunFile::open(&out.join("variant_002.h5")).unwrap(),
    );
    let n = a.snapshot_count().unwrap();
    assert_eq!(n, b.snapshot_count().unwrap());
    let (sa, sb) = (a.snapshot(n - 1).unwrap(), b.snapshot(n - 1).unwrap());
    assert_eq!(sa.position, sb.position);
    assert_eq!(sa.velocity, sb.velocity);
    assert_eq!(
        a.contacts(n - 1).unwrap().theta,
        b.contacts(n - 1).unwrap().theta
    );
}

#[test]
fn an_emitted_sweep_is_gathered_from_whatever_ran() {
    let (dir, scenario) = setup();
    let out = dir.path().join("emit");
    let o = out.display().to_string();
    ok(&[
        "sweep",
        &scenario,
        "--set",
        "friction.critical_slip_m=0.001,0.005,0.02",
        "--emit",
        "-o",
        &o,
    ]);
    for k in 1..=3 {
        assert!(out.join(format!("variant_{k:03}.toml")).exists());
        assert!(!out.join(format!("variant_{k:03}.h5")).exists());
    }
    let script = std::fs::read_to_string(out.join("array.slurm")).unwrap();
    assert!(script.contains("#SBATCH --array=1-3"), "{script}");
    // Task 2 of the array began and was stopped at its time limit; its
    // resubmission runs array.slurm, which resumes it.
    ok(&[
        "run",
        &out.join("variant_002.toml").display().to_string(),
        "-o",
        &out.join("variant_002.h5").display().to_string(),
        "--quiet",
        "--max-steps",
        "10",
    ]);
    let bin = out.join("bin");
    std::fs::create_dir(&bin).unwrap();
    let floe_on_path = bin.join("floe");
    std::fs::write(
        &floe_on_path,
        format!("#!/bin/sh\nexec '{}' \"$@\"\n", env!("CARGO_BIN_EXE_floe")),
    )
    .unwrap();
    Command::new("chmod")
        .arg("+x")
        .arg(&floe_on_path)
        .status()
        .unwrap();
    let job = Command::new("bash")
        .arg(out.join("array.slurm"))
        .env(
            "PATH",
            format!("{}:{}", bin.display(), std::env::var("PATH").unwrap()),
        )
        .env("SLURM_SUBMIT_DIR", &out)
        .env("SLURM_ARRAY_TASK_ID", "2")
        .env("SLURM_CPUS_PER_TASK", "1")
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&job.stderr);
    assert_eq!(job.status.code(), Some(0), "{said}");
    assert!(
        said.contains("resum"),
        "the resubmitted task resumes: {said}"
    );
    ok(&["sweep", "--gather", "-o", &o]);
    let table = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let status: Vec<String> = csv::Reader::from_reader(table.as_bytes())
        .records()
        .map(|r| r.unwrap()[2].to_string())
        .collect();
    assert_eq!(status, ["missing", "completed", "missing"], "{table}");
    assert!(out.join("results.md").exists());
}

#[test]
fn a_sweep_over_a_bad_key_names_it() {
    let (dir, scenario) = setup();
    let o = dir.path().join("bad").display().to_string();
    for (set, expected) in [
        ("friction.nonsense=1,2", "nonsense"),
        ("ice.thickness_m=1.0,-1.0", "thickness_m"),
        ("friction.a", "KEY=VALUE"),
    ] {
        let out = floe(&["sweep", &scenario, "--set", set, "-o", &o]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{set}: {err}");
        assert!(err.contains(expected), "`{expected}` in {err}");
        assert!(!err.contains("panicked"));
    }
}

/// A scenario whose floes break: the report gives each law's floe count
/// and sizes at the start and the end (the fitted exponent when one fits),
/// and only then.
#[test]
fn compare_reports_the_floe_sizes_when_floes_break() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("breaks.toml");
    std::fs::write(&scenario, include_str!("../data/run_fracture.toml")).unwrap();
    let out = dir.path().join("cmp");
    let (s, o) = (scenario.display().to_string(), out.display().to_string());
    ok(&["compare", &s, "-o", &o, "--quiet"]);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let sizes = report
        .split("## Floe sizes")
        .nth(1)
        .expect("a size section");
    for law in ["amontons", "rate", "rate-state"] {
        let f = RunFile::open(&out.join(format!("{law}.h5"))).unwrap();
        let n = f.snapshot_count().unwrap();
        let free = |k: usize| {
            let floes = f.floes_at(k).unwrap();
            floes.prescribed.iter().filter(|p| !**p).count()
        };
        let row = format!("| {law} | {} -> {} |", free(0), free(n - 1));
        assert!(
            free(n - 1) > free(0) && sizes.contains(&row),
            "{row}\n{sizes}"
        );
    }
    // Floes that never break: no such section.
    let (dir2, small) = setup();
    let o2 = dir2.path().join("cmp").display().to_string();
    ok(&["compare", &small, "-o", &o2, "--quiet"]);
    let plain = std::fs::read_to_string(dir2.path().join("cmp/report.md")).unwrap();
    assert!(!plain.contains("## Floe sizes"));
}
