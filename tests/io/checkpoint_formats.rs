//! Checkpoints of every format floe has written read back to the state
//! they hold, from frozen files (tests/data/checkpoints/, README.md there);
//! the encoder writes the current format's frozen bytes exactly.

use floe_dem::bonds::Bond;
use floe_dem::contacts::{BrokenContact, ContactRecord};
use floe_dem::energy_ledger::EnergyLedger;
use floe_dem::floes::{FloeColumns, Floes, Motion};
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::{MotionSchedule, MotionSegment, ScheduledMotion};
use floe_dem::pipeline::floe_stress::StressFilter;
use floe_dem::ridging::RidgingLedger;
use floe_dem::state::WorldState;
use floe_dem::stress_control::{ControlLaw, ServoWall, StressControl};
use floe_dem::welding::WeldingLedger;
use floe_dem::Vec2;
use floe_friction::rate_state::SOLVER_TREND;
use floe_friction::ContactState;
use floe_io::checkpoint::OutputCounts;

/// A friction state with all three rate-and-state slots set.
fn friction(force: f64, theta: f64, root: f64, trend: f64) -> ContactState {
    ContactState {
        tangential_force_n: force,
        law_state: [theta, root, trend],
    }
}

/// A contact between handles `a < b` with every field distinct.
fn contact(a: u32, b: u32, s: f64) -> ContactRecord {
    ContactRecord {
        a,
        b,
        image_offset: Vec2::new(0.0, -2e4 * (a % 2) as f64),
        friction: friction(-1.5e5 * s, 0.37 * s, 2.5e-6 / s, -1e-9 * s),
        age_steps: 17 * b as u64,
        overlap_m2: 0.125 * s,
        point: Vec2::new(101.0 * s, -7.0 / s),
        normal: Vec2::new(0.6, -0.8),
        length_m: 3.3 * s,
        normal_force_n: 4.4e5 * s,
        slip_rate_m_per_s: -2.2e-4 / s,
        friction_power_w: 31.0 * s,
        damping_power_w: 2.0 / 3.0 * s,
        elastic_force_n: 3.9e5 * s,
        normal_energy_j: 12.5 * s,
        tangential_energy_j: 0.1 * s,
    }
}

/// A square of half side `h` around its centroid.
fn square(h: f64) -> [Vec2; 4] {
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Vec2::new(h * x, h * y))
}

