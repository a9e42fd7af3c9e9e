//! The broad phase leaves out candidate pairs whose floes are too far apart
//! to touch before the next rebuild. Results must be bitwise those of the
//! bounding-circle list it is cut from: these runs step the same world with
//! the default rotation allowance and with an infinite one (circles alone)
//! and compare every bit.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::forcing::NoForcing;
use floe_dem::geometry::{overlap, ClipScratch};
use floe_dem::periodicity::{Period, Periodicity};
use floe_dem::pipeline::broad_phase::{BroadPhase, MAX_ROTATION_RAD};
use floe_dem::tessellation::{DiamondLattice, Rect, ThicknessDistribution};
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_friction::rate_state::THETA;

const RHO_ICE: f64 = 917.0;

/// Every bit of the floes' state, the contacts and the energy ledger.
fn bits(w: &World<NoForcing>) -> Vec<u64> {
    let f = &w.floes();
    let mut out = Vec::new();
    for i in 0..f.len() {
        out.extend([
            f.position[i].x,
            f.position[i].y,
            f.velocity[i].x,
            f.velocity[i].y,
            f.angle[i],
            f.angular_velocity[i],
        ]);
    }
    for c in w.contacts() {
        out.extend([
            f64::from(c.a),
            f64::from(c.b),
            c.normal_force_n,
            c.friction.tangential_force_n,
            c.friction.law_state[THETA],
            c.normal_energy_j,
            c.tangential_energy_j,
        ]);
    }
    let e = w.energy();
    out.extend([
        e.friction_dissipation_j,
        e.damping_dissipation_j,
        e.released_at_break_j,
    ]);
    out.into_iter().map(f64::to_bits).collect()
}

/// What a run with the default allowance and one with circles alone
/// report: the first step after which their states' bits differ, the most
/// contacts seen, candidate pairs after the first step, and rebuilds.
struct Runs {
    /// Step after which the two runs' states first differ, if any.
    first_difference: Option<usize>,
    most_contacts: usize,
    pairs_default: usize,
    pairs_circles: usize,
    rebuilds_default: u64,
    rebuilds_circles: u64,
}

fn run_both(make: impl Fn() -> World<NoForcing>, steps: usize) -> Runs {
    let (mut kept, mut circles) = (make(), make());
    circles.set_max_rotation_rad(f64::INFINITY).unwrap();
    let mut runs = Runs {
        first_difference: None,
        most_contacts: 0,
        pairs_default: 0,
        pairs_circles: 0,
        rebuilds_default: 0,
        rebuilds_circles: 0,
    };
    for step in 0..steps {
        kept.step();
        circles.step();
        if step == 0 {
            runs.pairs_default = kept.broad_phase().pairs.len();
            runs.pairs_circles = circles.broad_phase().pairs.len();
        }
        runs.most_contacts = runs.most_contacts.max(circles.contacts().len());
        if runs.first_difference.is_none() && bits(&kept) != bits(&circles) {
            runs.first_difference = Some(step);
        }
    }
    runs.rebuilds_default = kept.broad_phase().rebuilds;
    runs.rebuilds_circles = circles.broad_phase().rebuilds;
    runs
}

/// `floes` with the default contact model, unforced, stepped at half the
/// stable step.
fn world(floes: Floes, periodic: Periodicity) -> World<NoForcing> {
    let model = ContactModel::default();
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    World::new(floes, model, NoForcing, periodic, dt).unwrap()
}

fn bar(center: Vec2, length: f64, width: f64) -> Vec<Vec2> {
    let (a, b) = (0.5 * length, 0.5 * width);
    vec![
        center + Vec2::new(-a, -b),
        center + Vec2::new(a, -b),
        center + Vec2::new(a, b),
        center + Vec2::new(-a, b),
    ]
}

/// Two thin parallel bars, a 10 m one and one of `upper_length` above it,
/// their near edges `gap` apart and their right-hand ends level.
fn bars_apart(gap: f64, upper_length: f64) -> Floes {
    let (length, width) = (10.0, 0.01);
    let polys = [
        bar(Vec2::ZERO, length, width),
        bar(
            Vec2::new(0.5 * (length - upper_length), width + gap),
            upper_length,
            width,
        ),
    ];
    Floes::from_polygons(&polys, &[1.0, 1.0], RHO_ICE).unwrap()
}

