//! A world spread over K processes (threads standing in for MPI ranks)
//! steps bitwise as the single process does: snapshots, contacts with
//! their friction state, the memory of broken contacts, the energy ledger
//! and the checkpointed forces, for K = 1..4 and one or two threads each,
//! on a periodic sheared layer where floes migrate between subdomains and
//! across the periodic seam, against walls, with contact memory, wind and
//! ocean drag.

use floe_dem::cohesion::Cohesion;
use floe_dem::fracture::criteria::{FractureCriterion, MohrCoulomb};
use floe_dem::fracture::rule::{FractureRule, StrengthThickness};
use floe_dem::fracture::split::SplitRule;
use floe_dem::pipeline::floe_stress::StressFilter;
use floe_dem::ridging::Ridging;
use floe_dem::welding::Welding;
use floe_dem::world::FractureEvent;
use floe_dem::world::PlannedRidge;
use std::sync::atomic::AtomicBool;

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floe, Floes};
use floe_dem::forcing::{Forcing, NoForcing, VelocityField};
use floe_dem::geometry::FloeShape;
use floe_dem::periodicity::{Period, Periodicity};
use floe_dem::run::Stepper;
use floe_dem::state::WorldState;
use floe_dem::world::World;
use floe_dem::Vec2;
use floe_friction::experiments::Preset;
use floe_friction::{Form, Law, RateState, StateLaw};
use floe_parallel::{Communicator, DistributedWorld, Settings, ThreadComm};

use crate::shape_support;
use shape_support::rect;

const RHO_ICE: f64 = 917.0;
const NX: usize = 16;
const NY: usize = 6;
const S: f64 = 100.0;

/// Rate-and-state contacts (the tank's parameters) remembered `memory_s`.
fn rate_state(restitution: f64, memory_s: f64) -> ContactModel {
    ContactModel {
        law: Law::RateState(RateState::new(
            Preset::Tank.params(),
            Form::Regularized,
            StateLaw::Slip,
        )),
        restitution,
        memory_s,
        ..ContactModel::default()
    }
}

fn periodic_in_x(length_m: f64) -> Periodicity {
    Periodicity {
        x: Some(Period {
            min_m: 0.0,
            length_m,
        }),
        y: None,
    }
}

/// A layer of jostled squares, periodic in x, between a fixed floor and a
/// lid sliding in +x and pressing down; wind across it.
fn sheared_layer(seed: u64) -> World<Forcing> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut polys = Vec::new();
    for j in 0..NY {
        for i in 0..NX {
            let c = Vec2::new((i as f64 + 0.5) * S, (j as f64 + 0.5) * S);
            polys.push(rect(
                c + Vec2::new(rng.gen_range(-2.0..2.0), rng.gen_range(-0.4..0.4)),
                S * 0.97,
                S * 0.97,
            ));
        }
    }
    let n = polys.len();
    let mut floes = Floes::from_polygons(&polys, &vec![1.0; n], RHO_ICE).unwrap();
    // Rows slide past each other: pairs touch, part, and drift apart.
    let height = NY as f64 * S;
    for i in 0..n {
        let shear = 2.0 * (floes.position[i].y / height - 0.5);
        let v = Vec2::new(shear + rng.gen_range(-0.1..0.1), rng.gen_range(-0.1..0.1));
        floes.set_velocity(i, v, rng.gen_range(-2e-3..2e-3));
    }
    let length = NX as f64 * S;
    let wall = |y: f64| {
        FloeShape::from_world(0, &rect(Vec2::new(0.5 * length, y), length, 200.0)).unwrap()
    };
    let (floor, c0) = wall(-101.0);
    let (lid, c1) = wall(NY as f64 * S + 101.0);
    floes
        .insert(Floe::new(5000, &floor, c0, 1.0, RHO_ICE).prescribed(Vec2::ZERO))
        .unwrap();
    floes
        .insert(Floe::new(5001, &lid, c1, 1.0, RHO_ICE).prescribed(Vec2::new(1.0, -0.03)))
        .unwrap();
    // Memory longer than the run: pairs that part stay remembered.
    let model = rate_state(0.55, 1.0e4);
    let forcing = Forcing {
        wind: VelocityField::Uniform(Vec2::new(-12.0, 3.0)),
        ..Forcing::default()
    };
    let periodicity = periodic_in_x(length);
    let dt = 0.5 * floe_dem::world::stable_time_step(&floes, &model).0;
    let mut world = World::new(floes, model, forcing, periodicity, dt).unwrap();
    // Floe stress travels with migrating floes and is gathered with them.
    world.set_stress_filter(Some(StressFilter::new(30.0).unwrap()));
    world
}