/// Four floes, written field by field (no physics in them): a free one, a
/// scheduled wall (floe 5), a free floe on a load point (9) and a
/// stress-controlled servo wall (14); three contacts and two broken ones
/// whose friction states fill all three slots with non-zero trends.
pub fn rich_state() -> WorldState {
    let tri = [
        Vec2::new(-20.0, -10.0),
        Vec2::new(25.0, -5.0),
        Vec2::new(-5.0, 15.0),
    ];
    let mut vertices = Vec::new();
    vertices.extend_from_slice(&square(50.0));
    vertices.extend_from_slice(&tri);
    vertices.extend_from_slice(&square(1.0 / 3.0));
    vertices.extend_from_slice(&square(40.0));
    let columns = FloeColumns {
        id: vec![2, 5, 9, 14],
        position: vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(98.0, 0.7),
            Vec2::new(-1.0 / 7.0, 99.5),
            Vec2::new(97.25, 98.0),
        ],
        angle: vec![0.0, 0.1, -2.5, 1e-3],
        velocity: vec![
            Vec2::new(1e-3, -2e-3),
            Vec2::new(0.1, -0.3),
            Vec2::new(-0.05, 1.0 / 9.0),
            Vec2::ZERO,
        ],
        angular_velocity: vec![1e-5, 0.0, -3e-4, 0.0],
        thickness_m: vec![1.0, 1.5, 0.8, 2.0],
        mass_kg: vec![9.17e6, 4.2e5, 81.5, 1.2e7],
        inertia_kg_m2: vec![1.5e10, 8.8e7, 3.1, 1.3e10],
        area_m2: vec![1e4, 450.0, 4.0 / 9.0, 6.4e3],
        radius_m: vec![70.8, 26.0, 0.48, 56.6],
        r3_moment_m5: vec![1.1e9, 2.2e6, 0.031, 4.4e8],
        motion: vec![
            Motion::Free,
            Motion::Prescribed {
                velocity: Vec2::new(0.1, -0.3),
            },
            Motion::Free,
            Motion::Prescribed {
                velocity: Vec2::new(0.0, -1.25e-3),
            },
        ],
        vertex_start: vec![0, 4, 7, 11, 15],
        vertices,
    };
    let floes = Floes::from_columns(columns).unwrap();
    let schedule = MotionSchedule::new(vec![
        MotionSegment::ramp(0.7, Vec2::new(0.1, -0.3), Vec2::ZERO),
        MotionSegment {
            duration_s: 1.3,
            velocity_start: Vec2::new(-0.2, 0.1),
            velocity_end: Vec2::new(1.0 / 3.0, 0.0),
            angular_velocity_start: 1e-3,
            angular_velocity_end: -2e-3,
        },
    ])
    .unwrap();
    let mut servo = ServoWall::new(3e4, 7.0, 2.0).unwrap();
    servo.speed_m_per_s = -1.25e-3;
    servo.filtered_stress_n_per_m = 1e3 / 3.0 + 0.5;
    let wall = StressControl::new(
        vec![14],
        Vec2::new(0.6, -0.8),
        80.0,
        1e3 / 3.0,
        ControlLaw::Servo(servo),
    )
    .unwrap();
    let state = WorldState {
        floes,
        contacts: vec![contact(0, 1, 1.0), contact(0, 2, 0.3), contact(1, 3, 7.0)],
        bonds: Vec::new(),
        broken: vec![
            BrokenContact {
                a: 0,
                b: 3,
                friction: friction(2e4, 1.1, -3e-7, 4e-10),
                broke_at_s: 12.5,
            },
            BrokenContact {
                a: 2,
                b: 3,
                friction: friction(-1.0 / 3.0, 0.2, 1e-5, -7e-11),
                broke_at_s: 13.0,
            },
        ],
        time_s: 13.5,
        steps: 27,
        dt_s: 0.5,
        energy: EnergyLedger {
            forcing_work_j: 1.5e6,
            friction_dissipation_j: 2.5e5,
            damping_dissipation_j: 1.0 / 7.0,
            boundary_work_j: -3e4,
            released_at_break_j: 42.0,
        },
        force: vec![
            Vec2::new(1e5, -2e5),
            Vec2::new(0.5, 0.25),
            Vec2::new(-3.0, 1e-3),
            Vec2::new(0.0, 7e4),
        ],
        torque: vec![1e6, -2.0, 0.125, 3e3],
        external_force: vec![
            Vec2::new(10.0, 20.0),
            Vec2::ZERO,
            Vec2::new(-0.3, 0.4),
            Vec2::ZERO,
        ],
        external_torque: vec![-5.0, 0.0, 1e-2, 0.0],
        schedules: vec![ScheduledMotion {
            floe_id: 5,
            schedule: schedule.clone(),
        }],
        load_points: vec![
            LoadPoint::new(9, 2e6, Vec2::new(0.25, 99.5 - 1.0 / 3.0), schedule).unwrap(),
        ],
        stress_controls: vec![wall],
        stress_filter: None,
        floe_stress: Vec::new(),
        next_floe_id: 0,
        ridging: Default::default(),
        welding: Default::default(),
    };
    state.validate().unwrap();
    assert!(state
        .contacts
        .iter()
        .all(|c| c.friction.law_state[SOLVER_TREND] != 0.0));
    state
}

/// [`rich_state`] with a proportional wall (format 6 knows no servo).
pub fn proportional_state() -> WorldState {
    let mut state = rich_state();
    state.stress_controls[0].law = ControlLaw::Proportional {
        gain_m_per_s_per_n_per_m: 1e-7,
    };
    state
}

/// The output counts stored beside the state.
pub fn counts() -> OutputCounts {
    OutputCounts {
        snapshots: 12,
        contact_rows: 4096,
        observables: vec![("kinetic_translational".into(), 40), ("mean_mu".into(), 39)],
    }
}

