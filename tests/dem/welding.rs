//! Welding: a bonded pair becomes one floe with the pair's mass, volume,
//! momentum and angular momentum to round-off, its kinetic energy loss and
//! released contact energy in the ledger; a third floe touching both keeps
//! one contact and one bond (the longer); a pair welds only after the bond's
//! age and only when the hull adds little area; welds never touch each
//! other in one step; the bits do not depend on the thread count or a
//! resume.

use std::sync::atomic::AtomicBool;

use floe_dem::cohesion::Cohesion;
use floe_dem::contact_model::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::forcing::NoForcing;
use floe_dem::geometry::cross;
use floe_dem::periodicity::Periodicity;
use floe_dem::run::Stepper;
use floe_dem::welding::Welding;
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_fixtures::channel::sheared_channel;

fn rectangle(x0: f64, y0: f64, w: f64, h: f64) -> Vec<Vec2> {
    [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
        .map(|(x, y)| Vec2::new(x0 + x, y0 + y))
        .to_vec()
}

/// Every contact bonds at once, at full strength, and holds.
fn frozen_at_once() -> Cohesion {
    Cohesion {
        quiet_speed_m_per_s: 100.0,
        bond_after_s: 0.0,
        tensile_strength_n_per_m: 1e15,
        shear_strength_n_per_m: 1e15,
        growth_time_s: 0.0,
    }
}

/// Welding after `after_s` with room for the test's pairs (their centre of
/// mass moves by a tenth of the welded radius: thicknesses differ).
fn welding_after(after_s: f64) -> Welding {
    Welding {
        after_s,
        max_centre_shift_fraction: 0.5,
        check_every_s: 0.0,
        ..Welding::default()
    }
}

/// Floes 0 and 1, 100 m x 100 m side by side (1 cm overlap), 1 and 1.4 m
/// thick, and floe 2, 200 m x 50 m, 0.8 m thick, lying across both (1 cm
/// overlap); each moving and spinning differently, all bonding at once.
fn three_floes() -> World<NoForcing> {
    let polys = [
        rectangle(0.0, 0.0, 100.0, 100.0),
        rectangle(99.99, 0.0, 100.0, 100.0),
        rectangle(0.0, 99.99, 199.99, 50.0),
    ];
    let floes = Floes::from_polygons(&polys, &[1.0, 1.4, 0.8], 917.0).unwrap();
    let model = ContactModel::default();
    let dt = 0.25 * stable_time_step(&floes, &model).0;
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    for (id, v, spin) in [
        (0, Vec2::new(0.01, -0.002), 1e-5),
        (1, Vec2::new(-0.003, 0.004), -2e-5),
        (2, Vec2::new(0.002, 0.001), 3e-5),
    ] {
        let id = w.floes().id[id];
        w.set_velocity(id, v, spin).unwrap();
    }
    w.set_cohesion(Some(frozen_at_once())).unwrap();
    w
}

/// Mass, ice volume, momentum, angular momentum about the origin and
/// kinetic energy of the free floes.
fn totals(w: &World<NoForcing>) -> (f64, f64, Vec2, f64, f64) {
    let f = w.floes();
    let (mut m, mut v, mut p, mut l, mut k) = (0.0, 0.0, Vec2::ZERO, 0.0, 0.0);
    for i in (0..f.len()).filter(|&i| f.is_free(i)) {
        m += f.mass_kg[i];
        v += f.area_m2[i] * f.thickness_m[i];
        p += f.velocity[i] * f.mass_kg[i];
        l += f.mass_kg[i] * cross(f.position[i], f.velocity[i])
            + f.inertia_kg_m2[i] * f.angular_velocity[i];
        k += 0.5
            * (f.mass_kg[i] * f.velocity[i].length_squared()
                + f.inertia_kg_m2[i] * f.angular_velocity[i].powi(2));
    }
    (m, v, p, l, k)
}

/// Floe `h`'s vertices in the world.
fn world_vertices(w: &World<NoForcing>, h: usize) -> Vec<Vec2> {
    let f = w.floes();
    let (sin, cos) = f.angle[h].sin_cos();
    f.local_vertices(h)
        .iter()
        .map(|v| f.position[h] + Vec2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y))
        .collect()
}

/// The area of the convex hull of `points`: Andrew's monotone chain and
/// the shoelace formula (not the library hull the engine uses).
fn hull_area(points: &[Vec2]) -> f64 {
    let mut p = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let mut hull: Vec<Vec2> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        for &q in &p {
            while hull.len() >= start + 2
                && cross(
                    hull[hull.len() - 1] - hull[hull.len() - 2],
                    q - hull[hull.len() - 2],
                ) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
        if pass == 0 {
            p.reverse();
        }
    }
    let o = hull[0];
    (1..hull.len() - 1)
        .map(|i| 0.5 * cross(hull[i] - o, hull[i + 1] - o))
        .sum()
}