/// The state's every bit, as text (`{:?}` prints each `f64` so that it
/// reads back to the same bits, and `-0.0` apart from `0.0`).
fn bits(state: &WorldState) -> String {
    format!("{state:?}")
}

const STEPS: u64 = 2400;
const EVERY: u64 = 400;

fn single(threads: usize) -> Vec<String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut w = sheared_layer(3);
        let mut out = vec![bits(w.state())];
        while w.steps() < STEPS {
            w.step();
            if w.steps().is_multiple_of(EVERY) {
                out.push(bits(w.state()));
            }
        }
        out
    })
}

struct Parallel {
    states: Vec<String>,
    migrations: u64,
    rebalances: u64,
    owned_ids_changed: bool,
    most_parked: usize,
}

fn parallel(processes: usize, threads: usize, rebalance_threshold: f64) -> Parallel {
    let never = AtomicBool::new(false);
    let results = ThreadComm::run(processes, |comm| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (state, model, forcing, periodicity) = sheared_layer(3).into_parts();
            let settings = Settings {
                skin_fraction: 0.1,
                rebalance_threshold,
            };
            let mut d =
                DistributedWorld::from_whole(state, model, forcing, periodicity, comm, settings)
                    .unwrap();
            let owned_at_start = owned_ids(&d);
            let mut out = Vec::new();
            let mut grab = |d: &mut DistributedWorld<Forcing, ThreadComm>| {
                if let Some(s) = d.gather_whole().unwrap() {
                    out.push(bits(&s));
                }
            };
            grab(&mut d);
            let (mut changed, mut most_parked) = (false, 0);
            while d.steps() < STEPS {
                let report = d.step(&never);
                assert_eq!(report, Default::default(), "nothing ends the run");
                changed |= owned_ids(&d) != owned_at_start;
                most_parked = most_parked.max(d.stats().parked);
                if d.steps().is_multiple_of(EVERY) {
                    grab(&mut d);
                }
            }
            Parallel {
                states: out,
                migrations: d.stats().migrations,
                rebalances: d.stats().rebalances,
                owned_ids_changed: changed,
                most_parked,
            }
        })
    });
    let any_changed = results.iter().any(|r| r.owned_ids_changed);
    let most_parked = results.iter().map(|r| r.most_parked).max().unwrap();
    let mut root = results.into_iter().next().unwrap();
    root.owned_ids_changed = any_changed;
    root.most_parked = most_parked;
    root
}

fn owned_ids<C: Communicator>(d: &DistributedWorld<Forcing, C>) -> Vec<u64> {
    let w = d.local();
    let f = w.floes();
    (0..f.len())
        .filter(|&h| !w.ghosts().get(h).copied().unwrap_or(false))
        .map(|h| f.id[h])
        .collect()
}

