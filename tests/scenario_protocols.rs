//! The paper's slide-hold-slide and velocity step through the DEM
//! (`scenarios/*_double_shear_protocol.toml`) against `floe slider` with
//! the same law, normal load, series stiffness and protocol: each hold's
//! peak friction and delta mu, and the step's, within 3 %, except the
//! tank's tenfold step, where the 917 kg block's inertia (the slider has
//! none) adds 3-6 %: that difference falls about as the block's mass.

use std::path::Path;

use floe_friction::protocol::{Protocol, Segment};
use floe_friction::spring_slider::{Apparatus, SpringSlider};
use floe_scenario::{checks, Scenario};

/// Runs `f` on a one-thread rayon pool (stepping from outside a pool hands
/// every parallel loop to another thread).
fn pooled<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(f)
}

/// What one run of a protocol gives: `(t, mu)` and the pusher's segments
/// `(velocity, duration)`.
struct Record {
    mu: Vec<(f64, f64)>,
    segments: Vec<(f64, f64)>,
}

/// The DEM run: friction as the push force (the pusher contact's normal
/// force) over the normal load on both faces.
fn dem(text: &str, load_per_face: f64) -> Record {
    let s = Scenario::from_text(text, Path::new("protocol.toml")).unwrap();
    let mut w = s.build().unwrap().world;
    let schedule = w.schedules()[0].schedule.clone();
    let pusher = w.floes().handle_of(w.schedules()[0].floe_id).unwrap() as u32;
    let steps = (s.duration_s() / w.dt_s()).round() as usize;
    let mut mu = Vec::with_capacity(steps);
    for _ in 0..steps {
        w.step();
        let push: f64 = w
            .contacts()
            .iter()
            .filter(|c| c.a == pusher || c.b == pusher)
            .map(|c| c.normal_force_n)
            .sum();
        mu.push((w.time_s(), push / (2.0 * load_per_face)));
    }
    let segments = schedule
        .segments()
        .iter()
        .map(|g| (g.velocity_start.x, g.duration_s))
        .collect();
    Record { mu, segments }
}

/// The spring-slider with the scenario's law, the series stiffness of the
/// pusher and side contacts, the load on both faces, and the same segments.
fn slider(
    text: &str,
    geometry: (f64, [f64; 2], [f64; 2], f64),
    segments: &[(f64, f64)],
) -> Vec<(f64, f64)> {
    let s = Scenario::from_text(text, Path::new("protocol.toml")).unwrap();
    let (h, block, pusher, load) = geometry;
    let g = checks::double_shear_geometry(s.contact_model(), h, block, pusher, load);
    let dt = 1e-3;
    let apparatus = Apparatus::new(g.series_stiffness_n_per_m, 2.0 * load, dt).unwrap();
    let mut slider = SpringSlider::new(s.contact_model().law.clone(), apparatus, segments[0].0);
    let protocol = Protocol::new(
        segments
            .iter()
            .map(|&(v, d)| Segment::constant(v, d))
            .collect(),
    )
    .unwrap();
    let mut mu = Vec::new();
    slider.run(&protocol, |p| mu.push((p.t_s, p.mu)));
    mu
}

/// Mean of `series` over `[t0, t1)`.
fn mean(series: &[(f64, f64)], t0: f64, t1: f64) -> f64 {
    let v: Vec<f64> = series
        .iter()
        .filter(|s| s.0 >= t0 && s.0 < t1)
        .map(|s| s.1)
        .collect();
    v.iter().sum::<f64>() / v.len() as f64
}

