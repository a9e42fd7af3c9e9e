//! A [`WorldState`] as a self-checking byte string: a checkpoint.
//!
//! Layout (all integers little-endian, every `f64` as its IEEE bits, so the
//! state round-trips bitwise):
//!
//! | bytes | content |
//! | --- | --- |
//! | 8 | magic `FLOECKPT` |
//! | 4 | format version ([`FORMAT_VERSION`]) |
//! | 4 | zero |
//! | 8 | payload length |
//! | 8 | FNV-1a 64 checksum of the payload |
//! | ... | payload |
//!
//! The payload holds the output counts at the checkpoint, then every field
//! of the state in declaration order; a vector is its length (u64) then
//! its elements. Bytes after the payload are ignored (a slot is reused for
//! smaller states without shrinking).
//!
//! Each record's `write` and `read` sit side by side, one file per group:
//! `header` (the 32 bytes above), `counts` (snapshots, contact rows,
//! samples per observable), `floes` (the columns), `contacts` (touching
//! and broken, with their friction states), `clock_and_energy`,
//! `schedules` (motion schedules and load points), `stress_controls` and
//! `life_cycle` (floe stress, the next floe id), `bonds`, `ridging` and
//! `welding` (their ledgers). [`encode`] writes the current format
//! ([`FORMAT_VERSION`]) for a state that has welded, version 10 for one
//! that has ridged, version 9 for one with bonds, version 8
//! for one with floe stress or a next floe id but no bonds, and
//! version 7 for one with neither (the same bytes as before the life cycle
//! existed); the readers branch on the version
//! where an older format differs, and read a state without what the format
//! lacks:
//!
//! | version | differs from the next by |
//! | --- | --- |
//! | 10 | no welding ledger |
//! | 9 | no ridging ledger |
//! | 8 | no bonds |
//! | 7 | no life cycle (floe stress, next floe id) |
//! | 6 | a stress-controlled wall's law is its proportional gain alone (no tag, no servo) |
//! | 5 | no stress-controlled walls |
//! | 4 | no load points |
//! | 3 | no motion schedules |
//! | 2 | no time step (the caller gives it) and no slot counts (three slots implied), and the count of owned floes after the floes |
//! | 1 | two slots implied (`theta`, the solver's root): resumes with zero trends |
//!
//! tests/data/checkpoints/ holds a frozen checkpoint of each format, which
//! tests/io/checkpoint_formats.rs reads back.

mod bonds;
mod bytes;
mod clock_and_energy;
mod contacts;
mod counts;
mod floes;
mod header;
mod life_cycle;
mod ridging;
mod schedules;
mod stress_controls;
mod welding;

pub use counts::OutputCounts;
pub use header::{
    fnv1a64, verify, FORMAT_VERSION, HEADER_LEN, MAGIC, OLDEST_READABLE_VERSION,
    WITHOUT_BONDS_VERSION, WITHOUT_LIFE_CYCLE_VERSION, WITHOUT_RIDGING_VERSION,
    WITHOUT_WELDING_VERSION,
};

use bytes::{ReadResult, Reader, Writer};
use floe_dem::state::WorldState;
use floe_friction::LAW_STATE_SLOTS;

/// The checkpoint bytes of `state` with the output `counts`, each friction
/// state with `law_state_slots` slots of law state (the law's
/// `FrictionLaw::state_slots`, at most `LAW_STATE_SLOTS`).
pub fn encode(state: &WorldState, counts: &OutputCounts, law_state_slots: usize) -> Vec<u8> {
    assert!(
        law_state_slots <= LAW_STATE_SLOTS,
        "at most {LAW_STATE_SLOTS} slots"
    );
    let w = &mut Writer {
        bytes: Vec::with_capacity(estimate_len(state)),
        law_state_slots,
    };
    counts::write(w, counts);
    // Exhaustive destructuring: a field added to the engine's state fails
    // to compile here instead of being silently left out of checkpoints.
    let WorldState {
        floes,
        contacts,
        broken,
        bonds,
        time_s,
        steps,
        dt_s,
        energy,
        force,
        torque,
        external_force,
        external_torque,
        schedules,
        load_points,
        stress_controls,
        stress_filter,
        floe_stress,
        next_floe_id,
        ridging,
        welding,
    } = state;
    floes::write(w, floes);
    contacts::write_touching(w, contacts);
    contacts::write_broken(w, broken);
    clock_and_energy::write_clock(w, *time_s, *steps, *dt_s);
    clock_and_energy::write_energy(w, energy);
    w.v2s(force);
    w.f64s(torque);
    w.v2s(external_force);
    w.f64s(external_torque);
    schedules::write_schedules(w, schedules);
    schedules::write_load_points(w, load_points);
    stress_controls::write(w, stress_controls);
    // A state without the life cycle is written as version 7, byte for
    // byte what floe wrote before the life cycle existed.
    let welded = *welding != Default::default();
    let ridged = *ridging != Default::default() || welded;
    if stress_filter.is_none() && *next_floe_id == 0 && bonds.is_empty() && !ridged {
        return header::write(&w.bytes, WITHOUT_LIFE_CYCLE_VERSION);
    }
    let life = life_cycle::LifeCycle {
        stress_filter: *stress_filter,
        floe_stress: floe_stress.clone(),
        next_floe_id: *next_floe_id,
    };
    life_cycle::write(w, &life);
    if bonds.is_empty() && !ridged {
        return header::write(&w.bytes, WITHOUT_BONDS_VERSION);
    }
    bonds::write(w, bonds);
    if !ridged {
        return header::write(&w.bytes, WITHOUT_RIDGING_VERSION);
    }
    ridging::write(w, ridging);
    if !welded {
        return header::write(&w.bytes, WITHOUT_WELDING_VERSION);
    }
    welding::write(w, welding);
    header::write(&w.bytes, FORMAT_VERSION)
}