#[test]
fn the_layer_moves_across_the_seam_and_keeps_contact_memory() {
    // The test below is only as strong as this run is eventful.
    let mut w = sheared_layer(3);
    let x0: Vec<f64> = w.floes().position.iter().map(|p| p.x).collect();
    let (mut wrapped, mut remembered) = (false, 0usize);
    while w.steps() < STEPS {
        w.step();
        remembered = remembered.max(w.broken_contacts().len());
        let f = w.floes();
        wrapped |= (0..f.len())
            .any(|i| f.is_free(i) && (f.position[i].x - x0[i]).abs() > 0.5 * NX as f64 * S);
    }
    assert!(wrapped, "a floe crossed the periodic seam");
    let stressed = w.floe_stress().iter().filter(|s| s[0] != 0.0).count();
    assert!(stressed > NX * NY / 2, "floes carry stress ({stressed})");
    assert!(remembered > 0, "contacts broke and were remembered");
    assert!(w.energy().friction_dissipation_j > 0.0 && w.energy().forcing_work_j != 0.0);
}

#[test]
fn one_to_four_processes_step_bitwise_as_one() {
    let reference = single(1);
    assert_eq!(reference, single(2), "threads do not change the bits");
    // The last one cuts the domain anew at every migration.
    for (processes, threads, rebalance) in [
        (1, 1, 0.2),
        (2, 1, 0.2),
        (3, 2, 0.2),
        (4, 1, 0.2),
        (3, 1, 1e-9),
    ] {
        let p = parallel(processes, threads, rebalance);
        assert_eq!(p.states.len(), reference.len());
        for (k, (a, b)) in p.states.iter().zip(&reference).enumerate() {
            assert!(
                a == b,
                "{processes} processes x {threads} threads: the state at step {} differs",
                k as u64 * EVERY
            );
        }
        if processes > 1 {
            assert!(p.migrations > 2, "floes migrated ({} times)", p.migrations);
            assert!(p.owned_ids_changed, "a floe changed owner");
        }
        if rebalance < 1e-3 {
            assert!(
                p.rebalances > 2,
                "the domain was cut anew ({} times)",
                p.rebalances
            );
        }
    }
}

/// Two pairs of floes collide, bounce apart, travel round the periodic
/// domain apart (each remembered contact then lives with one floe, its
/// partner owned far away) and meet again: the second contact resumes the
/// first one's friction state, as in one process.
fn bouncing_pairs() -> World<Forcing> {
    let length = 3000.0;
    let polys: Vec<_> = [
        (1300.0, 0.0),
        (1700.0, 0.0),
        (1300.0, 400.0),
        (1700.0, 400.0),
    ]
    .iter()
    .map(|&(x, y)| rect(Vec2::new(x, y), S, S))
    .collect();
    let mut floes = Floes::from_polygons(&polys, &[1.0; 4], RHO_ICE).unwrap();
    for (i, vx) in [(0, 2.0), (1, -2.0), (2, 1.5), (3, -1.5)] {
        // A glancing blow, so the contact slides and its state moves.
        floes.set_velocity(i, Vec2::new(vx, 0.02 * vx), 0.0);
    }
    let model = rate_state(0.9, 1.0e5);
    let forcing = Forcing {
        air: floe_dem::forcing::DragParameters {
            drag_coefficient: 0.0,
            ..floe_dem::forcing::DragParameters::air()
        },
        ocean: floe_dem::forcing::DragParameters {
            drag_coefficient: 0.0,
            ..floe_dem::forcing::DragParameters::ocean()
        },
        ..Forcing::default()
    };
    let periodicity = periodic_in_x(length);
    let dt = 0.5 * floe_dem::world::stable_time_step(&floes, &model).0;
    World::new(floes, model, forcing, periodicity, dt).unwrap()
}