/// Largest value of `series` over `[t0, t1)`.
fn peak(series: &[(f64, f64)], t0: f64, t1: f64) -> f64 {
    series
        .iter()
        .filter(|s| s.0 >= t0 && s.0 < t1)
        .map(|s| s.1)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// One hold or step: what it is, and the DEM's relative differences from
/// the slider in the peak and in delta mu.
struct Event {
    what: String,
    peak: f64,
    delta_mu: f64,
}

/// Per hold (and the final step): steady mu before, peak after, in the DEM
/// and the slider, printed; the relative differences returned.
fn compare(name: &str, dem: &Record, slider: &[(f64, f64)]) -> Vec<Event> {
    let mut t = 0.0;
    let mut events = Vec::new();
    for (k, &(v, d)) in dem.segments.iter().enumerate() {
        let before = dem.segments.get(k.wrapping_sub(1)).map(|s| s.0);
        let what = match (before, v) {
            (Some(b), v) if b > 0.0 && v == 0.0 => Some(format!("hold {d} s")),
            (Some(b), v) if b > 0.0 && v > b => Some(format!("step to {v} m/s")),
            _ => None,
        };
        if let Some(what) = what {
            // The hold's peak comes when sliding resumes, after it.
            let (from, to) = if v == 0.0 {
                (t + d, t + d + dem.segments[k + 1].1)
            } else {
                (t, t + d)
            };
            events.push((what, t, from, to));
        }
        t += d;
    }
    assert!(events.len() >= 4, "{name}: {} events", events.len());
    eprintln!("{name}: event, steady mu before (DEM, slider), peak, delta mu, differences");
    let mut out = Vec::new();
    for (what, start, from, to) in events {
        let window = 2.0f64.min(0.1 * start);
        let (ss_d, ss_s) = (
            mean(&dem.mu, start - window, start),
            mean(slider, start - window, start),
        );
        let (p_d, p_s) = (peak(&dem.mu, from, to), peak(slider, from, to));
        let (dm_d, dm_s) = (p_d - ss_d, p_s - ss_s);
        let (e_peak, e_dmu) = ((p_d - p_s) / p_s, (dm_d - dm_s) / dm_s);
        eprintln!(
            "  {what}: steady {ss_d:.5} {ss_s:.5}, peak {p_d:.5} {p_s:.5}, delta mu {dm_d:.5} {dm_s:.5}, \
             {:+.2} % {:+.2} %",
            100.0 * e_peak,
            100.0 * e_dmu
        );
        out.push(Event {
            what,
            peak: e_peak,
            delta_mu: e_dmu,
        });
    }
    out
}

/// Every event within 3 % of the slider in its peak and delta mu.
fn assert_within_3_percent(name: &str, events: &[Event]) {
    for e in events {
        assert!(
            e.peak.abs() < 0.03 && e.delta_mu.abs() < 0.03,
            "{name} {}: peak {:+.2} %, delta mu {:+.2} %",
            e.what,
            100.0 * e.peak,
            100.0 * e.delta_mu
        );
    }
}

#[test]
fn the_tank_protocol_through_the_dem_matches_the_spring_slider() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/tank_double_shear_protocol.toml"),
    )
    .unwrap();
    let geometry = (0.25, [2.0, 2.0], [0.5, 2.0], 5e3);
    let record = pooled(|| dem(&text, 5e3));
    let reference = slider(&text, geometry, &record.segments);
    let events = compare("tank", &record, &reference);
    let (step, holds) = events.split_last().unwrap();
    assert_within_3_percent("tank", holds);
    // After the tenfold step the 917 kg block, unlike the massless slider,
    // must be accelerated through the spring, and overshoots the new speed.
    // A block 9.17 times lighter (density 100) brings the step within 3 %:
    // the difference falls about as the mass (measured 7.9 times), the
    // inertial force m dv/dt of the block's acceleration.
    let light = text.replace("[ice]\n", "[ice]\ndensity_kg_per_m3 = 100.0\n");
    assert_ne!(light, text);
    let record = pooled(|| dem(&light, 5e3));
    let events = compare("tank, block 9.17 x lighter", &record, &reference);
    let light_step = events.last().unwrap();
    assert_within_3_percent("tank, light block", &events);
    let ratio = step.delta_mu / light_step.delta_mu;
    eprintln!("step: delta mu differences fall {ratio:.2} times for a 9.17 times lighter block");
    assert!(
        (4.0..12.0).contains(&ratio),
        "delta mu differences {:.4} and {:.4}: ratio {ratio:.2}, mass ratio 9.17",
        step.delta_mu,
        light_step.delta_mu
    );
}

#[test]
fn the_lab_protocol_through_the_dem_matches_the_spring_slider() {
    // Without the 1000 s hold (26 million steps of 39 us): holds of 1, 10
    // and 100 s and the step.
    let full = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/lab_double_shear_protocol.toml"),
    )
    .unwrap();
    let long_hold = "[[tessellation.segment]]     # hold\nduration_s = 1000.0\n\n\
                     [[tessellation.segment]]\nduration_s = 10.0\nvelocity_m_per_s = [0.0001, 0.0]\n\n";
    assert!(full.contains(long_hold));
    let text = full
        .replace(long_hold, "")
        .replace("duration_s = 1172.0", "duration_s = 162.0");
    let record = pooled(|| dem(&text, 1e3));
    let reference = slider(&text, (0.1, [0.2, 0.1], [0.05, 0.1], 1e3), &record.segments);
    assert_within_3_percent("lab", &compare("lab", &record, &reference));
}
