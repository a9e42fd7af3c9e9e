//! Bad scenario files: one message naming file:line:column, the key and the
//! reason, for every class of mistake, and never a panic. Through the
//! library (`Scenario::from_text`); `floe run` passes the same error on
//! with exit code 2.

use crate::grid_support;

use std::path::Path;

use floe_scenario::{Scenario, ScenarioError};
use grid_support::{axis, Grid};

/// A small valid scenario that the cases below break one way each.
const BASE: &str = r#"title = "base"
duration_s = 100.0

[domain]
size_m = [4000.0, 4000.0]

[tessellation]
kind = "grid"
columns = 2
rows = 2
gap_m = 100.0

[ice]
thickness_m = 1.0
"#;

/// The error of `text` (which must fail to load or to build).
fn error(text: &str) -> ScenarioError {
    let origin = Path::new("bad.toml");
    match Scenario::from_text(text, origin) {
        Err(e) => e,
        Ok(s) => match s.build() {
            Err(e) => e,
            Ok(_) => panic!("accepted:\n{text}"),
        },
    }
}

/// `bad.toml:line:column` of the first occurrence of `needle` in `text`,
/// plus `offset` characters.
fn at(text: &str, needle: &str, offset: usize) -> String {
    let start = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle} not in text"))
        + offset;
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let column = start - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    format!("bad.toml:{line}:{column}")
}

/// Checks the message: located at `needle` (+ `offset`), names `key`, and
/// says each of `reasons`; exit code 2.
fn check(text: &str, needle: &str, offset: usize, key: &str, reasons: &[&str]) {
    let e = error(text);
    let msg = e.to_string();
    assert!(e.is_input(), "{msg}");
    assert!(matches!(e, ScenarioError::Input { .. }), "{msg}");
    let place = at(text, needle, offset);
    assert!(msg.starts_with(&place), "expected {place}: {msg}");
    assert!(msg.contains(key), "expected key {key}: {msg}");
    for r in reasons {
        assert!(msg.contains(r), "expected `{r}`: {msg}");
    }
}

/// `BASE` with `from` replaced by `to`.
fn edit(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "{from}");
    BASE.replacen(from, to, 1)
}

#[test]
fn the_base_scenario_builds() {
    let s = Scenario::from_text(BASE, Path::new("base.toml")).unwrap();
    assert_eq!(s.build().unwrap().world.floes().len(), 4);
}

#[test]
fn toml_syntax_errors_are_located() {
    let t = edit("columns = 2", "columns = = 2");
    let msg = error(&t).to_string();
    assert!(msg.starts_with("bad.toml:9:"), "{msg}");
}

#[test]
fn unknown_keys_are_refused_everywhere() {
    let t = edit("duration_s = 100.0", "duration_s = 100.0\ndurration = 3.0");
    check(&t, "durration", 0, "durration", &["unknown field"]);
    let t = edit("thickness_m = 1.0", "thickness_m = 1.0\ncolour = \"white\"");
    check(&t, "colour", 0, "colour", &["unknown field"]);
    let t = format!("{BASE}\n[[wall]]\nside = \"left\"\nspeed_m_per_s = [0.0, 1.0]\n");
    check(&t, "speed_m_per_s", 0, "speed_m_per_s", &["unknown field"]);
    let t = format!("{BASE}\n[wind]\nshear = {{ y_min_m = 0.0, y_max_m = 1.0, velocity_at_y_min_m_per_s = [0.0, 0.0], velocity_at_y_max_m_per_s = [1.0, 0.0], kink = 2.0 }}\n");
    let msg = error(&t).to_string();
    assert!(msg.contains("unknown field `kink`"), "{msg}");
    assert!(msg.starts_with("bad.toml:17:"), "{msg}");
}

#[test]
fn wrong_types_are_refused() {
    let t = edit("duration_s = 100.0", "duration_s = \"long\"");
    check(&t, "\"long\"", 0, "duration_s", &["invalid type"]);
    let t = edit("columns = 2", "columns = 2.5");
    check(&t, "2.5", 0, "columns", &["invalid type"]);
}

#[test]
fn missing_required_keys_are_named() {
    let t = edit("duration_s = 100.0\n", "");
    let msg = error(&t).to_string();
    assert!(msg.starts_with("bad.toml:1:1"), "{msg}");
    assert!(msg.contains("duration_s"), "{msg}");
    let t = edit("columns = 2\n", "");
    check(
        &t,
        "[tessellation]",
        0,
        "tessellation.columns",
        &["missing"],
    );
}

#[test]
fn non_positive_sizes_thickness_density_and_durations_are_refused() {
    let t = edit("thickness_m = 1.0", "thickness_m = 0.0");
    check(
        &t,
        "thickness_m = 0.0",
        14,
        "ice.thickness_m",
        &["> 0", "got 0"],
    );
    let t = edit(
        "thickness_m = 1.0",
        "thickness_m = 1.0\ndensity_kg_per_m3 = -917.0",
    );
    check(&t, "-917", 0, "ice.density_kg_per_m3", &["> 0"]);
    let t = edit("size_m = [4000.0, 4000.0]", "size_m = [4000.0, 0.0]");
    check(&t, "[4000.0, 0.0]", 0, "domain.size_m", &["> 0"]);
    let t = edit("duration_s = 100.0", "duration_s = -1.0");
    check(&t, "-1.0", 0, "duration_s", &["> 0"]);
    let t = edit("duration_s = 100.0", "duration_s = 100.0\ndt_s = 0.0");
    check(&t, "0.0\n\n[domain]", 0, "dt_s", &["> 0"]);
}