fn sin_cos(floes: &Floes) -> Vec<(f64, f64)> {
    floes.angle.iter().map(|a| a.sin_cos()).collect()
}

/// The allowance is tight, not just safe: two thin bars whose right-hand
/// tips turn towards each other as they move together come within a
/// fraction of a per cent of the bound (a tip at radius r turned by phi
/// moves r sin(phi) towards the other bar, against r phi allowed). Just
/// inside the bound the pair is kept, and indeed the bars then overlap
/// after a motion the list allows (each half the skin closer, turned by the
/// allowance); just outside it the pair is left out. With the rotation's
/// term the larger and with the skin's, and with bars of equal and of
/// unequal length: the test fails if either term of the bound is cut by
/// more than a few per cent, or the radii are not both counted.
#[test]
fn a_pair_is_kept_exactly_when_a_motion_within_the_allowance_could_make_it_touch() {
    for skin in [0.25, 4.0] {
        for upper_length in [10.0, 2.0] {
            kept_exactly_when_it_could_touch(skin, upper_length);
        }
    }
}

fn kept_exactly_when_it_could_touch(skin: f64, upper_length: f64) {
    let case = format!("skin {skin}, upper bar {upper_length} m");
    let probe = bars_apart(1.0, upper_length);
    let bound = skin + MAX_ROTATION_RAD * (probe.radius_m[0] + probe.radius_m[1]);
    let pairs_at = |gap: f64| {
        let floes = bars_apart(gap, upper_length);
        let mut bp = BroadPhase::new(skin);
        bp.rebuild(&floes, &sin_cos(&floes), Periodicity::default());
        (floes, bp)
    };
    let (_, outside) = pairs_at(1.01 * bound);
    assert!(
        outside.pairs.is_empty(),
        "{case}: left out beyond the bound"
    );
    let (mut floes, bp) = pairs_at(0.99 * bound);
    assert_eq!(bp.pairs.len(), 1, "{case}: kept inside the bound");
    // The motion the list allows: half the skin towards each other, the
    // lower bar turned counter-clockwise and the upper one clockwise (their
    // right-hand tips towards each other), each by the allowance.
    let (shift, turn) = (0.5 * skin * (1.0 - 1e-9), MAX_ROTATION_RAD * (1.0 - 1e-9));
    floes.set_pose(0, floes.position[0] + Vec2::new(0.0, shift), turn);
    floes.set_pose(1, floes.position[1] - Vec2::new(0.0, shift), -turn);
    assert!(
        !bp.is_stale(&floes, Periodicity::default()),
        "{case}: within the allowance"
    );
    let trig = sin_cos(&floes);
    let touch = overlap(
        floes.placed(0, Vec2::ZERO, trig[0]),
        floes.placed(1, Vec2::ZERO, trig[1]),
        &mut ClipScratch::default(),
    );
    assert!(
        touch.is_some(),
        "{case}: the kept pair can touch before a rebuild"
    );
    // Past the allowance, by translation or by rotation alone, the list is stale.
    let (_, fresh) = pairs_at(0.99 * bound);
    let start = bars_apart(0.99 * bound, upper_length);
    let mut shifted = start.clone();
    shifted.set_pose(
        1,
        shifted.position[1] - Vec2::new(0.0, 0.5 * skin * 1.01),
        shifted.angle[1],
    );
    let mut turned = start.clone();
    turned.set_pose(1, turned.position[1], -MAX_ROTATION_RAD * 1.01);
    for (what, floes) in [("moved", shifted), ("turned", turned)] {
        assert!(
            fresh.is_stale(&floes, Periodicity::default()),
            "{case}: {what} past the allowance"
        );
    }
}

