//! `floe pack-friction` on the shipped stepped cell
//! (`scenarios/shear_cell_wide_steps.toml`) with its schedule cut tenfold:
//! the events are where the schedule puts them, each reading is the
//! series' own numbers, the series is the runs' stresses summed over
//! seeds, the pack relaxes while the wall holds, and what the study
//! cannot read is refused before anything runs.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use floe_friction::LawRegistry;
use floe_io::RunFile;
use floe_run::run_file::{Provenance, Quiet};
use floe_scenario::law_variants::{LawChoice, Matching};
use floe_scenario::settings::parse_setting;
use floe_study::pack_friction::{pack_friction, EventKind, PackFrictionArgs, Schedule};
use floe_study::rheology::Mode;

use crate::table::csv_rows;

fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name)
}

fn args(scenario: PathBuf, out: &Path) -> PackFrictionArgs {
    PackFrictionArgs {
        scenario,
        settings: Vec::new(),
        laws: LawChoice::parse_list("amontons,rate-state", &LawRegistry::builtin()).unwrap(),
        seeds: vec![1, 2],
        sample_every_s: 10.0,
        out_dir: out.to_path_buf(),
        threads: Some(2),
        force: false,
        mode: Mode::Run,
        matching: Matching {
            reference_slip_m_per_s: 1e-2,
            amontons_mu: None,
        },
        provenance: Provenance::of_this_process("test"),
        registry: LawRegistry::builtin(),
        step_limit: floe_scenario::MAX_RUN_STEPS,
        linear_start: true,
    }
}

/// The shipped stepped cell with every segment a tenth as long, in `dir`.
fn reduced_cell(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(shipped("shear_cell_wide_steps.toml")).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        match line.strip_prefix("duration_s = ") {
            Some(v) => out.push_str(&format!(
                "duration_s = {:?}\n",
                v.parse::<f64>().unwrap() / 10.0
            )),
            None => out.push_str(&format!("{line}\n")),
        }
    }
    let path = dir.join("steps.toml");
    std::fs::write(&path, out).unwrap();
    path
}

fn num(row: &HashMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key}: {:?}", row[key]))
}

#[test]
fn the_shipped_schedule_has_four_steps_and_three_holds_where_it_says() {
    let scenario = floe_scenario::Scenario::load(&shipped("shear_cell_wide_steps.toml")).unwrap();
    let segments = scenario.wall_schedule("top").unwrap().segments();
    let schedule = Schedule::new(segments).unwrap();
    let kinds: Vec<(f64, EventKind)> = schedule.events().iter().map(|e| (e.at_s, e.kind)).collect();
    let step = |from, to| EventKind::Step { from, to };
    let hold = |hold_s| EventKind::Hold { hold_s, speed: 1.5 };
    assert_eq!(
        kinds,
        vec![
            (16000.0, step(1.5, 4.5)),
            (18700.0, step(4.5, 1.5)),
            (26700.0, step(1.5, 0.5)),
            (42700.0, step(0.5, 1.5)),
            (50800.0, hold(100.0)),
            (59800.0, hold(1000.0)),
            (77800.0, hold(10000.0)),
        ]
    );
    assert_eq!(schedule.duration_s(), 85800.0);
    // The wall's travel in each sliding segment: 8 to 24 km.
    for s in segments.iter().filter(|s| s.velocity_start.x > 0.0) {
        let (d, v) = (s.duration_s, s.velocity_start.x);
        assert!((8000.0..=24000.0).contains(&(d * v)), "{d} s at {v} m/s");
    }
}