#[test]
fn a_time_step_above_the_stable_limit_is_refused_with_the_limit() {
    let s = Scenario::from_text(BASE, Path::new("base.toml")).unwrap();
    let limit = s.build().unwrap().stable_limit_s;
    let t = edit(
        "duration_s = 100.0",
        &format!("duration_s = 100.0\ndt_s = {}", 2.0 * limit),
    );
    let e = error(&t);
    let msg = e.to_string();
    assert!(msg.starts_with("bad.toml:3:8"), "{msg}");
    assert!(
        msg.contains("`dt_s`") && msg.contains("above the stable limit"),
        "{msg}"
    );
    let shown = format!("{:.3}", limit);
    assert!(msg.contains(&shown[..4]), "limit {limit} not in {msg}");
    // Just below the limit is accepted.
    let t = edit(
        "duration_s = 100.0",
        &format!("duration_s = 100.0\ndt_s = {}", 0.99 * limit),
    );
    Scenario::from_text(&t, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
}

#[test]
fn overlapping_floes_are_named() {
    let t = r#"duration_s = 10.0
[domain]
size_m = [100.0, 100.0]

[[floe]]
box_m = [10.0, 10.0, 30.0, 30.0]

[[floe]]
box_m = [50.0, 10.0, 70.0, 30.0]

[[floe]]
box_m = [25.0, 10.0, 45.0, 30.0]
"#;
    check(
        t,
        "[[floe]]\nbox_m = [25.0",
        0,
        "floe[2]",
        &["overlaps floe[0]"],
    );
    // Touching is fine.
    let ok = t.replace("[25.0, 10.0, 45.0, 30.0]", "[30.0, 10.0, 45.0, 30.0]");
    Scenario::from_text(&ok, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    // A non-convex outline.
    let t = r#"duration_s = 10.0
[domain]
size_m = [100.0, 100.0]

[[floe]]
vertices_m = [[0.0, 0.0], [10.0, 0.0], [5.0, 2.0], [10.0, 10.0], [0.0, 10.0]]
"#;
    check(t, "[[floe]]", 0, "floe[0]", &["not convex"]);
}

#[test]
fn walls_outside_the_domain_or_across_a_periodic_axis_are_refused() {
    let t = format!("{BASE}\n[[wall]]\nside = \"left\"\ninset_m = 2500.0\n\n[[wall]]\nside = \"right\"\ninset_m = 2000.0\n");
    check(
        &t,
        "2000.0\n",
        0,
        "wall[1].inset_m",
        &["outside the domain"],
    );
    let t = edit(
        "size_m = [4000.0, 4000.0]",
        "size_m = [4000.0, 4000.0]\nperiodic = [true, false]",
    );
    let t = format!("{t}\n[[wall]]\nside = \"right\"\n");
    check(&t, "\"right\"", 0, "wall[0].side", &["periodic along x"]);
    let t = format!("{BASE}\n[[wall]]\nside = \"middle\"\n");
    check(
        &t,
        "\"middle\"",
        0,
        "wall[0].side",
        &["unknown value `middle`"],
    );
    let t = format!("{BASE}\n[[wall]]\nside = \"top\"\n\n[[wall]]\nside = \"top\"\n");
    check(
        &t,
        "\"top\"\n\n[[wall]]\nside = \"top",
        23,
        "wall[1].side",
        &["already on the top side"],
    );
}

#[test]
fn walls_that_would_cross_each_other_are_refused() {
    let t = format!("{BASE}\n[[wall]]\nside = \"bottom\"\nvelocity_m_per_s = [0.0, 30.0]\n\n[[wall]]\nside = \"top\"\nvelocity_m_per_s = [0.0, -30.0]\n");
    check(
        &t,
        "[0.0, -30.0]",
        0,
        "wall[1].velocity_m_per_s",
        &["before duration_s", "cross each other"],
    );
}

#[test]
fn keys_that_do_not_apply_and_unknown_kinds_are_refused() {
    let t = edit("gap_m = 100.0", "gap_m = 100.0\nside_m = 3.0");
    check(
        &t,
        "3.0",
        0,
        "tessellation.side_m",
        &["does not apply to kind `grid`"],
    );
    let t = edit("gap_m = 100.0", "gap_m = 100.0\nfill_fraction = 0.8");
    check(
        &t,
        "0.8",
        0,
        "tessellation.fill_fraction",
        &["does not apply to kind `grid`"],
    );
    let voronoi = edit(
        "kind = \"grid\"\ncolumns = 2\nrows = 2\ngap_m = 100.0",
        "kind = \"voronoi\"\ncount = 20\nfill_fraction = 1.5",
    );
    check(
        &voronoi,
        "1.5",
        0,
        "tessellation.fill_fraction",
        &["[0.1, 1]"],
    );
    let t = edit(
        "thickness_m = 1.0",
        "thickness_m = 1.0\ninitial_shear_rate_per_s = 2.0",
    );
    check(&t, "2.0", 0, "ice.initial_shear_rate_per_s", &["[-1, 1]"]);
    let t = edit("kind = \"grid\"", "kind = \"hexagon\"");
    check(
        &t,
        "\"hexagon\"",
        0,
        "tessellation.kind",
        &["unknown kind `hexagon`"],
    );
    let t = format!("{BASE}\n[friction]\nlaw = \"amontons\"\nmu = 0.3\na = 0.01\n");
    check(
        &t,
        "a = 0.01",
        0,
        "friction.a",
        &["does not apply to law `amontons`", "it takes `mu`"],
    );
    let t = format!("{BASE}\n[friction]\nlaw = \"coulomb\"\n");
    check(
        &t,
        "\"coulomb\"",
        0,
        "friction.law",
        &["unknown law `coulomb`"],
    );
    // A misspelt law beside a preset is reported as the unknown law.
    let t = format!("{BASE}\n[friction]\nlaw = \"rate-stat\"\npreset = \"lab\"\n");
    check(
        &t,
        "\"rate-stat\"",
        0,
        "friction.law",
        &["unknown law `rate-stat`"],
    );
    // A key that does not apply, in an inline table: located at that key.
    let t = format!("friction = {{ law = \"amontons\", mu = 0.3, bogus = 1.0 }}\n{BASE}");
    check(
        &t,
        "bogus",
        0,
        "friction.bogus",
        &["unknown key `bogus`", "`mu`"],
    );
    let t = format!("{BASE}\n[friction]\nlaw = \"amontons\"\n");
    check(&t, "\"amontons\"", 0, "friction.law", &["needs `mu`"]);
    let t = format!("{BASE}\n[friction]\nstate_law = \"sticky\"\n");
    check(
        &t,
        "\"sticky\"",
        0,
        "friction.state_law",
        &["unknown value `sticky`"],
    );
    let t = format!("{BASE}\n[wind]\nsea_surface_tilt = false\n");
    check(
        &t,
        "false",
        0,
        "wind.sea_surface_tilt",
        &["belongs in [ocean]"],
    );
}

#[test]
fn out_of_range_parameters_are_refused() {
    let t = format!("{BASE}\n[coriolis]\nlatitude_deg = 100.0\n");
    check(
        &t,
        "latitude_deg = 100.0",
        15,
        "coriolis.latitude_deg",
        &["[-90, 90]"],
    );
    let t = format!("{BASE}\n[contact]\npoisson_ratio = 0.7\n");
    check(&t, "0.7", 0, "contact.poisson_ratio", &["[0, 0.5)"]);
    let t = format!("{BASE}\n[ocean]\nturning_angle_deg = 95.0\n");
    check(
        &t,
        "95.0",
        0,
        "ocean.turning_angle_deg",
        &["between -90 and 90"],
    );
    let t = format!("{BASE}\n[wind]\ntime_series = {{ times_s = [0.0, 10.0, 5.0], velocities_m_per_s = [[1.0, 0.0], [2.0, 0.0], [3.0, 0.0]] }}\n");
    check(
        &t,
        "{ times_s",
        0,
        "wind.time_series",
        &["strictly increasing"],
    );
    let t = format!("{BASE}\n[wind]\nvelocity_m_per_s = [1.0, 0.0]\ngyre = {{ center_m = [0.0, 0.0], core_radius_m = 10.0, max_speed_m_per_s = 1.0 }}\n");
    check(&t, "{ center_m", 0, "wind", &["give one of"]);
    let diamond = edit(
        "kind = \"grid\"\ncolumns = 2\nrows = 2\ngap_m = 100.0",
        "kind = \"diamond\"\nside_m = 500.0\njitter_fraction = 0.5",
    );
    check(
        &diamond,
        "0.5\n",
        0,
        "tessellation.jitter_fraction",
        &["must lie in [0, 0.125"],
    );
}

#[test]
fn double_shear_set_ups_that_do_not_fit_are_refused() {
    let t = r#"duration_s = 100.0
[domain]
size_m = [8.0, 8.0]

[tessellation]
kind = "double-shear"
block_m = [2.0, 2.0]
side_block_m = [2.5, 2.0]
normal_load_per_face_n = 5000.0
push_velocity_m_per_s = 0.008
"#;
    check(
        t,
        "[tessellation]",
        0,
        "tessellation.side_block_m",
        &["too short", "at least 2.8"],
    );
    let small = t
        .replace("[2.5, 2.0]", "[4.0, 2.0]")
        .replace("[8.0, 8.0]", "[3.0, 8.0]");
    check(
        &small,
        "[tessellation]",
        0,
        "domain.size_m",
        &["does not fit"],
    );
    let heavy = t
        .replace("[2.5, 2.0]", "[4.0, 2.0]")
        .replace("5000.0", "5e9");
    check(
        &heavy,
        "[tessellation]",
        0,
        "tessellation.normal_load_per_face_n",
        &["youngs_modulus_pa"],
    );
}

#[test]
fn load_reports_unreadable_files() {
    let e = Scenario::load(Path::new("/nonexistent/scenario.toml")).unwrap_err();
    // A path that is not there is the user's input to fix (exit 2).
    assert!(e.is_input() && matches!(e, ScenarioError::Io { .. }));
    assert!(e.to_string().contains("/nonexistent/scenario.toml"));
}

#[test]
fn the_published_form_is_refused_for_dem_contacts_with_the_reason() {
    // Eq. 4b slips only along perp(normal), so mirror-image
    // contacts (the double shear's two faces) get different friction.
    let t = format!("{BASE}\n[friction]\nlaw = \"rate-state\"\nform = \"published\"\n");
    check(
        &t,
        "\"published\"",
        0,
        "friction.form",
        &[
            "spring-slider",
            "counter-clockwise",
            "mirror-image",
            "`regularized`",
        ],
    );
    let t = format!("{BASE}\n[friction]\nlaw = \"rate-state\"\nform = \"regularized\"\n");
    Scenario::from_text(&t, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
}

/// `BASE` between walls, the top one on `segments` (TOML text).
fn with_top_schedule(segments: &str) -> String {
    format!("{BASE}\n[[wall]]\nside = \"bottom\"\n\n[[wall]]\nside = \"top\"\n{segments}")
}

#[test]
fn a_motion_schedule_is_checked_where_it_is_written() {
    let ok = with_top_schedule(
        "\n[[wall.segment]]\nduration_s = 10.0\nvelocity_m_per_s = [0.1, 0.0]\n\n\
         [[wall.segment]]\nduration_s = 20.0\nend_velocity_m_per_s = [-0.1, 0.0]\n",
    );
    let s = Scenario::from_text(&ok, Path::new("ok.toml")).unwrap();
    let world = s.build().unwrap().world;
    let f = world.floes();
    let walls = (0..f.len()).filter(|&i| !f.is_free(i)).count();
    assert_eq!(
        world.schedules().len(),
        walls / 2,
        "one per piece of the top wall"
    );
    // Both a velocity and segments.
    let both =
        with_top_schedule("velocity_m_per_s = [0.1, 0.0]\n\n[[wall.segment]]\nduration_s = 10.0\n");
    check(
        &both,
        "[0.1, 0.0]\n\n[[wall",
        0,
        "wall[1].velocity_m_per_s",
        &["not both"],
    );
    // A segment without a duration, or a zero one.
    let missing = with_top_schedule("\n[[wall.segment]]\nvelocity_m_per_s = [0.1, 0.0]\n");
    check(
        &missing,
        "[[wall.segment]]",
        0,
        "wall[1].segment[0].duration_s",
        &["missing"],
    );
    let zero = with_top_schedule("\n[[wall.segment]]\nduration_s = 0.0\n");
    check(
        &zero,
        "duration_s = 0.0",
        13,
        "wall[1].segment[0].duration_s",
        &["> 0"],
    );
    // A turning wall.
    let turning = with_top_schedule(
        "\n[[wall.segment]]\nduration_s = 10.0\nangular_velocity_rad_per_s = 0.01\n",
    );
    check(
        &turning,
        "0.01",
        0,
        "wall[1].segment[0].angular_velocity_rad_per_s",
        &["prescribed [[floe]]"],
    );
    // A key the segment does not have.
    let typo = with_top_schedule("\n[[wall.segment]]\nduration_s = 10.0\nspeed = 1.0\n");
    check(&typo, "speed", 0, "speed", &["unknown field"]);
    // Travel beyond 100 domain sizes (4000 m domain, 100 s run) in the
    // second segment.
    let far = with_top_schedule(
        "\n[[wall.segment]]\nduration_s = 10.0\nvelocity_m_per_s = [0.0, 0.1]\n\n\
         [[wall.segment]]\nduration_s = 50.0\nvelocity_m_per_s = [0.0, 1e4]\n",
    );
    check(
        &far,
        "[[wall.segment]]\nduration_s = 50.0",
        0,
        "wall[1].segment[1]",
        &["100 domain sizes"],
    );
    // Walls that a schedule drives into each other within the run: the top
    // wall comes down 4000 m by t = 60 s.
    let crossing = with_top_schedule(
        "\n[[wall.segment]]\nduration_s = 20.0\n\n[[wall.segment]]\nduration_s = 80.0\n\
         velocity_m_per_s = [0.0, -100.0]\n",
    );
    check(
        &crossing,
        "[[wall]]\nside = \"top\"",
        0,
        "wall[1].segment",
        &["close 4000 m in 60 s"],
    );
}

#[test]
fn only_a_prescribed_floe_follows_a_schedule() {
    let floes = r#"title = "floes"
duration_s = 100.0

[domain]
size_m = [4000.0, 4000.0]

[[floe]]
box_m = [100.0, 100.0, 900.0, 900.0]

[[floe]]
box_m = [2000.0, 100.0, 2900.0, 900.0]
PRESCRIBED
[[floe.segment]]
duration_s = 10.0
angular_velocity_rad_per_s = 0.01
"#;
    let free = floes.replace("PRESCRIBED\n", "");
    check(
        &free,
        "[[floe.segment]]",
        0,
        "floe[1].segment",
        &["prescribed = true"],
    );
    let both = floes.replace(
        "PRESCRIBED",
        "prescribed = true\nvelocity_m_per_s = [0.1, 0.0]\n",
    );
    check(
        &both,
        "[0.1, 0.0]",
        0,
        "floe[1].velocity_m_per_s",
        &["not both"],
    );
    let ok = floes.replace("PRESCRIBED", "prescribed = true\n");
    let s = Scenario::from_text(&ok, Path::new("ok.toml")).unwrap();
    assert_eq!(s.build().unwrap().world.schedules().len(), 1);
}

#[test]
fn a_load_point_is_checked_where_it_is_written() {
    let floes = r#"title = "load point"
duration_s = 10.0

[domain]
size_m = [100.0, 100.0]

[[floe]]
box_m = [10.0, 10.0, 11.0, 11.0]
PRESCRIBED
[floe.load_point]
STIFFNESS
SEGMENTS"#;
    let make = |p: &str, k: &str, s: &str| {
        floes
            .replace("PRESCRIBED", p)
            .replace("STIFFNESS", k)
            .replace("SEGMENTS", s)
    };
    let segment =
        "\n[[floe.load_point.segment]]\nduration_s = 5.0\nvelocity_m_per_s = [0.01, 0.0]\n";
    let k = "stiffness_n_per_m = 1000.0";
    let ok = make("", k, segment);
    let s = Scenario::from_text(&ok, Path::new("ok.toml")).unwrap();
    let world = s.build().unwrap().world;
    let lp = &world.load_points()[0];
    assert_eq!(lp.stiffness_n_per_m, 1000.0);
    assert_eq!(
        lp.anchor,
        world.floes().position[0],
        "anchored where the floe starts"
    );
    check(
        &make("prescribed = true", k, segment),
        "[floe.load_point]",
        0,
        "floe[0].load_point",
        &["free floe"],
    );
    check(
        &make("", "", segment),
        "[floe.load_point]",
        0,
        "floe[0].load_point.stiffness_n_per_m",
        &["missing", "N/m"],
    );
    check(
        &make("", "stiffness_n_per_m = -1.0", segment),
        "-1.0",
        0,
        "floe[0].load_point.stiffness_n_per_m",
        &["[0.001, 1e12] N/m"],
    );
    check(
        &make("", k, ""),
        "[floe.load_point]",
        0,
        "floe[0].load_point.segment",
        &["missing"],
    );
    let turning = segment.replace(
        "duration_s = 5.0",
        "duration_s = 5.0\nangular_velocity_rad_per_s = 1.0",
    );
    check(
        &make("", k, &turning),
        "1.0\nvelocity",
        0,
        "floe[0].load_point.segment[0].angular_velocity_rad_per_s",
        &["translates only"],
    );
    // A spring too stiff for the given step names the spring.
    let stiff = make("", "stiffness_n_per_m = 1e12", segment)
        .replace("duration_s = 10.0\n", "duration_s = 10.0\ndt_s = 0.001\n");
    check(&stiff, "0.001", 0, "dt_s", &["load-point spring"]);
}

#[test]
fn the_double_shear_pusher_schedule_is_checked_where_it_is_written() {
    let shear = r#"title = "double shear"
duration_s = 10.0

[domain]
size_m = [8.0, 8.0]

[tessellation]
kind = "double-shear"
block_m = [2.0, 2.0]
side_block_m = [4.0, 2.0]
normal_load_per_face_n = 5000.0
PUSH
[[tessellation.segment]]
duration_s = 5.0
velocity_m_per_s = VELOCITY

[ice]
thickness_m = 0.25
"#;
    let make = |push: &str, v: &str| shear.replace("PUSH", push).replace("VELOCITY", v);
    let ok = make("", "[0.008, 0.0]");
    let s = Scenario::from_text(&ok, Path::new("ok.toml")).unwrap();
    assert_eq!(s.build().unwrap().world.schedules().len(), 1, "the pusher");
    check(
        &make("push_velocity_m_per_s = 0.008", "[0.008, 0.0]"),
        "0.008\n",
        0,
        "tessellation.push_velocity_m_per_s",
        &["not both"],
    );
    check(
        &make("", "[0.008, 0.001]"),
        "[[tessellation.segment]]",
        0,
        "tessellation.segment[0]",
        &["along the block"],
    );
    // Segments belong to the double shear only.
    let grid = format!("{BASE}\n[[tessellation.segment]]\nduration_s = 1.0\n");
    check(
        &grid,
        "[[tessellation.segment]]",
        0,
        "tessellation.segment",
        &["grid"],
    );
}

#[test]
fn a_dt_fraction_outside_zero_to_one_or_beside_dt_s_is_refused() {
    for bad in ["0.0", "-0.25", "1.5", "nan", "inf"] {
        let t = edit(
            "duration_s = 100.0",
            &format!("duration_s = 100.0\ndt_fraction = {bad}"),
        );
        check(
            &t,
            &format!("{bad}\n\n[domain]"),
            0,
            "dt_fraction",
            &["(0, 1]", "fraction of the stable time step"],
        );
    }
    // Both ends of (0, 1] that are allowed build.
    for ok in ["1.0", "1e-3"] {
        let t = edit(
            "duration_s = 100.0",
            &format!("duration_s = 100.0\ndt_fraction = {ok}"),
        );
        Scenario::from_text(&t, Path::new("ok.toml"))
            .unwrap()
            .build()
            .unwrap();
    }
    let both = edit(
        "duration_s = 100.0",
        "duration_s = 100.0\ndt_s = 0.1\ndt_fraction = 0.5",
    );
    check(&both, "0.5\n", 0, "dt_fraction", &["dt_s", "not both"]);
    // A fraction so small that the run is too long is blamed on it.
    let tiny = edit(
        "duration_s = 100.0",
        "duration_s = 100.0\ndt_fraction = 1e-12",
    );
    check(
        &tiny,
        "1e-12",
        0,
        "dt_fraction",
        &["above the limit", "raise dt_fraction", "--step-limit"],
    );
}

/// `BASE` with one `[[output.window]]` of `body`, after a window that is fine.
fn with_window(body: &str) -> String {
    format!(
        "{BASE}\n[output]\nobservables_every_s = 1.0\n\n[[output.window]]\nfrom_s = 0.0\n\
         to_s = 100.0\nsnapshot_every_s = 5.0\n\n[[output.window]]\n{body}\n"
    )
}

#[test]
fn output_windows_outside_the_run_backwards_or_without_a_cadence_are_refused() {
    let ok = with_window("from_s = 10.0\nto_s = 20.0\nobservables_every_s = 0.1");
    let s = Scenario::from_text(&ok, Path::new("ok.toml")).unwrap();
    assert_eq!(s.output().windows.len(), 2);
    s.build().unwrap();
    let second = "[[output.window]]\nfrom_s = 10";
    let cases: [(&str, &str, &str, &[&str]); 8] = [
        (
            "from_s = -1.0\nto_s = 20.0\nobservables_every_s = 0.1",
            "-1.0",
            "output.window[1].from_s",
            &["[0, 100] s"],
        ),
        (
            "from_s = 10.0\nto_s = 100.5\nobservables_every_s = 0.1",
            "100.5",
            "output.window[1].to_s",
            &["[0, 100] s"],
        ),
        (
            "from_s = 10.0\nto_s = 10.0\nobservables_every_s = 0.1",
            "10.0\nobservables",
            "output.window[1].to_s",
            &["after from_s = 10 s"],
        ),
        (
            "from_s = 10.0\nto_s = 20.0",
            second,
            "output.window[1]",
            &["snapshot_every_s", "observables_every_s"],
        ),
        (
            "from_s = 10.0\nto_s = 20.0\nsnapshot_every_s = 0.0",
            "0.0\n",
            "output.window[1].snapshot_every_s",
            &["> 0"],
        ),
        (
            "from_s = 10.0\nto_s = 20.0\nobservables_every_s = nan",
            "nan",
            "output.window[1].observables_every_s",
            &["> 0"],
        ),
        (
            "to_s = 20.0\nsnapshot_every_s = 1.0",
            "[[output.window]]\nto_s",
            "output.window[1].from_s",
            &["missing"],
        ),
        (
            "from_s = 10.0\nto_s = 20.0\nevery_s = 1.0",
            "every_s = 1.0",
            "every_s",
            &["unknown field"],
        ),
    ];
    for (body, needle, key, reasons) in cases {
        let t = with_window(body);
        // The needle's last occurrence: the second window's.
        let offset = t.rfind(needle).unwrap() - t.find(needle).unwrap();
        check(&t, needle, offset, key, reasons);
    }
}

#[test]
fn more_than_a_thousand_windows_or_more_outputs_than_steps_are_refused() {
    let window = "[[output.window]]\nfrom_s = 0.0\nto_s = 1.0\nsnapshot_every_s = 1.0\n\n";
    let many = format!("{BASE}\n{}", window.repeat(1001));
    let first = many.find("[[output.window]]").unwrap();
    let last = many.rfind("[[output.window]]").unwrap();
    check(
        &many,
        "[[output.window]]",
        last - first,
        "output.window[1000]",
        &["1000 windows"],
    );
    // 1000 are fine.
    let thousand = format!("{BASE}\n{}", window.repeat(1000));
    Scenario::from_text(&thousand, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();

    // Two windows over the whole run at every step of 0.01 s: 10,001
    // snapshots each, 20,002 outputs, above a step limit of 15,000 that
    // the 10,000 steps themselves are within.
    let every_step = "[[output.window]]\nfrom_s = 0.0\nto_s = 100.0\nsnapshot_every_s = 0.01\n\n";
    let text = format!(
        "{}\n{}",
        edit("duration_s = 100.0", "duration_s = 100.0\ndt_s = 0.01"),
        every_step.repeat(2)
    );
    let s = Scenario::from_text(&text, Path::new("bad.toml")).unwrap();
    let msg = s
        .clone()
        .with_max_steps(15_000.0)
        .build()
        .err()
        .expect("refused")
        .to_string();
    let place = at(&text, "[[output.window]]", every_step.len());
    assert!(msg.starts_with(&place), "expected {place}: {msg}");
    for part in ["`output.window[1]`", "20,002 snapshots", "--step-limit"] {
        assert!(msg.contains(part), "`{part}` in {msg}");
    }
    // At the limit they are accepted, and the report counts their outputs.
    let setup = s.with_max_steps(20_002.0).build().unwrap();
    assert!(
        setup
            .report
            .iter()
            .any(|l| l.contains("2 windows") && l.contains("20,002 snapshots")),
        "{:?}",
        setup.report
    );
}

/// `BASE` with land from a GeoJSON file holding `geojson`, written in a
/// fresh directory (returned with the text; the file key gives the
/// absolute path).
fn with_land(geojson: &str, extra: &str) -> (tempfile::TempDir, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("coast.geojson");
    std::fs::write(&path, geojson).unwrap();
    let file = path.to_string_lossy().into_owned();
    let t = format!("{BASE}\n[[land]]\nfile = \"{file}\"\ncoordinates = \"xy\"\n{extra}");
    (dir, t, file)
}

/// A GeoJSON polygon of the (x, y) ring `ring` (closed here).
fn polygon(ring: &[(f64, f64)]) -> String {
    let mut c: Vec<String> = ring.iter().map(|(x, y)| format!("[{x}, {y}]")).collect();
    c.push(c[0].clone());
    format!(
        r#"{{"type": "Feature", "properties": {{}}, "geometry": {{"type": "Polygon", "coordinates": [[{}]]}}}}"#,
        c.join(", ")
    )
}

#[test]
fn map_and_land_keys_are_checked_where_written() {
    let t = format!("{BASE}\n[map]\nprojection = \"mercator\"\n");
    check(&t, "\"mercator\"", 0, "map.projection", &["EPSG:3413"]);
    let t = format!("{BASE}\n[map]\nprojection = \"EPSG:4326\"\n");
    check(
        &t,
        "\"EPSG:4326\"",
        0,
        "map.projection",
        &["longitude-latitude"],
    );
    let t = format!("{BASE}\n[map]\nzone = 3\n");
    check(&t, "zone", 0, "zone", &["unknown field"]);
    let t = format!("{BASE}\n[[land]]\ncoordinates = \"xy\"\n");
    check(&t, "[[land]]", 0, "land[0].file", &["missing", "GeoJSON"]);
    let t = format!("{BASE}\n[[land]]\nfile = \"coast.geojson\"\n");
    check(
        &t,
        "[[land]]",
        0,
        "land[0].coordinates",
        &["[map]", "\"xy\""],
    );
    let t = format!("{BASE}\n[[land]]\nfile = \"coast.geojson\"\ncoordinates = \"utm\"\n");
    check(
        &t,
        "\"utm\"",
        0,
        "land[0].coordinates",
        &["unknown value", "`lonlat`"],
    );
    let t = format!(
        "{BASE}\n[[land]]\nfile = \"c.geojson\"\ncoordinates = \"xy\"\nthickness_m = 2.0\n"
    );
    check(
        &t,
        "thickness_m = 2.0",
        0,
        "thickness_m",
        &["unknown field"],
    );
}

#[test]
fn land_files_that_are_missing_or_wrong_name_the_file_and_what_is_wrong() {
    let square = [
        (5000.0, 0.0),
        (9000.0, 0.0),
        (9000.0, 4000.0),
        (5000.0, 4000.0),
    ];
    // Missing.
    let (_d, t, file) = with_land("", "");
    std::fs::remove_file(&file).unwrap();
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &[&file, "cannot read"],
    );
    // Not JSON, not GeoJSON.
    let (_d, t, file) = with_land("{ coast", "");
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &[&file, "not GeoJSON"],
    );
    // A line is not land; the feature is named.
    let line = format!(
        r#"{{"type": "FeatureCollection", "features": [{}, {{"type": "Feature", "properties": {{}}, "geometry": {{"type": "LineString", "coordinates": [[0, 0], [1, 1]]}}}}]}}"#,
        polygon(&square)
    );
    let (_d, t, file) = with_land(&line, "");
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &["feature 1", "LineString"],
    );
    // A figure eight.
    let eight = polygon(&[
        (5000.0, 0.0),
        (9000.0, 4000.0),
        (9000.0, 0.0),
        (5000.0, 4000.0),
    ]);
    let (_d, t, file) = with_land(&eight, "");
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &["feature 0", "not simple"],
    );
    // Degenerate: all on a line.
    let flat = polygon(&[(5000.0, 0.0), (6000.0, 0.0), (7000.0, 0.0)]);
    let (_d, t, file) = with_land(&flat, "");
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &["feature 0", "not simple"],
    );
    let two = polygon(&[(5000.0, 0.0), (6000.0, 0.0), (5000.0, 0.0)]);
    let (_d, t, file) = with_land(&two, "");
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &["distinct vertices"],
    );
    // A hole.
    let hole = r#"{"type": "Polygon", "coordinates": [[[5000, 0], [9000, 0], [9000, 4000], [5000, 0]], [[8000, 500], [8500, 500], [8500, 1000], [8000, 500]]]}"#;
    let (_d, t, file) = with_land(hole, "");
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &["1 holes", "lake"],
    );
    // Longitude and latitude out of range (x/y given as lon/lat).
    let (_d, t, file) = with_land(&polygon(&square), "\n[map]\nprojection = \"EPSG:3413\"\n");
    let t = t.replace("coordinates = \"xy\"\n", "coordinates = \"lonlat\"\n");
    check(
        &t,
        &format!("\"{file}\""),
        0,
        "land[0].file",
        &["latitude", "\"xy\""],
    );
}

