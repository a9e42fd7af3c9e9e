//! Cohesion: a floe frozen to a wall holds until the pull per unit length
//! reaches the bond's strength (and, without cohesion, leaves at no pull);
//! a split that would leave a bond on a piece too small for it is refused;
//! bonds form only after the quiet time; a bonded pair conserves linear
//! and angular momentum to round-off and its energy is in the ledger; a
//! split floe's bond goes on from the piece holding its anchor with the
//! same energy and loads; the bits do not depend on the thread count or a
//! resume.

use floe_dem::bond_kernel::{evaluate_bond, BondEnd};
use floe_dem::cohesion::Cohesion;
use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floes, Motion};
use floe_dem::forcing::NoForcing;
use floe_dem::geometry::cross;
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::{MotionSchedule, MotionSegment};
use floe_dem::periodicity::Periodicity;
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_fixtures::channel::sheared_channel;

const SIDE_M: f64 = 100.0;
const TENSILE_N_PER_M: f64 = 1e4;
const QUIET_S: f64 = 60.0;
const HOLD_S: f64 = 200.0;
const PULL_M_PER_S: f64 = 1e-3;
const LOAD_STIFFNESS: f64 = 1e6;

fn square(x0: f64, y0: f64, side: f64) -> Vec<Vec2> {
    [(0.0, 0.0), (side, 0.0), (side, side), (0.0, side)]
        .map(|(x, y)| Vec2::new(x0 + x, y0 + y))
        .to_vec()
}

/// A free 100 m square, 1 m thick, against a fixed wall on its left,
/// overlapping it by 1 cm and held there by a load point (1 MN/m) at the
/// overlap force's equilibrium, which after `HOLD_S` pulls it away at 1
/// mm/s.
fn pulled_off(cohesion: Option<Cohesion>) -> World<NoForcing> {
    pulled_off_turned(cohesion, 0.0)
}

/// [`pulled_off`] with everything turned by `angle` about the origin.
fn pulled_off_turned(cohesion: Option<Cohesion>, angle: f64) -> World<NoForcing> {
    let overlap = 0.01;
    let (sin, cos) = angle.sin_cos();
    let turn = |p: Vec2| Vec2::new(cos * p.x - sin * p.y, sin * p.x + cos * p.y);
    let polys = [square(-SIDE_M, 0.0, SIDE_M), square(-overlap, 0.0, SIDE_M)]
        .map(|p| p.into_iter().map(turn).collect::<Vec<_>>());
    let mut floes = Floes::from_polygons(&polys, &[1.0, 1.0], 917.0).unwrap();
    floes.set_motion(
        0,
        Motion::Prescribed {
            velocity: Vec2::ZERO,
        },
    );
    let model = ContactModel::default();
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    let centroid = floes.position[1];
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    // The wall pushes with kappa l overlap, kappa = E h / sqrt(A).
    let push = 6e6 / SIDE_M * SIDE_M * overlap;
    let schedule = MotionSchedule::new(vec![
        MotionSegment::constant(HOLD_S, Vec2::ZERO),
        MotionSegment::constant(1e9, turn(Vec2::new(PULL_M_PER_S, 0.0))),
    ])
    .unwrap();
    let anchor = centroid - turn(Vec2::new(push / LOAD_STIFFNESS, 0.0));
    let id = w.floes().id[1];
    w.set_load_point(LoadPoint::new(id, LOAD_STIFFNESS, anchor, schedule).unwrap())
        .unwrap();
    w.set_cohesion(cohesion).unwrap();
    w
}

fn frozen_at_once_after(quiet_s: f64) -> Cohesion {
    Cohesion {
        quiet_speed_m_per_s: 1e-4,
        bond_after_s: quiet_s,
        tensile_strength_n_per_m: TENSILE_N_PER_M,
        shear_strength_n_per_m: TENSILE_N_PER_M,
        growth_time_s: 0.0,
    }
}

/// The floes' energy (kinetic and stored) less the ledger's net input.
fn energy_residual(w: &World<NoForcing>) -> f64 {
    let o = w.observables(1.0);
    let l = o.ledger;
    o.kinetic_translational_j + o.kinetic_rotational_j + o.contact_energy_j
        - (l.forcing_work_j + l.boundary_work_j
            - l.friction_dissipation_j
            - l.damping_dissipation_j
            - l.released_at_break_j)
}