#[test]
fn the_reduced_study_reads_each_event_from_the_runs_own_stresses() {
    let dir = tempfile::tempdir().unwrap();
    let cell = reduced_cell(dir.path());
    let out = dir.path().join("out");
    let a = args(cell, &out);
    let report = pack_friction(&a, &Quiet).unwrap();
    assert!(report.exists() && out.join("pack_friction.png").exists());

    // series.csv: each law's friction is its seeds' summed shear stress
    // over their summed pressure, read here from the run files.
    let series = csv_rows(&out.join("series.csv"));
    assert_eq!(series.len(), 859);
    for law in ["amontons", "rate-state"] {
        let stress: Vec<_> = [1, 2]
            .iter()
            .map(|s| {
                RunFile::open(&out.join(format!("{law}_s{s}.h5")))
                    .unwrap()
                    .observable("mean_stress")
                    .unwrap()
            })
            .collect();
        let mut checked = 0;
        for row in series.iter().skip(1).step_by(50) {
            let t = num(row, "t_s");
            // Each run's stress at t, between the samples either side.
            let at = |s: &floe_io::Series, k: usize| -> f64 {
                let j = s
                    .time_s
                    .iter()
                    .position(|&x| x > t)
                    .unwrap_or(s.time_s.len() - 1);
                let (t0, t1) = (s.time_s[j - 1], s.time_s[j]);
                let w = ((t - t0) / (t1 - t0)).min(1.0);
                (1.0 - w) * s.value[4 * (j - 1) + k] + w * s.value[4 * j + k]
            };
            let tau: f64 = stress.iter().map(|s| 0.5 * (at(s, 1) + at(s, 2))).sum();
            let p: f64 = stress.iter().map(|s| -at(s, 3)).sum();
            let mu = num(row, &format!("{law}_mu"));
            if p == 0.0 {
                // No contact yet in the loose start: 0 / 0.
                assert!(mu.is_nan());
                continue;
            }
            assert!(
                (mu - tau / p).abs() < 1e-9 * (tau / p).abs(),
                "{law} at {t} s: {mu} against {}",
                tau / p
            );
            checked += 1;
        }
        assert!(checked > 10, "{law}: {checked} times checked");
    }

    // events.csv: the mean row of each hold is the series' mean over the
    // last half of the segment before it and the peak of the first half
    // of the reslide.
    let events = csv_rows(&out.join("events.csv"));
    assert_eq!(events.len(), 2 * 3 * 7);
    let mu_at = |law: &str, from: f64, to: f64| -> Vec<f64> {
        series
            .iter()
            .filter(|r| num(r, "t_s") > from && num(r, "t_s") <= to)
            .map(|r| num(r, &format!("{law}_mu")))
            .collect()
    };
    for e in events
        .iter()
        .filter(|e| e["seed"] == "mean" && e["kind"] == "hold")
    {
        let law = e["law"].as_str();
        let (at, hold) = (num(e, "at_s"), num(e, "hold_s"));
        // Before: the last half of the 800 s slide ending where the hold starts.
        let start = at - hold;
        let before = {
            let v: Vec<f64> = series
                .iter()
                .filter(|r| (start - 400.0..=start).contains(&num(r, "t_s")))
                .map(|r| num(r, &format!("{law}_mu")))
                .collect();
            v.iter().sum::<f64>() / v.len() as f64
        };
        assert!((num(e, "before") - before).abs() < 1e-12, "{e:?}");
        let peak = mu_at(law, at, at + 400.0)
            .into_iter()
            .fold(f64::NEG_INFINITY, f64::max);
        assert!((num(e, "healing") - (peak - before)).abs() < 1e-12, "{e:?}");
        // While the wall holds, the sheared pack relaxes: at the end of
        // the longest hold its friction is below the sliding friction.
        if hold == 1000.0 {
            let end = series.iter().position(|r| num(r, "t_s") == at).unwrap();
            assert!(
                num(&series[end], &format!("{law}_mu")) < 0.9 * before,
                "{law}: {:?}",
                series[end]
            );
        }
    }
    // A step's mean row: before over the last half of the segment before,
    // the new steady friction over the last half of the new one.
    let mean_of = |law: &str, from: f64, to: f64| -> f64 {
        let v: Vec<f64> = series
            .iter()
            .filter(|r| (from..=to).contains(&num(r, "t_s")))
            .map(|r| num(r, &format!("{law}_mu")))
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    // The reduced schedule's steps: (at, length of the segment before, of the one after).
    let steps = [
        (1600.0, 1600.0, 270.0),
        (1870.0, 270.0, 800.0),
        (2670.0, 800.0, 1600.0),
        (4270.0, 1600.0, 800.0),
    ];
    for e in events
        .iter()
        .filter(|e| e["seed"] == "mean" && e["kind"] == "step")
    {
        let law = e["law"].as_str();
        let at = num(e, "at_s");
        let &(_, d0, d1) = steps
            .iter()
            .find(|s| s.0 == at)
            .expect("a step of the schedule");
        let before = mean_of(law, at - d0 / 2.0, at);
        let after = mean_of(law, at + d1 / 2.0, at + d1);
        assert!((num(e, "before") - before).abs() < 1e-12, "{e:?}");
        assert!((num(e, "after") - after).abs() < 1e-12, "{e:?}");
        let ln = (num(e, "to_m_per_s") / num(e, "from_m_per_s")).ln();
        assert!((num(e, "steady_per_ln") - (after - before) / ln).abs() < 1e-12);
    }
    let md = std::fs::read_to_string(report).unwrap();
    assert!(md.contains("## Velocity steps") && md.contains("## Holds"));
    assert!(md.contains("a = A = 0.31"), "the contact law's own values");
}

#[test]
fn what_the_study_cannot_read_is_refused_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let fails = |a: &PackFrictionArgs| pack_friction(a, &Quiet).unwrap_err().to_string();
    // A cell whose wall slides at one speed.
    let message = fails(&args(shipped("shear_cell_wide.toml"), &out));
    assert!(
        message.contains("shear_cell_wide.toml") && message.contains("schedule"),
        "{message}"
    );
    // A ramp.
    let ramp = dir.path().join("ramp.toml");
    let text = std::fs::read_to_string(shipped("shear_cell_wide_steps.toml"))
        .unwrap()
        .replacen(
            "velocity_m_per_s = [4.5, 0.0]",
            "velocity_m_per_s = [4.5, 0.0]\nend_velocity_m_per_s = [3.0, 0.0]",
            1,
        );
    std::fs::write(&ramp, text).unwrap();
    assert!(fails(&args(ramp, &out)).contains("ramp"));
    // A hold that resumes at another speed hides a step inside the healing.
    let other = dir.path().join("other.toml");
    let text = std::fs::read_to_string(shipped("shear_cell_wide_steps.toml")).unwrap();
    let hold = text.find("# hold 100 s").unwrap();
    let resume = hold + text[hold..].find("velocity_m_per_s = [1.5, 0.0]").unwrap();
    let text = format!(
        "{}velocity_m_per_s = [3.0, 0.0]{}",
        &text[..resume],
        &text[resume + 29..]
    );
    std::fs::write(&other, text).unwrap();
    assert!(fails(&args(other, &out)).contains("resumes at its speed"));
    // Keys the study sets itself, and a bad spacing.
    let mut a = args(shipped("shear_cell_wide_steps.toml"), &out);
    a.settings = vec![parse_setting("seed=4").unwrap()];
    assert!(fails(&a).contains("--set seed"));
    let mut a = args(shipped("shear_cell_wide_steps.toml"), &out);
    a.sample_every_s = 0.0;
    assert!(fails(&a).contains("--sample-every"));
    let mut a = args(shipped("shear_cell_wide_steps.toml"), &out);
    a.seeds = vec![3, 3];
    assert!(fails(&a).contains("twice"));
    assert!(!out.exists(), "nothing written");
}
