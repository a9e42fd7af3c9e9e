//! Stable floe identity: floes taken out of a world and put back, floes
//! added in another order, handles shifting under the contact memory, and
//! the stages of a step called one by one.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floe, Floes};
use floe_dem::forcing::NoForcing;
use floe_dem::geometry::FloeShape;
use floe_dem::periodicity::Periodicity;
use floe_dem::pipeline::Stage;
use floe_dem::world::{stable_time_step, World};
use floe_dem::{DemError, Vec2};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const RHO_ICE: f64 = 917.0;

fn square(c: Vec2, side: f64) -> Vec<Vec2> {
    let h = 0.5 * side;
    [(-h, -h), (h, -h), (h, h), (-h, h)]
        .map(|(x, y)| c + Vec2::new(x, y))
        .to_vec()
}

/// 36 squares (ids 10..46) with random velocities in a closed box of four
/// fixed walls (ids 100..104), restitution 0.9: floes collide, part and
/// collide again, so contacts break and re-form within the contact memory.
/// With `far_floe`, one more square (id 1, below every other id) rests far
/// outside the box, touching nothing.
fn bouncing_box(far_floe: bool) -> Vec<Floe> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut floes = Vec::new();
    let floe = |id: u64, poly: &[Vec2], h: f64| {
        let (shape, c) = FloeShape::from_world(0, poly).unwrap();
        Floe::new(id, &shape, c, h, RHO_ICE)
    };
    for k in 0..36 {
        let c = Vec2::new((k % 6) as f64 * 104.0, (k / 6) as f64 * 104.0);
        let v = Vec2::new(rng.gen_range(-0.3..0.3), rng.gen_range(-0.3..0.3));
        let f = floe(10 + k, &square(c, 100.0), 1.0 + 0.02 * k as f64);
        floes.push(f.with_velocity(v, rng.gen_range(-2e-3..2e-3)));
    }
    let (lo, hi) = (-90.0, 5.0 * 104.0 + 90.0);
    let mid = 0.5 * (lo + hi);
    let walls = [
        (Vec2::new(mid, lo - 50.0), 900.0, 100.0),
        (Vec2::new(mid, hi + 50.0), 900.0, 100.0),
        (Vec2::new(lo - 50.0, mid), 100.0, 900.0),
        (Vec2::new(hi + 50.0, mid), 100.0, 900.0),
    ];
    for (k, (c, w, h)) in walls.into_iter().enumerate() {
        let poly = [(-w, -h), (w, -h), (w, h), (-w, h)]
            .map(|(x, y)| c + 0.5 * Vec2::new(x, y))
            .to_vec();
        floes.push(floe(100 + k as u64, &poly, 1.0).prescribed(Vec2::ZERO));
    }
    if far_floe {
        floes.push(floe(1, &square(Vec2::new(-5e3, -5e3), 100.0), 1.0));
    }
    floes
}

fn world_of(floes: Vec<Floe>) -> World<NoForcing> {
    let mut set = Floes::new();
    for f in floes {
        set.insert(f).unwrap();
    }
    let model = ContactModel {
        memory_s: 1e6,
        restitution: 0.9,
        ..ContactModel::default()
    };
    let dt = 0.5 * stable_time_step(&set, &model).0;
    World::new(set, model, NoForcing, Periodicity::default(), dt).unwrap()
}

/// Everything about floe `id` and its contacts and memory, by ids, as bits
/// (Debug prints every f64 exactly, -0.0 included).
fn by_id(w: &World<NoForcing>, id: u64) -> String {
    let f = w.floes();
    let h = f.handle_of(id).unwrap();
    let ids = |a: u32, b: u32| (f.id[a as usize], f.id[b as usize]);
    let contacts: Vec<String> = w
        .contacts()
        .iter()
        .filter(|c| c.a as usize == h || c.b as usize == h)
        .map(|c| {
            format!(
                "{:?} {:?}",
                ids(c.a, c.b),
                (c.friction, c.normal_force_n, c.point)
            )
        })
        .collect();
    let broken: Vec<String> = w
        .broken_contacts()
        .iter()
        .filter(|c| c.a as usize == h || c.b as usize == h)
        .map(|c| format!("{:?} {:?}", ids(c.a, c.b), (c.friction, c.broke_at_s)))
        .collect();
    format!(
        "{:?} {contacts:?} {broken:?}",
        (
            f.position[h],
            f.velocity[h],
            f.angle[h],
            f.angular_velocity[h],
            w.state().force[h],
            w.state().torque[h]
        )
    )
}

