//! `floe rheology` on the shipped shear cell (`scenarios/shear_cell.toml`):
//! the stress the ice puts on the walls and the stress inside the layer
//! from the Love-Weber sum of the contacts (plus the momentum flux of the
//! floes' fluctuations) are two independent measures of the same stress
//! and agree; the layer's friction is the contacts' Amontons coefficient
//! or above; three speeds are too few for the three-parameter `mu(I)` fit.

use std::path::Path;

use floe_friction::LawRegistry;
use floe_run::run_file::{Provenance, Quiet};
use floe_scenario::law_variants::{LawChoice, Matching};
use floe_study::rheology::{rheology, Mode, RheologyArgs};

use crate::table::csv_rows;

/// The laws `names` (comma-separated), as `--laws` names them.
fn laws(names: &str) -> Vec<LawChoice> {
    LawChoice::parse_list(names, &LawRegistry::builtin()).unwrap()
}

fn args(out: &Path, laws: Vec<LawChoice>, speeds: Vec<f64>) -> RheologyArgs {
    RheologyArgs {
        scenario: Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shear_cell.toml"),
        laws,
        speeds_m_per_s: speeds,
        seeds: Vec::new(),
        settings: Vec::new(),
        strain: 3.0,
        snapshots: 150,
        transient_fraction: 1.0 / 3.0,
        out_dir: out.to_path_buf(),
        threads: Some(2),
        force: false,
        mode: Mode::Run,
        matching: Matching {
            reference_slip_m_per_s: 1e-2,
            amontons_mu: Some(0.4),
        },
        provenance: Provenance::of_this_process("test"),
        registry: LawRegistry::builtin(),
        step_limit: floe_scenario::MAX_RUN_STEPS,
        linear_start: false,
    }
}

/// `results.csv` as rows of (column -> value).
fn results(dir: &Path) -> Vec<std::collections::HashMap<String, String>> {
    csv_rows(&dir.join("results.csv"))
}

/// `over_seeds.csv` as rows of (column -> value).
fn seed_rows(dir: &Path) -> Vec<std::collections::HashMap<String, String>> {
    csv_rows(&dir.join("over_seeds.csv"))
}

#[test]
fn wall_and_contact_stresses_agree() {
    let dir = tempfile::tempdir().unwrap();
    let report = rheology(
        &args(dir.path(), laws("amontons"), vec![0.5, 1.0, 2.0]),
        &Quiet,
    )
    .unwrap();
    assert!(report.exists());
    assert!(dir.path().join("rheology.png").exists());
    let rows = results(dir.path());
    assert_eq!(rows.len(), 3);
    let mut inertial = Vec::new();
    for row in &rows {
        let get = |k: &str| row[k].parse::<f64>().unwrap();
        let (pw, pb) = (
            get("wall_normal_stress_n_per_m"),
            get("bulk_normal_stress_n_per_m"),
        );
        let (tw, tb) = (
            get("wall_shear_stress_n_per_m"),
            get("bulk_shear_stress_n_per_m"),
        );
        let (mu, mu_err) = (get("mu"), get("mu_error"));
        eprintln!(
            "v = {} m/s: I = {:.3e}, P wall {pw:.0} bulk {pb:.0} (+- {:.0}), tau wall {tw:.0} bulk {tb:.0}, mu {mu:.3} +- {mu_err:.3}, solid fraction {:.3}",
            row["speed_m_per_s"],
            get("inertial_number"),
            get("wall_normal_stress_error"),
            get("solid_fraction"),
        );
        // Two measures of one stress.
        assert!((pw - pb).abs() < 0.03 * pw, "P: wall {pw}, bulk {pb}");
        assert!((tw - tb).abs() < 0.06 * tw, "tau: wall {tw}, bulk {tb}");
        // A layer of Amontons contacts cannot slide with less friction
        // than its contacts (mu = 0.4): interlocking only adds.
        assert!(mu > 0.4 - 2.0 * mu_err, "mu = {mu} +- {mu_err}");
        assert!(get("solid_fraction") < 1.0 && get("solid_fraction") > 0.5);
        inertial.push(get("inertial_number"));
    }
    // I grows with the wall speed.
    assert!(inertial.windows(2).all(|w| w[1] > w[0]), "{inertial:?}");
    let md = std::fs::read_to_string(&report).unwrap();
    assert!(md.contains("| amontons | "), "{md}");
    assert!(md.contains("| amontons | | | | needs four speeds"), "{md}");

    // Measuring the same runs again (--gather) gives the same table.
    let before = std::fs::read_to_string(dir.path().join("results.csv")).unwrap();
    let mut gather = args(dir.path(), laws("amontons"), vec![0.5, 1.0, 2.0]);
    gather.mode = Mode::Gather;
    rheology(&gather, &Quiet).unwrap();
    let after = std::fs::read_to_string(dir.path().join("results.csv")).unwrap();
    assert_eq!(before, after);
    // A speed that was not run is not there to gather.
    gather.speeds_m_per_s = vec![0.5, 0.7];
    let e = rheology(&gather, &Quiet).unwrap_err().to_string();
    assert!(e.contains("amontons_v0.7.h5: not there to gather"), "{e}");
}

