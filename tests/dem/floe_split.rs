//! A floe split between steps (`World::split_floe`): mass, linear and
//! angular momentum, kinetic energy and area are the parent's to round-off;
//! its contacts go on, with their friction states, from the pieces that
//! hold their points; momentum stays conserved in the steps after; the
//! result does not depend on threads and resumes bitwise; bad splits are
//! refused and change nothing.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::forcing::NoForcing;
use floe_dem::fracture::split::{clip_half_plane, split_polygon, SplitKey, SplitRule};
use floe_dem::geometry::cross;
use floe_dem::periodicity::Periodicity;
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_fixtures::channel::sheared_channel;

/// A 5 x 5 block of 200 m squares pressed together (each overlaps its
/// neighbours by 1 m), spinning and drifting: not periodic, so angular
/// momentum about the origin is defined.
fn pressed_block() -> World<NoForcing> {
    let polys: Vec<Vec<Vec2>> = (0..25)
        .map(|k| {
            let c = Vec2::new(
                (k % 5) as f64 * 199.0,
                (k / 5) as f64 * 199.0 + 0.3 * (k % 5) as f64,
            );
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| c + 100.0 * Vec2::new(x, y))
                .to_vec()
        })
        .collect();
    let mut floes = Floes::from_polygons(&polys, &[1.0; 25], 917.0).unwrap();
    for i in 0..25 {
        let p = floes.position[i];
        // A rigid turn about the block's middle, plus a drift.
        let v = Vec2::new(0.05, -0.02) + 1e-4 * Vec2::new(-(p.y - 400.0), p.x - 400.0);
        floes.set_velocity(i, v, 1e-4);
    }
    let model = ContactModel::default();
    // Room for pieces: a floe a third the size needs a shorter step.
    let dt = 0.25 * stable_time_step(&floes, &model).0;
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    for _ in 0..5 {
        w.step();
    }
    w
}

/// Mass, momentum, angular momentum about the origin, kinetic energy and
/// area of the free floes.
fn totals(w: &World<NoForcing>) -> [f64; 6] {
    let f = w.floes();
    let mut t = [0.0; 6];
    for i in (0..f.len()).filter(|&i| f.is_free(i)) {
        let (m, v, om) = (f.mass_kg[i], f.velocity[i], f.angular_velocity[i]);
        t[0] += m;
        t[1] += m * v.x;
        t[2] += m * v.y;
        t[3] += f.inertia_kg_m2[i] * om + m * cross(f.position[i], v);
        t[4] += 0.5 * (m * v.length_squared() + f.inertia_kg_m2[i] * om * om);
        t[5] += f.area_m2[i];
    }
    t
}

/// Floe `id`'s polygon about its centroid in world orientation, split in
/// three by the default rule, keyed on the world's step.
fn pieces_of(w: &World<NoForcing>, id: u64) -> Vec<Vec<Vec2>> {
    pieces_keyed(w, id, w.steps())
}

/// [`pieces_of`] keyed on `step`.
fn pieces_keyed(w: &World<NoForcing>, id: u64, step: u64) -> Vec<Vec<Vec2>> {
    let f = w.floes();
    let h = f.handle_of(id).unwrap();
    let (s, c) = f.angle[h].sin_cos();
    let polygon: Vec<Vec2> = f
        .local_vertices(h)
        .iter()
        .map(|v| Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y))
        .collect();
    let key = SplitKey {
        seed: 9,
        floe_id: id,
        step,
    };
    split_polygon(&polygon, &SplitRule::default(), key)
        .unwrap()
        .0
}

