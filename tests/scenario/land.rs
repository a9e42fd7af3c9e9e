//! Land from `[[land]]` GeoJSON files in scenarios: floes driven at 10 m/s
//! into a concave coast (a bay with a sharp corner, a 100 m spit) and a
//! 150 m island never pass through land, at the time step the scenario
//! machinery picks and with the run's blow-up checks after every step; the tessellated ice starts off land; land pieces are
//! fixed. `cargo test --release -p floe-scenario --test scenario land:: --
//! --nocapture` prints the largest overlap.

use std::path::Path;

use floe_basin::{read_land, Coordinates, Land};
use floe_dem::Vec2;
use floe_scenario::Scenario;

/// The coast (feature 0: land east of x = 14 km with a wedge-shaped bay
/// whose tip is a 52 degree corner, and a 5 km spit 100 m wide) and a thin
/// island (feature 1: 150 m x 4 km across the ice's path), in metres.
const COAST: &str = r#"{"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"name": "coast"}, "geometry": {"type": "Polygon", "coordinates": [[
    [14000, -3000], [26000, -3000], [26000, 16000], [14000, 16000],
    [14000, 11050], [9000, 11050], [9000, 10950], [14000, 10950],
    [14000, 8000], [19000, 5000], [14000, 3000], [14000, -3000]]]}},
  {"type": "Feature", "properties": {"name": "island"}, "geometry": {"type": "Polygon", "coordinates": [[
    [10925, -1500], [11075, -1500], [11075, 2500], [10925, 2500], [10925, -1500]]]}}
]}"#;

/// Voronoi floes of about 700 m (the smallest, below half the mean area,
/// dropped) filling the domain, the bay included, all moving at 10 m/s
/// towards the land (and slightly north, onto the spit's flank), pushed on
/// by a gale; no ocean drag, so that they arrive at 10 m/s. Contacts ten
/// times stiffer than the default: an overlap-area contact stops a floe
/// within a depth of about `v s sqrt(rho / E)` (floe size `s`), 12 % of
/// the floe at 10 m/s with the default 6 MPa, and a pack ramming itself
/// at up to 15 m/s (floes bouncing off the coast into the next ones) then
/// trips the run's blow-up check (a quarter of the smaller floe) between
/// floes, not at the land. At 60 MPa the depth is 4 % (and dt a third).
const SCENARIO: &str = r#"title = "floes rammed into a coast at 10 m/s"
duration_s = 1400.0
seed = 3

[domain]
size_m = [20000.0, 16000.0]
min_m = [0.0, -3000.0]

[tessellation]
kind = "voronoi"
floe_scale_m = 700.0
min_area_fraction = 0.5

[ice]
initial_velocity_m_per_s = [9.6, 2.8]

[wind]
velocity_m_per_s = [40.0, 10.0]

[ocean]
drag_coefficient = 0.0

[contact]
youngs_modulus_pa = 6.0e7

[[land]]
file = "coast.geojson"
coordinates = "xy"
"#;

fn world_polygon(f: &floe_dem::floes::Floes, i: usize) -> Vec<Vec2> {
    f.world_vertices(i)
}

#[test]
fn floes_at_ten_metres_per_second_never_pass_through_land() {
    let dir = tempfile::tempdir().unwrap();
    let geo = dir.path().join("coast.geojson");
    std::fs::write(&geo, COAST).unwrap();
    let path = dir.path().join("coast.toml");
    std::fs::write(&path, SCENARIO).unwrap();
    let scenario = Scenario::load(&path).unwrap();
    let setup = scenario.build().unwrap();
    for line in &setup.report {
        println!("{line}");
    }
    // The land the test judges by: the file's polygons, on their own.
    let polygons = read_land(&geo, Coordinates::Xy, None).unwrap();
    let island = Land::new(vec![polygons[1].clone()], 1e3).unwrap();
    let land = Land::new(polygons, 1e3).unwrap();
    let mut world = setup.world;
    let f = world.floes();
    let free: Vec<usize> = (0..f.len()).filter(|&i| f.is_free(i)).collect();
    assert!(free.len() > 200, "{} free floes", free.len());
    assert!(!setup.land_floe_ids.is_empty());
    // The ice starts off land.
    for &i in &free {
        let on = land.overlap_area_m2(&world_polygon(f, i));
        assert!(
            on <= 1e-6 * f.area_m2[i],
            "floe {i} starts {on} m^2 on land"
        );
    }
    let land_start: Vec<Vec2> = setup
        .land_floe_ids
        .iter()
        .map(|&id| f.position[f.handle_of(id).unwrap()])
        .collect();
    let steps = (scenario.duration_s() / world.dt_s()).round() as u64;
    println!("dt = {} s, {steps} steps", world.dt_s());
    let (mut worst, mut worst_at, mut island_worst) = (0.0f64, 0u64, 0.0f64);
    let mut fastest_on_land = 0.0f64;
    for step in 1..=steps {
        world.step();
        // What `floe run` checks after every step (a blow-up stops it).
        if let Some(b) = floe_dem::run::check_health(&world) {
            panic!("step {step}: {b}");
        }
        let f = world.floes();
        for &i in &free {
            let c = f.position[i];
            assert!(
                !land.contains(c),
                "step {step}: the centroid of floe {} is on land at ({:.1}, {:.1}) m",
                f.id[i],
                c.x,
                c.y
            );
            let poly = world_polygon(f, i);
            let fraction = land.overlap_area_m2(&poly) / f.area_m2[i];
            if fraction > 0.0 {
                fastest_on_land = fastest_on_land.max(f.velocity[i].length());
            }
            if fraction > worst {
                (worst, worst_at) = (fraction, step);
            }
            island_worst = island_worst.max(island.overlap_area_m2(&poly) / f.area_m2[i]);
        }
    }
    println!(
        "largest overlap with land: {:.4} of a floe's area (step {worst_at}); with the island {:.4}; fastest floe touching land {:.2} m/s",
        worst, island_worst, fastest_on_land
    );
    // The ice reached the land, the island too, at speed.
    assert!(island_worst > 1e-3, "no floe hit the island");
    assert!(fastest_on_land > 9.0, "{fastest_on_land} m/s");
    assert!(worst < 0.2, "a floe overlapped land by {worst} of its area");
    // Land did not move.
    let f = world.floes();
    for (&id, &p) in setup.land_floe_ids.iter().zip(&land_start) {
        assert_eq!(f.position[f.handle_of(id).unwrap()], p);
    }
}

#[test]
fn land_in_lonlat_needs_a_map_and_ice_on_land_is_dropped() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("coast.geojson"), COAST).unwrap();
    let text = SCENARIO.replace("coordinates = \"xy\"\n", "");
    let e = Scenario::from_text(&text, &dir.path().join("s.toml"))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("land[0].coordinates") && e.contains("[map]"),
        "{e}"
    );
    let s = Scenario::from_text(SCENARIO, &dir.path().join("s.toml")).unwrap();
    let setup = s.build().unwrap();
    let dropped = setup
        .report
        .iter()
        .find(|l| l.contains("floes on land dropped"))
        .unwrap();
    assert!(!dropped.contains(" 0 floes"), "{dropped}");
    assert!(Path::new(&dir.path().join("coast.geojson")).exists());
}
