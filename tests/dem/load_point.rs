//! A block driven through a spring from a moving load point (the paper's
//! apparatus): against the mass-spring solution, through a hold, in the
//! energy ledger, and across a pause and resume.

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::Floes;
use floe_dem::forcing::NoForcing;
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::{MotionSchedule, MotionSegment};
use floe_dem::periodicity::{Period, Periodicity};
use floe_dem::world::World;
use floe_dem::Vec2;

const V: f64 = 0.01; // load-point speed, m/s

/// A 1 m square block 0.1 m thick (91.7 kg) on nothing, its load point
/// pulling along x at `V` for `slide_s`, then holding.
fn world(k: f64, slide_s: f64, dt: f64, periodicity: Periodicity) -> World<NoForcing> {
    let c = Vec2::new(2.0, 3.0);
    let square = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
        .map(|(x, y)| c + Vec2::new(x, y))
        .to_vec();
    let floes = Floes::from_polygons(&[square], &[0.1], 917.0).unwrap();
    let model = ContactModel {
        youngs_modulus_pa: 1e3,
        ..ContactModel::default()
    };
    let mut w = World::new(floes, model, NoForcing, periodicity, dt).unwrap();
    let schedule = MotionSchedule::new(vec![
        MotionSegment::constant(slide_s, Vec2::new(V, 0.0)),
        MotionSegment::constant(1e9, Vec2::ZERO),
    ])
    .unwrap();
    let id = w.floes().id[0];
    w.set_load_point(LoadPoint::new(id, k, c, schedule).unwrap())
        .unwrap();
    w
}

/// The block's displacement from rest while the load point slides:
/// `x'' = w^2 (V t - x)`, `x = V t - (V / w) sin(w t)`.
fn sliding(t: f64, omega: f64) -> f64 {
    V * t - V / omega * (omega * t).sin()
}

#[test]
fn a_spring_driven_block_follows_the_mass_spring_solution_at_second_order() {
    let (k, mass): (f64, f64) = (1e3, 91.7);
    let omega = (k / mass).sqrt(); // 3.3 rad/s, period 1.9 s
    let t_end = 6.0;
    let errors: Vec<f64> = [0.02, 0.01, 0.005]
        .iter()
        .map(|&dt| {
            let mut w = world(k, 100.0, dt, Periodicity::default());
            for _ in 0..(t_end / dt).round() as usize {
                w.step();
            }
            let x = w.floes().position[0].x - 2.0;
            assert_eq!(w.floes().position[0].y, 3.0, "no force across");
            (x - sliding(t_end, omega)).abs() / (V * t_end)
        })
        .collect();
    eprintln!("relative errors {errors:?}");
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 2.0).abs() < 0.15, "order {order}: {errors:?}");
    }
    assert!(errors[0] < 2e-4, "{errors:?}");
}

#[test]
fn after_a_hold_the_block_oscillates_about_the_load_point_and_the_ledger_balances() {
    let (k, mass): (f64, f64) = (1e3, 91.7);
    let omega = (k / mass).sqrt();
    let (slide, dt) = (2.0, 0.002);
    let mut w = world(k, slide, dt, Periodicity::default());
    for _ in 0..(10.0 / dt) as usize {
        w.step();
    }
    // From the hold on: an oscillation about the load point's stop (V
    // slide) with the state at the hold's start.
    let (x0, v0) = (
        sliding(slide, omega) - V * slide,
        V - V * (omega * slide).cos(),
    );
    let t = 10.0 - slide;
    let expected = V * slide + x0 * (omega * t).cos() + v0 / omega * (omega * t).sin();
    let x = w.floes().position[0].x - 2.0;
    assert!((x - expected).abs() < 1e-5 * V * slide, "{x} vs {expected}");
    // Work and energy: the spring is the block's only force, so its work
    // (counted as forcing work) is the block's kinetic energy, to the
    // trapezoidal rule's accuracy.
    let o = w.observables(1.0);
    let spring = (x - V * slide).powi(2) * 0.5 * k;
    let ke = o.kinetic_translational_j;
    let work = o.ledger.forcing_work_j;
    eprintln!("work {work}, kinetic {ke}, spring {spring}");
    assert!((o.load_point_force_n[0] - k * (V * slide - x)).abs() < 1e-9 * k * V);
    assert!((work - ke).abs() < 1e-6 * (ke + spring), "{work} vs {ke}");
}

#[test]
fn a_run_resumed_in_the_middle_of_the_load_points_schedule_is_bitwise_the_same() {
    // Periodic along x, with the block crossing the period's edge.
    let periodicity = Periodicity {
        x: Some(Period {
            min_m: 0.0,
            length_m: 2.5,
        }),
        y: None,
    };
    let mut whole = world(1e3, 2.0, 0.01, periodicity);
    let mut part = world(1e3, 2.0, 0.01, periodicity);
    for _ in 0..150 {
        whole.step();
        part.step();
    }
    let state = part.state().clone();
    let model = part.model().clone();
    let mut resumed = World::resume(state, model, NoForcing, periodicity).unwrap();
    for _ in 0..350 {
        whole.step();
        resumed.step();
    }
    assert!(whole.state() == resumed.state());
    assert_eq!(whole.load_points().len(), 1);
}
