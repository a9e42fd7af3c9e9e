//! A run continued from a saved state is bitwise the uninterrupted run.

use floe_dem::contact_model::ContactModel;

use floe_dem::forcing::Forcing;

use floe_dem::periodicity::Periodicity;
use floe_dem::state::WorldState;
use floe_dem::world::World;
use floe_dem::Vec2;
use floe_fixtures::wind_pack::wind_pack;
use floe_friction::experiments::Preset;
use floe_friction::{Form, Law, RateState, StateLaw};

/// The shared wind pack (`floe_fixtures::wind_pack`: velocity-dependent
/// drag, so the forces depend on the half-step velocity, and contact
/// memory, so broken contacts are part of the state) under rate-and-state
/// friction with the tank parameters.
fn setup() -> (WorldState, ContactModel, Forcing, f64) {
    let tank = Law::RateState(RateState::new(
        Preset::Tank.params(),
        Form::Regularized,
        StateLaw::Slip,
    ));
    let (world, parts) = wind_pack(ContactModel::default().with_law(tank));
    (world.state().clone(), parts.model, parts.forcing, parts.dt)
}

#[test]
fn resuming_from_a_saved_state_is_bitwise_the_uninterrupted_run() {
    let (start, model, forcing, _) = setup();
    let n = 4000;
    let resume = |s: WorldState| {
        World::resume(s, model.clone(), forcing.clone(), Periodicity::default()).unwrap()
    };
    let mut straight = resume(start.clone());
    for _ in 0..2 * n {
        straight.step();
    }
    let mut first = resume(start);
    for _ in 0..n {
        first.step();
    }
    let saved = first.state().clone();
    assert!(
        !saved.contacts.is_empty(),
        "the pack is in contact at the save"
    );
    let mut second = resume(saved);
    for _ in 0..n {
        second.step();
    }
    let (a, b) = (straight.state(), second.state());
    assert!(a.steps == 2 * n as u64 && b.steps == 2 * n as u64);
    // PartialEq on f64 would accept -0.0 == 0.0; compare bits.
    let bits = |v: &[Vec2]| {
        v.iter()
            .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&a.floes.position), bits(&b.floes.position));
    assert_eq!(bits(&a.floes.velocity), bits(&b.floes.velocity));
    assert_eq!(bits(&a.force), bits(&b.force));
    assert_eq!(format!("{:?}", a.contacts), format!("{:?}", b.contacts));
    assert_eq!(format!("{:?}", a.broken), format!("{:?}", b.broken));
    assert_eq!(a.energy, b.energy);
    assert!(!a.broken.is_empty() || a.contacts.len() > 10);
}

#[test]
fn a_resumed_world_that_recomputed_forces_would_differ() {
    // The reason the forces are saved: re-evaluating them at the end-of-step
    // velocity (what a naive resume would do) changes the drag.
    let (start, model, forcing, _) = setup();
    let mut w = World::resume(
        start,
        model.clone(),
        forcing.clone(),
        Periodicity::default(),
    )
    .unwrap();
    for _ in 0..500 {
        w.step();
    }
    let saved = w.state();
    let fresh = World::new(
        saved.floes.clone(),
        model,
        forcing,
        Periodicity::default(),
        saved.dt_s,
    )
    .unwrap();
    let differs = saved
        .external_force
        .iter()
        .zip(&fresh.state().external_force)
        .any(|(p, q)| p != q);
    assert!(
        differs,
        "drag at the full-step velocity equals drag at the half step"
    );
}

#[test]
fn a_damaged_state_is_refused() {
    let (mut s, model, forcing, _) = setup();
    s.torque.pop();
    let err = World::resume(s, model, forcing, Periodicity::default())
        .err()
        .unwrap();
    assert!(err.to_string().contains("torque"), "{err}");
}