#[test]
fn emit_writes_the_scenario_files_and_runs_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons,rate-state"), vec![0.1, 1.0]);
    a.mode = Mode::Emit;
    rheology(&a, &Quiet).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "amontons_v0.1.toml",
            "amontons_v1.toml",
            "rate-state_v0.1.toml",
            "rate-state_v1.toml"
        ]
    );
    // Each file shears at its speed for the set strain (3 x 5000 m / v).
    let text = std::fs::read_to_string(dir.path().join("rate-state_v0.1.toml")).unwrap();
    let s = floe_scenario::Scenario::from_text(&text, Path::new("x.toml")).unwrap();
    assert_eq!(s.duration_s(), 3.0 * 5000.0 / 0.1);
    assert!(text.contains("velocity_m_per_s = [0.1, 0.0]"), "{text}");
}

#[test]
fn a_scenario_that_is_not_a_shear_cell_is_refused_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons"), vec![0.5]);
    a.scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/free_drift.toml");
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(e.contains("not a shear cell"), "{e}");
    let mut a = args(dir.path(), laws("amontons"), vec![0.5, -1.0]);
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(e.contains("--speeds -1"), "{e}");
    a.speeds_m_per_s = vec![0.5];
    a.strain = 0.0;
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(e.contains("--strain"), "{e}");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing written"
    );
}

#[test]
fn seeds_make_different_packs_and_their_mean_carries_a_t_interval() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons"), vec![2.0]);
    a.seeds = vec![1, 2, 3];
    a.strain = 2.0;
    a.snapshots = 64;
    rheology(&a, &Quiet).unwrap();
    let rows = results(dir.path());
    assert_eq!(rows.len(), 3);
    let seeds: Vec<&str> = rows.iter().map(|r| r["seed"].as_str()).collect();
    assert_eq!(seeds, ["1", "2", "3"]);
    // Each seed draws its own tessellation, so its own steady state.
    let mu: Vec<f64> = rows.iter().map(|r| r["mu"].parse().unwrap()).collect();
    assert!(mu[0] != mu[1] && mu[1] != mu[2], "{mu:?}");
    // The mean over seeds and its 95 % interval, recomputed here from the
    // runs' own values: t(0.975, 2) = 4.3027.
    let mean = mu.iter().sum::<f64>() / 3.0;
    let s = (mu.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / 2.0).sqrt();
    let point = &seed_rows(dir.path())[0];
    let got = |k: &str| point[k].parse::<f64>().unwrap();
    assert_eq!(point["runs"], "3");
    assert!((got("mu") - mean).abs() < 1e-12, "{} {mean}", got("mu"));
    let ci = 4.3027 * s / 3f64.sqrt();
    assert!(
        (got("mu_ci95") - ci).abs() < 1e-4 * ci,
        "{} {ci}",
        got("mu_ci95")
    );
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(md.contains("## Means over seeds"), "{md}");
    assert!(dir.path().join("amontons_v2_s3.h5").exists());
    assert_eq!(
        point["mu_less_first_law_paired"], "",
        "the first law has no pair"
    );
}

#[test]
fn a_second_law_is_compared_with_the_first_seed_by_seed() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons,rate-state"), vec![2.0]);
    a.seeds = vec![1, 2, 3];
    a.strain = 1.0;
    a.snapshots = 32;
    rheology(&a, &Quiet).unwrap();
    let rows = results(dir.path());
    let mu = |law: &str, seed: &str| -> f64 {
        rows.iter()
            .find(|r| r["law"] == law && r["seed"] == seed)
            .unwrap()["mu"]
            .parse()
            .unwrap()
    };
    // The differences recomputed here, pair by pair, from the runs' values.
    let d: Vec<f64> = ["1", "2", "3"]
        .iter()
        .map(|s| mu("rate-state", s) - mu("amontons", s))
        .collect();
    let mean = d.iter().sum::<f64>() / 3.0;
    let sd = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 2.0).sqrt();
    let second = seed_rows(dir.path())
        .into_iter()
        .find(|r| r["law"] == "rate-state")
        .unwrap();
    let got = |k: &str| second[k].parse::<f64>().unwrap();
    assert!((got("mu_less_first_law_paired") - mean).abs() < 1e-12);
    let ci = 4.3027 * sd / 3f64.sqrt();
    assert!((got("mu_less_first_law_paired_ci95") - ci).abs() < 1e-4 * ci.max(1e-12));
}