/// A 10 m bar spinning next to a parallel one 2 m away: their bounding
/// circles overlap, but the gap is wider than the skin plus the rotation
/// allowed between rebuilds, so the pair is left out of the first list. It
/// only touches after the spinning bar has turned by about 0.4 rad, without
/// moving its centre: only a rebuild forced by rotation brings the pair back
/// in time (the test fails if rotation does not force one).
#[test]
fn a_floe_turning_into_a_neighbour_left_out_of_the_list_meets_it_as_if_kept() {
    let make = || {
        let polys = [
            bar(Vec2::ZERO, 10.0, 1.0),
            bar(Vec2::new(0.0, 3.0), 10.0, 1.0),
        ];
        let mut floes = Floes::from_polygons(&polys, &[1.0, 1.0], RHO_ICE).unwrap();
        floes.set_velocity(0, floes.velocity[0], 0.5);
        world(floes, Periodicity::default())
    };
    let w = make();
    let steps = (1.2 / (0.5 * w.dt_s())).ceil() as usize; // 0.6 rad of turning
    let runs = run_both(make, steps);
    assert_eq!(runs.pairs_circles, 1);
    assert_eq!(runs.pairs_default, 0, "the far pair is left out at first");
    assert!(runs.most_contacts > 0, "the bars collide");
    assert!(
        runs.rebuilds_default > runs.rebuilds_circles,
        "rotation forced rebuilds: {} against {}",
        runs.rebuilds_default,
        runs.rebuilds_circles
    );
    assert_eq!(runs.first_difference, None);
}

/// Floes of a jittered 60-degree diamond lattice of 100 m sides on a
/// 1500 m x 1200 m domain, each shrunk about its centroid by `shrink`
/// (1: edge to edge), thickness 0.5-2 m; without the slivers clipped at
/// the domain's edge unless `slivers` (they set a stable step 30 times
/// shorter, and are the fastest floes once shaken).
fn lattice(shrink: f64, slivers: bool) -> Floes {
    let lattice = DiamondLattice {
        domain: Rect {
            min: Vec2::ZERO,
            max: Vec2::new(1500.0, 1200.0),
        },
        side_m: 100.0,
        acute_angle_deg: 60.0,
        orientation_deg: 15.0,
        thickness: ThicknessDistribution::UniformRange {
            min_m: 0.5,
            max_m: 2.0,
        },
        jitter_fraction: 0.05,
        seed: 3,
    };
    let mut t = lattice.build().unwrap();
    if !slivers {
        t.drop_floes_smaller_than(0.5 * 100.0 * 100.0 * 60f64.to_radians().sin());
    }
    let polygons: Vec<Vec<Vec2>> = t
        .polygons
        .iter()
        .map(|p| {
            let c = p.iter().copied().sum::<Vec2>() / p.len() as f64;
            p.iter().map(|&v| c + (v - c) * shrink).collect()
        })
        .collect();
    Floes::from_polygons(&polygons, &t.thickness_m, RHO_ICE).unwrap()
}

/// `floes` with random velocities (up to `speed` per component, on a flow
/// spreading from the domain's centre at `spreading` per second) and spins
/// (up to `spin`), periodic along x, stepped at half the stable step.
fn shaken(mut floes: Floes, speed: f64, spreading: f64, spin: f64) -> World<NoForcing> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let centre = Vec2::new(750.0, 600.0);
    for i in 0..floes.len() {
        floes.set_velocity(
            i,
            (floes.position[i] - centre) * spreading
                + Vec2::new(rng.gen_range(-speed..speed), rng.gen_range(-speed..speed)),
            floes.angular_velocity[i],
        );
        floes.set_velocity(i, floes.velocity[i], rng.gen_range(-spin..spin));
    }
    let periodic = Periodicity {
        x: Some(Period {
            min_m: 0.0,
            length_m: 1500.0,
        }),
        y: None,
    };
    world(floes, periodic)
}