fn assert_conserved(before: (f64, f64, Vec2, f64, f64), after: (f64, f64, Vec2, f64, f64)) {
    let close = |a: f64, b: f64, scale: f64, what: &str| {
        assert!((a - b).abs() <= 1e-12 * scale, "{what}: {a} against {b}");
    };
    close(after.0, before.0, before.0, "mass");
    close(after.1, before.1, before.1, "volume");
    let p_scale = before.0 * 0.01;
    close(after.2.x, before.2.x, p_scale, "momentum x");
    close(after.2.y, before.2.y, p_scale, "momentum y");
    // Angular momentum about the origin: the floes sit 100 m from it.
    close(after.3, before.3, p_scale * 200.0, "angular momentum");
}

#[test]
fn a_welded_pair_keeps_mass_volume_momentum_and_angular_momentum() {
    let mut w = three_floes();
    w.set_welding(Some(welding_after(30.0))).unwrap();
    // Bonds form at the first step; none welds before it is 30 s old.
    loop {
        w.step();
        let formed_at = w.bonds().first().map_or(w.time_s(), |b| b.formed_at_s);
        if w.time_s() - formed_at >= 30.0 {
            break;
        }
        assert!(w.weld().unwrap().is_empty(), "at {} s", w.time_s());
    }
    assert_eq!(w.bonds().iter().filter(|b| b.formed).count(), 3);
    let hull = hull_area(&[world_vertices(&w, 0), world_vertices(&w, 1)].concat());
    let before = totals(&w);
    let f = w.floes();
    let areas = [f.area_m2[0], f.area_m2[1]];
    let contacts_before: Vec<_> = w.contacts().to_vec();
    let bonds_before: Vec<_> = w.bonds().to_vec();
    let welds = w.weld().unwrap();
    // Three bonded pairs, all touching: the first (0, 1) welds, the others wait.
    assert_eq!(welds.len(), 1, "{welds:?}");
    let weld = &welds[0];
    assert_eq!(weld.ids, [0, 1]);
    assert_eq!(weld.floe.id, 3);
    let after = totals(&w);
    assert_conserved(before, after);
    // The welded floe is the hull of the two, here near their rectangle.
    assert!((weld.floe.area_m2 - hull).abs() < 1e-9 * hull);
    assert!((hull - 199.99 * 100.0).abs() < 10.0, "{hull}");
    let ledger = *w.welding_ledger();
    assert_eq!(ledger.events, 1);
    assert!((ledger.area_added_m2 - (hull - areas[0] - areas[1])).abs() < 1e-6);
    assert!(
        ((before.4 - after.4) - ledger.kinetic_energy_lost_j).abs() <= 1e-9 * before.4,
        "kinetic energy {} J lost, {} J booked",
        before.4 - after.4,
        ledger.kinetic_energy_lost_j
    );
    // The pair, bonded for 30 s, hardly moves relative to itself: what
    // changes is the spin that keeps angular momentum as the centre of
    // mass moves 8 m to the hull's centroid, a few per cent of the energy
    // either way.
    eprintln!(
        "kinetic energy {} J, lost {} J, centre shift {} m",
        before.4, ledger.kinetic_energy_lost_j, weld.centre_shift_m
    );
    assert!(ledger.kinetic_energy_lost_j.abs() < 0.05 * before.4);
    // Floe 2 touched both: one contact and one bond remain, the longer
    // ones, with their friction state and age; the energy of the pair's own
    // and of the shorter ones is released.
    let f = w.floes();
    assert_eq!(f.id.to_vec(), vec![2, 3]);
    assert_eq!((w.contacts().len(), w.bonds().len()), (1, 1));
    let (c02, c12, c01) = (
        contacts_before
            .iter()
            .find(|c| (c.a, c.b) == (0, 2))
            .unwrap(),
        contacts_before
            .iter()
            .find(|c| (c.a, c.b) == (1, 2))
            .unwrap(),
        contacts_before
            .iter()
            .find(|c| (c.a, c.b) == (0, 1))
            .unwrap(),
    );
    let (b02, b12, b01) = (
        bonds_before.iter().find(|b| (b.a, b.b) == (0, 2)).unwrap(),
        bonds_before.iter().find(|b| (b.a, b.b) == (1, 2)).unwrap(),
        bonds_before.iter().find(|b| (b.a, b.b) == (0, 1)).unwrap(),
    );
    let (kept_c, dropped_c) = if c12.length_m > c02.length_m {
        (c12, c02)
    } else {
        (c02, c12)
    };
    let (kept_b, dropped_b) = if b12.length_m > b02.length_m {
        (b12, b02)
    } else {
        (b02, b12)
    };
    let c = &w.contacts()[0];
    assert_eq!(c.friction, kept_c.friction);
    assert_eq!(c.age_steps, kept_c.age_steps);
    assert_eq!(w.bonds()[0].formed_at_s, kept_b.formed_at_s);
    assert_eq!(w.bonds()[0].energy_j, kept_b.energy_j);
    let released =
        c01.elastic_energy_j() + b01.energy_j + dropped_c.elastic_energy_j() + dropped_b.energy_j;
    assert!(
        (ledger.contact_energy_released_j - released).abs() <= 1e-12 * released,
        "{} against {released}",
        ledger.contact_energy_released_j
    );

    // The welded floe and floe 2 are bonded (the kept bond's age): they
    // weld at the next step, into one floe, again conserving.
    w.step();
    let before = totals(&w);
    let welds = w.weld().unwrap();
    assert_eq!(welds.len(), 1);
    assert_eq!((welds[0].ids, welds[0].floe.id), ([2, 3], 4));
    assert_conserved(before, totals(&w));
    assert_eq!(w.floes().len(), 1);
    assert!((w.contacts().len(), w.bonds().len()) == (0, 0));
    // Stepping on, the lone floe drifts and spins freely.
    let p = totals(&w);
    for _ in 0..100 {
        w.step();
    }
    assert_conserved(p, totals(&w));
}