#[test]
fn ice_on_land_is_dropped_and_explicit_floes_on_land_are_refused() {
    // The right half of the 2 x 2 grid is on land: two floes dropped.
    let right = polygon(&[
        (2000.0, -100.0),
        (5000.0, -100.0),
        (5000.0, 4100.0),
        (2000.0, 4100.0),
    ]);
    let (_d, t, _) = with_land(&right, "");
    let setup = Scenario::from_text(&t, Path::new("land.toml"))
        .unwrap()
        .build()
        .unwrap();
    let w = setup.world.floes();
    let free = (0..w.len()).filter(|&i| w.is_free(i)).count();
    assert_eq!(free, 2);
    assert!(setup
        .report
        .iter()
        .any(|l| l.contains("2 floes on land dropped")));
    // All of it on land: nothing left to run.
    let all = polygon(&[
        (-100.0, -100.0),
        (5000.0, -100.0),
        (5000.0, 4100.0),
        (-100.0, 4100.0),
    ]);
    let (_d, t, _) = with_land(&all, "");
    check(
        &t,
        "[tessellation]",
        0,
        "tessellation",
        &["no free floes", "on land"],
    );
    // An explicit floe on land is an overlap, named.
    let t = "duration_s = 10.0\n\n[domain]\nsize_m = [4000.0, 4000.0]\n\n[[floe]]\nbox_m = [100.0, 100.0, 900.0, 900.0]\n\n[[floe]]\nbox_m = [2500.0, 100.0, 3300.0, 900.0]\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("coast.geojson");
    std::fs::write(&path, &right).unwrap();
    let t = format!(
        "{t}\n[[land]]\nfile = \"{}\"\ncoordinates = \"xy\"\n",
        path.display()
    );
    let msg = error(&t).to_string();
    assert!(
        msg.contains("overlaps") && msg.contains("floe[1]") && msg.contains("land[0]"),
        "{msg}"
    );
}