/// The lattice edge to edge, pulled apart and shaken: floes (the slivers
/// clipped at the domain's edge fastest) move many half-skins, contacts
/// form and break, and the list is rebuilt tens of times, mostly by
/// translation. Every step must match circles alone.
#[test]
fn leaving_far_pairs_out_changes_no_result_in_a_shaken_spreading_lattice() {
    let make = || shaken(lattice(1.0, true), 0.3, 2e-3, 0.02);
    let steps = (20.0 / make().dt_s()).ceil() as usize;
    let runs = run_both(make, steps);
    assert!(runs.most_contacts > 100, "contacts: {}", runs.most_contacts);
    assert!(
        (runs.pairs_default as f64) < 0.8 * runs.pairs_circles as f64,
        "pairs left out: {} of {}",
        runs.pairs_circles - runs.pairs_default,
        runs.pairs_circles
    );
    assert!(
        runs.rebuilds_circles >= 20,
        "rebuilds {}",
        runs.rebuilds_circles
    );
    assert_eq!(runs.first_difference, None);
}

/// The lattice with wide gaps (floes shrunk by 30 %), spinning at up to
/// 0.02 rad/s and barely drifting: the long corners sweep into their
/// neighbours, which then drift off faster than they turn, so rotation
/// forces some of the rebuilds (measured: 24 against 20 for circles alone,
/// which rebuild for translation only). Every step must match circles
/// alone.
#[test]
fn leaving_far_pairs_out_changes_no_result_in_a_lattice_of_spinning_floes() {
    let make = || shaken(lattice(0.7, false), 0.01, 0.0, 0.02);
    let steps = (100.0 / make().dt_s()).ceil() as usize;
    let runs = run_both(make, steps);
    assert!(runs.most_contacts > 20, "contacts: {}", runs.most_contacts);
    // The circle run rebuilds once more at its start (the allowance was
    // changed after the world was built).
    assert!(
        runs.rebuilds_default > runs.rebuilds_circles + 2,
        "rotation forced rebuilds: {} against {}",
        runs.rebuilds_default,
        runs.rebuilds_circles
    );
    assert_eq!(runs.first_difference, None);
}

/// A trapezoid 8 m long, tall (4 m) at its left end and short (0.4 m) at
/// its right, or the mirror image, centred on the box centre `at`.
fn trapezoid(at: Vec2, mirrored: bool) -> Vec<Vec2> {
    let s = if mirrored { -1.0 } else { 1.0 };
    let mut v = vec![
        at + Vec2::new(-4.0 * s, -2.0),
        at + Vec2::new(4.0 * s, -0.2),
        at + Vec2::new(4.0 * s, 0.2),
        at + Vec2::new(-4.0 * s, 2.0),
    ];
    if mirrored {
        v.reverse();
    }
    v
}

/// In a period barely wider than two floes, the image of a neighbour that
/// is nearest by centroid is not the one nearest by outline: here the
/// floes' wide ends face each other 3 m apart across one side of the
/// period, their narrow ends 0.1 m apart across the other, and the
/// centroids (shifted 1.1 m towards the wide ends) make the 3 m image the
/// nearest, and the pair is left out at first. The second floe drifts
/// towards the narrow side; once its other image becomes the nearest, the
/// narrow phase sees that image. The pair must be back in the list by
/// then, from a rebuild where its centroids were within a skin of half the
/// period apart, although its nearest image was still far; without that
/// rule the run departed from circles alone from the step the image
/// switched.
#[test]
fn a_pair_whose_nearest_image_can_switch_in_a_narrow_period_is_kept() {
    let period = 19.1;
    let make = || {
        let polys = [
            trapezoid(Vec2::ZERO, false),
            trapezoid(Vec2::new(0.5 * period - 1.45, 0.0), true),
        ];
        let mut floes = Floes::from_polygons(&polys, &[1.0, 1.0], RHO_ICE).unwrap();
        floes.set_velocity(1, Vec2::new(-0.5, 0.0), floes.angular_velocity[1]);
        let periodic = Periodicity {
            x: Some(Period {
                min_m: -0.5 * period,
                length_m: period,
            }),
            y: None,
        };
        world(floes, periodic)
    };
    let w = make();
    let steps = (2.0 / (0.5 * w.dt_s())).ceil() as usize; // 2 m of drift
    let runs = run_both(make, steps);
    assert_eq!(runs.pairs_circles, 1);
    assert_eq!(runs.pairs_default, 0, "left out at first: 3 m apart");
    assert!(runs.most_contacts > 0, "the narrow ends meet");
    assert_eq!(runs.first_difference, None);
}