fn fixture_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/checkpoints")
}

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(fixture_dir().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// `back` equals `expected` field by field (through `Debug`: a servo wall
/// at rest holds NaN).
fn assert_same(back: &WorldState, expected: &WorldState, what: &str) {
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
    } = expected;
    macro_rules! same {
        ($($field:ident),*) => {$(
            let (got, want) = (format!("{:?}", back.$field), format!("{:?}", $field));
            assert_eq!(got, want, "{what}: {}", stringify!($field));
        )*};
    }
    same!(
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
        welding
    );
}

/// Versions 1 and 2 (the rate-and-state law's slots implied, no time
/// step) read with the time step given, version 1 with zero trends;
/// without a time step they are refused. Version 1 is version 2 without
/// the trend's 8 bytes per friction state; version 3 adds the time step
/// and two slot counts, and drops the owned-floe count.
#[test]
fn versions_1_and_2_read_with_the_given_time_step() {
    use floe_io::checkpoint::decode;
    let state = rich_state();
    let [v1, v2, v3] = [1, 2, 3].map(|v| fixture(&format!("format_v{v}.bin")));
    let frictions = state.contacts.len() + state.broken.len();
    assert_eq!(v2.len() - v1.len(), 8 * frictions);
    let (dt, slot_counts, owned) = (8, 2 * 4, 8);
    assert_eq!(v3.len(), v2.len() + dt + slot_counts - owned);
    // What versions 1 and 2 lack: schedules, load points, walls.
    let mut expected = state.clone();
    expected.schedules.clear();
    expected.load_points.clear();
    expected.stress_controls.clear();
    let given_dt = || Some(state.dt_s);
    let (back, back_counts) = decode(&v2, given_dt, None).unwrap();
    assert_same(&back, &expected, "version 2");
    assert_eq!(back_counts, counts());
    expected
        .contacts
        .iter_mut()
        .for_each(|c| c.friction.law_state[SOLVER_TREND] = 0.0);
    expected
        .broken
        .iter_mut()
        .for_each(|c| c.friction.law_state[SOLVER_TREND] = 0.0);
    let (back, back_counts) = decode(&v1, given_dt, None).unwrap();
    assert_same(&back, &expected, "version 1");
    assert_eq!(back_counts, counts());
    for old in [&v1, &v2] {
        let e = decode(old, || None, None).expect_err("no time step");
        assert!(e.contains("does not store the time step"), "{e}");
    }
}

/// Versions 3 to 6 read as the state without what each lacks: 6 the
/// servo (it holds a proportional wall), 5 the stress controls, 4 also
/// the load points, 3 also the schedules.
#[test]
fn versions_3_to_6_read_without_what_they_lack() {
    use floe_io::checkpoint::decode;
    let no_dt = || panic!("versions from 3 store the time step");
    let (back, back_counts) = decode(&fixture("format_v6.bin"), no_dt, Some(3)).unwrap();
    assert_same(&back, &proportional_state(), "version 6");
    assert_eq!(back_counts, counts());
    let mut without = rich_state();
    without.stress_controls.clear();
    for v in [5, 4, 3] {
        if v == 4 {
            without.load_points.clear();
        }
        if v == 3 {
            without.schedules.clear();
        }
        let name = format!("format_v{v}.bin");
        let (back, back_counts) = decode(&fixture(&name), no_dt, Some(3)).unwrap();
        assert_same(&back, &without, &name);
        assert_eq!(back_counts, counts());
    }
}

