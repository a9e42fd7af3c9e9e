//! A 1e6-floe diamond tessellation builds and steps; prints time and memory
//! (docs/performance.md): `cargo run --release -p floe-dem --example million
//! [N] [life-cycle|bonded|stress|cohesion]`: `stress` with floe stress on,
//! `cohesion` with cohesion at its defaults, `life-cycle` with floe stress, fracture (the
//! anchors' cone, checked every step), ridging, cohesion and welding on at
//! their defaults; `bonded` also with every contact bonded at once (the
//! most memory cohesion takes).
use floe_fixtures::channel as channel_pack;

/// A `/proc/self/status` memory line in MB: `VmRSS` (resident now) or
/// `VmHWM` (the peak).
fn status_mb(key: &str) -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb: f64 = status
        .lines()
        .find(|l| l.starts_with(key))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.0);
    kb / 1024.0
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let t0 = std::time::Instant::now();
    // The benchmark's sheared channel: build, world, 20 warm-up steps.
    let mut w = channel_pack::sheared_channel(n);
    let mode = std::env::args().nth(2).unwrap_or_default();
    match mode.as_str() {
        "life-cycle" | "bonded" => life_cycle_on(&mut w, mode == "bonded"),
        "stress" => w.set_stress_filter(Some(Default::default())),
        "cohesion" => w.set_cohesion(Some(Default::default())).expect("cohesion"),
        _ => {}
    }
    let build_s = t0.elapsed().as_secs_f64();
    let t1 = std::time::Instant::now();
    let steps = 5;
    let never = std::sync::atomic::AtomicBool::new(false);
    for _ in 0..steps {
        let report = floe_dem::run::Stepper::step(&mut w, &never);
        assert!(report.blow_up.is_none(), "{:?}", report.blow_up);
    }
    let step_s = t1.elapsed().as_secs_f64() / steps as f64;
    let (rss, peak) = (status_mb("VmRSS:"), status_mb("VmHWM:"));
    let record = std::mem::size_of::<floe_dem::contacts::ContactRecord>();
    let per_floe = |bytes: f64| bytes / w.floes().len() as f64;
    println!(
        "{} floes, {} contacts, {} bonds ({} quiet pairs): build + 20 steps {:.2} s, {:.2} s/step, RSS {:.0} MB = {:.0} B/floe, \
         peak RSS {:.0} MB = {:.0} B/floe \
         (floe arrays {:.0} B/floe, contact records {:.0} B/floe at {} B each)",
        w.floes().len(),
        w.contacts().len(),
        w.bonds().iter().filter(|b| b.formed).count(),
        w.bonds().iter().filter(|b| !b.formed).count(),
        build_s,
        step_s,
        rss,
        per_floe(rss * 1048576.0),
        peak,
        per_floe(peak * 1048576.0),
        per_floe(w.floes().heap_bytes() as f64),
        per_floe((w.state().contacts.capacity() * record) as f64),
        record
    );
}

/// Floe stress, fracture (checked every step), ridging, cohesion and
/// welding on `w` at their defaults; with `all_bonded`, every contact
/// bonds at once and no bond breaks.
fn life_cycle_on<F: floe_dem::forcing::ExternalForces>(
    w: &mut floe_dem::world::World<F>,
    all_bonded: bool,
) {
    use floe_dem::fracture::rule::{FractureRule, Fracturing, StrengthThickness};
    let area: f64 = w.floes().area_m2.iter().sum();
    w.set_fracturing(Some(Fracturing {
        rule: FractureRule {
            criterion: floe_dem::fracture::criteria::FractureCriterion::MohrCoulomb(
                Default::default(),
            ),
            check_every_steps: 1,
            min_floe_area_m2: 1e6,
            split: Default::default(),
            strength_thickness: StrengthThickness::Own,
            seed: 1,
        },
        domain_area_m2: area,
    }))
    .expect("fracture");
    w.set_ridging(Some(Default::default())).expect("ridging");
    let cohesion = if all_bonded {
        floe_dem::cohesion::Cohesion {
            quiet_speed_m_per_s: 1e3,
            bond_after_s: 0.0,
            tensile_strength_n_per_m: 1e15,
            shear_strength_n_per_m: 1e15,
            growth_time_s: 0.0,
        }
    } else {
        Default::default()
    };
    w.set_cohesion(Some(cohesion)).expect("cohesion");
    w.set_welding(Some(Default::default())).expect("welding");
}