/// A generous guess of the encoded size, for reserving slot space.
pub fn estimate_len(state: &WorldState) -> usize {
    HEADER_LEN
        + 1024
        + state.floes.len() * 200
        + state.floes.vertices.len() * 16
        + state.contacts.len() * 176
        + state.broken.len() * 48
        + state.floe_stress.len() * 24
        + state.bonds.len() * 200
}

/// The state and counts of checkpoint `bytes`, after checking the header,
/// the checksum and the state's consistency. Versions before 3 do not
/// store the time step: `fallback_dt_s` gives it (the scenario's), and is
/// not called for version 3. With `law_state_slots`, a version-3
/// checkpoint whose friction states hold another number of slots is
/// refused (it was written under another law).
pub fn decode(
    bytes: &[u8],
    fallback_dt_s: impl FnOnce() -> Option<f64>,
    law_state_slots: Option<usize>,
) -> ReadResult<(WorldState, OutputCounts)> {
    let payload = verify(bytes)?;
    let r = &mut Reader {
        buf: payload,
        pos: 0,
        version: header::version_of(bytes),
    };
    let counts = counts::read(r)?;
    let floes = floes::read(r)?;
    let contacts = contacts::read_touching(r, law_state_slots)?;
    let broken = contacts::read_broken(r)?;
    let (time_s, steps, dt_s) = clock_and_energy::read_clock(r, fallback_dt_s)?;
    let energy = clock_and_energy::read_energy(r)?;
    let state = WorldState {
        floes,
        contacts,
        broken,
        bonds: Vec::new(),
        time_s,
        steps,
        dt_s,
        energy,
        force: r.v2s()?,
        torque: r.f64s()?,
        external_force: r.v2s()?,
        external_torque: r.f64s()?,
        schedules: schedules::read_schedules(r)?,
        load_points: schedules::read_load_points(r)?,
        stress_controls: stress_controls::read(r)?,
        stress_filter: None,
        floe_stress: Vec::new(),
        next_floe_id: 0,
        ridging: Default::default(),
        welding: Default::default(),
    };
    let mut state = state;
    let life = life_cycle::read(r)?;
    (state.stress_filter, state.floe_stress, state.next_floe_id) =
        (life.stress_filter, life.floe_stress, life.next_floe_id);
    state.bonds = bonds::read(r)?;
    state.ridging = ridging::read(r)?;
    state.welding = welding::read(r)?;
    if r.unread() != 0 {
        return Err(format!("{} unread bytes after the state", r.unread()));
    }
    state.validate().map_err(|e| e.to_string())?;
    Ok((state, counts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use floe_dem::contact_model::ContactModel;
    use floe_dem::floes::{Floes, Motion};
    use floe_dem::forcing::NoForcing;
    use floe_dem::load_point::LoadPoint;
    use floe_dem::periodicity::Periodicity;
    use floe_dem::stress_control::{ControlLaw, ServoWall, StressControl};
    use floe_dem::world::{stable_time_step, World};
    use floe_dem::Vec2;
    use floe_friction::{Amontons, FrictionLaw, Law};

    /// A 4 x 4 grid of squares pressed into each other and let go, a few
    /// steps in: its contacts slip at changing rates, so their friction
    /// states carry non-zero trends.
    fn springing_pack(model: ContactModel) -> WorldState {
        let polys: Vec<Vec<Vec2>> = (0..16)
            .map(|k| {
                let c = Vec2::new(
                    (k % 4) as f64 * 98.0,
                    (k / 4) as f64 * 98.0 + 0.7 * (k % 4) as f64,
                );
                [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(x, y)| c + 50.0 * Vec2::new(x, y))
                    .to_vec()
            })
            .collect();
        let floes = Floes::from_polygons(&polys, &[1.0; 16], 917.0).unwrap();
        let dt = 0.5 * stable_time_step(&floes, &model).0;
        let mut world = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
        for _ in 0..3 {
            world.step();
        }
        world.state().clone()
    }

    /// The motion schedules, load points and stress controls (a servo
    /// wall's state too) round-trip bitwise. The older formats, without
    /// them, are read from frozen files in tests/io/checkpoint_formats.rs.
    #[test]
    fn boundaries_round_trip() {
        use floe_dem::motion_schedule::{MotionSchedule, MotionSegment};
        let model = ContactModel::default();
        let state = springing_pack(model.clone());
        let mut world =
            World::resume(state, model.clone(), NoForcing, Periodicity::default()).unwrap();
        let id = world.floes().id[0];
        let v = Vec2::new(0.1, -0.3);
        world
            .set_motion(id, Motion::Prescribed { velocity: v })
            .unwrap();
        let schedule = MotionSchedule::new(vec![
            MotionSegment::ramp(0.7, v, Vec2::ZERO),
            MotionSegment {
                duration_s: 1.3,
                velocity_start: Vec2::new(-0.2, 0.1),
                velocity_end: Vec2::new(1.0 / 3.0, 0.0),
                angular_velocity_start: 1e-3,
                angular_velocity_end: -2e-3,
            },
        ])
        .unwrap();
        world.set_schedule(id, schedule.clone()).unwrap();
        let driven = world.floes().id[5];
        let anchor = world.floes().position[5] + Vec2::new(0.25, -1.0 / 3.0);
        world
            .set_load_point(LoadPoint::new(driven, 2e6, anchor, schedule).unwrap())
            .unwrap();
        let wall = world.floes().id[9];
        world
            .set_motion(
                wall,
                Motion::Prescribed {
                    velocity: Vec2::ZERO,
                },
            )
            .unwrap();
        let normal = Vec2::new(0.6, 0.8);
        let servo = ControlLaw::Servo(ServoWall::new(3e4, 7.0, 2.0).unwrap());
        let control = StressControl::new(vec![wall], normal, 98.0, 1e3 / 3.0, servo).unwrap();
        world.add_stress_control(control).unwrap();
        for _ in 0..3 {
            world.step();
        }
        let state = world.state().clone();
        assert_eq!(
            (
                state.schedules.len(),
                state.load_points.len(),
                state.stress_controls.len()
            ),
            (1, 1, 1)
        );
        let counts = OutputCounts::default();
        let (back, _) = decode(&encode(&state, &counts, 3), || None, Some(3)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{state:?}"));
        let ControlLaw::Servo(moved) = state.stress_controls[0].law else {
            panic!("a servo wall")
        };
        assert!(
            moved.speed_m_per_s != 0.0,
            "the servo's state is not trivial"
        );
    }

    /// Each law's friction states take its own number of slots: Amontons
    /// none, 8 bytes less per slot and contact than the rate-and-state law.
    #[test]
    fn a_law_stores_the_slots_it_declares() {
        let law = Law::Amontons(Amontons { mu: 0.6 });
        let slots = law.state_slots();
        assert_eq!(slots, 0);
        let state = springing_pack(ContactModel::default().with_law(law));
        let counts = OutputCounts::default();
        let (none, three) = (encode(&state, &counts, slots), encode(&state, &counts, 3));
        let frictions = state.contacts.len() + state.broken.len();
        assert!(frictions > 0);
        assert_eq!(three.len() - none.len(), 3 * 8 * frictions);
        let (back, _) = decode(&none, || None, Some(0)).unwrap();
        assert_eq!(format!("{back:?}"), format!("{state:?}"));
        // Read for a law of another slot count: refused.
        let e = decode(&three, || None, Some(0)).expect_err("3 slots for a 0-slot law");
        assert!(e.contains("another law"), "{e}");
        // More slots than a contact state holds is refused.
        let mut bad = encode(&state, &counts, 0);
        let at = bad.len() - payload_tail(&state);
        bad[at..at + 4].copy_from_slice(&((LAW_STATE_SLOTS + 1) as u32).to_le_bytes());
        let payload = bad[HEADER_LEN..].to_vec();
        bad[24..32].copy_from_slice(&fnv1a64(&payload).to_le_bytes());
        let e = decode(&bad, || None, None).expect_err("too many slots");
        assert!(e.contains("law state slots"), "{e}");
    }

    /// Bytes from the slot count before the contacts to the end of the
    /// payload, for a state whose friction states have no slots.
    fn payload_tail(state: &WorldState) -> usize {
        let n = state.floes.len();
        let contact = 4 + 4 + 16 + 8 + 8 + 13 * 8;
        4 + 8
            + state.contacts.len() * contact
            + 4
            + 8
            + state.broken.len() * (4 + 4 + 8 + 8)
            + 8
            + 8
            + 8
            + 5 * 8
            + 4 * 8
            + n * (16 + 8 + 16 + 8)
            + 8 // the schedule count (none here)
            + 8 // the load-point count (none here)
            + 8 // the stress-control count (none here)
    }
}
