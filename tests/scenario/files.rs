//! The shipped scenario files (`scenarios/*.toml`): every one loads and
//! builds, and the cheap physics checks hold: free drift reaches the
//! analytic velocity, the double-shear set-ups carry the intended normal
//! load and slide at the law's steady friction.

use std::path::{Path, PathBuf};

use floe_dem::floes::Motion;
use floe_dem::forcing::{free_drift_velocity, DragParameters};
use floe_dem::Vec2;
use floe_friction::FrictionLaw;
use floe_scenario::{checks, Scenario};

use crate::pool_support;
use pool_support::pooled;

fn scenario_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

fn scenario(name: &str) -> Scenario {
    let path = scenario_dir().join(name);
    Scenario::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_scenario_file_loads_and_builds() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenario_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for expected in [
        "demo.toml",
        "shear_zone.toml",
        "lab_double_shear.toml",
        "tank_double_shear.toml",
        "free_drift.toml",
        "uniaxial_compression.toml",
    ] {
        assert!(names.iter().any(|n| n == expected), "{expected} missing");
    }
    for path in &files {
        let s = Scenario::load(path).unwrap_or_else(|e| panic!("{e}"));
        let setup = s.build().unwrap_or_else(|e| panic!("{e}"));
        let w = &setup.world;
        assert!(!w.floes().is_empty(), "{}: no floes", path.display());
        assert!(setup.dt_s > 0.0 && setup.dt_s <= setup.stable_limit_s);
        assert_eq!(w.dt_s(), setup.dt_s);
        assert!(!setup.report.is_empty());
        assert!(s.title().is_some(), "{}: give a title", path.display());
        // Resuming uses the same model, forcing, periodicity and dt.
        let parts = s.engine_parts();
        assert_eq!(s.time_step().unwrap().to_bits(), setup.dt_s.to_bits());
        assert_eq!(&parts.model, w.model());
        assert_eq!(&parts.forcing, w.forcing());
        assert_eq!(parts.periodicity, w.periodicity());
        // The text is kept verbatim (it is stored in the output file).
        assert_eq!(s.text(), std::fs::read_to_string(path).unwrap());
        let out = s.output();
        assert!(out.snapshot_every_s > 0.0 && out.observables_every_s > 0.0);
        // Building is deterministic.
        let again = s.build().unwrap().world;
        assert_eq!(again.floes(), w.floes(), "{}", path.display());
    }
}

#[test]
fn free_drift_reaches_the_analytic_velocity() {
    pooled(free_drift)
}

fn free_drift() {
    let s = scenario("free_drift.toml");
    let mut w = s.build().unwrap().world;
    // The file's parameters, written out independently of the reader.
    let ocean = DragParameters {
        turning_angle_deg: 20.0,
        ..DragParameters::ocean()
    };
    let f = 2.0 * floe_dem::forcing::EARTH_ROTATION_RATE_RAD_PER_S * 75f64.to_radians().sin();
    let rho_h = 917.0 * 2.0;
    let expected = free_drift_velocity(
        Vec2::new(10.0, 0.0),
        Vec2::ZERO,
        &DragParameters::air(),
        &ocean,
        f,
        rho_h,
        true,
    )
    .unwrap();
    let from_forcing = w
        .forcing()
        .free_drift_velocity_at(0.0, w.floes().position[0], rho_h)
        .unwrap();
    assert!((from_forcing - expected).length() < 1e-12 * expected.length());
    // Turned to the right of the wind, and about 1.5 % of its speed.
    assert!(expected.y < 0.0 && (0.01..0.02).contains(&(expected.length() / 10.0)));
    // Two days of stepping: inertial oscillations have decayed.
    let steps = (2.0 * 86400.0 / w.dt_s()) as usize;
    for _ in 0..steps {
        w.step();
    }
    assert!(w.contacts().is_empty());
    for i in 0..w.floes().len() {
        let err = (w.floes().velocity[i] - expected).length() / expected.length();
        assert!(
            err < 1e-3,
            "floe {i}: {:?} vs {expected:?}",
            w.floes().velocity[i]
        );
    }
}