#[test]
fn a_remembered_contact_travels_with_its_floe_and_is_resumed() {
    let never = AtomicBool::new(false);
    // One process: the pairs touch, part, and touch again.
    let mut w = bouncing_pairs();
    let (mut touches, mut touching, mut remembered) = (0, false, false);
    let mut end = 0;
    while end == 0 || w.steps() < end {
        w.step();
        let now = !w.contacts().is_empty();
        touches += usize::from(now && !touching);
        touching = now;
        remembered |= !w.broken_contacts().is_empty();
        if touches == 2 && end == 0 {
            end = w.steps() + 200;
        }
        assert!(w.steps() < 200_000, "the floes met again");
    }
    assert!(remembered);
    let reference = bits(w.state());
    for processes in [2, 4] {
        let got = ThreadComm::run(processes, |comm| {
            let (state, model, forcing, periodicity) = bouncing_pairs().into_parts();
            let mut d = DistributedWorld::from_whole(
                state,
                model,
                forcing,
                periodicity,
                comm,
                Settings::default(),
            )
            .unwrap();
            let mut most_parked = 0;
            while d.steps() < end {
                d.step(&never);
                most_parked = most_parked.max(d.stats().parked);
            }
            (d.gather_whole().unwrap().map(|s| bits(&s)), most_parked)
        });
        assert!(
            got.iter().any(|g| g.1 > 0),
            "a memory was parked with its floe"
        );
        assert!(
            got[0].0.as_ref() == Some(&reference),
            "{processes} processes"
        );
    }
}

/// Two diamonds closing tip to tip across a cut that passes 5 mm from
/// one of them (a third floe sets it there), with a skin of 19 steps'
/// travel: their tips touch in the very step that brings the migration
/// due. The migration must come a step early, or the owner of the first
/// floe misses the contact (found by review: it did).
fn tips_closing(skin_steps: f64) -> (World<NoForcing>, Settings) {
    let diamond = |c: Vec2| {
        [(70.0, 0.0), (0.0, 30.0), (-70.0, 0.0), (0.0, -30.0)]
            .map(|(x, y)| c + Vec2::new(x, y))
            .to_vec()
    };
    let model = rate_state(0.5, 1.0e4);
    let probe = Floes::from_polygons(&[diamond(Vec2::ZERO)], &[1.0], RHO_ICE).unwrap();
    let dt = 0.5 * floe_dem::world::stable_time_step(&probe, &model).0;
    let step = 0.01; // each floe's travel per step, m
    let skin = skin_steps * step;
    let r = probe.radius_m[0];
    let gap = 2.0 * r + skin + 0.006;
    let centres = [
        Vec2::new(-1000.0, 0.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(0.01, 1000.0),
        Vec2::new(gap, 0.0),
    ];
    let polys: Vec<_> = centres.iter().map(|&c| diamond(c)).collect();
    let mut floes = Floes::from_polygons(&polys, &[1.0; 4], RHO_ICE).unwrap();
    let v = step / dt;
    floes.set_velocity(1, Vec2::new(v, 0.0), 0.0);
    floes.set_velocity(3, Vec2::new(-v, 0.0), 0.0);
    let world = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    let settings = Settings {
        skin_fraction: skin / r,
        ..Settings::default()
    };
    (world, settings)
}

#[test]
fn a_contact_that_forms_as_a_migration_comes_due_is_found() {
    let never = AtomicBool::new(false);
    let steps = 30;
    let (mut w, _) = tips_closing(19.0);
    let mut touched_at = None;
    while w.steps() < steps {
        w.step();
        if touched_at.is_none() && !w.contacts().is_empty() {
            touched_at = Some(w.steps());
        }
    }
    assert_eq!(touched_at, Some(10), "the tips touch in step 10");
    let reference = bits(w.state());
    let got = ThreadComm::run(2, |comm| {
        let (world, settings) = tips_closing(19.0);
        let (state, model, forcing, periodicity) = world.into_parts();
        let mut d =
            DistributedWorld::from_whole(state, model, forcing, periodicity, comm, settings)
                .unwrap();
        let cut = d.boxes()[0].max.x;
        while d.steps() < steps {
            d.step(&never);
        }
        (d.gather_whole().unwrap().map(|s| bits(&s)), cut)
    });
    assert!((got[0].1 - 0.005).abs() < 1e-9, "the cut: {}", got[0].1);
    assert!(
        got[0].0.as_ref() == Some(&reference),
        "two processes differ from one"
    );
}

/// Rows of squares sliding past each other fast, in an open domain, with a
/// halo skin far thinner than a step's travel: the skin grows to two steps
/// of the fastest floe, floes migrate every few steps, and the run stays
/// the single process's.
fn fast_rows() -> World<Forcing> {
    let (nx, ny) = (24usize, 4usize);
    let polys: Vec<_> = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| rect(Vec2::new(i as f64 * 103.0, j as f64 * 101.0), S, S))
        })
        .collect();
    let n = polys.len();
    let mut floes = Floes::from_polygons(&polys, &vec![1.0; n], RHO_ICE).unwrap();
    for i in 0..n {
        let row = i / nx;
        let v = if row % 2 == 0 { 3.0 } else { -3.0 };
        floes.set_velocity(i, Vec2::new(v, if row == 0 { 0.05 } else { -0.05 }), 0.0);
    }
    let model = rate_state(0.5, 1.0e4);
    let dt = 0.5 * floe_dem::world::stable_time_step(&floes, &model).0;
    World::new(floes, model, Forcing::default(), Periodicity::default(), dt).unwrap()
}