/// Removing floes between steps and putting them back, in another order,
/// continues the run bitwise as if they had never been taken out: their
/// contacts (springs, friction state, stored energy) and their remembered
/// broken contacts come back with them, and the floes whose handles shifted
/// keep theirs.
#[test]
fn removing_floes_and_putting_them_back_reproduces_the_run() {
    let mut straight = world_of(bouncing_box(false));
    let mut edited = world_of(bouncing_box(false));
    let (mut removals, mut restored_contacts, mut restored_memory) = (0, 0, 0);
    for step in 1..=6000 {
        if step % 500 == 0 {
            // The floe with the most contacts, one with remembered broken
            // contacts, and the lowest id (every handle after it shifts).
            let f = edited.floes();
            let count = |h: usize, list: &mut dyn Iterator<Item = (u32, u32)>| {
                list.filter(|&(a, b)| a as usize == h || b as usize == h)
                    .count()
            };
            let busiest = (0..36)
                .max_by_key(|&h| count(h, &mut edited.contacts().iter().map(|c| (c.a, c.b))))
                .unwrap();
            let remembering = (0..36)
                .find(|&h| {
                    h != busiest
                        && count(h, &mut edited.broken_contacts().iter().map(|c| (c.a, c.b))) > 0
                })
                .unwrap_or(35);
            let mut ids = vec![f.id[busiest], f.id[remembering], f.id[0]];
            ids.dedup();
            let mut taken = Vec::new();
            for &id in &ids {
                let d = edited.remove_floe(id).unwrap();
                restored_contacts += d.contacts.len();
                restored_memory += d.broken.len();
                taken.push(d);
            }
            assert_eq!(edited.floes().len(), 40 - ids.len());
            taken.reverse();
            for d in taken {
                edited.insert_detached(d).unwrap();
            }
            removals += 1;
        }
        straight.step();
        edited.step();
    }
    assert_eq!(removals, 12);
    assert!(restored_contacts > 10, "{restored_contacts} contacts moved");
    assert!(
        restored_memory > 10,
        "{restored_memory} remembered contacts moved"
    );
    assert_eq!(
        format!("{:?}", straight.state()),
        format!("{:?}", edited.state())
    );
}

/// The contact memory is keyed by the floes' ids: a remembered pair whose
/// handles shift (a floe with a smaller id is removed) resumes its state
/// when it touches again, exactly as in the run where nothing shifted. The
/// removed floe touched nothing and there is no forcing, so the other
/// floes' motion does not depend on it.
#[test]
fn contact_memory_survives_the_floe_arrays_shifting() {
    let mut reference = world_of(bouncing_box(true));
    let mut shifted = world_of(bouncing_box(true));
    for _ in 0..2000 {
        reference.step();
        shifted.step();
    }
    let remembered: Vec<(u64, u64)> = {
        let f = shifted.floes();
        shifted
            .broken_contacts()
            .iter()
            .map(|c| (f.id[c.a as usize], f.id[c.b as usize]))
            .collect()
    };
    assert!(remembered.len() > 5, "{} remembered", remembered.len());
    let far = shifted.remove_floe(1).unwrap();
    assert!(far.contacts.is_empty() && far.broken.is_empty());
    let mut reformed = 0;
    for _ in 0..4000 {
        reference.step();
        shifted.step();
        let f = shifted.floes();
        reformed += shifted
            .contacts()
            .iter()
            .filter(|c| c.age_steps == 0)
            .filter(|c| remembered.contains(&(f.id[c.a as usize], f.id[c.b as usize])))
            .count();
    }
    assert!(reformed > 3, "{reformed} remembered contacts formed again");
    for id in (10..46).chain(100..104) {
        assert_eq!(by_id(&reference, id), by_id(&shifted, id), "floe {id}");
    }
    assert_eq!(reference.energy(), shifted.energy());
}

/// Floes added to a running world, in any order, make the same run: the
/// set orders them by id (each arrival shifts the handles of the floes
/// after it, and their forces, contacts and memory with them), and they
/// form contacts as they come. Half the squares are in from the start; the
/// others arrive in batches of six between steps, each batch in ascending
/// id order in one world and in another order in the other.
#[test]
fn floes_added_to_a_running_world_in_any_order_make_the_same_run() {
    let all = bouncing_box(false);
    let (walls, squares): (Vec<Floe>, Vec<Floe>) = all.into_iter().partition(|f| f.id >= 100);
    let (first, later): (Vec<Floe>, Vec<Floe>) = squares.into_iter().partition(|f| f.id % 2 == 0);
    let start = || world_of(walls.iter().chain(&first).cloned().collect());
    let (mut a, mut b) = (start(), start());
    for batch in later.chunks(6) {
        let mut shuffled = batch.to_vec();
        shuffled.reverse();
        shuffled.swap(0, 2);
        for f in batch {
            a.insert_floe(f.clone()).unwrap();
        }
        for f in shuffled {
            b.insert_floe(f).unwrap();
        }
        for _ in 0..200 {
            a.step();
            b.step();
        }
    }
    for _ in 0..1000 {
        a.step();
        b.step();
    }
    assert_eq!(a.floes().len(), 40);
    assert!(a.contacts().len() > 5 && !a.broken_contacts().is_empty());
    let (sa, sb) = (format!("{:?}", a.state()), format!("{:?}", b.state()));
    assert!(sa == sb, "the two orders of arrival gave different runs");
}