#[test]
fn set_and_seeds_reach_every_emitted_run() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons"), vec![0.5, 1.0]);
    a.mode = Mode::Emit;
    a.seeds = vec![1, 9];
    a.settings =
        vec![floe_scenario::settings::parse_setting("contact.youngs_modulus_pa=6e7").unwrap()];
    rheology(&a, &Quiet).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "amontons_v0.5_s1.toml",
            "amontons_v0.5_s9.toml",
            "amontons_v1_s1.toml",
            "amontons_v1_s9.toml"
        ]
    );
    let shipped = floe_scenario::Scenario::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shear_cell.toml"),
    )
    .unwrap();
    let text = std::fs::read_to_string(dir.path().join("amontons_v1_s9.toml")).unwrap();
    assert!(text.contains("seed = 9"), "{text}");
    // Ten times the stiffness, the same floes (seed 1, the shipped file's):
    // the automatic step is sqrt(10) times shorter.
    let text = std::fs::read_to_string(dir.path().join("amontons_v1_s1.toml")).unwrap();
    let s = floe_scenario::Scenario::from_text(&text, Path::new("x.toml")).unwrap();
    let ratio = shipped.time_step().unwrap() / s.time_step().unwrap();
    assert!((ratio - 10f64.sqrt()).abs() < 1e-9, "dt ratio {ratio}");
    // A key given twice or with several values is refused before anything is written.
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons"), vec![0.5]);
    a.settings = vec![floe_scenario::settings::parse_setting("dt_s=0.1,0.2").unwrap()];
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(e.contains("--set dt_s: one value per key"), "{e}");
    // A key the scenario does not take is blamed on the flag that set it.
    a.settings = vec![floe_scenario::settings::parse_setting("contact.youngs=0.1").unwrap()];
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(
        e.contains("shear_cell.toml with --set contact.youngs=0.1:") && e.contains("unknown field"),
        "{e}"
    );
    // Keys floe rheology sets itself would be overridden: refused.
    a.settings = vec![floe_scenario::settings::parse_setting("duration_s=10.0").unwrap()];
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(
        e.contains("--set duration_s: floe rheology sets this key itself"),
        "{e}"
    );
    a.settings.clear();
    a.seeds = vec![u64::MAX];
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(
        e.contains("--seeds 18446744073709551615: seeds from 0 to"),
        "{e}"
    );
    a.seeds = vec![3, 3];
    let e = rheology(&a, &Quiet).unwrap_err().to_string();
    assert!(e.contains("--seeds: a seed is given twice"), "{e}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_linear_start_gives_every_free_floe_the_cells_shear_profile() {
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons"), vec![2.0]);
    a.mode = Mode::Emit;
    a.linear_start = true;
    rheology(&a, &Quiet).unwrap();
    let text = std::fs::read_to_string(dir.path().join("amontons_v2.toml")).unwrap();
    // The top wall's speed over the domain height (5 km).
    assert!(text.contains("initial_shear_rate_per_s = 0.0004"), "{text}");
    let s = floe_scenario::Scenario::from_text(&text, Path::new("x.toml")).unwrap();
    let w = s.build().unwrap().world;
    let f = w.floes().columns();
    let mut free = 0;
    for i in (0..f.len()).filter(|&i| f.is_free(i)) {
        // u = 2 m/s x y / 5000 m at the centroid; no spin, no v.
        let expected = 2.0 * f.position[i].y / 5000.0;
        let u = f.velocity[i];
        assert!(
            (u.x - expected).abs() < 1e-12,
            "floe {i}: {u:?} against {expected}"
        );
        assert_eq!(u.y, 0.0);
        free += 1;
    }
    assert!(free > 100, "{free} free floes");
}

#[test]
fn the_wide_cell_study_reduced_shears_homogeneously_from_its_linear_start() {
    // The study of docs/studies/shear-cell.md on its shipped cell, cut to
    // a strain of 0.3 and two seeds: the linear start gives a shear rate
    // across the layer equal to the walls' from the first snapshots, and
    // the servo wall holds its 2 kN/m while the loose pack compacts (the
    // fixed wall feels it later: at this strain the layer is not steady).
    let dir = tempfile::tempdir().unwrap();
    let mut a = args(dir.path(), laws("amontons,rate-state"), vec![5.0]);
    a.scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/shear_cell_wide.toml");
    a.seeds = vec![1, 2];
    a.strain = 0.3;
    a.snapshots = 24;
    a.linear_start = true;
    rheology(&a, &Quiet).unwrap();
    let rows = results(dir.path());
    assert_eq!(rows.len(), 4);
    for row in &rows {
        let get = |k: &str| row[k].parse::<f64>().unwrap();
        let (fit, walls) = (get("shear_rate_per_s"), get("wall_shear_rate_per_s"));
        assert!((fit / walls - 1.0).abs() < 0.2, "{row:?}");
        let servo = get("top_wall_normal_stress_n_per_m");
        assert!((servo - 2000.0).abs() < 300.0, "{row:?}");
    }
    let points = seed_rows(dir.path());
    assert_eq!(points.len(), 2);
    assert!(!points[1]["mu_less_first_law_paired"].is_empty());
}