#[test]
fn a_skin_thinner_than_a_step_grows_and_the_run_stays_bitwise() {
    let never = AtomicBool::new(false);
    let steps = 400;
    let mut w = fast_rows();
    for _ in 0..steps {
        w.step();
    }
    assert!(!w.contacts().is_empty());
    let reference = bits(w.state());
    for processes in [2, 3] {
        let got = ThreadComm::run(processes, |comm| {
            let (state, model, forcing, periodicity) = fast_rows().into_parts();
            let settings = Settings {
                skin_fraction: 1e-4,
                ..Settings::default()
            };
            let mut d =
                DistributedWorld::from_whole(state, model, forcing, periodicity, comm, settings)
                    .unwrap();
            while d.steps() < steps {
                d.step(&never);
            }
            (
                d.gather_whole().unwrap().map(|s| bits(&s)),
                d.stats().migrations,
            )
        });
        assert!(got[0].1 > 10, "migrations: {}", got[0].1);
        assert!(
            got[0].0.as_ref() == Some(&reference),
            "{processes} processes"
        );
    }
}

/// The sheared layer at half its time step (room for pieces), fracturing
/// under a weak Mohr-Coulomb cone (uniaxial strength about 400 Pa).
fn fracturing_layer() -> (World<Forcing>, FractureRule) {
    let (mut state, model, forcing, periodicity) = sheared_layer(3).into_parts();
    state.dt_s *= 0.5;
    let world = World::resume(state, model, forcing, periodicity).unwrap();
    let rule = FractureRule {
        criterion: FractureCriterion::MohrCoulomb(MohrCoulomb {
            q: 5.2,
            sigma_c_pa: 2500.0,
            sigma_11_pa: -337.5,
        }),
        check_every_steps: 50,
        min_floe_area_m2: 0.3 * S * S,
        split: SplitRule {
            pieces: 2,
            min_piece_area_m2: 0.15 * S * S,
            attempts: 10,
        },
        strength_thickness: StrengthThickness::Pack,
        seed: 3,
    };
    (world, rule)
}

/// The fracturing layer's states every `EVERY` steps and its fracture
/// events, on one process.
fn fracturing_single(cohesion: Option<Cohesion>) -> (Vec<String>, Vec<FractureEvent>) {
    let (mut w, rule) = fracturing_layer();
    w.set_cohesion(cohesion).unwrap();
    let domain = NX as f64 * S * NY as f64 * S;
    let (mut states, mut events) = (vec![bits(w.state())], Vec::new());
    while w.steps() < STEPS {
        w.step();
        events.extend(w.fracture(&rule, domain).unwrap());
        if w.steps().is_multiple_of(EVERY) {
            states.push(bits(w.state()));
        }
    }
    (states, events)
}