/// Format 7 reads back to the state, the servo's state
/// and a proportional wall's tag included.
#[test]
fn version_7_reads_back_to_the_state() {
    use floe_io::checkpoint::decode;
    let (v6, v7) = (
        fixture("format_v6.bin"),
        fixture("format_v7_proportional.bin"),
    );
    assert_eq!(v7.len(), v6.len() + 1, "the control law's tag");
    let (back, _) = decode(&v7, || None, Some(3)).unwrap();
    assert_same(&back, &proportional_state(), "version 7, proportional");
    let (back, back_counts) = decode(&fixture("format_v7.bin"), || None, Some(3)).unwrap();
    assert_same(&back, &rich_state(), "version 7");
    assert_eq!(back_counts, counts());
    let mut no_slots = rich_state();
    for c in &mut no_slots.contacts {
        c.friction.law_state = [0.0; 3];
    }
    for c in &mut no_slots.broken {
        c.friction.law_state = [0.0; 3];
    }
    let (back, _) = decode(&fixture("format_v7_no_slots.bin"), || None, Some(0)).unwrap();
    assert_same(&back, &no_slots, "version 7, no slots");
}

/// `rich_state` with the life cycle: floe stress with a 30 s filter, each
/// free floe's stress distinct, the walls' zero; the next floe id 57.
pub fn stressed_state() -> WorldState {
    let mut state = rich_state();
    state.stress_filter = Some(StressFilter::new(30.0).unwrap());
    state.floe_stress = vec![
        [-1.25e5, 3.5e3, -2.0e4 / 3.0],
        [0.0; 3],
        [7.5e2, -1.0e5, -4.0e5],
        [0.0; 3],
    ];
    state.next_floe_id = 57;
    state
}

/// Version 8 is version 7 with the life cycle after everything else: a
/// flag, the floe stress (time scale, a length-prefixed list of three
/// `f64` per floe) when the flag is 1, and the next floe id. It reads back
/// to the state; the encoder writes its frozen bytes exactly, still writes
/// version 7 for a state without the life cycle, and version 8 with the
/// flag 0 for a next id alone.
#[test]
fn version_8_is_version_7_with_the_life_cycle() {
    use floe_io::checkpoint::{decode, encode, HEADER_LEN};
    let (v7, v8) = (fixture("format_v7.bin"), fixture("format_v8.bin"));
    let stressed = stressed_state();
    let n = stressed.floes.len();
    assert_eq!(v8.len(), v7.len() + 1 + 8 + 8 + 24 * n + 8);
    assert_eq!(&v8[8..12], &8u32.to_le_bytes());
    assert_eq!(
        &v8[HEADER_LEN..v7.len()],
        &v7[HEADER_LEN..],
        "the payload of 7 first"
    );
    let (back, back_counts) = decode(&v8, || None, Some(3)).unwrap();
    assert_same(&back, &stressed, "version 8");
    assert_eq!(back_counts, counts());
    assert!(encode(&stressed, &counts(), 3) == v8);
    let mut id_only = rich_state();
    id_only.next_floe_id = 9;
    let bytes = encode(&id_only, &counts(), 3);
    assert_eq!(bytes.len(), v7.len() + 1 + 8);
    assert_same(
        &decode(&bytes, || None, Some(3)).unwrap().0,
        &id_only,
        "an id alone",
    );
    let mut wrong = stressed.clone();
    wrong.floe_stress.pop();
    let e = decode(&encode(&wrong, &counts(), 3), || None, Some(3)).expect_err("3 of 4");
    assert!(e.contains("floe_stress has 3 entries for 4 floes"), "{e}");
}

/// [`stressed_state`] with bonds: a formed one between the free floes 0
/// and 2 (every field distinct) and a quiet pair 1-3 on its way to one.
pub fn bonded_state() -> WorldState {
    let mut state = stressed_state();
    let mut formed = Bond::candidate(0, 2, 12.5);
    formed.formed = true;
    formed.formed_at_s = 100.0 / 3.0;
    formed.anchor_a = Vec2::new(0.5, -1.0 / 7.0);
    formed.anchor_b = Vec2::new(-0.5, 0.25);
    formed.normal_a = Vec2::new(0.6, 0.8);
    formed.rest_angle_rad = -0.125;
    formed.length_m = 0.75;
    formed.stiffness_n_per_m = 4.5e6;
    formed.point_a = Vec2::new(1.5, 2.0 / 3.0);
    formed.point_b = Vec2::new(1.5 + 1e-3, 2.0 / 3.0);
    formed.force_on_b = Vec2::new(-4.5e3, 2.0);
    formed.torque_on_a = 17.0;
    formed.torque_on_b = -3.0;
    formed.energy_j = 2.25;
    formed.damping_power_w = 1e-3;
    formed.tension_n_per_m = 6e3;
    formed.shear_n_per_m = 2.0 / 3.0;
    state.bonds = vec![formed, Bond::candidate(1, 3, 40.0)];
    state.validate().unwrap();
    state
}