#[test]
fn a_split_keeps_mass_momentum_angular_momentum_energy_and_area() {
    let mut w = pressed_block();
    let before = totals(&w);
    let contacts_before = w.contacts().len();
    // The middle floe and an edge one; ids from 100.
    let mut next = 100;
    for id in [12, 3] {
        let pieces = pieces_of(&w, id);
        let ids: Vec<u64> = (next..next + pieces.len() as u64).collect();
        next += pieces.len() as u64;
        let theirs: Vec<_> = w
            .contacts()
            .iter()
            .filter(|c| [c.a, c.b].contains(&(w.floes().handle_of(id).unwrap() as u32)))
            .map(|c| c.friction)
            .collect();
        assert!(theirs.len() >= 3, "floe {id} is in contact");
        w.split_floe(id, &pieces, &ids).unwrap();
        // Every friction state went on with one piece.
        for fr in theirs {
            assert_eq!(w.contacts().iter().filter(|c| c.friction == fr).count(), 1);
        }
    }
    assert_eq!(w.floes().len(), 25 - 2 + 6);
    assert_eq!(
        w.contacts().len(),
        contacts_before,
        "no contact lost or made"
    );
    let after = totals(&w);
    for (k, name) in [
        "mass",
        "p_x",
        "p_y",
        "angular momentum",
        "kinetic energy",
        "area",
    ]
    .iter()
    .enumerate()
    {
        assert!(
            (after[k] - before[k]).abs() <= 1e-12 * before[k].abs(),
            "{name}: {} against {}",
            after[k],
            before[k]
        );
    }
    // The moved contacts continue (their age goes on) and momentum stays
    // conserved by the contact forces from the pieces.
    let aged: Vec<u64> = w.contacts().iter().map(|c| c.age_steps).collect();
    w.step();
    let continued = w
        .contacts()
        .iter()
        .filter(|c| c.age_steps > 1 && aged.contains(&(c.age_steps - 1)))
        .count();
    assert!(
        continued >= contacts_before,
        "{continued} of {contacts_before} continued"
    );
    for _ in 0..200 {
        w.step();
    }
    let later = totals(&w);
    let p = before[1].hypot(before[2]);
    assert!(
        (later[1] - before[1]).hypot(later[2] - before[2]) < 1e-10 * p,
        "momentum after 200 steps: {later:?} against {before:?}"
    );
}

#[test]
fn a_split_is_bitwise_for_threads_and_resumes() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = sheared_channel(400);
            w.set_stress_filter(Some(Default::default()));
            for id in [40, 41, 200] {
                let ids = [10_000 + 3 * id, 10_001 + 3 * id, 10_002 + 3 * id];
                w.split_floe(id, &pieces_of(&w, id), &ids).unwrap();
            }
            for _ in 0..30 {
                w.step();
            }
            w
        })
    };
    let bits = |w: &World<NoForcing>| format!("{:?}", w.state());
    let one = run(1);
    assert_eq!(bits(&one), bits(&run(2)));
    let (state, model, forcing, periodicity) = run(1).into_parts();
    let mut resumed = World::resume(state, model, forcing, periodicity).unwrap();
    let mut straight = one;
    for _ in 0..20 {
        resumed.step();
        straight.step();
    }
    assert_eq!(bits(&resumed), bits(&straight));
}

#[test]
fn bad_splits_are_refused_and_change_nothing() {
    let mut w = pressed_block();
    let bits = format!("{:?}", w.state());
    let pieces = pieces_of(&w, 12);
    let ids = [100, 101, 102];
    let refused = |w: &mut World<NoForcing>, id: u64, pieces: &[Vec<Vec2>], ids: &[u64]| {
        w.split_floe(id, pieces, ids)
            .expect_err("refused")
            .to_string()
    };
    assert!(refused(&mut w, 12, &pieces, &[100, 101, 5]).contains("unused"));
    assert!(refused(&mut w, 12, &pieces, &[100, 100, 101]).contains("distinct"));
    assert!(refused(&mut w, 12, &pieces, &[12, 100, 101]).contains("unused"));
    assert!(refused(&mut w, 12, &pieces[..1], &ids[..1]).contains("two or more"));
    assert!(refused(&mut w, 99, &pieces, &ids).contains("no such floe"));
    // Pieces that leave part of the floe out.
    assert!(refused(&mut w, 12, &pieces[..2], &ids[..2]).contains("do not tile"));
    // A sliver (5 cm wide) needs a time step far below the world's.
    let h = w.floes().handle_of(12).unwrap();
    let (s, c) = w.floes().angle[h].sin_cos();
    let parent: Vec<Vec2> = w
        .floes()
        .local_vertices(h)
        .iter()
        .map(|v| Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y))
        .collect();
    let cut = parent.iter().map(|v| v.x).fold(f64::MIN, f64::max) - 0.05;
    let sliver = vec![
        clip_half_plane(&parent, Vec2::new(1.0, 0.0), cut),
        clip_half_plane(&parent, Vec2::new(-1.0, 0.0), -cut),
    ];
    assert!(refused(&mut w, 12, &sliver, &ids[..2]).contains("time step"));
    let mut walled = pressed_block();
    walled
        .set_motion(
            7,
            floe_dem::floes::Motion::Prescribed {
                velocity: Vec2::ZERO,
            },
        )
        .unwrap();
    assert!(refused(&mut walled, 7, &pieces, &ids).contains("free floe"));
    assert_eq!(format!("{:?}", w.state()), bits, "nothing changed");
    w.split_floe(12, &pieces, &ids).unwrap();
}