#[test]
fn a_rotation_allowance_that_is_not_positive_is_refused() {
    let polys = [bar(Vec2::ZERO, 10.0, 1.0)];
    let floes = Floes::from_polygons(&polys, &[1.0], RHO_ICE).unwrap();
    let model = ContactModel::default();
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), 0.01).unwrap();
    for bad in [0.0, -0.1, f64::NAN] {
        let e = w.set_max_rotation_rad(bad).unwrap_err();
        assert!(e.to_string().contains("max_rotation_rad"), "{e}");
    }
    assert!(w.set_max_rotation_rad(0.05).is_ok());
    assert_eq!(w.broad_phase().max_rotation_rad(), 0.05);
}

/// Floes far apart do not make the cell grid grow with their distance:
/// cells are widened to at most about four per floe, and the pairs found
/// (none here) are those of cells one reach wide. A grid of 10 m cells
/// over 1e15 m would need 1e14 cells.
#[test]
fn floes_far_apart_do_not_grow_the_grid() {
    let polys: Vec<Vec<Vec2>> = [0.0, 1e15, -3e14]
        .iter()
        .map(|&x| bar(Vec2::new(x, 0.5 * x), 10.0, 10.0))
        .collect();
    let floes = Floes::from_polygons(&polys, &[1.0; 3], RHO_ICE).unwrap();
    let mut w = world(floes, Periodicity::default());
    for _ in 0..3 {
        w.step();
    }
    assert!(w.broad_phase().pairs.is_empty());
    assert!(w.contacts().is_empty());
    // Beside a touching pair, far floes leave the pair in the list.
    let mut polys = polys;
    polys.push(bar(Vec2::new(0.0, 9.99), 10.0, 10.0));
    let floes = Floes::from_polygons(&polys, &[1.0; 4], RHO_ICE).unwrap();
    let w = world(floes, Periodicity::default());
    assert_eq!(w.contacts().len(), 1);
}

/// Two prescribed floes never touch (the narrow phase skips them), so the
/// list leaves them out: a block of fixed squares, as a coastline's pieces
/// are, with free floes along its edge, gives exactly the pairs with a
/// free floe that bounding circles within the skin give, found here by
/// testing every pair.
#[test]
fn pairs_of_two_prescribed_floes_are_left_out_and_no_other() {
    let mut polys = Vec::new();
    for j in 0..30 {
        for i in 0..30 {
            polys.push(bar(Vec2::new(10.0 * i as f64, 10.0 * j as f64), 10.0, 10.0));
        }
    }
    // Free floes along the block's top edge, touching it.
    for i in 0..30 {
        polys.push(bar(Vec2::new(10.0 * i as f64 + 3.0, 299.9), 9.0, 9.0));
    }
    let n = polys.len();
    let mut floes = Floes::from_polygons(&polys, &vec![1.0; n], RHO_ICE).unwrap();
    for h in 0..900 {
        floes.set_motion(
            h,
            floe_dem::floes::Motion::Prescribed {
                velocity: Vec2::ZERO,
            },
        );
    }
    let skin = 0.5;
    let mut broad = BroadPhase::new(skin);
    broad.set_max_rotation_rad(f64::INFINITY).unwrap();
    broad.rebuild(floes.columns(), &sin_cos(&floes), Periodicity::default());
    let f = floes.columns();
    let mut expected = Vec::new();
    for a in 0..n {
        for b in (a + 1)..n {
            let near =
                (f.position[b] - f.position[a]).length() <= f.radius_m[a] + f.radius_m[b] + skin;
            if near && (f.is_free(a) || f.is_free(b)) {
                expected.push((a as u32, b as u32));
            }
        }
    }
    let found: Vec<(u32, u32)> = broad.pairs.iter().map(|p| (p.a, p.b)).collect();
    assert!(
        expected.len() > 60,
        "{} pairs with a free floe",
        expected.len()
    );
    assert_eq!(found, expected);
}