/// [`fracturing_single`] on `processes` processes (ThreadComm).
fn fracturing_parallel(
    processes: usize,
    cohesion: Option<Cohesion>,
) -> (Vec<String>, Vec<FractureEvent>) {
    let never = AtomicBool::new(false);
    let results = ThreadComm::run(processes, |comm| {
        let (w, rule) = fracturing_layer();
        let domain = NX as f64 * S * NY as f64 * S;
        let (state, model, forcing, periodicity) = w.into_parts();
        let settings = Settings {
            skin_fraction: 0.1,
            rebalance_threshold: 0.2,
        };
        let mut d =
            DistributedWorld::from_whole(state, model, forcing, periodicity, comm, settings)
                .unwrap();
        d.set_cohesion(cohesion).unwrap();
        let (mut states, mut events) = (Vec::new(), Vec::new());
        if let Some(s) = d.gather_whole().unwrap() {
            states.push(bits(&s));
        }
        while d.steps() < STEPS {
            assert_eq!(d.step(&never), Default::default());
            events.extend(d.fracture(&rule, domain).unwrap());
            if d.steps().is_multiple_of(EVERY) {
                if let Some(s) = d.gather_whole().unwrap() {
                    states.push(bits(&s));
                }
            }
        }
        (states, events)
    });
    let events = results[0].1.clone();
    for (_, theirs) in &results {
        assert_eq!(theirs, &events, "every process returns every event");
    }
    results.into_iter().next().unwrap()
}

/// The fracturing layer with `cohesion` on 1-4 processes gives `states`
/// and `events`, one process's, bitwise.
fn fracturing_on_one_to_four_processes_is(
    states: &[String],
    events: &[FractureEvent],
    cohesion: Option<Cohesion>,
) {
    for processes in [1, 2, 3, 4] {
        let (p_states, p_events) = fracturing_parallel(processes, cohesion);
        assert_eq!(p_events, events, "{processes} processes: the events");
        assert_eq!(p_states.len(), states.len());
        for (k, (a, b)) in p_states.iter().zip(states).enumerate() {
            assert!(
                a == b,
                "{processes} processes: the state at step {} differs",
                k as u64 * EVERY
            );
        }
    }
}

#[test]
fn fracture_over_one_to_four_processes_is_bitwise_as_one() {
    let (states, events) = fracturing_single(None);
    let splits = events.iter().filter(|e| !e.piece_ids.is_empty()).count();
    assert!(splits >= 3, "floes broke ({splits})");
    fracturing_on_one_to_four_processes_is(&states, &events, None);
}

/// Floes of the fracturing layer freeze together where they rest against
/// each other: weak bonds that form and break within the run.
fn weak_cohesion() -> Cohesion {
    Cohesion {
        quiet_speed_m_per_s: 0.3,
        bond_after_s: 5.0,
        tensile_strength_n_per_m: 3000.0,
        shear_strength_n_per_m: 1500.0,
        growth_time_s: 60.0,
    }
}

#[test]
fn cohesion_with_fracture_over_one_to_four_processes_is_bitwise_as_one() {
    // The run is only as strong a test as it is eventful.
    let (mut w, rule) = fracturing_layer();
    w.set_cohesion(Some(weak_cohesion())).unwrap();
    let domain = NX as f64 * S * NY as f64 * S;
    let (mut most_bonds, mut splits) = (0, 0);
    while w.steps() < STEPS {
        w.step();
        splits += w
            .fracture(&rule, domain)
            .unwrap()
            .iter()
            .filter(|e| !e.piece_ids.is_empty())
            .count();
        most_bonds = most_bonds.max(w.bonds().iter().filter(|b| b.formed).count());
    }
    eprintln!(
        "at most {most_bonds} bonds, {} broken, {splits} splits",
        w.bonds_broken()
    );
    assert!(most_bonds >= 5 && w.bonds_broken() >= 5 && splits >= 1);

    let (states, events) = fracturing_single(Some(weak_cohesion()));
    fracturing_on_one_to_four_processes_is(&states, &events, Some(weak_cohesion()));
}

