//! Order in time of velocity-dependent forcing: drag and Coriolis through
//! the world's step, against closed forms. The second half kick is
//! implicit in them, so the error falls as dt^2; a forcing that reports no
//! rates is stepped explicitly and falls as dt (the check that the
//! measurement can tell the two apart).

use floe_dem::contact_model::ContactModel;
use floe_dem::floes::{FloeColumns, Floes};
use floe_dem::forcing::{Coriolis, DragParameters, ExternalForces, Forcing};
use floe_dem::periodicity::Periodicity;
use floe_dem::world::World;
use floe_dem::Vec2;

const RHO_ICE: f64 = 917.0;
const STEPS: [f64; 4] = [1.0, 0.5, 0.25, 0.125];

fn square(side: f64, h: f64) -> Floes {
    let a = 0.5 * side;
    let c = Vec2::new(5e4, -2e4);
    let poly = vec![
        c + Vec2::new(-a, -a),
        c + Vec2::new(a, -a),
        c + Vec2::new(a, a),
        c + Vec2::new(-a, a),
    ];
    Floes::from_polygons(&[poly], &[h], RHO_ICE).unwrap()
}

/// The same forcing without its rates: stepped explicitly.
struct Explicit(Forcing);

impl ExternalForces for Explicit {
    fn force_and_torque(&self, t_s: f64, floes: &FloeColumns, i: usize) -> (Vec2, f64) {
        ExternalForces::force_and_torque(&self.0, t_s, floes, i)
    }
}

/// Runs one floe with `forcing` from `(u0, w0)` for `t_end` s at `dt`;
/// returns the final position, velocity and angular velocity.
fn run<F: ExternalForces>(forcing: F, u0: Vec2, w0: f64, t_end: f64, dt: f64) -> (Vec2, Vec2, f64) {
    let mut floes = square(200.0, 1.0);
    floes.set_velocity(0, u0, w0);
    // A lone floe: no contact sets the time step.
    let model = ContactModel {
        youngs_modulus_pa: 1.0,
        ..ContactModel::default()
    };
    let mut w = World::new(floes, model, forcing, Periodicity::default(), dt).unwrap();
    for _ in 0..(t_end / dt).round() as usize {
        w.step();
    }
    let f = w.floes();
    (f.position[0], f.velocity[0], f.angular_velocity[0])
}

/// Still water and air, ocean drag only.
fn still_water() -> Forcing {
    Forcing {
        air: DragParameters {
            drag_coefficient: 0.0,
            ..DragParameters::air()
        },
        ..Forcing::default()
    }
}

fn sci(xs: &[f64]) -> String {
    let v: Vec<String> = xs.iter().map(|x| format!("{x:.2e}")).collect();
    v.join(", ")
}

/// log2 of successive error ratios.
fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect()
}

#[test]
fn a_floe_spinning_down_in_still_water_converges_at_second_order() {
    let floes = square(200.0, 1.0);
    let (inertia, r3) = (floes.inertia_kg_m2[0], floes.r3_moment_m5[0]);
    let c = 1027.0 * 5.5e-3 * r3;
    // w' = -(c / I) |w| w: w(t) = w0 / (1 + w0 c t / I); time scale ~60 s.
    let w0 = inertia / (c * 60.0);
    let t_end = 120.0;
    let exact = w0 / (1.0 + w0 * c * t_end / inertia);
    let error = |implicit: bool, dt: f64| {
        let w = if implicit {
            run(still_water(), Vec2::ZERO, w0, t_end, dt).2
        } else {
            run(Explicit(still_water()), Vec2::ZERO, w0, t_end, dt).2
        };
        ((w - exact) / exact).abs()
    };
    let implicit: Vec<f64> = STEPS.iter().map(|&dt| error(true, dt)).collect();
    let explicit: Vec<f64> = STEPS.iter().map(|&dt| error(false, dt)).collect();
    eprintln!(
        "spin-down relative errors: implicit {}, explicit {}",
        sci(&implicit),
        sci(&explicit)
    );
    for p in orders(&implicit) {
        assert!((p - 2.0).abs() < 0.1, "implicit order {p}: {implicit:?}");
    }
    for p in orders(&explicit) {
        assert!((p - 1.0).abs() < 0.1, "explicit order {p}: {explicit:?}");
    }
    assert!(implicit[0] < 1e-4, "{implicit:?}");
}