/// Bytes of a bond in format 9.
const BOND_BYTES: usize = 4 + 4 + 8 + 1 + 8 + 3 * 16 + 3 * 8 + 3 * 16 + 6 * 8;

/// Version 9 is version 8 with the bonds after everything else (a
/// length, then every field of each). It reads back to the state; the
/// encoder writes its frozen bytes exactly, and still writes version 8 for
/// a state with the life cycle and no bonds.
#[test]
fn version_9_is_version_8_with_the_bonds() {
    use floe_io::checkpoint::{decode, encode, HEADER_LEN};
    let (v8, v9) = (fixture("format_v8.bin"), fixture("format_v9.bin"));
    let bonded = bonded_state();
    assert_eq!(v9.len(), v8.len() + 8 + 2 * BOND_BYTES);
    assert_eq!(&v9[8..12], &9u32.to_le_bytes());
    assert_eq!(
        &v9[HEADER_LEN..v8.len()],
        &v8[HEADER_LEN..],
        "the payload of 8 first"
    );
    let (back, back_counts) = decode(&v9, || None, Some(3)).unwrap();
    assert_same(&back, &bonded, "version 9");
    assert_eq!(back_counts, counts());
    assert!(encode(&bonded, &counts(), 3) == v9);
    assert!(encode(&stressed_state(), &counts(), 3) == v8);
    // A bond naming a floe that is not there is refused.
    let mut wrong = bonded.clone();
    wrong.bonds[1].b = 4;
    let e = decode(&encode(&wrong, &counts(), 3), || None, Some(3)).expect_err("floe 4 of 4");
    assert!(e.contains("bonds are not sorted pairs"), "{e}");
}

/// [`bonded_state`] after ridging: every field of the ledger distinct.
pub fn ridged_state() -> WorldState {
    let mut state = bonded_state();
    state.ridging = RidgingLedger {
        events: 1234,
        volume_to_floes_m3: 5.0e3 / 3.0,
        volume_to_coast_m3: 0.125,
        momentum_to_coast_n_s: Vec2::new(-2.5e6, 1.0 / 7.0),
        angular_momentum_to_coast: 3.0e9,
        kinetic_energy_lost_j: 4.4e4,
        contact_energy_released_j: 1e-3,
    };
    state
}

/// Bytes of the ridging ledger in format 10.
const LEDGER_BYTES: usize = 8 + 7 * 8;

/// Version 10 is version 9 with the ridging ledger after everything else
/// (the event count, then its seven `f64`). It reads back to the state;
/// the encoder writes its frozen bytes exactly, still writes version 9 for
/// a state with bonds that has not ridged, and for a state that has
/// ridged without bonds an empty bond list before the ledger.
#[test]
fn version_10_is_version_9_with_the_ridging_ledger() {
    use floe_io::checkpoint::{decode, encode, HEADER_LEN};
    let (v9, v10) = (fixture("format_v9.bin"), fixture("format_v10.bin"));
    let ridged = ridged_state();
    assert_eq!(v10.len(), v9.len() + LEDGER_BYTES);
    assert_eq!(&v10[8..12], &10u32.to_le_bytes());
    assert_eq!(
        &v10[HEADER_LEN..v9.len()],
        &v9[HEADER_LEN..],
        "the payload of 9 first"
    );
    let (back, back_counts) = decode(&v10, || None, Some(3)).unwrap();
    assert_same(&back, &ridged, "version 10");
    assert_eq!(back_counts, counts());
    assert!(encode(&ridged, &counts(), 3) == v10);
    assert!(encode(&bonded_state(), &counts(), 3) == v9);
    let mut unbonded = ridged.clone();
    unbonded.bonds.clear();
    let bytes = encode(&unbonded, &counts(), 3);
    let v8 = fixture("format_v8.bin");
    assert_eq!(bytes.len(), v8.len() + 8 + LEDGER_BYTES);
    assert_same(
        &decode(&bytes, || None, Some(3)).unwrap().0,
        &unbonded,
        "ridged without bonds",
    );
}