#[test]
fn a_floe_frozen_to_a_wall_holds_until_the_pull_reaches_the_bond_strength() {
    let mut w = pulled_off(Some(frozen_at_once_after(QUIET_S)));
    let e0 = energy_residual(&w);
    let dt = w.dt_s();
    let (mut formed_at, mut broke_at) = (None, None);
    let (mut last_tension, mut last_pull, mut most_energy) = (0.0f64, 0.0f64, 0.0f64);
    while w.time_s() < HOLD_S + 2000.0 && broke_at.is_none() {
        w.step();
        let bond = w.bonds().iter().find(|b| b.formed);
        match (bond, formed_at) {
            (Some(b), _) => {
                formed_at.get_or_insert(b.formed_at_s);
                last_tension = b.tension_n_per_m;
                most_energy = most_energy.max(b.energy_j);
                last_pull = w.observables(1.0).load_point_force_n[0];
            }
            (None, Some(_)) => broke_at = Some(w.time_s()),
            (None, None) => {}
        }
    }
    let formed_at = formed_at.expect("a bond formed");
    let broke_at = broke_at.expect("the bond broke");
    // Quiet from the first step (the floe is at its equilibrium).
    assert!(
        formed_at >= QUIET_S && formed_at <= QUIET_S + 2.0 * dt,
        "formed at {formed_at} s"
    );
    // It broke in pure tension at the strength, within a step's load increment.
    let kappa = 6e6 / SIDE_M;
    let per_step = kappa * PULL_M_PER_S * dt;
    assert!(
        (TENSILE_N_PER_M - last_tension).abs() <= 2.0 * per_step,
        "tension {last_tension} N/m before the break, strength {TENSILE_N_PER_M}, step {per_step}"
    );
    // The pull that broke it: strength times length, quasi-statically.
    let expected = TENSILE_N_PER_M * SIDE_M;
    assert!(
        (last_pull / expected - 1.0).abs() < 0.01,
        "pull {last_pull} N at the break, {expected} N expected"
    );
    // The time it took: the load point's travel from pushing (the wall's
    // push) to that pull, plus the bond's stretch.
    let push = kappa * SIDE_M * 0.01;
    let travel = (push + expected) / LOAD_STIFFNESS + TENSILE_N_PER_M / kappa;
    let predicted = HOLD_S + travel / PULL_M_PER_S;
    assert!(
        (broke_at - predicted).abs() < 0.02 * (predicted - HOLD_S),
        "broke at {broke_at} s, {predicted} s predicted"
    );
    // The floes' energy and the ledger agree through the break (which
    // releases the bond's energy, about 8e4 J).
    for _ in 0..2000 {
        w.step();
    }
    let residual = energy_residual(&w) - e0;
    assert!(
        residual.abs() < 1e-3 * most_energy,
        "energy residual {residual} J, bond energy {most_energy} J"
    );
    assert!(w.contacts().is_empty(), "the floe left the wall");
    assert_eq!(w.bonds_broken(), 1);
}

#[test]
fn without_cohesion_or_before_the_quiet_time_the_floe_leaves_at_no_pull() {
    for cohesion in [None, Some(frozen_at_once_after(HOLD_S + 1e6))] {
        let mut w = pulled_off(cohesion);
        let mut most_pull = f64::NEG_INFINITY;
        while w.time_s() < HOLD_S + 500.0 {
            w.step();
            most_pull = most_pull.max(w.observables(1.0).load_point_force_n[0]);
            assert!(w.bonds().iter().all(|b| !b.formed));
        }
        assert!(w.contacts().is_empty(), "the floe left the wall");
        // It left as the wall's push fell to zero: the spring pulled at most
        // the floe's lag behind the load point, V sqrt(k m) (3 kN).
        let lag = PULL_M_PER_S * (LOAD_STIFFNESS * w.floes().mass_kg[1]).sqrt();
        assert!(
            most_pull < 2.0 * lag && lag < 0.01 * TENSILE_N_PER_M * SIDE_M,
            "pull {most_pull} N with cohesion {cohesion:?}"
        );
    }
}

