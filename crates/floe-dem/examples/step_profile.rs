//! Where a DEM step's time goes (docs/performance.md):
//! `cargo run --release -p floe-dem --example step_profile -- 10000 [amontons|rate-state] [threads] [steps] [stress|cohesion]`
//! prints the time per step and a fingerprint of the final state (`stress`:
//! with floe stress on, the default average; `cohesion`: every contact
//! bonded at once, none breaking);
//! `... --example step_profile -- full [threads]` only the fingerprint of a
//! run with walls, forcing and contact memory (see `full_scenario`).
use floe_fixtures::channel as channel_pack;

use floe_friction::rate_state::{SOLVER_GUESS, SOLVER_TREND, THETA};

fn main() {
    if std::env::args().nth(1).as_deref() == Some("full") {
        full_scenario();
        return;
    }
    let n: usize = arg(1, 10_000);
    pool_of(arg(3, 1)).install(|| {
        let law = std::env::args().nth(2).unwrap_or_default();
        let model = match law.as_str() {
            "amontons" => channel_pack::amontons_model(),
            _ => floe_dem::contact_model::ContactModel::default(),
        };
        eprintln!("rayon threads in use: {}", rayon::current_num_threads());
        let mut w = channel_pack::sheared_channel_with(n, model);
        match std::env::args().nth(5).as_deref() {
            Some("stress") => w.set_stress_filter(Some(Default::default())),
            // Every contact bonds at once and no bond breaks: cohesion's
            // most work per contact.
            Some("cohesion") => w
                .set_cohesion(Some(floe_dem::cohesion::Cohesion {
                    quiet_speed_m_per_s: 1e3,
                    bond_after_s: 0.0,
                    tensile_strength_n_per_m: 1e15,
                    shear_strength_n_per_m: 1e15,
                    growth_time_s: 0.0,
                }))
                .expect("valid cohesion"),
            _ => {}
        }
        let r0 = w.broad_phase().rebuilds;
        let t = std::time::Instant::now();
        let steps: usize = arg(4, 20);
        // The step's four stages called one by one (as `World::step` does),
        // each timed: wall seconds in drift, contacts, forces, kick.
        let mut stage_s = [0.0; 4];
        for _ in 0..steps {
            let mut lap = std::time::Instant::now();
            let mut mark = |k: usize| {
                stage_s[k] += lap.elapsed().as_secs_f64();
                lap = std::time::Instant::now();
            };
            w.drift();
            mark(0);
            w.detect_contacts();
            mark(1);
            w.gather_forces();
            mark(2);
            w.kick();
            mark(3);
        }
        let per_step = t.elapsed().as_secs_f64() / steps as f64;
        println!(
            "{} floes, {} contacts, {} candidate pairs, {} rebuilds in {steps} steps, {:.2} ms/step, {:.0} ns per contact",
            w.floes().len(),
            w.contacts().len(),
            w.broad_phase().pairs.len(),
            w.broad_phase().rebuilds - r0,
            per_step * 1e3,
            per_step * 1e9 / w.contacts().len() as f64
        );
        let total: f64 = stage_s.iter().sum();
        println!(
            "stages: drift {:.1} %, contact detection (broad and narrow phase, friction) {:.1} %, force gathering (with the contacts' power sums) {:.1} %, kick {:.1} %",
            100.0 * stage_s[0] / total,
            100.0 * stage_s[1] / total,
            100.0 * stage_s[2] / total,
            100.0 * stage_s[3] / total
        );
        // Bit pattern of the final state, to check that a speed change left
        // the numbers unchanged (compare across code versions and thread counts).
        println!("state fingerprint {:016x}", fingerprint(&w));
        // Cost of one broad-phase rebuild, against the step it would add to.
        let mut bp = floe_dem::pipeline::broad_phase::BroadPhase::new(w.broad_phase().skin_m);
        let trig: Vec<(f64, f64)> = w.floes().angle.iter().map(|a| a.sin_cos()).collect();
        let t = std::time::Instant::now();
        let reps = 5;
        for _ in 0..reps {
            bp.rebuild(w.floes(), &trig, w.periodicity());
        }
        let rebuild = t.elapsed().as_secs_f64() / reps as f64;
        println!(
            "broad-phase rebuild {:.2} ms ({:.0} % of a step); skin {:.0} m; a floe at 0.1 m/s and dt {:.2} s crosses half the skin in {:.0} steps",
            rebuild * 1e3,
            100.0 * rebuild / per_step,
            bp.skin_m,
            w.dt_s(),
            0.5 * bp.skin_m / (0.1 * w.dt_s())
        );
    });
}