/// The double-shear set-up's side contacts carry the file's load, and after
/// the push the block slides at the push speed with the law's steady
/// friction, the pusher carrying twice the friction force.
fn double_shear(name: &str, load: f64, speed: f64, run_s: f64) {
    let s = load_and_check_geometry(name, load);
    let mut w = s.build().unwrap().world;
    let steps = (run_s / w.dt_s()) as usize;
    for _ in 0..steps {
        w.step();
    }
    let block = w
        .floes()
        .motion
        .iter()
        .position(|m| matches!(m, Motion::Free))
        .unwrap();
    let v = w.floes().velocity[block].x;
    assert!((v - speed).abs() < 1e-4 * speed, "{name}: block at {v} m/s");
    let mu_ss = w.model().law.mu_steady(speed);
    let mut friction = 0.0;
    let mut push = 0.0;
    for c in w.contacts() {
        if c.normal.y.abs() > 0.99 {
            assert!((c.normal_force_n - load).abs() < 1e-6 * load);
            assert!((c.mu() - mu_ss).abs() < 1e-4, "mu {} vs {mu_ss}", c.mu());
            friction += c.tangential_force_n().abs();
        } else {
            push += c.normal_force_n;
        }
    }
    assert!(
        (push - friction).abs() < 1e-4 * friction,
        "{push} vs {friction}"
    );
}

fn load_and_check_geometry(name: &str, load: f64) -> Scenario {
    let s = scenario(name);
    let setup = s.build().unwrap();
    let w = &setup.world;
    // At t = 0 the side blocks press on the block with the intended load.
    let side: Vec<f64> = w
        .contacts()
        .iter()
        .filter(|c| c.normal.y.abs() > 0.99)
        .map(|c| c.normal_force_n)
        .collect();
    assert_eq!(side.len(), 2, "{name}: two side contacts");
    for n in side {
        assert!((n - load).abs() < 1e-9 * load, "{name}: {n} N vs {load} N");
    }
    assert!(setup
        .report
        .iter()
        .any(|l| l.contains("loading spring") && l.contains("in series")));
    s
}

#[test]
fn tank_double_shear_carries_5_kn_and_slides_at_steady_friction() {
    pooled(|| double_shear("tank_double_shear.toml", 5000.0, 0.008, 60.0));
    // The stiffness matches the tank apparatus, 2 MN/m.
    let s = scenario("tank_double_shear.toml");
    let g = checks::double_shear_geometry(s.contact_model(), 0.25, [2.0, 2.0], [0.5, 2.0], 5e3);
    assert!((g.series_stiffness_n_per_m - 2e6).abs() < 0.01 * 2e6);
}

#[test]
fn lab_double_shear_carries_1_kn_per_face() {
    let s = load_and_check_geometry("lab_double_shear.toml", 1000.0);
    let g = checks::double_shear_geometry(s.contact_model(), 0.1, [0.2, 0.1], [0.05, 0.1], 1e3);
    assert!((g.series_stiffness_n_per_m - 20e6).abs() < 0.01 * 20e6);
    // The whole run (20 s, 10 L of slip, 517,000 steps) reaches steady sliding.
    pooled(|| double_shear("lab_double_shear.toml", 1000.0, 1e-4, 20.0));
}

#[test]
fn the_minimal_example_in_the_docs_builds() {
    let docs = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scenarios.md"),
    )
    .unwrap();
    let start = docs.find("```toml\n").unwrap() + "```toml\n".len();
    let end = start + docs[start..].find("```").unwrap();
    let s = Scenario::from_text(&docs[start..end], Path::new("docs/scenarios.md")).unwrap();
    let n = s.build().unwrap().world.floes().len();
    assert!((440..520).contains(&n), "{n} floes");
}

/// docs/scenarios.md holds the law registry's parameter tables as the
/// registry prints them (regenerate with
/// `cargo run -p floe-friction --example law_tables`).
#[test]
fn the_scenario_docs_hold_the_law_registry_tables() {
    let docs = include_str!("../../docs/scenarios.md");
    let begin = "<!-- law tables: generated, do not edit by hand -->\n";
    let end = "<!-- end of law tables -->";
    let start = docs.find(begin).expect("begin marker") + begin.len();
    let stop = docs[start..].find(end).expect("end marker") + start;
    let expected = floe_friction::LawRegistry::builtin().markdown();
    assert_eq!(
        docs[start..stop].trim_end(),
        expected.trim_end(),
        "docs/scenarios.md's law tables differ from the registry's; replace them with \
         the output of `cargo run -p floe-friction --example law_tables`"
    );
}