#[test]
fn no_weld_when_the_hull_adds_too_much_area_or_moves_the_mass_too_far() {
    // Floe 1 set diagonally off floe 0's corner: the hull of the pair adds
    // about a third of their area.
    let polys = [
        rectangle(0.0, 0.0, 100.0, 100.0),
        rectangle(99.99, 60.0, 100.0, 100.0),
    ];
    let floes = Floes::from_polygons(&polys, &[1.0, 1.5], 917.0).unwrap();
    let model = ContactModel::default();
    let dt = 0.25 * stable_time_step(&floes, &model).0;
    let make = || {
        let mut w = World::new(
            floes.clone(),
            model.clone(),
            NoForcing,
            Periodicity::default(),
            dt,
        )
        .unwrap();
        w.set_cohesion(Some(frozen_at_once())).unwrap();
        w.step();
        w.step();
        assert_eq!(w.bonds().iter().filter(|b| b.formed).count(), 1);
        w
    };
    let plan = |welding: Welding| make().plan_welding(&welding).unwrap().len();
    let d = welding_after(0.0);
    assert_eq!(plan(d), 0, "the default 5 % of added area");
    assert_eq!(
        plan(Welding {
            max_added_area_fraction: 0.5,
            ..d
        }),
        1
    );
    // The same pair with room for the area, but not for a larger floe.
    assert_eq!(
        plan(Welding {
            max_added_area_fraction: 0.5,
            max_area_m2: 2e4,
            ..d
        }),
        0
    );
    // Or for the centre of mass to move (from the pair's, 60 % of the
    // way to the thicker floe, to the hull's centroid half way: 12 m).
    assert_eq!(
        plan(Welding {
            max_added_area_fraction: 0.5,
            max_centre_shift_fraction: 1e-3,
            ..d
        }),
        0
    );
    // Welding needs cohesion's bonds.
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    assert!(w.set_welding(Some(d)).is_err());
}

#[test]
fn welding_is_bitwise_the_same_for_any_thread_count_and_across_a_resume() {
    let cohesion = Cohesion {
        quiet_speed_m_per_s: 0.05,
        bond_after_s: 20.0,
        tensile_strength_n_per_m: 2e4,
        shear_strength_n_per_m: 1e4,
        growth_time_s: 100.0,
    };
    let welding = Welding {
        after_s: 40.0,
        max_added_area_fraction: 0.5,
        max_centre_shift_fraction: 0.5,
        check_every_s: 0.0,
        ..Welding::default()
    };
    let stop = AtomicBool::new(false);
    let run = |threads: usize, resume_at: Option<usize>| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = sheared_channel(400);
            w.set_cohesion(Some(cohesion)).unwrap();
            w.set_welding(Some(welding)).unwrap();
            let mut welds = Vec::new();
            for k in 0..600 {
                if Some(k) == resume_at {
                    let (state, model, forcing, periodicity) = w.into_parts();
                    w = World::resume(state, model, forcing, periodicity).unwrap();
                    w.set_cohesion(Some(cohesion)).unwrap();
                    w.set_welding(Some(welding)).unwrap();
                }
                welds.extend(Stepper::step(&mut w, &stop).welds);
            }
            (w.state().clone(), welds)
        })
    };
    let (one, welds) = run(1, None);
    eprintln!(
        "{} welds, {} floes left, ledger {:?}",
        welds.len(),
        one.floes.len(),
        one.welding
    );
    assert!(welds.len() >= 3, "{} welds", welds.len());
    assert_eq!(one.welding.events, welds.len() as u64);
    let (two, welds_two) = run(2, None);
    assert_eq!(two, one);
    assert_eq!(welds_two, welds);
    assert_eq!(run(2, Some(300)).0, one);
}