#[test]
fn a_floe_slowing_in_still_water_converges_at_second_order_in_speed_and_position() {
    // u' = -k |u| u with k = rho_w C_w / (rho_i h): u = u0 / (1 + k u0 t),
    // x = x0 + ln(1 + k u0 t) / k. Time scale 1 / (k u0) ~ 160 s.
    let k = 1027.0 * 5.5e-3 / (RHO_ICE * 1.0);
    let u0 = Vec2::new(0.6, 0.8);
    let s0 = u0.length();
    let t_end = 300.0;
    let speed = s0 / (1.0 + k * s0 * t_end);
    let travel = (1.0 + k * s0 * t_end).ln() / k;
    let x0 = square(200.0, 1.0).position[0];
    let mut speed_errors = Vec::new();
    let mut travel_errors = Vec::new();
    for dt in STEPS {
        let (x, u, _) = run(still_water(), u0, 0.0, t_end, dt);
        // The direction never changes (no turning angle, no Coriolis).
        assert!(u.perp_dot(u0).abs() < 1e-12 * s0, "{u}");
        speed_errors.push((u.length() - speed).abs() / speed);
        travel_errors.push(((x - x0).length() - travel).abs() / travel);
    }
    eprintln!(
        "slowing: speed errors {}, travel errors {}",
        sci(&speed_errors),
        sci(&travel_errors)
    );
    for p in orders(&speed_errors)
        .into_iter()
        .chain(orders(&travel_errors))
    {
        assert!(
            (p - 2.0).abs() < 0.1,
            "order {p}: {speed_errors:?} {travel_errors:?}"
        );
    }
}

#[test]
fn an_inertial_oscillation_keeps_its_speed_and_converges_at_second_order_in_phase() {
    // Coriolis alone: the velocity turns clockwise (north) at f, its speed
    // constant. The implicit kick is the trapezoidal rule on a rotation,
    // which keeps the speed to round-off; the explicit one gains energy.
    let no_drag = |p: DragParameters| DragParameters {
        drag_coefficient: 0.0,
        ..p
    };
    let forcing = Forcing {
        air: no_drag(DragParameters::air()),
        ocean: no_drag(DragParameters::ocean()),
        coriolis: Coriolis::ParameterPerS(1.4e-4),
        ..Forcing::default()
    };
    let u0 = Vec2::new(0.3, 0.0);
    // About half an inertial period, a whole number of the longest step.
    let t_end: f64 = 40.0 * 561.0;
    let (sin, cos) = (-1.4e-4 * t_end).sin_cos();
    let exact = Vec2::new(cos * u0.x - sin * u0.y, sin * u0.x + cos * u0.y);
    let steps = [40.0, 20.0, 10.0, 5.0];
    let mut phase_errors = Vec::new();
    for dt in steps {
        let (_, u, _) = run(forcing.clone(), u0, 0.0, t_end, dt);
        assert!(
            (u.length() - u0.length()).abs() < 1e-12 * u0.length(),
            "dt {dt}: speed {} vs {}",
            u.length(),
            u0.length()
        );
        phase_errors.push((u - exact).length() / u0.length());
    }
    eprintln!("inertial oscillation phase errors {}", sci(&phase_errors));
    for p in orders(&phase_errors) {
        assert!((p - 2.0).abs() < 0.1, "order {p}: {phase_errors:?}");
    }
    let (_, explicit, _) = run(Explicit(forcing), u0, 0.0, t_end, 40.0);
    assert!(
        explicit.length() > u0.length() * (1.0 + 1e-3),
        "the explicit kick gains speed: {}",
        explicit.length()
    );
}