/// The area of convex polygon `p` inside the rectangle `[x0, x1] x [y0, y1]`
/// (Sutherland-Hodgman against the four sides).
fn area_in_rect(p: &[Vec2], [x0, x1, y0, y1]: [f64; 4]) -> f64 {
    let mut poly = p.to_vec();
    let sides: [(Vec2, f64); 4] = [
        (Vec2::new(1.0, 0.0), x0),
        (Vec2::new(-1.0, 0.0), -x1),
        (Vec2::new(0.0, 1.0), y0),
        (Vec2::new(0.0, -1.0), -y1),
    ];
    for (n, c) in sides {
        let mut out = Vec::new();
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (da, db) = (n.dot(a) - c, n.dot(b) - c);
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                out.push(a + (b - a) * (da / (da - db)));
            }
        }
        poly = out;
        if poly.len() < 3 {
            return 0.0;
        }
    }
    let o = poly[0];
    0.5 * (1..poly.len() - 1)
        .map(|k| (poly[k] - o).perp_dot(poly[k + 1] - o))
        .sum::<f64>()
}

/// A periodic diamond pack has no seam: away from the walls every 1 km
/// column across the channel, those beside the periodic seam included, is
/// covered exactly once (floes and their periodic images), and every floe
/// there is a whole diamond.
#[test]
fn periodic_diamond_packs_have_no_seam() {
    for name in [
        "demo.toml",
        "jam_flow.toml",
        "shear_zone.toml",
        "wind_pause.toml",
    ] {
        let s = scenario(name);
        let d = s.domain();
        assert_eq!(d.periodic, [true, false], "{name}");
        let setup = s.build().unwrap();
        let floes = setup.world.floes();
        let period = d.size_m.x;
        // The band across the channel, 1.5 km clear of the walls.
        let (y0, y1) = (d.min_m.y + 1500.0, d.min_m.y + d.size_m.y - 1500.0);
        let columns = (period / 1000.0).round() as usize;
        let mut covered = vec![0.0; columns];
        for i in 0..floes.len() {
            let p = floes.world_vertices(i);
            let in_band = p.iter().all(|v| v.y > y0 && v.y < y1);
            if in_band {
                assert_eq!(p.len(), 4, "{name}: floe {i} is not a whole diamond: {p:?}");
            }
            for shift in [-period, 0.0, period] {
                let image: Vec<Vec2> = p.iter().map(|&v| v + Vec2::new(shift, 0.0)).collect();
                for (k, c) in covered.iter_mut().enumerate() {
                    let x0 = d.min_m.x + 1000.0 * k as f64;
                    *c += area_in_rect(&image, [x0, x0 + 1000.0, y0, y1]);
                }
            }
        }
        for (k, c) in covered.iter().enumerate() {
            let concentration = c / (1000.0 * (y1 - y0));
            assert!(
                (concentration - 1.0).abs() < 1e-9,
                "{name}: column {k} of {columns} has concentration {concentration}"
            );
        }
    }
}

#[test]
fn the_wide_shear_cell_starts_loose_with_a_quarter_of_its_cells_open_water() {
    // fill_fraction = 0.75: every Voronoi floe shrunk to 3/4 of its cell.
    let loose = scenario("shear_cell_wide.toml");
    let tiled_text = loose.text().replace("fill_fraction = 0.75\n", "");
    let tiled = Scenario::from_text(&tiled_text, Path::new("tiled.toml")).unwrap();
    let free_area = |s: &Scenario| {
        let w = s.build().unwrap().world;
        let f = w.floes().columns();
        (0..f.len())
            .filter(|&i| f.is_free(i))
            .map(|i| f.area_m2[i])
            .sum::<f64>()
    };
    let (a, b) = (free_area(&loose), free_area(&tiled));
    // The walls glue the floes within 500 m of their faces: a shrunk floe
    // may fall out of that band, so the free floes differ by a few at most.
    let ratio = a / b;
    assert!(
        (0.72..0.78).contains(&ratio),
        "free ice {a} against {b}: {ratio}"
    );
}