/// Ridging weak enough that the lid's press cuts floes within the run.
fn weak_ridging() -> Ridging {
    Ridging {
        strength_n_per_m: 3e4,
        ..Ridging::default()
    }
}

/// The life cycle's tables a sheared-layer run turns on.
#[derive(Debug, Clone, Copy, Default)]
struct LifeTables {
    ridging: Option<Ridging>,
    cohesion: Option<Cohesion>,
    welding: Option<Welding>,
}

/// The sheared layer with `tables`: its states every `EVERY` steps and the
/// events `pick` takes from each step's report, on `processes` processes
/// (0: one world, no communicator).
fn layer_run<E: Clone + PartialEq + std::fmt::Debug + Send>(
    processes: usize,
    tables: LifeTables,
    pick: fn(floe_dem::run::StepReport) -> Vec<E>,
) -> (Vec<String>, Vec<E>) {
    let never = AtomicBool::new(false);
    if processes == 0 {
        let mut w = sheared_layer(3);
        w.set_ridging(tables.ridging).unwrap();
        w.set_cohesion(tables.cohesion).unwrap();
        w.set_welding(tables.welding).unwrap();
        let (mut states, mut events) = (vec![bits(w.state())], Vec::new());
        while w.steps() < STEPS {
            let report = Stepper::step(&mut w, &never);
            assert!(report.blow_up.is_none(), "{:?}", report.blow_up);
            events.extend(pick(report));
            if w.steps().is_multiple_of(EVERY) {
                states.push(bits(w.state()));
            }
        }
        return (states, events);
    }
    let results = ThreadComm::run(processes, |comm| {
        let (state, model, forcing, periodicity) = sheared_layer(3).into_parts();
        let settings = Settings {
            skin_fraction: 0.1,
            rebalance_threshold: 0.2,
        };
        let mut d =
            DistributedWorld::from_whole(state, model, forcing, periodicity, comm, settings)
                .unwrap();
        d.set_ridging(tables.ridging).unwrap();
        d.set_cohesion(tables.cohesion).unwrap();
        d.set_welding(tables.welding).unwrap();
        let (mut states, mut events) = (Vec::new(), Vec::new());
        if let Some(s) = d.gather_whole().unwrap() {
            states.push(bits(&s));
        }
        while d.steps() < STEPS {
            let report = d.step(&never);
            assert!(report.blow_up.is_none() && report.forcing_failure.is_none());
            events.extend(pick(report));
            if d.steps().is_multiple_of(EVERY) {
                if let Some(s) = d.gather_whole().unwrap() {
                    states.push(bits(&s));
                }
            }
        }
        (states, events)
    });
    let events = results[0].1.clone();
    for (_, theirs) in &results {
        assert_eq!(theirs, &events, "every process returns every event");
    }
    results.into_iter().next().unwrap()
}

/// The layer with `tables` on 1-4 processes gives one process's states and
/// events, bitwise.
fn on_one_to_four_processes_is<E: Clone + PartialEq + std::fmt::Debug + Send>(
    states: &[String],
    events: &[E],
    tables: LifeTables,
    pick: fn(floe_dem::run::StepReport) -> Vec<E>,
) {
    for processes in [1, 2, 3, 4] {
        let (p_states, p_events) = layer_run(processes, tables, pick);
        assert_eq!(p_events, events, "{processes} processes: the events");
        assert_eq!(p_states.len(), states.len());
        for (k, (a, b)) in p_states.iter().zip(states).enumerate() {
            assert!(
                a == b,
                "{processes} processes: the state at step {} differs",
                k as u64 * EVERY
            );
        }
    }
}

/// The sheared layer ridging: its states and ridging events
/// ([`layer_run`]).
fn ridging_run(processes: usize, ridging: Ridging) -> (Vec<String>, Vec<PlannedRidge>) {
    layer_run(processes, ridging_tables(ridging), |r| r.ridges)
}