/// `BASE` with the `[ice]` table's body replaced by `ice`.
fn with_ice(ice: &str) -> String {
    edit("thickness_m = 1.0\n", &format!("{ice}\n"))
}

#[test]
fn ice_grids_are_checked_where_they_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str| dir.path().join(name).display().to_string();
    // 500 m nodes over [-500, 4500] m: the base's 4 km domain and a margin.
    let grid = |variable, units| Grid {
        x: axis(-500.0, 500.0, 11),
        y: axis(-500.0, 500.0, 11),
        times: None,
        variable,
        units,
    };
    grid("siconc", Some("1")).write(Path::new(&file("conc.nc")), |_, _, _| 0.5);
    grid("siconc", Some("1")).write(Path::new(&file("open.nc")), |_, _, _| 0.0);
    grid("siconc", Some("1")).write(Path::new(&file("high.nc")), |x, y, _| {
        if x > 2000.0 && y > 2000.0 {
            1.3
        } else {
            0.5
        }
    });
    grid("siconc", Some("%")).write(Path::new(&file("pct.nc")), |_, _, _| 150.0);
    grid("siconc", Some("1")).write(Path::new(&file("ambiguous.nc")), |_, _, _| 80.0);
    grid("siconc", Some("K")).write(Path::new(&file("kelvin.nc")), |_, _, _| 0.5);
    grid("sithick", Some("m")).write(Path::new(&file("thick.nc")), |_, _, _| 2e4);
    grid("sithick", Some("kg m-2")).write(Path::new(&file("mass.nc")), |_, _, _| 900.0);
    Grid {
        x: axis(0.0, 500.0, 5),
        y: axis(0.0, 500.0, 5),
        times: None,
        variable: "siconc",
        units: Some("1"),
    }
    .write(Path::new(&file("small.nc")), |_, _, _| 0.5);
    Grid {
        times: Some(3),
        ..grid("siconc", Some("1"))
    }
    .write(Path::new(&file("timed.nc")), |_, _, _| 0.5);

    let conc = |name: &str, extra: &str| {
        with_ice(&format!(
            "concentration_grid = {{ file = \"{}\", variable = \"siconc\"{extra} }}",
            file(name)
        ))
    };
    let key = "ice.concentration_grid";
    // The file and its variable.
    check(
        &conc("missing.nc", ""),
        "{ file",
        0,
        key,
        &["missing.nc", "no such file"],
    );
    let t = with_ice(&format!(
        "concentration_grid = {{ file = \"{}\", variable = \"ice\" }}",
        file("conc.nc")
    ));
    check(
        &t,
        "{ file",
        0,
        key,
        &["conc.nc", "no variable \"ice\"", "siconc"],
    );
    let t = with_ice(&format!(
        "concentration_grid = {{ file = \"{}\" }}",
        file("conc.nc")
    ));
    check(
        &t,
        "{ file",
        0,
        "ice.concentration_grid.variable",
        &["missing"],
    );
    let t = with_ice(&format!(
        "concentration_grid = {{ file = \"{}\", varible = \"siconc\" }}",
        file("conc.nc")
    ));
    check(&t, "varible", 0, "varible", &["unknown field"]);
    // A grid that does not cover the domain.
    check(
        &conc("small.nc", ""),
        "{ file",
        0,
        key,
        &["small.nc", "covers the domain"],
    );
    // No ice at all.
    check(&conc("open.nc", ""), "{ file", 0, key, &["leaves no floe"]);
    // Values and units.
    check(
        &conc("high.nc", ""),
        "{ file",
        0,
        key,
        &["concentration 1.3", "outside [0, 1]"],
    );
    check(
        &conc("pct.nc", ""),
        "{ file",
        0,
        key,
        &["concentration 150", "[0, 100] %"],
    );
    check(
        &conc("ambiguous.nc", ""),
        "{ file",
        0,
        key,
        &["values reach 80", "ambiguous", "units = "],
    );
    check(
        &conc("kelvin.nc", ""),
        "{ file",
        0,
        key,
        &["units \"K\"", "not a concentration"],
    );
    // Stating the units settles the ambiguity: 80 % is read as 0.8.
    let s = Scenario::from_text(
        &conc("ambiguous.nc", ", units = \"percent\""),
        Path::new("ok.toml"),
    )
    .unwrap()
    .build()
    .unwrap();
    assert!(s
        .report
        .iter()
        .any(|l| l.contains("percent as stated in the scenario")));
    check(
        &conc("conc.nc", ", units = \"permille\""),
        "\"permille\"",
        0,
        "ice.concentration_grid.units",
        &["unknown value `permille`"],
    );
    // Time records.
    check(
        &conc("timed.nc", ""),
        "{ file",
        0,
        key,
        &["3 time records", "time index"],
    );
    check(
        &conc("timed.nc", ", time_index = 3"),
        "{ file",
        0,
        key,
        &["time index 3 is beyond the last, 2"],
    );
    check(
        &conc("timed.nc", ", time_index = -1"),
        "-1",
        0,
        "ice.concentration_grid.time_index",
        &["integer from 0"],
    );
    // Thickness.
    let thick = |name: &str, extra: &str| {
        with_ice(&format!(
            "thickness_grid = {{ file = \"{}\", variable = \"sithick\"{extra} }}",
            file(name)
        ))
    };
    check(
        &thick("thick.nc", ""),
        "{ file",
        0,
        "ice.thickness_grid",
        &["20000 m", "thickest"],
    );
    check(
        &thick("mass.nc", ""),
        "{ file",
        0,
        "ice.thickness_grid",
        &["units \"kg m-2\"", "m or cm"],
    );
    check(
        &thick("thick.nc", ", units = \"percent\""),
        "\"percent\"",
        0,
        "ice.thickness_grid.units",
        &["concentration_grid only"],
    );
    let t = edit(
        "thickness_m = 1.0\n",
        &format!(
            "thickness_m = 1.0\nthickness_grid = {{ file = \"{}\", variable = \"sithick\" }}\n",
            file("thick.nc")
        ),
    );
    check(&t, "[ice]", 0, "ice", &["give one of", "thickness_grid"]);
    // Only generated floes are placed from a grid.
    let t = format!(
        "duration_s = 10.0\n[domain]\nsize_m = [100.0, 100.0]\n[[floe]]\nbox_m = [0.0, 0.0, 10.0, 10.0]\n\
         [ice]\nconcentration_grid = {{ file = \"{}\", variable = \"siconc\" }}\n",
        file("conc.nc")
    );
    check(
        &t,
        "{ file",
        0,
        key,
        &["[tessellation]", "not explicit [[floe]] tables"],
    );
}