#[test]
fn a_bond_forms_only_after_the_quiet_time_and_strength_grows_with_age() {
    let growth = 600.0;
    let cohesion = Cohesion {
        growth_time_s: growth,
        ..frozen_at_once_after(QUIET_S)
    };
    let mut w = pulled_off(Some(cohesion));
    let mut broke_at = None;
    while w.time_s() < HOLD_S + 3000.0 && broke_at.is_none() {
        let before = w.bonds().iter().find(|b| b.formed).copied();
        w.step();
        if w.time_s() < QUIET_S {
            assert!(w.bonds().iter().all(|b| !b.formed), "at {} s", w.time_s());
        }
        if let (Some(b), None) = (before, w.bonds().iter().find(|b| b.formed)) {
            broke_at = Some((w.time_s(), b));
        }
    }
    let (t, b) = broke_at.expect("the bond broke");
    // It broke when its tension reached the strength of its age.
    let strength = TENSILE_N_PER_M * cohesion.strength_fraction(t - b.formed_at_s);
    assert!(strength < 0.999 * TENSILE_N_PER_M, "still growing");
    let per_step = 6e6 / SIDE_M * PULL_M_PER_S * w.dt_s();
    assert!(
        (b.tension_n_per_m - strength).abs()
            <= 2.0 * per_step + TENSILE_N_PER_M * w.dt_s() / growth,
        "tension {} N/m at the break, strength {strength} N/m",
        b.tension_n_per_m
    );
}

/// Two free squares frozen together at once (strong bond), the second
/// moving and spinning relative to the first.
fn bonded_pair(dt_fraction: f64, restitution: f64) -> World<NoForcing> {
    bonded_pair_of(SIDE_M, dt_fraction, restitution)
}

/// [`bonded_pair`] of squares of side `side` (the second offset by a fifth).
fn bonded_pair_of(side: f64, dt_fraction: f64, restitution: f64) -> World<NoForcing> {
    let polys = [
        square(0.0, 0.0, side),
        square(side - 1e-3, 0.2 * side, side),
    ];
    let floes = Floes::from_polygons(&polys, &[1.0, 1.5], 917.0).unwrap();
    let model = ContactModel {
        restitution,
        ..ContactModel::default()
    };
    let dt = dt_fraction * stable_time_step(&floes, &model).0;
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    let id = w.floes().id[1];
    w.set_velocity(id, Vec2::new(0.01, 0.02), 1e-4).unwrap();
    w.set_cohesion(Some(Cohesion {
        quiet_speed_m_per_s: 100.0,
        bond_after_s: 0.0,
        tensile_strength_n_per_m: 1e15,
        shear_strength_n_per_m: 1e15,
        growth_time_s: 0.0,
    }))
    .unwrap();
    w
}

fn momenta(w: &World<NoForcing>) -> (Vec2, f64) {
    let f = w.floes();
    let mut p = Vec2::ZERO;
    let mut l = 0.0;
    for i in 0..f.len() {
        p += f.velocity[i] * f.mass_kg[i];
        l += f.mass_kg[i] * cross(f.position[i], f.velocity[i])
            + f.inertia_kg_m2[i] * f.angular_velocity[i];
    }
    (p, l)
}

#[test]
fn a_bonded_pair_conserves_momentum_and_angular_momentum_and_the_ledger_balances() {
    let mut w = bonded_pair(0.25, 0.5);
    let e0 = energy_residual(&w);
    let (p0, l0) = momenta(&w);
    let mut most_energy = 0.0f64;
    for _ in 0..4000 {
        w.step();
        let (p, l) = momenta(&w);
        assert!((p - p0).length() < 1e-12 * p0.length(), "{p} vs {p0}");
        assert!((l - l0).abs() < 1e-11 * l0.abs(), "{l} vs {l0}");
        if let Some(b) = w.bonds().first() {
            most_energy = most_energy.max(b.energy_j);
        }
    }
    assert_eq!(w.bonds().len(), 1);
    assert!(w.bonds()[0].formed && most_energy > 0.0);
    // Held together: the second floe did not fly off.
    let gap = (w.floes().position[1] - w.floes().position[0]).length();
    assert!((gap - SIDE_M).abs() < 25.0, "centroids {gap} m apart");
    assert!(w.energy().damping_dissipation_j > 0.0);

    // The ledger follows the floes' energy through the bond's work and
    // damping and the overlap contact's coming and going (forces as the
    // energy's exact gradient: the kernel's unit tests).
    let o = w.observables(1.0);
    let ke = o.kinetic_translational_j + o.kinetic_rotational_j;
    let residual = energy_residual(&w) - e0;
    assert!(
        residual.abs() < 0.01 * ke,
        "residual {residual} J of {ke} J"
    );
}

