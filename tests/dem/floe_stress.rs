//! Floe stress: a floe squeezed between two walls carries the wall force
//! over its cross-section, in any orientation; the exponential average
//! follows `1 - exp(-t/T)` whatever the time step; the floes' stresses sum
//! to the pack's Love-Weber mean stress; the bits do not depend on threads,
//! resumes or a floe taken out and put back.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{Floes, Motion};
use floe_dem::forcing::NoForcing;
use floe_dem::periodicity::Periodicity;
use floe_dem::pipeline::floe_stress::{principal, StressFilter};
use floe_dem::world::{stable_time_step, World};
use floe_dem::Vec2;
use floe_fixtures::channel::sheared_channel;

const SIDE_M: f64 = 100.0;
const OVERLAP_M: f64 = 0.5;

fn rotate(p: Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y)
}

fn rect(x0: f64, x1: f64, y0: f64, y1: f64, angle: f64) -> Vec<Vec2> {
    [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        .map(|(x, y)| rotate(Vec2::new(x, y), angle))
        .to_vec()
}

/// A free square of side 100 m, 1 m thick, between two fixed walls that
/// overlap it by 0.5 m on its two sides normal to `angle`, at time step
/// `dt_fraction` of the stable one; the stress averaged over `time_scale_s`.
fn squeezed(angle: f64, dt_fraction: f64, time_scale_s: f64) -> World<NoForcing> {
    let h = 0.5 * SIDE_M;
    let polys = [
        rect(-h - 100.0, -h + OVERLAP_M, -2.0 * h, 2.0 * h, angle),
        rect(-h, h, -h, h, angle),
        rect(h - OVERLAP_M, h + 100.0, -2.0 * h, 2.0 * h, angle),
    ];
    let mut floes = Floes::from_polygons(&polys, &[1.0; 3], 917.0).unwrap();
    for wall in [0, 2] {
        floes.set_motion(
            wall,
            Motion::Prescribed {
                velocity: Vec2::ZERO,
            },
        );
    }
    let model = ContactModel::default();
    let dt = dt_fraction * stable_time_step(&floes, &model).0;
    let mut w = World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap();
    w.set_stress_filter(Some(StressFilter::new(time_scale_s).unwrap()));
    w
}

/// The wall force over the floe's cross-section (`N / (L h)`), Pa.
fn uniaxial_pa(w: &World<NoForcing>) -> f64 {
    let n: Vec<f64> = w.contacts().iter().map(|c| c.normal_force_n).collect();
    assert_eq!(n.len(), 2, "the floe touches both walls");
    assert!(
        (n[0] - n[1]).abs() < 1e-9 * n[0],
        "equal and opposite: {n:?}"
    );
    0.5 * (n[0] + n[1]) / SIDE_M
}

#[test]
fn a_squeezed_floe_carries_the_wall_force_over_its_cross_section_in_any_orientation() {
    for k in 0..6 {
        let angle = 0.37 * k as f64;
        let mut w = squeezed(angle, 0.5, 1e-9);
        for _ in 0..20 {
            w.step();
        }
        let p = uniaxial_pa(&w);
        assert!(p > 1e3, "a real load: {p} Pa");
        let s = w.floe_stress()[1];
        let (s1, s2) = principal(s);
        // The contact point sits half the overlap inside the floe's edge:
        // the arm is short by OVERLAP / 2 of SIDE / 2.
        let arm = 1.0 - OVERLAP_M / SIDE_M;
        assert!(
            (s2 / -p - arm).abs() < 0.01 * OVERLAP_M / SIDE_M,
            "{angle}: sigma_2 {s2} against {}",
            -p * arm
        );
        assert!(s1.abs() < 1e-9 * p, "{angle}: no load across: {s1}");
        // The compressive direction is the walls' normal.
        let n = rotate(Vec2::new(1.0, 0.0), angle);
        let along = s[0] * n.x * n.x + 2.0 * s[1] * n.x * n.y + s[2] * n.y * n.y;
        assert!((along - s2).abs() < 1e-9 * p, "{angle}: {along} {s2}");
        // The walls carry none.
        assert_eq!(w.floe_stress()[0], [0.0; 3]);
        assert_eq!(w.floe_stress()[2], [0.0; 3]);
    }
}

#[test]
fn the_average_follows_one_minus_exp_whatever_the_step() {
    let time_scale_s = 5.0;
    let mut at_3t = Vec::new();
    for dt_fraction in [0.5, 0.25, 0.1] {
        let mut w = squeezed(0.0, dt_fraction, time_scale_s);
        let mut worst: f64 = 0.0;
        while w.time_s() < 3.0 * time_scale_s {
            w.step();
            let now = w.instantaneous_stress(1)[0];
            let expected = now * -(-w.time_s() / time_scale_s).exp_m1();
            worst = worst.max((w.floe_stress()[1][0] - expected).abs() / now.abs());
        }
        // The load is constant (the floe does not move): the discrete
        // average is the continuous one to round-off.
        assert!(worst < 1e-12, "dt fraction {dt_fraction}: {worst:e}");
        at_3t.push(w.floe_stress()[1][0] / w.instantaneous_stress(1)[0]);
    }
    // Different steps land at different times just past 3T; each is on
    // the curve, so the ratios differ only by how far past.
    for r in at_3t {
        assert!(
            r > 1.0 - (-3.0f64).exp() && r < 1.0 - (-3.1f64).exp(),
            "{r}"
        );
    }
}

#[test]
fn the_floes_stresses_sum_to_the_packs_mean_stress() {
    let mut w = sheared_channel(400);
    // A time scale far below the step: the average is the stress now.
    w.set_stress_filter(Some(StressFilter::new(1e-9).unwrap()));
    for _ in 0..40 {
        w.step();
    }
    assert!(
        w.contacts().iter().any(|c| c.image_offset != Vec2::ZERO),
        "contacts across the periodic seam"
    );
    let f = w.floes();
    let mut total = [0.0; 3];
    let mut largest: f64 = 0.0;
    for h in 0..f.len() {
        let s = w.floe_stress()[h];
        let scan = w.instantaneous_stress(h);
        for k in 0..3 {
            // Through the force gathering's index and through a scan of
            // the contact list: the same contacts in the same order.
            assert!(
                (s[k] - scan[k]).abs() <= 1e-13 * scan[k].abs(),
                "{h}: {s:?} {scan:?}"
            );
            total[k] += s[k] * f.area_m2[h] * f.thickness_m[h];
        }
        largest = largest.max(s[0].abs().max(s[2].abs()));
    }
    assert!(largest > 1.0, "the pack is loaded: {largest} Pa");
    let m = w.observables(1.0).mean_stress_n_per_m;
    let sum = [m[0], 0.5 * (m[1] + m[2]), m[3]];
    let scale = sum[0].abs().max(sum[2].abs());
    for k in 0..3 {
        assert!(
            (total[k] - sum[k]).abs() < 1e-10 * scale,
            "component {k}: floes {} against the pack's {}",
            total[k],
            sum[k]
        );
    }
}

/// The sheared channel with floe stress, 60 steps, on `threads` threads.
fn stressed_channel(threads: usize) -> World<NoForcing> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut w = sheared_channel(400);
        w.set_stress_filter(Some(StressFilter::new(20.0).unwrap()));
        for _ in 0..60 {
            w.step();
        }
        w
    })
}