/// The tables of a ridging run.
fn ridging_tables(ridging: Ridging) -> LifeTables {
    LifeTables {
        ridging: Some(ridging),
        ..LifeTables::default()
    }
}

/// The ridging layer on 1-4 processes gives one process's states and
/// events, bitwise.
fn ridging_on_one_to_four_processes_is(
    states: &[String],
    events: &[PlannedRidge],
    ridging: Ridging,
) {
    on_one_to_four_processes_is(states, events, ridging_tables(ridging), |r| r.ridges);
}

#[test]
fn ridging_over_one_to_four_processes_is_bitwise_as_one() {
    let (states, events) = ridging_run(0, weak_ridging());
    let gains = events.iter().filter(|e| e.gainer_free).count();
    eprintln!("{} ridging events, {gains} onto floes", events.len());
    assert!(events.len() >= 20 && gains >= 5, "an eventful run");
    ridging_on_one_to_four_processes_is(&states, &events, weak_ridging());
}

#[test]
fn floes_crushed_whole_over_one_to_four_processes_are_bitwise_as_one() {
    // Every cut would leave less than 95 % of a floe: each ridging floe goes
    // whole, onto a thicker floe, a wall, or (through a floe that goes
    // whole in the same step) further on.
    let crushing = Ridging {
        min_floe_area_m2: 0.95 * S * S,
        ..weak_ridging()
    };
    let (states, events) = ridging_run(0, crushing);
    let whole = events.iter().filter(|e| e.kept.is_empty()).count();
    eprintln!("{} floes crushed", whole);
    assert!(whole >= 5, "floes went whole ({whole})");
    ridging_on_one_to_four_processes_is(&states, &events, crushing);
}

#[test]
fn rubble_shared_by_both_floes_over_one_to_four_processes_is_bitwise_as_one() {
    // The loser's share lands on its kept part, held by other processes
    // as a ghost: the same gains everywhere.
    let both = Ridging {
        rubble: floe_dem::ridging::Rubble::Both,
        ..weak_ridging()
    };
    let (states, events) = ridging_run(0, both);
    let shared = events.iter().filter(|e| e.loser_share > 0.0).count();
    eprintln!("{} ridging events, {shared} shared", events.len());
    assert!(shared >= 5, "shared events ({shared})");
    ridging_on_one_to_four_processes_is(&states, &events, both);
}

/// Bonds strong enough to last the few seconds welding waits.
fn strong_cohesion() -> Cohesion {
    Cohesion {
        tensile_strength_n_per_m: 1e5,
        shear_strength_n_per_m: 1e5,
        growth_time_s: 0.0,
        ..weak_cohesion()
    }
}

/// Welding loose enough that bonded squares of the sheared layer weld
/// within the run (their hulls add up to half their area).
fn loose_welding() -> Welding {
    Welding {
        after_s: 5.0,
        max_added_area_fraction: 0.5,
        max_centre_shift_fraction: 0.5,
        check_every_s: 0.0,
        ..Welding::default()
    }
}

/// The tables of the welding run: strong bonds, loose welding.
fn welding_tables() -> LifeTables {
    LifeTables {
        cohesion: Some(strong_cohesion()),
        welding: Some(loose_welding()),
        ..LifeTables::default()
    }
}

#[test]
fn welding_over_one_to_four_processes_is_bitwise_as_one() {
    let (states, welds) = layer_run(0, welding_tables(), |r| r.welds);
    let chained = welds
        .iter()
        .filter(|w| welds.iter().any(|v| w.ids.contains(&v.floe.id)))
        .count();
    eprintln!("{} welds, {chained} of a welded floe", welds.len());
    assert!(welds.len() >= 5 && chained >= 1, "{} welds", welds.len());
    on_one_to_four_processes_is(&states, &welds, welding_tables(), |r| r.welds);
}