/// Floe `h` of `w` as the bond kernel sees it.
fn end(w: &World<NoForcing>, h: usize) -> BondEnd {
    let f = w.floes();
    BondEnd::of(f, h, Vec2::ZERO, f.angle[h].sin_cos())
}

/// [`bonded_pair`] with floe ids `ids` (taken out before the first step
/// and put back renumbered; the contact is found again by the next step).
fn bonded_pair_with_ids(ids: [u64; 2]) -> World<NoForcing> {
    let mut w = bonded_pair(0.25, 0.5);
    let mut taken: Vec<_> = [1, 0].map(|id| w.remove_floe(id).unwrap()).into();
    for (d, id) in taken.iter_mut().rev().zip(ids) {
        d.floe.id = id;
        d.contacts.clear();
    }
    for d in taken {
        w.insert_detached(d).unwrap();
    }
    w
}

#[test]
fn a_split_floes_bond_goes_on_from_the_piece_that_holds_its_anchor() {
    // Each floe of the pair splits, its pieces numbered below or above the
    // other's id: the four ways the roles can fall.
    for (parent, piece_ids) in [(10, [1, 2]), (10, [30, 31]), (20, [30, 31]), (20, [1, 2])] {
        let mut w = bonded_pair_with_ids([10, 20]);
        for _ in 0..300 {
            w.step();
        }
        let bond = w.bonds()[0];
        assert!(bond.formed && bond.energy_j > 0.0);
        let model = w.model().clone();
        let before = {
            let mut b = bond;
            evaluate_bond(
                &model,
                model.damping_ratio(),
                &end(&w, 0),
                &end(&w, 1),
                &mut b,
            );
            b
        };
        let h = w.floes().handle_of(parent).unwrap();
        // Cut through the centroid, across the bond's side.
        let half = SIDE_M / 2.0;
        let (s, c) = w.floes().angle[h].sin_cos();
        let world = |x: f64, y: f64| Vec2::new(c * x - s * y, s * x + c * y);
        let pieces = vec![
            vec![
                world(-half, -half),
                world(half, -half),
                world(half, 0.0),
                world(-half, 0.0),
            ],
            vec![
                world(-half, 0.0),
                world(half, 0.0),
                world(half, half),
                world(-half, half),
            ],
        ];
        w.split_floe(parent, &pieces, &piece_ids).unwrap();
        let case = format!("parent {parent}, pieces {piece_ids:?}");
        let after: Vec<_> = w.bonds().iter().filter(|b| b.formed).copied().collect();
        assert_eq!(after.len(), 1, "{case}: the bond went on");
        let mut re = after[0];
        let (ha, hb) = (re.a as usize, re.b as usize);
        evaluate_bond(
            &model,
            model.damping_ratio(),
            &end(&w, ha),
            &end(&w, hb),
            &mut re,
        );
        assert!(
            (re.energy_j - before.energy_j).abs() < 1e-6 * before.energy_j,
            "{case}: energy {} vs {}",
            re.energy_j,
            before.energy_j
        );
        for (x, y) in [
            (re.tension_n_per_m, before.tension_n_per_m),
            (re.shear_n_per_m, before.shear_n_per_m),
        ] {
            assert!((x - y).abs() < 1e-6 * (1.0 + y.abs()), "{case}: {x} vs {y}");
        }
        // The anchors are where they were in the world (swapped with the roles).
        let swapped = (piece_ids[0] < 15) != (parent == 10);
        let (qa, qb) = if swapped {
            (before.point_b, before.point_a)
        } else {
            (before.point_a, before.point_b)
        };
        assert!(
            (re.point_a - qa).length() < 1e-9 * SIDE_M
                && (re.point_b - qb).length() < 1e-9 * SIDE_M,
            "{case}"
        );
        // And it steps on, held.
        for _ in 0..100 {
            w.step();
        }
        assert!(w.bonds().iter().any(|b| b.formed), "{case}");
    }
}

#[test]
fn cohesion_is_bitwise_the_same_for_any_thread_count_and_across_a_resume() {
    let cohesion = Cohesion {
        quiet_speed_m_per_s: 0.05,
        bond_after_s: 20.0,
        tensile_strength_n_per_m: 2e3,
        shear_strength_n_per_m: 1e3,
        growth_time_s: 100.0,
    };
    let run = |threads: usize, resume_at: Option<usize>| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = sheared_channel(400);
            w.set_cohesion(Some(cohesion)).unwrap();
            for k in 0..600 {
                if Some(k) == resume_at {
                    let (state, model, forcing, periodicity) = w.into_parts();
                    w = World::resume(state, model, forcing, periodicity).unwrap();
                    w.set_cohesion(Some(cohesion)).unwrap();
                }
                w.step();
            }
            (w.state().clone(), w.bonds_broken())
        })
    };
    let (one, broken) = run(1, None);
    let formed = one.bonds.iter().filter(|b| b.formed).count();
    eprintln!("{formed} bonds, {broken} broken");
    assert!(
        formed > 0 && broken > 0,
        "bonds form and break: {formed}, {broken}"
    );
    assert_eq!(run(2, None).0, one);
    assert_eq!(run(2, Some(300)).0, one);
}