#[test]
fn floe_stress_is_bitwise_for_threads_resumes_and_a_floe_taken_out_and_back() {
    let bits = |w: &World<NoForcing>| format!("{:?}", w.state());
    let one = stressed_channel(1);
    assert!(one.floe_stress().iter().any(|s| s[0] != 0.0));
    assert_eq!(bits(&one), bits(&stressed_channel(2)), "threads");
    let (state, model, forcing, periodicity) = stressed_channel(1).into_parts();
    let mut resumed = World::resume(state, model, forcing, periodicity).unwrap();
    let mut edited = stressed_channel(1);
    let id = edited.floes().id[7];
    let detached = edited.remove_floe(id).unwrap();
    assert!(detached.stress.is_some_and(|s| s[0] != 0.0));
    edited.insert_detached(detached).unwrap();
    let mut straight = stressed_channel(1);
    for w in [&mut resumed, &mut edited, &mut straight] {
        for _ in 0..30 {
            w.step();
        }
    }
    assert_eq!(bits(&resumed), bits(&straight), "resumed");
    assert_eq!(bits(&edited), bits(&straight), "taken out and put back");
}

#[test]
fn turning_floe_stress_off_and_on_starts_it_from_zero() {
    let mut w = stressed_channel(1);
    w.set_stress_filter(None);
    assert!(w.floe_stress().is_empty() && w.state().stress_filter.is_none());
    w.step();
    w.set_stress_filter(Some(StressFilter::default()));
    assert!(w.floe_stress().iter().all(|s| *s == [0.0; 3]));
    assert_eq!(w.floe_stress().len(), w.floes().len());
    assert!(StressFilter::new(0.0).is_err() && StressFilter::new(f64::NAN).is_err());
}