/// Writes `format_v10.bin` (run once, by hand, when the format was made).
#[test]
#[ignore]
fn write_format_10_fixture() {
    let bytes = floe_io::checkpoint::encode(&ridged_state(), &counts(), 3);
    std::fs::write(fixture_dir().join("format_v10.bin"), bytes).unwrap();
}

/// [`ridged_state`] after welding: every field of the ledger distinct.
pub fn welded_state() -> WorldState {
    let mut state = ridged_state();
    state.welding = WeldingLedger {
        events: 77,
        area_added_m2: 1.0e6 / 3.0,
        kinetic_energy_lost_j: -2.5e-3,
        contact_energy_released_j: 6.0e7,
    };
    state
}

/// Bytes of the welding ledger in format 11.
const WELD_LEDGER_BYTES: usize = 8 + 3 * 8;

/// Version 11 is version 10 with the welding ledger after everything else
/// (the event count, then its three `f64`). It reads back to the state;
/// the encoder writes its frozen bytes exactly and still writes version 10
/// for a state that has ridged but not welded; a state that has welded
/// without ridging writes a zero ridging ledger before it.
#[test]
fn version_11_is_version_10_with_the_welding_ledger() {
    use floe_io::checkpoint::{decode, encode, HEADER_LEN};
    let (v10, v11) = (fixture("format_v10.bin"), fixture("format_v11.bin"));
    let welded = welded_state();
    assert_eq!(v11.len(), v10.len() + WELD_LEDGER_BYTES);
    assert_eq!(&v11[8..12], &11u32.to_le_bytes());
    assert_eq!(
        &v11[HEADER_LEN..v10.len()],
        &v10[HEADER_LEN..],
        "the payload of 10 first"
    );
    let (back, back_counts) = decode(&v11, || None, Some(3)).unwrap();
    assert_same(&back, &welded, "version 11");
    assert_eq!(back_counts, counts());
    assert!(encode(&welded, &counts(), 3) == v11);
    assert!(encode(&ridged_state(), &counts(), 3) == v10);
    let mut unridged = welded.clone();
    unridged.ridging = RidgingLedger::default();
    let bytes = encode(&unridged, &counts(), 3);
    assert_eq!(bytes.len(), v11.len());
    assert_same(
        &decode(&bytes, || None, Some(3)).unwrap().0,
        &unridged,
        "welded without ridging",
    );
}

/// Writes `format_v11.bin` (run once, by hand, when the format was made).
#[test]
#[ignore]
fn write_format_11_fixture() {
    let bytes = floe_io::checkpoint::encode(&welded_state(), &counts(), 3);
    std::fs::write(fixture_dir().join("format_v11.bin"), bytes).unwrap();
}

/// The encoder writes the frozen bytes of the current format exactly.
#[test]
fn the_encoder_writes_the_frozen_current_format() {
    use floe_io::checkpoint::encode;
    let (rich, prop, counts) = (rich_state(), proportional_state(), counts());
    assert!(encode(&rich, &counts, 3) == fixture("format_v7.bin"));
    assert!(encode(&prop, &counts, 3) == fixture("format_v7_proportional.bin"));
    assert!(encode(&rich, &counts, 0) == fixture("format_v7_no_slots.bin"));
}

/// A version from the future is refused, by name.
#[test]
fn a_version_from_the_future_is_refused() {
    use floe_io::checkpoint::{decode, FORMAT_VERSION};
    let mut future = fixture("format_v7.bin");
    future[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    let e = decode(&future, || Some(0.5), None).expect_err("a future version");
    assert!(
        e.contains(&format!("format version {}", FORMAT_VERSION + 1)),
        "{e}"
    );
}