#[test]
fn a_bond_in_a_turned_frame_forms_and_lasts_the_hold() {
    // The floe held against the wall, all turned by 0.3 rad: the bond forms
    // at the quiet time and lasts the hold with its strength still growing
    // (growth time 1 day), as in the unturned frame. (A bond is not judged
    // in the step it forms: its loads are then the round-off of its
    // anchors' rotation, its strength zero.)
    let cohesion = Cohesion {
        growth_time_s: 86_400.0,
        ..frozen_at_once_after(QUIET_S)
    };
    let mut w = pulled_off_turned(Some(cohesion), 0.3);
    while w.time_s() < HOLD_S {
        w.step();
    }
    assert_eq!(w.bonds_broken(), 0);
    assert!(w.bonds().iter().any(|b| b.formed));
}

#[test]
fn a_split_that_would_leave_a_bond_on_a_piece_too_small_for_it_is_refused() {
    // 1 km floes: a bond along most of an edge is far stiffer in turning
    // than a 25 m piece of the floe can carry at the pieces' own step.
    let side = 1000.0;
    let mut w = bonded_pair_of(side, 0.25, 0.5);
    for _ in 0..50 {
        w.step();
    }
    let bond = *w.bonds().iter().find(|b| b.formed).unwrap();
    // Floe 0's anchor is on its right edge; a 25 m square piece holds it.
    let h = bond.a as usize;
    let f = w.floes();
    let (s, c) = f.angle[h].sin_cos();
    let at = Vec2::new(
        c * bond.anchor_a.x - s * bond.anchor_a.y,
        s * bond.anchor_a.x + c * bond.anchor_a.y,
    );
    let world = |x: f64, y: f64| Vec2::new(c * x - s * y, s * x + c * y);
    let local = Vec2::new(c * at.x + s * at.y, -s * at.x + c * at.y);
    let (y0, y1) = (local.y - 12.5, local.y + 12.5);
    let rect = |x0: f64, x1: f64, ya: f64, yb: f64| {
        vec![world(x0, ya), world(x1, ya), world(x1, yb), world(x0, yb)]
    };
    let half = side / 2.0;
    let pieces = vec![
        rect(half - 25.0, half, y0, y1),
        rect(half - 25.0, half, y1, half),
        rect(half - 25.0, half, -half, y0),
        rect(-half, half - 25.0, -half, half),
    ];
    // The piece's own contacts' limit, and the bond's on it (0.3 x 2/omega).
    let piece = Floes::from_polygons(&[pieces[0].clone()], &[1.0], 917.0).unwrap();
    let contact_limit = stable_time_step(&piece, w.model()).0;
    let (m, inertia) = (piece.mass_kg[0], piece.inertia_kg_m2[0]);
    let arm = (local - Vec2::new(half - 12.5, 0.5 * (y0 + y1))).length();
    let k = bond.stiffness_n_per_m;
    let turn = k * (bond.length_m.powi(2) / 12.0 + arm * arm);
    let bond_limit = 0.6 / (k / m).max(turn / inertia).sqrt();
    assert!(bond_limit < contact_limit, "{bond_limit} {contact_limit}");
    // A world at a step between the two: the pieces alone would do.
    let (state, model, forcing, periodicity) = w.into_parts();
    let mut state = state;
    state.dt_s = 0.5 * (bond_limit + contact_limit);
    let mut w = World::resume(state, model, forcing, periodicity).unwrap();
    w.set_cohesion(bonded_pair(0.25, 0.5).cohesion()).unwrap();
    let before = w.state().clone();
    let e = w
        .split_floe(w.floes().id[h], &pieces, &[100, 101, 102, 103])
        .unwrap_err();
    assert!(e.to_string().contains("a bond"), "{e}");
    assert_eq!(w.state(), &before, "the world unchanged");
}