/// The four stages called one by one are the step; out of order they panic.
#[test]
fn the_stages_called_one_by_one_are_the_step() {
    let mut whole = world_of(bouncing_box(false));
    let mut staged = world_of(bouncing_box(false));
    for _ in 0..300 {
        whole.step();
        assert_eq!(staged.pipeline().next_stage(), Stage::Drift);
        staged.drift();
        staged.detect_contacts();
        staged.gather_forces();
        staged.kick();
    }
    assert_eq!(
        format!("{:?}", whole.state()),
        format!("{:?}", staged.state())
    );
    let wrong = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| staged.kick()));
    assert!(wrong.is_err(), "a kick before the drift panics");
}

/// A pose set between the drift and the contact detection is seen by that
/// detection (the stage order's point): a floe moved onto a floe at the
/// other side of the box touches it in the same step, though the candidate
/// list was built for the old positions.
#[test]
fn a_pose_set_between_stages_is_seen_by_the_next_stage() {
    let mut w = world_of(bouncing_box(false));
    w.drift();
    let f = w.floes();
    let target = f.position[f.handle_of(45).unwrap()];
    w.set_pose(
        10,
        target + Vec2::new(0.0, 99.0),
        f.angle[f.handle_of(45).unwrap()],
    )
    .unwrap();
    w.detect_contacts();
    let f = w.floes();
    let (h10, h45) = (f.handle_of(10).unwrap(), f.handle_of(45).unwrap());
    assert!(w
        .contacts()
        .iter()
        .any(|c| (c.a as usize, c.b as usize) == (h10, h45)));
    w.gather_forces();
    w.kick();
}

/// Edits that cannot be made are refused and change nothing.
#[test]
fn impossible_edits_are_refused_and_change_nothing() {
    let mut w = world_of(bouncing_box(false));
    for _ in 0..400 {
        w.step();
    }
    let unchanged = |w: &World<NoForcing>, then: &str| assert_eq!(format!("{:?}", w.state()), then);
    let before = format!("{:?}", w.state());
    let unknown = w.remove_floe(999).unwrap_err();
    unchanged(&w, &before);
    assert!(
        matches!(unknown, DemError::FloeEdit { id: 999, .. }),
        "{unknown}"
    );
    let mut d = w.remove_floe(12).unwrap();
    assert!(!d.contacts.is_empty() || !d.broken.is_empty());
    // A floe whose contacts name a floe not present.
    let partner = d
        .contacts
        .iter()
        .map(|(ids, _)| ids)
        .chain(d.broken.iter().map(|(ids, _)| ids))
        .flat_map(|ids| ids.iter().copied())
        .find(|&id| id != 12)
        .unwrap();
    let partner_floe = w.remove_floe(partner).unwrap();
    let before = format!("{:?}", w.state());
    let e = w.insert_detached(d.clone()).unwrap_err();
    assert!(e.to_string().contains("cannot be restored"), "{e}");
    unchanged(&w, &before);
    w.insert_detached(partner_floe).unwrap();
    // An id already present.
    let mut twin = d.clone();
    twin.floe.id = 13;
    let before = format!("{:?}", w.state());
    assert!(w.insert_detached(twin).is_err());
    unchanged(&w, &before);
    // A pair listed twice.
    let mut doubled = d.clone();
    doubled.contacts.push(doubled.contacts[0]);
    let before = format!("{:?}", w.state());
    let e = w.insert_detached(doubled).unwrap_err();
    assert!(e.to_string().contains("listed twice"), "{e}");
    unchanged(&w, &before);
    // A free floe the time step is too long for (a thousandth the mass).
    let mut light = Floe::new(
        77,
        &FloeShape::from_world(0, &square(Vec2::new(9e3, 9e3), 1.0))
            .unwrap()
            .0,
        Vec2::new(9e3, 9e3),
        1e-3,
        RHO_ICE,
    );
    let e = w.insert_floe(light.clone()).unwrap_err();
    assert!(matches!(e, DemError::UnstableTimeStep { .. }), "{e}");
    unchanged(&w, &before);
    light = light.prescribed(Vec2::ZERO);
    w.insert_floe(light).unwrap();
    let e = w.set_motion(77, floe_dem::floes::Motion::Free).unwrap_err();
    assert!(matches!(e, DemError::UnstableTimeStep { .. }), "{e}");
    let _ = w.remove_floe(77).unwrap();
    // Inside a step.
    w.drift();
    let before = format!("{:?}", w.state());
    let e = w.insert_detached(d.clone()).unwrap_err();
    assert!(e.to_string().contains("between steps"), "{e}");
    assert!(w.remove_floe(14).is_err());
    // Non-finite values.
    assert!(w.set_velocity(14, Vec2::new(f64::NAN, 0.0), 0.0).is_err());
    assert!(w.set_pose(14, Vec2::new(0.0, f64::INFINITY), 0.0).is_err());
    unchanged(&w, &before);
    w.detect_contacts();
    w.gather_forces();
    w.kick();
    d.floe.velocity = Vec2::new(f64::NAN, 0.0);
    let before = format!("{:?}", w.state());
    assert!(w.insert_detached(d).is_err());
    unchanged(&w, &before);
}