/// The sheared channel moved 150 m along its period (so that floes
/// straddle the seam), one step on.
fn straddling_channel() -> World<NoForcing> {
    let mut w = sheared_channel(400);
    let p = w.periodicity();
    for h in 0..w.floes().len() {
        let f = w.floes();
        let (id, at, angle) = (f.id[h], f.position[h], f.angle[h]);
        w.set_pose(id, p.wrap(at + Vec2::new(150.0, 0.0)), angle)
            .unwrap();
    }
    w.step();
    w
}

#[test]
fn moved_contacts_keep_their_place_across_the_periodic_seam() {
    let w = straddling_channel();
    // A free floe with a contact across the seam, as `b` or as `a`.
    let f = w.floes();
    let seam = w
        .contacts()
        .iter()
        .find(|c| {
            c.image_offset != Vec2::ZERO && f.is_free(c.a as usize) && f.is_free(c.b as usize)
        })
        .expect("a contact across the seam");
    // And the free floe reaching furthest across the seam, split so that
    // a piece's centroid falls beyond it (stored a period away).
    let length = w.periodicity().x.unwrap().length_m;
    let beyond = |i: usize| {
        let (s, c) = f.angle[i].sin_cos();
        f.local_vertices(i)
            .iter()
            .map(|v| {
                let x = f.position[i].x + c * v.x - s * v.y;
                (x - length).max(-x)
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let nearest = (0..f.len())
        .filter(|&i| f.is_free(i))
        .max_by(|&i, &j| beyond(i).total_cmp(&beyond(j)))
        .unwrap();
    assert!(beyond(nearest) > 50.0, "a floe straddles the seam");
    let (x0, id0) = (f.position[nearest].x, f.id[nearest]);
    let across = (0..200)
        .find(|&step| {
            pieces_keyed(&w, id0, step).iter().any(|p| {
                let cx = p.iter().map(|v| v.x).sum::<f64>() / p.len() as f64;
                !(0.0..length).contains(&(x0 + cx))
            })
        })
        .expect("a split with a piece across the seam");
    for (parent_handle, step) in [
        (seam.a as usize, 0),
        (seam.b as usize, 0),
        (nearest, across),
    ] {
        let mut w = straddling_channel();
        let id = w.floes().id[parent_handle];
        let pieces = pieces_keyed(&w, id, step);
        let ids = [50_000, 50_001, 50_002];
        w.split_floe(id, &pieces, &ids).unwrap();
        if parent_handle == nearest {
            let f = w.floes();
            let far = |p: u64| (f.position[f.handle_of(p).unwrap()].x - x0).abs() > 0.5 * length;
            assert!(
                ids.iter().any(|&p| far(p)),
                "a piece is stored a period away"
            );
        }
        let ids_of = |w: &World<NoForcing>, a: u32, b: u32| {
            [w.floes().id[a as usize], w.floes().id[b as usize]]
        };
        let moved: Vec<_> = w
            .contacts()
            .iter()
            .filter(|c| {
                let pair = ids_of(&w, c.a, c.b);
                ids.contains(&pair[0]) || ids.contains(&pair[1])
            })
            .map(|c| (ids_of(&w, c.a, c.b), c.point, c.image_offset, c.normal))
            .collect();
        if parent_handle != nearest {
            assert!(
                moved.iter().any(|m| m.2 != Vec2::ZERO),
                "one crosses the seam"
            );
        }
        w.step();
        for (pair, point, offset, normal) in moved {
            let now = w
                .contacts()
                .iter()
                .find(|c| ids_of(&w, c.a, c.b) == pair)
                .unwrap_or_else(|| panic!("{pair:?} goes on"));
            assert_eq!(now.image_offset, offset, "{pair:?}");
            // In the same frame: the point moves within the floes' 1 km
            // sides (to the middle of the overlap the piece keeps of the
            // parent's), not by the 37 km period.
            assert!(
                (now.point - point).length() < 1000.0,
                "{pair:?}: {} {}",
                now.point,
                point
            );
            assert!(now.normal.dot(normal) > 0.9, "{pair:?}");
        }
    }
}
