//! Ridging: a floe squeezed between walls bears at most the ridging
//! strength per metre of contact and loses the rest of its overlap to the
//! coast, its volume and mass kept with the ledger's to round-off; two
//! free floes that ridge keep volume, momentum and angular momentum to
//! round-off, the energy ledger balanced with ridging's losses; the bits
//! do not depend on the thread count or a resume.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floes, Motion};
use floe_dem::forcing::NoForcing;
use floe_dem::geometry::cross;
use floe_dem::periodicity::Periodicity;
use floe_dem::ridging::{Ridging, Rubble};
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_fixtures::channel::sheared_channel;

const DENSITY: f64 = 917.0;

fn rect(x0: f64, y0: f64, w: f64, h: f64) -> Vec<Vec2> {
    [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
        .map(|(x, y)| Vec2::new(x0 + x, y0 + y))
        .to_vec()
}

/// Free floes' volume, m^3.
fn volume(w: &World<NoForcing>) -> f64 {
    let f = w.floes();
    (0..f.len())
        .filter(|&i| f.is_free(i))
        .map(|i| f.area_m2[i] * f.thickness_m[i])
        .sum()
}

/// A 100 m x 100 m floe 0.5 m thick between a fixed wall on its left and
/// a wall on its right closing at 1 cm/s; both walls 150 m long, so that
/// the contacts are the floe's whole sides.
fn squeezed() -> World<NoForcing> {
    let polys = [
        rect(-100.0, -25.0, 100.0, 150.0),
        rect(0.0, 0.0, 100.0, 100.0),
        rect(100.0, -25.0, 100.0, 150.0),
    ];
    let mut floes = Floes::from_polygons(&polys, &[1.0, 0.5, 1.0], DENSITY).unwrap();
    floes.set_motion(
        0,
        Motion::Prescribed {
            velocity: Vec2::ZERO,
        },
    );
    floes.set_motion(
        2,
        Motion::Prescribed {
            velocity: Vec2::new(-0.01, 0.0),
        },
    );
    let model = ContactModel::default();
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    w.set_ridging(Some(Ridging::default())).unwrap();
    w
}

#[test]
fn a_floe_squeezed_between_walls_bears_the_ridging_strength_and_loses_the_rest() {
    let mut w = squeezed();
    let r = Ridging::default();
    let cap_per_m = r.strength_at(0.5);
    let (v0, m0) = (volume(&w), w.floes().mass_kg[1]);
    let dt = w.dt_s();
    // The capped penetration, strength / kappa with kappa = E h / sqrt(A):
    // reached at both walls before the floe ridges.
    let kappa = 6e6 * 0.5 / 100.0;
    let depth = cap_per_m / kappa;
    let duration = 3000.0;
    let steps = (duration / dt).ceil() as usize;
    let mut most_over = 0.0f64;
    let mut at_cap = 0usize;
    for _ in 0..steps {
        w.step();
        w.ridge().unwrap();
        for c in w.contacts() {
            let ratio = c.elastic_force_n / (cap_per_m * c.length_m);
            most_over = most_over.max(ratio);
            if ratio > 0.97 {
                at_cap += 1;
            }
        }
        // Volume and mass: the floe's and the coast's add up to the start's.
        let ledger = w.ridging_ledger();
        let v = volume(&w) + ledger.volume_to_coast_m3;
        assert!((v - v0).abs() < 1e-12 * v0, "{v} vs {v0}");
        let m = w.floes().mass_kg[1] + DENSITY * ledger.volume_to_coast_m3;
        assert!((m - m0).abs() < 1e-12 * m0, "{m} vs {m0}");
    }
    let ledger = *w.ridging_ledger();
    let t = w.time_s();
    eprintln!(
        "{} events, {:.4} m^3 to the coast, force at most {most_over:.4} x the cap, {at_cap} contact-steps at it",
        ledger.events, ledger.volume_to_coast_m3
    );
    // The force never goes more than a step's squeeze and its damping over
    // the cap, and sits at it once the floe ridges.
    assert!(most_over < 1.02, "{most_over}");
    assert!(at_cap > steps, "{at_cap} of {} contact-steps", 2 * steps);
    // The walls closed by 1 cm/s x t; all but the two capped penetrations
    // went to the coast: h x 100 m x (v t - 2 depth), to a step's closing.
    let expected = 0.5 * 100.0 * (0.01 * t - 2.0 * depth);
    assert!(
        (ledger.volume_to_coast_m3 - expected).abs() < 0.02 * expected,
        "{} m^3 vs {expected} m^3",
        ledger.volume_to_coast_m3
    );
    // The floe is narrower by as much, and still 0.5 m thick.
    let f = w.floes();
    assert_eq!(f.thickness_m[1], 0.5);
    assert!(ledger.kinetic_energy_lost_j > 0.0 && ledger.momentum_to_coast_n_s.x != 0.0);
}

#[test]
fn a_floe_squeezed_to_less_than_its_smallest_part_goes_whole_to_the_coast() {
    let mut w = squeezed();
    // The wall closes 150 m on the 100 m floe at 5 cm/s.
    let id = w.floes().id[2];
    w.set_velocity(id, Vec2::new(-0.05, 0.0), 0.0).unwrap();
    let (v0, m0) = (volume(&w), w.floes().mass_kg[1]);
    let floe = w.floes().id[1];
    let mut gone_at = None;
    for k in 0..(3000.0 / w.dt_s()) as usize {
        w.step();
        w.ridge().unwrap();
        let ledger = w.ridging_ledger();
        let v = volume(&w) + ledger.volume_to_coast_m3;
        assert!((v - v0).abs() < 1e-12 * v0, "{v} vs {v0}");
        if gone_at.is_none() && w.floes().handle_of(floe).is_none() {
            gone_at = Some(k);
        }
    }
    let ledger = *w.ridging_ledger();
    let k = gone_at.expect("the floe went whole");
    eprintln!("gone at step {k}, {} events", ledger.events);
    assert_eq!(volume(&w), 0.0);
    assert!((ledger.volume_to_coast_m3 - v0).abs() < 1e-12 * v0);
    assert!((DENSITY * ledger.volume_to_coast_m3 - m0).abs() < 1e-12 * m0);
    // The walls never met the ice again: no contact is left.
    assert!(w.contacts().is_empty());
}

#[test]
fn without_ridging_the_squeezed_floe_overlaps_past_the_cap() {
    let mut w = squeezed();
    w.set_ridging(None).unwrap();
    let cap_per_m = Ridging::default().strength_at(0.5);
    for _ in 0..(3000.0 / w.dt_s()) as usize {
        w.step();
    }
    let most = w
        .contacts()
        .iter()
        .map(|c| c.elastic_force_n / (cap_per_m * c.length_m))
        .fold(0.0, f64::max);
    assert!(most > 5.0, "{most}");
    assert_eq!(w.ridging_ledger().events, 0);
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

/// A thin floe (0.3 m, 100 m square) driven off-centre into a thick one
/// (2 m, 200 m square) at 0.5 m/s: the thin one ridges onto the thick.
fn collision() -> World<NoForcing> {
    let polys = [
        rect(0.0, 0.0, 200.0, 200.0),
        rect(-100.0, 130.0, 100.0, 100.0),
    ];
    let floes = Floes::from_polygons(&polys, &[2.0, 0.3], DENSITY).unwrap();
    let model = ContactModel::default();
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    let id = w.floes().id[1];
    w.set_velocity(id, Vec2::new(1.0, -0.05), 2e-4).unwrap();
    w.set_ridging(Some(Ridging {
        strength_n_per_m: 5e3,
        ..Ridging::default()
    }))
    .unwrap();
    w
}

/// Energy held and lost, less the work done on the floes: constant if the
/// ledger balances.
fn energy_residual(w: &World<NoForcing>) -> f64 {
    let o = w.observables(1.0);
    let l = o.ledger;
    let r = w.ridging_ledger();
    o.kinetic_translational_j
        + o.kinetic_rotational_j
        + o.contact_energy_j
        + l.friction_dissipation_j
        + l.damping_dissipation_j
        + l.released_at_break_j
        + r.kinetic_energy_lost_j
        + r.contact_energy_released_j
        - l.forcing_work_j
        - l.boundary_work_j
}

/// Steps `w` with ridging `steps` times, checking after each step that
/// volume (1e-12), momentum (1e-12) and angular momentum (1e-11) are kept;
/// returns the change of the energy residual (held + lost - work) and the
/// kinetic energy at the start.
fn ridge_conserving(w: &mut World<NoForcing>, steps: usize) -> (f64, f64) {
    let (v0, (p0, l0)) = (volume(w), momenta(w));
    let e0 = energy_residual(w);
    let ke0 = {
        let o = w.observables(1.0);
        o.kinetic_translational_j + o.kinetic_rotational_j
    };
    for _ in 0..steps {
        w.step();
        w.ridge().unwrap();
        let (p, l) = momenta(w);
        assert!((p - p0).length() < 1e-12 * p0.length(), "{p} vs {p0}");
        assert!((l - l0).abs() < 1e-11 * l0.abs(), "{l} vs {l0}");
        let v = volume(w);
        assert!((v - v0).abs() < 1e-12 * v0, "{v} vs {v0}");
    }
    (energy_residual(w) - e0, ke0)
}

#[test]
fn free_floes_that_ridge_keep_volume_momentum_and_angular_momentum() {
    let mut w = collision();
    let h0 = w.floes().thickness_m[0];
    let (residual, ke0) = ridge_conserving(&mut w, 3000);
    let ledger = *w.ridging_ledger();
    let f = w.floes();
    eprintln!(
        "{} events, {:.3} m^3 ridged, thick floe {} m, thin floe {} m^2; KE lost {:.3e} J of {ke0:.3e} J",
        ledger.events, ledger.volume_to_floes_m3, f.thickness_m[0], f.area_m2[1], ledger.kinetic_energy_lost_j
    );
    assert!(ledger.events > 5, "{}", ledger.events);
    assert_eq!(ledger.volume_to_coast_m3, 0.0);
    // The thin floe's lost area is the thick floe's gain in volume.
    let lost = (1e4 - f.area_m2[1]) * 0.3;
    assert!((lost - ledger.volume_to_floes_m3).abs() < 1e-9 * lost);
    let gained = (f.thickness_m[0] - h0) * f.area_m2[0];
    assert!((gained - lost).abs() < 1e-9 * lost, "{gained} vs {lost}");
    // The ledger follows the floes' energy through ridging.
    assert!(
        residual.abs() < 0.01 * ke0,
        "residual {residual} J of {ke0} J"
    );
}

#[test]
fn rubble_on_both_floes_thickens_them_alike_keeping_volume_and_both_momenta() {
    let mut w = collision();
    let both = Ridging {
        rubble: Rubble::Both,
        ..w.ridging().unwrap()
    };
    w.set_ridging(Some(both)).unwrap();
    let h0: Vec<f64> = w.floes().thickness_m.clone();
    let (residual, ke0) = ridge_conserving(&mut w, 3000);
    let ledger = *w.ridging_ledger();
    let f = w.floes();
    let gain = |i: usize| f.thickness_m[i] - h0[i];
    eprintln!(
        "{} events, {:.3} m^3 ridged; thick floe +{} m, thin floe +{} m ({} m^2 left)",
        ledger.events,
        ledger.volume_to_floes_m3,
        gain(0),
        gain(1),
        f.area_m2[1]
    );
    assert!(ledger.events > 5, "{}", ledger.events);
    // Each event gives both the same thickness, V / (A_gainer + A_kept).
    assert!(gain(1) > 0.0);
    assert!(
        (gain(0) - gain(1)).abs() < 1e-9 * gain(1),
        "{} vs {}",
        gain(0),
        gain(1)
    );
    // The volume ridged is the thin floe's lost area at its start thickness
    // plus what its kept part took back on later cuts (ridged again).
    let onto_thick = gain(0) * f.area_m2[0];
    let lost_by_thin = 1e4 * 0.3 - f.area_m2[1] * f.thickness_m[1];
    assert!((onto_thick - lost_by_thin).abs() < 1e-9 * lost_by_thin);
    assert!(
        residual.abs() < 0.01 * ke0,
        "residual {residual} J of {ke0} J"
    );
}

#[test]
fn ridging_is_bitwise_the_same_for_any_thread_count_and_across_a_resume() {
    let ridging = Ridging {
        strength_n_per_m: 100.0,
        ..Ridging::default()
    };
    let run = |threads: usize, resume_at: Option<usize>| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = sheared_channel(400);
            w.set_ridging(Some(ridging)).unwrap();
            for k in 0..600 {
                if Some(k) == resume_at {
                    let (state, model, forcing, periodicity) = w.into_parts();
                    w = World::resume(state, model, forcing, periodicity).unwrap();
                    w.set_ridging(Some(ridging)).unwrap();
                }
                w.step();
                w.ridge().unwrap();
            }
            w.state().clone()
        })
    };
    let one = run(1, None);
    eprintln!("{} ridging events", one.ridging.events);
    assert!(one.ridging.events > 10, "{}", one.ridging.events);
    assert_eq!(run(2, None), one);
    assert_eq!(run(2, Some(300)), one);
}