/// Command-line argument `i` as a number, or `default`.
fn arg(i: usize, default: usize) -> usize {
    std::env::args()
        .nth(i)
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// A rayon pool of `threads` threads.
fn pool_of(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

/// FNV-1a over the bits of every floe's position, velocity, angle and
/// angular velocity, and every contact's forces and friction state.
fn fingerprint<F: floe_dem::forcing::ExternalForces>(w: &floe_dem::world::World<F>) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325_u64;
    let mut mix = |x: f64| {
        for b in x.to_bits().to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    let f = &w.floes();
    for i in 0..f.len() {
        mix(f.position[i].x);
        mix(f.position[i].y);
        mix(f.velocity[i].x);
        mix(f.velocity[i].y);
        mix(f.angle[i]);
        mix(f.angular_velocity[i]);
    }
    for c in w.contacts() {
        mix(c.normal_force_n);
        mix(c.friction.tangential_force_n);
        mix(c.friction.law_state[THETA]);
        mix(c.friction.law_state[SOLVER_GUESS]);
        mix(c.friction.law_state[SOLVER_TREND]);
        mix(c.normal_energy_j);
        mix(c.tangential_energy_j);
    }
    mix(w.energy().friction_dissipation_j);
    h
}

/// `step_profile full [threads]`: a fingerprint of a run that exercises
/// what the sheared channel does not: jittered floes of mixed thickness,
/// walls (the bottom row fixed, the top row moving), free floes spreading
/// apart so that contacts break as well as form, wind and current with
/// Coriolis, sea-surface tilt and rotational drag, contact memory short
/// enough (1 s) that remembered contacts also expire within the run. The
/// fingerprint also covers the remembered broken contacts and every entry
/// of the energy ledger. The run is 3,000 steps of about a millisecond, so
/// the forcing's effect is small (`f t` is about 6e-4): it checks that a
/// change meant to leave results alone does so on these code paths, not
/// the physics.
fn full_scenario() {
    use floe_dem::contact_model::ContactModel;
    use floe_dem::floes::{Floes, Motion};
    use floe_dem::forcing::{Coriolis, Forcing, VelocityField};
    use floe_dem::periodicity::{Period, Periodicity};
    use floe_dem::tessellation::{DiamondLattice, Rect, ThicknessDistribution};
    use floe_dem::world::{stable_time_step, World};
    use floe_dem::Vec2;
    pool_of(arg(2, 1)).install(|| {
        let (side, width) = (1000.0, 20_000.0);
        let lattice = DiamondLattice {
            domain: Rect {
                min: Vec2::new(0.0, 0.0),
                max: Vec2::new(4.0 * width, width),
            },
            side_m: side,
            acute_angle_deg: 60.0,
            orientation_deg: 0.0,
            thickness: ThicknessDistribution::UniformRange {
                min_m: 0.5,
                max_m: 2.0,
            },
            jitter_fraction: 0.05,
            seed: 7,
        };
        let t = lattice.build().expect("lattice");
        let mut floes = Floes::from_polygons(&t.polygons, &t.thickness_m, 917.0).expect("floes");
        for i in 0..floes.len() {
            let y = floes.position[i].y;
            let velocity = if y < side {
                Vec2::ZERO
            } else if y > width - side {
                Vec2::new(0.05, 0.0)
            } else {
                // Free floes start spreading apart along x from every
                // tenth column of the lattice, so that contacts break
                // (and are remembered) as well as form.
                let x = floes.position[i].x;
                floes.set_velocity(i, Vec2::new(if (x / side) as i64 % 10 < 5 { -0.2 } else { 0.2 }, 0.0), floes.angular_velocity[i]);
                continue;
            };
            floes.set_motion(i, Motion::Prescribed { velocity });
        }
        let model = ContactModel {
            memory_s: 1.0,
            ..ContactModel::default()
        };
        let forcing = Forcing {
            wind: VelocityField::Uniform(Vec2::new(10.0, 2.0)),
            current: VelocityField::Uniform(Vec2::new(0.05, 0.0)),
            coriolis: Coriolis::LatitudeDeg(75.0),
            ..Forcing::default()
        };
        let periodic = Periodicity {
            x: Some(Period {
                min_m: 0.0,
                length_m: 4.0 * width,
            }),
            y: None,
        };
        let dt = 0.5 * stable_time_step(&floes, &model).0;
        let mut w = World::new(floes, model, forcing, periodic, dt).expect("world");
        for _ in 0..3000 {
            w.step();
        }
        let mut h = fingerprint(&w);
        let mut mix = |x: f64| {
            for b in x.to_bits().to_le_bytes() {
                h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
            }
        };
        for c in w.broken_contacts() {
            mix(f64::from(c.a));
            mix(f64::from(c.b));
            mix(c.friction.law_state[THETA]);
            mix(c.broke_at_s);
        }
        let e = w.energy();
        for x in [
            e.forcing_work_j,
            e.friction_dissipation_j,
            e.damping_dissipation_j,
            e.boundary_work_j,
            e.released_at_break_j,
        ] {
            mix(x);
        }
        println!(
            "full scenario: {} floes, {} contacts, {} broken remembered, {:.0} s in steps of {:.3} s, {:?}, {} threads; fingerprint {h:016x}",
            w.floes().len(),
            w.contacts().len(),
            w.broken_contacts().len(),
            w.time_s(),
            w.dt_s(),
            w.energy(),
            rayon::current_num_threads()
        );
    });
}