#[test]
fn size_distributions_are_checked_where_they_are_written() {
    let voronoi = |fsd: &str| {
        edit(
            "kind = \"grid\"\ncolumns = 2\nrows = 2\ngap_m = 100.0",
            &format!("kind = \"voronoi\"\nsize_distribution = {{ {fsd} }}"),
        )
    };
    let key = "tessellation.size_distribution";
    let t = voronoi("kind = \"power_law\", exponent = 2.0, min_m = 300.0, max_m = 300.0");
    check(
        &t,
        "max_m = 300.0",
        8,
        &format!("{key}.max_m"),
        &["must be above min_m"],
    );
    let t = voronoi("kind = \"power_law\", exponent = 0.0, min_m = 100.0, max_m = 300.0");
    check(
        &t,
        "0.0, min_m",
        0,
        &format!("{key}.exponent"),
        &["(0, 20]"],
    );
    let t = voronoi("kind = \"power_law\", exponent = -1.5, min_m = 100.0, max_m = 300.0");
    check(&t, "-1.5", 0, &format!("{key}.exponent"), &["(0, 20]"]);
    let t = voronoi("kind = \"lognormal\", exponent = 2.0, min_m = 100.0, max_m = 300.0");
    check(
        &t,
        "\"lognormal\"",
        0,
        &format!("{key}.kind"),
        &["unknown kind", "power_law"],
    );
    let t = voronoi("kind = \"power_law\", exponent = 2.0, max_m = 300.0");
    check(&t, "{ kind", 0, &format!("{key}.min_m"), &["missing"]);
    let t = voronoi("kind = \"power_law\", exponent = 2.0, min_m = -5.0, max_m = 300.0");
    check(&t, "-5.0", 0, &format!("{key}.min_m"), &["> 0"]);
    // What the 4 km ice region allows.
    let t = voronoi("kind = \"power_law\", exponent = 2.0, min_m = 100.0, max_m = 5000.0");
    check(
        &t,
        "5000.0",
        0,
        &format!("{key}.max_m"),
        &["wider than the ice region's shorter side, 4000 m"],
    );
    let t = voronoi("kind = \"power_law\", exponent = 3.0, min_m = 0.5, max_m = 300.0");
    check(
        &t,
        "0.5, max_m",
        0,
        &format!("{key}.min_m"),
        &["above the limit of 200,000", "allows min_m of at least"],
    );
    let t = voronoi("kind = \"power_law\", exponent = 2.0, min_m = 20.0, max_m = 300.0").replace(
        "kind = \"voronoi\"",
        "kind = \"voronoi\"\nrelax_iterations = 500",
    );
    check(
        &t,
        "500",
        0,
        "tessellation.relax_iterations",
        &["above the limit", "iterations"],
    );
    // With the floes' count or scale, or on another kind.
    let t = voronoi("kind = \"power_law\", exponent = 2.0, min_m = 100.0, max_m = 300.0")
        .replace("kind = \"voronoi\"", "kind = \"voronoi\"\ncount = 10");
    check(&t, "10\n", 0, "tessellation.count", &["not both"]);
    let t = edit(
        "kind = \"grid\"\ncolumns = 2\nrows = 2\ngap_m = 100.0",
        "kind = \"diamond\"\nside_m = 500.0\nsize_distribution = { kind = \"power_law\", exponent = 2.0, min_m = 100.0, max_m = 300.0 }",
    );
    check(&t, "{ kind", 0, key, &["does not apply to kind `diamond`"]);
    // A valid one builds, and says what it made.
    let t = voronoi("kind = \"power_law\", exponent = 2.0, min_m = 100.0, max_m = 800.0");
    let s = Scenario::from_text(&t, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert!(
        s.report.iter().any(|l| l.contains("Laguerre cells")),
        "{:?}",
        s.report
    );
    assert!(s.report.iter().any(|l| l.contains("fitted exponent")));
}

#[test]
fn floe_stress_takes_a_positive_time_scale_and_nothing_else() {
    let t = format!("{BASE}\n[floe_stress]\ntime_scale_s = 0.0\n");
    check(
        &t,
        "time_scale_s = 0.0",
        15,
        "floe_stress.time_scale_s",
        &["> 0", "got 0"],
    );
    let t = format!("{BASE}\n[floe_stress]\ntime_scale_s = -30.0\n");
    check(&t, "-30.0", 0, "floe_stress.time_scale_s", &["> 0"]);
    let t = format!("{BASE}\n[floe_stress]\ntimescale_s = 30.0\n");
    check(&t, "timescale_s", 0, "timescale_s", &["unknown field"]);
    // The table alone: the anchors' averaging, 44.8 s.
    let t = format!("{BASE}\n[floe_stress]\n");
    let setup = Scenario::from_text(&t, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    let filter = setup.world.stress_filter().expect("floe stress on");
    assert!((filter.time_scale_s + 10.0 / 0.8f64.ln()).abs() < 1e-12);
    assert!(
        setup
            .report
            .iter()
            .any(|l| l.contains("averaged over 44.81 s")),
        "{:?}",
        setup.report
    );
    let plain = Scenario::from_text(BASE, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert!(plain.world.stress_filter().is_none() && plain.world.floe_stress().is_empty());
}

#[test]
fn ridging_tables_are_checked_key_by_key() {
    let with = |table: &str| format!("{BASE}\n[ridging]\n{table}\n");
    for key in ["strength_n_per_m", "max_thickness_m", "min_floe_area_m2"] {
        let text = with(&format!("{key} = -2.5"));
        check(&text, "-2.5", 0, &format!("ridging.{key}"), &["> 0"]);
        let text = with(&format!("{key} = nan"));
        check(&text, "nan", 0, &format!("ridging.{key}"), &[]);
    }
    check(
        &with("thickness_exponent = -0.5"),
        "-0.5",
        0,
        "ridging.thickness_exponent",
        &[">= 0"],
    );
    check(
        &with("rubble = \"loser\""),
        "\"loser\"",
        0,
        "ridging.rubble",
        &["`gainer`", "`both`"],
    );
    let shared = Scenario::from_text(&with("rubble = \"both\""), Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert_eq!(
        shared.world.ridging().map(|r| r.rubble),
        Some(floe_dem::ridging::Rubble::Both)
    );
    assert!(
        shared
            .report
            .iter()
            .any(|l| l.contains("goes to both floes by area")),
        "{:?}",
        shared.report
    );
    check(
        &with("strength = 1e5"),
        "strength",
        0,
        "strength",
        &["unknown field"],
    );
    // The table alone: the defaults, reported.
    let setup = Scenario::from_text(&with(""), Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert_eq!(
        setup.world.ridging(),
        Some(floe_dem::ridging::Ridging::default())
    );
    assert!(
        setup
            .report
            .iter()
            .any(|l| l
                .contains("ridging: a floe up to 5 m thick bears at most 100000 h^1.5 N per m")),
        "{:?}",
        setup.report
    );
    let plain = Scenario::from_text(BASE, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert!(plain.world.ridging().is_none());
    // The event log: off by default, refused without ridging to log.
    let log = "\n[output]\nridging_log = true\n";
    check(
        &format!("{BASE}{log}"),
        "ridging_log = true",
        14,
        "output.ridging_log",
        &["no [ridging] table"],
    );
    check(
        &format!("{}{}", with(""), "\n[output]\nridging_log = 1\n"),
        "ridging_log = 1",
        14,
        "ridging_log",
        &["bool"],
    );
    let logged = Scenario::from_text(&format!("{}{log}", with("")), Path::new("ok.toml")).unwrap();
    assert!(logged.output().ridging_log);
    let unlogged = Scenario::from_text(&with(""), Path::new("ok.toml")).unwrap();
    assert!(!unlogged.output().ridging_log);
}

#[test]
fn welding_tables_are_checked_key_by_key() {
    let cohesion = "\n[cohesion]\n";
    let with = |table: &str| format!("{BASE}{cohesion}\n[welding]\n{table}\n");
    for key in [
        "after_s",
        "max_added_area_fraction",
        "max_centre_shift_fraction",
        "check_every_s",
    ] {
        let text = with(&format!("{key} = -2.5"));
        check(&text, "-2.5", 0, &format!("welding.{key}"), &[">= 0"]);
        let text = with(&format!("{key} = inf"));
        check(&text, "inf", 0, &format!("welding.{key}"), &[]);
    }
    check(
        &with("max_area_m2 = 0.0"),
        "max_area_m2 = 0.0",
        14,
        "welding.max_area_m2",
        &["> 0"],
    );
    check(
        &with("after = 1.0"),
        "after",
        0,
        "after",
        &["unknown field"],
    );
    // Welding joins bonds: without [cohesion] it is refused at its table.
    check(
        &format!("{BASE}\n[welding]\nafter_s = 10.0\n"),
        "[welding]",
        0,
        "welding",
        &["no [cohesion] table"],
    );
    // The table alone: the defaults, reported.
    let setup = Scenario::from_text(&with(""), Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert_eq!(
        setup.world.welding(),
        Some(floe_dem::welding::Welding::default())
    );
    assert!(
        setup.report.iter().any(|l| l.contains(
            "welding: floes bonded for 172800 s become their convex hull if it adds at most 5 %"
        )),
        "{:?}",
        setup.report
    );
    let plain = Scenario::from_text(&format!("{BASE}{cohesion}"), Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert!(plain.world.welding().is_none());
}

#[test]
fn cohesion_tables_are_checked_key_by_key() {
    let with = |table: &str| format!("{BASE}\n[cohesion]\n{table}\n");
    check(
        &with("quiet_speed_m_per_s = 0.0"),
        "quiet_speed_m_per_s = 0.0",
        22,
        "cohesion.quiet_speed_m_per_s",
        &["> 0"],
    );
    for key in [
        "bond_after_s",
        "tensile_strength_n_per_m",
        "shear_strength_n_per_m",
        "growth_time_s",
    ] {
        let text = with(&format!("{key} = -1.0"));
        check(&text, "-1.0", 0, &format!("cohesion.{key}"), &[">= 0"]);
        let text = with(&format!("{key} = nan"));
        check(&text, "nan", 0, &format!("cohesion.{key}"), &[]);
    }
    check(
        &with("tensile_strength = 1e4"),
        "tensile_strength",
        0,
        "tensile_strength",
        &["unknown field"],
    );
    check(
        &with("bond_after_s = \"1 h\""),
        "\"1 h\"",
        0,
        "bond_after_s",
        &[],
    );
    // The table alone: the defaults, reported.
    let setup = Scenario::from_text(&with(""), Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert_eq!(
        setup.world.cohesion(),
        Some(floe_dem::cohesion::Cohesion::default())
    );
    assert!(
        setup
            .report
            .iter()
            .any(|l| l.contains("cohesion: contacts slower than 1e-4 m/s for 3600 s")),
        "{:?}",
        setup.report
    );
    let plain = Scenario::from_text(BASE, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
    assert!(plain.world.cohesion().is_none());
    // With Hibler's ellipse (no tensile strength) the report says what
    // bonds will do; not with the cone.
    let note = "no tensile strength, so a bond that pulls breaks";
    for (criterion, noted) in [("hibler", true), ("mohr_coulomb", false)] {
        let text = format!(
            "{BASE}\n[cohesion]\n\n[fracture]\ncriterion = \"{criterion}\"\nmin_floe_area_m2 = 1e5\n"
        );
        let setup = Scenario::from_text(&text, Path::new("ok.toml"))
            .unwrap()
            .build()
            .unwrap();
        assert_eq!(
            setup.report.iter().any(|l| l.contains(note)),
            noted,
            "{criterion}"
        );
    }
}

#[test]
fn fracture_tables_are_checked_key_by_key() {
    let with = |table: &str| format!("{BASE}\n[fracture]\n{table}\n");
    check(
        &with("check_every_s = 10.0"),
        "[fracture]",
        0,
        "fracture.criterion",
        &["missing", "mohr_coulomb"],
    );
    let t = with("criterion = \"griffith\"");
    check(
        &t,
        "\"griffith\"",
        0,
        "fracture.criterion",
        &["\"mohr_coulomb\" or \"hibler\""],
    );
    let t = with("criterion = \"mohr_coulomb\"\np_star_pa_per_m = 1e5");
    check(
        &t,
        "1e5",
        0,
        "fracture.p_star_pa_per_m",
        &["does not apply to criterion \"mohr_coulomb\""],
    );
    let t = with("criterion = \"hibler\"\nq = 3.0");
    check(
        &t,
        "q = 3.0",
        4,
        "fracture.q",
        &["does not apply to criterion \"hibler\""],
    );
    let t = with("criterion = \"mohr_coulomb\"\nq = 0.5");
    check(&t, "q = 0.5", 4, "fracture.q", &["> 1"]);
    let t = with("criterion = \"mohr_coulomb\"\nsigma_11_pa = -1e6");
    check(&t, "-1e6", 0, "fracture.sigma_11_pa", &["outside the cone"]);
    let t = with("criterion = \"hibler\"\nc = -1.0");
    check(&t, "c = -1.0", 4, "fracture.c", &[">= 0"]);
    let t = with("criterion = \"hibler\"\nstrength_thickness = \"mean\"");
    check(
        &t,
        "\"mean\"",
        0,
        "fracture.strength_thickness",
        &["\"own\"", "\"pack\""],
    );
    let t = with("criterion = \"hibler\"\ncheck_every_s = 0.0");
    check(
        &t,
        "check_every_s = 0.0",
        16,
        "fracture.check_every_s",
        &["> 0"],
    );
    let t = with("criterion = \"hibler\"\npieces = 1");
    check(&t, "pieces = 1", 9, "fracture.pieces", &["from 2 to 16"]);
    let t = with("criterion = \"hibler\"\nmin_floe_area_m2 = -5.0");
    check(&t, "-5.0", 0, "fracture.min_floe_area_m2", &[">= 0"]);
    let t = with("criterion = \"hibler\"\nnpieces = 3");
    check(&t, "npieces", 0, "npieces", &["unknown field"]);
    // A good table: floe stress on, the rule in whole steps, the seed.
    let s = Scenario::from_text(
        &with("criterion = \"hibler\"\ncheck_every_s = 30.0"),
        Path::new("ok.toml"),
    )
    .unwrap();
    let setup = s.build().unwrap();
    assert!(setup.world.stress_filter().is_some());
    let f = setup.world.fracturing().expect("fracture on");
    assert_eq!(f.rule.check_every_steps, (30.0 / setup.dt_s).round() as u64);
    assert_eq!(f.rule.split.pieces, 3);
    assert_eq!(f.rule.min_floe_area_m2, 1e6);
    assert!((f.rule.split.min_piece_area_m2 - 1e6 / 6.0).abs() < 1e-6);
    assert_eq!(f.domain_area_m2, 4000.0 * 4000.0);
    assert!(
        setup
            .report
            .iter()
            .any(|l| l.starts_with("fracture: Hibler's ellipse")),
        "{:?}",
        setup.report
    );
    // The automatic step was shortened for the smallest piece.
    assert!(
        setup.report.iter().any(|l| l.contains("shortened to")),
        "{:?}",
        setup.report
    );
    // A given step too long for the pieces is refused at the piece area.
    let t = edit("duration_s = 100.0", "duration_s = 100.0\ndt_s = 4.0")
        + "\n[fracture]\ncriterion = \"hibler\"\nmin_piece_area_m2 = 100000.0\n";
    check(
        &t,
        "100000.0",
        0,
        "fracture.min_piece_area_m2",
        &["time step", "shorter dt_s"],
    );
    let t = with("criterion = \"hibler\"\nmin_floe_area_m2 = 3e5\nmin_piece_area_m2 = 2e5");
    check(
        &t,
        "2e5",
        0,
        "fracture.min_piece_area_m2",
        &["do not fit", "at most 100000"],
    );
    // Only sigma_c given: the cap keeps its place relative to it.
    let t = with("criterion = \"mohr_coulomb\"\nsigma_c_pa = 5000.0");
    Scenario::from_text(&t, Path::new("ok.toml"))
        .unwrap()
        .build()
        .unwrap();
}
