//! Wind/ocean forcing of `floe-dem`: free drift against closed forms and the
//! independent steady-state solver, Coriolis, turning angle, velocity
//! fields, rotational drag and `∫ r³ dA`, serde, and no allocation in the
//! per-floe evaluation.

use std::f64::consts::{PI, SQRT_2};

use floe_dem::forcing::*;
use floe_dem::{DemError, Vec2};

use crate::counting_allocator::allocations;

// ---------------------------------------------------------------------------
// Helpers.

const RHO_ICE: f64 = 917.0;
const RHO_AIR: f64 = 1.2;
const C_AIR: f64 = 1.2e-3;
const RHO_WATER: f64 = 1027.0;
const C_WATER: f64 = 5.5e-3;

/// A 1 km x 1 km floe, 1 m thick, at rest at the origin.
fn floe(thickness_m: f64) -> FloeDynamics {
    let side = 1000.0;
    let a = 0.5 * side;
    let area = side * side;
    FloeDynamics {
        position: Vec2::ZERO,
        velocity: Vec2::ZERO,
        angular_velocity: 0.0,
        area_m2: area,
        mass_kg: RHO_ICE * thickness_m * area,
        r3_moment_m5: square_r3(a),
    }
}

/// `∫ r³ dA` over a square of half-side `a`, derived in polar coordinates:
/// 8 triangles `0 ≤ θ ≤ π/4`, `r ≤ a/cos θ`, so `8 a⁵/5 ∫₀^{π/4} sec⁵θ dθ`
/// `= a⁵ (7√2 + 3 ln(1 + √2)) / 5`.
fn square_r3(a: f64) -> f64 {
    a.powi(5) * (7.0 * SQRT_2 + 3.0 * (1.0 + SQRT_2).ln()) / 5.0
}

/// `∫₀^α sec⁵ψ dψ` (reduction formula).
fn int_sec5(alpha: f64) -> f64 {
    let (s, t) = (1.0 / alpha.cos(), alpha.tan());
    0.25 * s.powi(3) * t + 0.375 * (s * t + (s + t).ln())
}

/// Classical RK4 on the velocity of a floe held at its position (uniform
/// fields), `steps` steps of `dt_s`; returns the final velocity.
fn integrate(forcing: &Forcing, mut state: FloeDynamics, dt_s: f64, steps: usize) -> Vec2 {
    let accel = |t: f64, u: Vec2| {
        let s = FloeDynamics {
            velocity: u,
            ..state
        };
        forcing.force_and_torque(t, &s).0 / s.mass_kg
    };
    let mut t = 0.0;
    for _ in 0..steps {
        let u = state.velocity;
        let k1 = accel(t, u);
        let k2 = accel(t + 0.5 * dt_s, u + 0.5 * dt_s * k1);
        let k3 = accel(t + 0.5 * dt_s, u + 0.5 * dt_s * k2);
        let k4 = accel(t + dt_s, u + dt_s * k3);
        state.velocity = u + dt_s / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        t += dt_s;
    }
    state.velocity
}

fn rel_err(a: Vec2, b: Vec2) -> f64 {
    (a - b).length() / b.length()
}

/// Signed angle from `a` to `b`, radians, counterclockwise positive.
fn angle_from(a: Vec2, b: Vec2) -> f64 {
    a.perp_dot(b).atan2(a.dot(b))
}

fn wind_only(wind: Vec2) -> Forcing {
    Forcing {
        wind: VelocityField::Uniform(wind),
        ..Forcing::default()
    }
}

// ---------------------------------------------------------------------------
// (1) Free drift without Coriolis.

#[test]
fn defaults_are_the_documented_values() {
    let f = Forcing::default();
    assert_eq!(f.air.density_kg_per_m3, RHO_AIR);
    assert_eq!(f.air.drag_coefficient, C_AIR);
    assert_eq!(f.air.turning_angle_deg, 0.0);
    assert!(!f.air.relative_to_ice);
    assert_eq!(f.ocean.density_kg_per_m3, RHO_WATER);
    assert_eq!(f.ocean.drag_coefficient, C_WATER);
    assert_eq!(f.ocean.turning_angle_deg, 0.0);
    assert!(f.ocean.relative_to_ice);
    assert_eq!(f.coriolis, Coriolis::Off);
    assert_eq!(f.wind.velocity(Vec2::new(3.0, 4.0), 5.0), Vec2::ZERO);
    assert_eq!(f.current.velocity(Vec2::new(3.0, 4.0), 5.0), Vec2::ZERO);
    assert!(f.validate().is_ok());
    // No forcing at all on a floe at rest.
    let (force, torque) = f.force_and_torque(0.0, &floe(1.0));
    assert_eq!((force, torque), (Vec2::ZERO, 0.0));
}

#[test]
fn free_drift_without_coriolis_converges_to_the_closed_form() {
    let wind = Vec2::new(8.0, -6.0); // 10 m/s
    let forcing = wind_only(wind);
    // rho_w C_w |u| u = rho_a C_a |U_a| U_a  =>  u = sqrt(rho_a C_a / (rho_w C_w)) U_a.
    let factor = (RHO_AIR * C_AIR / (RHO_WATER * C_WATER)).sqrt();
    assert!(
        (0.015..0.02).contains(&factor),
        "wind factor {factor} is not the ~2 % rule"
    );
    let expected = factor * wind;

    // The library's steady-state solver agrees with the closed form.
    let solved = free_drift_velocity(
        wind,
        Vec2::ZERO,
        &forcing.air,
        &forcing.ocean,
        0.0,
        RHO_ICE,
        true,
    )
    .unwrap();
    assert!(rel_err(solved, expected) < 1e-14, "{solved} vs {expected}");

    // Time integration from rest (relaxation time ~ m' / (2 rho_w C_w |u|) ~ 500 s).
    for thickness in [0.5, 1.0, 3.0] {
        let u = integrate(&forcing, floe(thickness), 10.0, 8000);
        let e = rel_err(u, expected);
        assert!(
            e < 1e-6,
            "h = {thickness} m: {u} vs {expected}, rel err {e:e}"
        );
    }

    // With a current as well: u = U_w + factor U_a.
    let current = Vec2::new(-0.05, 0.12);
    let forcing = Forcing {
        current: VelocityField::Uniform(current),
        ..forcing
    };
    let expected = current + factor * wind;
    let u = integrate(&forcing, floe(1.0), 10.0, 8000);
    assert!(rel_err(u, expected) < 1e-6, "{u} vs {expected}");
    let solved = forcing
        .free_drift_velocity_at(0.0, Vec2::ZERO, RHO_ICE)
        .unwrap();
    assert!(rel_err(solved, expected) < 1e-14);
}

// ---------------------------------------------------------------------------
// (2) Free drift with Coriolis.

#[test]
fn free_drift_with_coriolis_turns_right_and_slows_in_the_north() {
    let wind = Vec2::new(10.0, 0.0);
    let thickness = 2.0;
    let mass_per_area = RHO_ICE * thickness;
    let no_rotation = wind_only(wind);
    let north = Forcing {
        coriolis: Coriolis::LatitudeDeg(75.0),
        ..no_rotation.clone()
    };
    let f = north.coriolis.parameter_per_s();
    assert!((f - 2.0 * 7.2921e-5 * 75f64.to_radians().sin()).abs() < 1e-18);

    let steady = north
        .free_drift_velocity_at(0.0, Vec2::ZERO, mass_per_area)
        .unwrap();
    let steady_no_rotation = no_rotation
        .free_drift_velocity_at(0.0, Vec2::ZERO, mass_per_area)
        .unwrap();

    // Time integration (inertial oscillations damped on ~1000 s).
    let u = integrate(&north, floe(thickness), 10.0, 20_000);
    let e = rel_err(u, steady);
    assert!(e < 1e-6, "{u} vs steady {steady}: rel err {e:e}");

    // Deflected to the right of the wind (clockwise), by less than 90 deg.
    let turn = angle_from(wind, steady);
    assert!(
        turn < -1f64.to_radians() && turn > -90f64.to_radians(),
        "deflection {} deg",
        turn.to_degrees()
    );
    // Slower than without rotation.
    assert!(steady.length() < steady_no_rotation.length());
    assert!(steady.length() > 0.5 * steady_no_rotation.length());

    // The force at the steady velocity vanishes to round-off.
    let mut s = floe(thickness);
    s.velocity = steady;
    let (force, _) = north.force_and_torque(0.0, &s);
    let scale = s.area_m2 * RHO_AIR * C_AIR * wind.length_squared();
    assert!(
        force.length() < 1e-13 * scale,
        "residual {force} vs scale {scale}"
    );

    // Southern Hemisphere: mirror image, deflected to the left.
    let south = Forcing {
        coriolis: Coriolis::LatitudeDeg(-75.0),
        ..no_rotation.clone()
    };
    let steady_south = south
        .free_drift_velocity_at(0.0, Vec2::ZERO, mass_per_area)
        .unwrap();
    assert!((angle_from(wind, steady_south) + turn).abs() < 1e-12);
    assert!((steady_south.length() - steady.length()).abs() < 1e-15);

    // Thicker ice (more inertia per area): more deflection.
    let thick = north
        .free_drift_velocity_at(0.0, Vec2::ZERO, RHO_ICE * 5.0)
        .unwrap();
    assert!(angle_from(wind, thick) < turn);
}

#[test]
fn free_drift_general_case_matches_integration() {
    // Wind, current, ocean turning angle, air drag relative to the ice,
    // Coriolis without sea-surface tilt: the fixed-point/bisection solver
    // against time integration.
    let forcing = Forcing {
        wind: VelocityField::Uniform(Vec2::new(-7.0, 12.0)),
        current: VelocityField::Uniform(Vec2::new(0.1, -0.05)),
        air: DragParameters {
            relative_to_ice: true,
            turning_angle_deg: 10.0,
            ..DragParameters::air()
        },
        ocean: DragParameters {
            turning_angle_deg: 25.0,
            ..DragParameters::ocean()
        },
        coriolis: Coriolis::ParameterPerS(1.4e-4),
        sea_surface_tilt: false,
        rotational_drag: true,
        sea_surface_height: None,
    };
    let thickness = 1.5;
    let steady = forcing
        .free_drift_velocity_at(0.0, Vec2::ZERO, RHO_ICE * thickness)
        .unwrap();
    let u = integrate(&forcing, floe(thickness), 10.0, 20_000);
    assert!(rel_err(u, steady) < 1e-6, "{u} vs {steady}");
    let mut s = floe(thickness);
    s.velocity = steady;
    let (force, _) = forcing.force_and_torque(0.0, &s);
    let scale = s.area_m2 * RHO_AIR * C_AIR * 14f64.powi(2);
    assert!(force.length() < 1e-12 * scale, "residual {force}");
}

#[test]
fn sea_surface_tilt_balances_coriolis_for_ice_moving_with_the_current() {
    let current = Vec2::new(0.2, -0.1);
    let forcing = Forcing {
        current: VelocityField::Uniform(current),
        coriolis: Coriolis::LatitudeDeg(80.0),
        sea_surface_tilt: true,
        ..Forcing::default()
    };
    let mut s = floe(2.0);
    s.velocity = current;
    let (force, _) = forcing.force_and_torque(0.0, &s);
    assert_eq!(force, Vec2::ZERO);
    let steady = forcing
        .free_drift_velocity_at(0.0, Vec2::ZERO, RHO_ICE * 2.0)
        .unwrap();
    assert!(rel_err(steady, current) < 1e-15);

    // Without the tilt, the ice lags and turns right of the current.
    let no_tilt = Forcing {
        sea_surface_tilt: false,
        ..forcing
    };
    let (force, _) = no_tilt.force_and_torque(0.0, &s);
    assert!(current.perp_dot(force) < 0.0, "Coriolis pushes right");
    let steady = no_tilt
        .free_drift_velocity_at(0.0, Vec2::ZERO, RHO_ICE * 2.0)
        .unwrap();
    assert!(angle_from(current, steady) < 0.0);
    assert!(steady.length() < current.length());
    let u = integrate(&no_tilt, floe(2.0), 10.0, 20_000);
    assert!(rel_err(u, steady) < 1e-6, "{u} vs {steady}");
}

// ---------------------------------------------------------------------------
// (3) Coriolis does no work.

#[test]
fn coriolis_is_perpendicular_to_the_velocity_and_does_no_work() {
    let mass = 1.834e9;
    let f = 1.4e-4;
    for (k, u) in [
        Vec2::new(0.3, 0.0),
        Vec2::new(0.0, -0.2),
        Vec2::new(0.17, 0.41),
        Vec2::new(-1e-3, 2e-3),
    ]
    .into_iter()
    .enumerate()
    {
        let fc = coriolis_force(mass, f, u);
        assert!(
            fc.dot(u).abs() <= 1e-15 * fc.length() * u.length(),
            "case {k}: power {}",
            fc.dot(u)
        );
        assert!((fc.length() - mass * f * u.length()).abs() <= 1e-15 * fc.length());
        // To the right of the motion for f > 0, to the left for f < 0.
        assert!(u.perp_dot(fc) < 0.0);
        assert!(u.perp_dot(coriolis_force(mass, -f, u)) > 0.0);
    }

    // Inertial oscillation with no drag: speed conserved, and the velocity
    // returns to its start after one inertial period 2 pi / f.
    let forcing = Forcing {
        air: DragParameters {
            drag_coefficient: 0.0,
            ..DragParameters::air()
        },
        ocean: DragParameters {
            drag_coefficient: 0.0,
            ..DragParameters::ocean()
        },
        coriolis: Coriolis::ParameterPerS(f),
        ..Forcing::default()
    };
    let mut s = floe(1.0);
    let u0 = Vec2::new(0.3, 0.1);
    s.velocity = u0;
    let (force, _) = forcing.force_and_torque(0.0, &s);
    assert!(force.dot(u0).abs() <= 1e-15 * force.length() * u0.length());
    let period = 2.0 * PI / f;
    let steps = 10_000;
    let u = integrate(&forcing, s, period / steps as f64, steps);
    assert!(
        (u.length() - u0.length()).abs() < 1e-10 * u0.length(),
        "speed {} vs {}",
        u.length(),
        u0.length()
    );
    assert!(rel_err(u, u0) < 1e-9, "{u} vs {u0}");
}

// ---------------------------------------------------------------------------
// (4) Turning angle.

#[test]
fn turning_angle_rotates_the_stress_by_the_angle() {
    let water = Vec2::new(0.1, 0.3);
    let ice = Vec2::new(0.25, -0.1);
    let straight = DragParameters::ocean();
    let tau0 = straight.stress(water, ice);
    // phi = 0: along the relative velocity, magnitude rho C |U_rel|^2.
    let rel = water - ice;
    assert!(angle_from(rel, tau0).abs() < 1e-15);
    assert!(
        (tau0.length() - RHO_WATER * C_WATER * rel.length_squared()).abs() < 1e-14 * tau0.length()
    );
    for phi_deg in [25.0, -25.0, 15.0, 60.0, -80.0] {
        let turned = DragParameters {
            turning_angle_deg: phi_deg,
            ..straight
        };
        let tau = turned.stress(water, ice);
        assert!((tau.length() - tau0.length()).abs() < 1e-14 * tau0.length());
        let angle = angle_from(tau0, tau);
        assert!(
            (angle - f64::to_radians(phi_deg)).abs() < 1e-13,
            "phi {phi_deg}: rotated by {} deg",
            angle.to_degrees()
        );
    }
    // +25 deg (Northern Hemisphere) is counterclockwise: the stress lies to
    // the left of the relative velocity.
    let nh = DragParameters {
        turning_angle_deg: 25.0,
        ..straight
    };
    assert!(rel.perp_dot(nh.stress(water, ice)) > 0.0);
    // Helper `rotate` agrees.
    assert!((rotate(Vec2::X, 0.5 * PI) - Vec2::Y).length() < 1e-16);

    // Air drag neglects the ice velocity unless asked otherwise.
    let wind = Vec2::new(10.0, 2.0);
    let air = DragParameters::air();
    assert_eq!(air.stress(wind, ice), air.stress(wind, Vec2::ZERO));
    let air_rel = DragParameters {
        relative_to_ice: true,
        ..air
    };
    assert_eq!(
        air_rel.stress(wind, ice),
        air.stress(wind - ice, Vec2::ZERO)
    );

    // Ocean drag on ice moving through still water opposes the motion.
    let tau = straight.stress(Vec2::ZERO, ice);
    assert!(tau.dot(ice) < 0.0);
    assert!(angle_from(-ice, tau).abs() < 1e-15);
}

// ---------------------------------------------------------------------------
// (5) Velocity fields.

#[test]
fn time_series_interpolates_linearly_and_clamps() {
    let field = VelocityField::TimeSeries {
        times_s: vec![0.0, 100.0, 300.0],
        values: vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(10.0, 0.0),
            Vec2::new(10.0, -4.0),
        ],
    };
    field.validate().unwrap();
    let p = Vec2::new(123.0, -4.0); // position is irrelevant
    let at = |t: f64| field.velocity(p, t);
    assert_eq!(at(-50.0), Vec2::ZERO);
    assert_eq!(at(0.0), Vec2::ZERO);
    assert!((at(25.0) - Vec2::new(2.5, 0.0)).length() < 1e-15);
    assert_eq!(at(100.0), Vec2::new(10.0, 0.0));
    assert!((at(250.0) - Vec2::new(10.0, -3.0)).length() < 1e-15);
    assert_eq!(at(300.0), Vec2::new(10.0, -4.0));
    assert_eq!(at(1e9), Vec2::new(10.0, -4.0));
    assert_eq!(at(f64::NAN), Vec2::ZERO);
    assert_eq!(field.vorticity(p, 50.0), 0.0);

    // A single sample is constant.
    let one = VelocityField::TimeSeries {
        times_s: vec![5.0],
        values: vec![Vec2::new(1.0, 2.0)],
    };
    one.validate().unwrap();
    assert_eq!(one.velocity(p, -1.0), Vec2::new(1.0, 2.0));
    assert_eq!(one.velocity(p, 99.0), Vec2::new(1.0, 2.0));

    // Invalid series are reported by validate().
    let unsorted = VelocityField::TimeSeries {
        times_s: vec![0.0, 10.0, 10.0],
        values: vec![Vec2::ZERO; 3],
    };
    assert!(matches!(
        unsorted.validate(),
        Err(DemError::InvalidParameter {
            name: "time-series.times_s",
            ..
        })
    ));
    let short = VelocityField::TimeSeries {
        times_s: vec![0.0, 10.0],
        values: vec![Vec2::ZERO],
    };
    assert!(short.validate().is_err());
    let empty = VelocityField::TimeSeries {
        times_s: vec![],
        values: vec![],
    };
    assert!(empty.validate().is_err());
    assert_eq!(empty.velocity(p, 1.0), Vec2::ZERO); // but no panic
}

#[test]
fn linear_shear_profile_values() {
    let field = VelocityField::LinearShear {
        y_min_m: -5000.0,
        y_max_m: 5000.0,
        velocity_at_y_min_m_per_s: Vec2::new(-0.2, 0.0),
        velocity_at_y_max_m_per_s: Vec2::new(0.3, 0.0),
    };
    field.validate().unwrap();
    let at = |y: f64| field.velocity(Vec2::new(777.0, y), 0.0);
    assert_eq!(at(-5000.0), Vec2::new(-0.2, 0.0));
    assert_eq!(at(5000.0), Vec2::new(0.3, 0.0));
    assert!((at(0.0) - Vec2::new(0.05, 0.0)).length() < 1e-16);
    assert!((at(2500.0) - Vec2::new(0.175, 0.0)).length() < 1e-16);
    assert_eq!(at(-9000.0), Vec2::new(-0.2, 0.0)); // clamped outside
    assert_eq!(at(9000.0), Vec2::new(0.3, 0.0));
    // Uniform in x.
    assert_eq!(
        field.velocity(Vec2::new(-1e5, 1234.0), 0.0),
        field.velocity(Vec2::new(1e5, 1234.0), 0.0)
    );
    // Vorticity -du_x/dy inside, zero outside.
    assert!((field.vorticity(Vec2::new(0.0, 100.0), 0.0) + 0.5 / 10000.0).abs() < 1e-19);
    assert_eq!(field.vorticity(Vec2::new(0.0, 6000.0), 0.0), 0.0);

    let bad = VelocityField::LinearShear {
        y_min_m: 1.0,
        y_max_m: 1.0,
        velocity_at_y_min_m_per_s: Vec2::ZERO,
        velocity_at_y_max_m_per_s: Vec2::ZERO,
    };
    assert!(bad.validate().is_err());
}

#[test]
fn gyre_velocity_is_tangential_rankine() {
    let center = Vec2::new(1000.0, -2000.0);
    let (radius, speed) = (5000.0, 0.4);
    let field = VelocityField::Gyre {
        center_m: center,
        core_radius_m: radius,
        max_speed_m_per_s: speed,
    };
    field.validate().unwrap();
    assert_eq!(field.velocity(center, 0.0), Vec2::ZERO);
    for r in [100.0, 2500.0, 5000.0, 7500.0, 20_000.0] {
        for deg in [0.0, 37.0, 90.0, 200.0, 315.0] {
            let p = center + r * Vec2::from_angle(f64::to_radians(deg));
            let (rhat, r) = ((p - center).normalize(), (p - center).length());
            let v = field.velocity(p, 0.0);
            // Tangential, counterclockwise for positive speed.
            assert!(v.dot(rhat).abs() < 1e-15 * v.length(), "radial part");
            assert!(rhat.perp_dot(v) > 0.0);
            let expected = if r <= radius {
                speed * r / radius
            } else {
                speed * radius / r
            };
            assert!(
                (v.length() - expected).abs() < 1e-14 * expected,
                "r = {r}: {} vs {expected}",
                v.length()
            );
        }
    }
    // Solid-body core: vorticity 2 V / R; irrotational outside.
    assert!(
        (field.vorticity(center + Vec2::new(10.0, 0.0), 0.0) - 2.0 * speed / radius).abs() < 1e-18
    );
    assert_eq!(field.vorticity(center + Vec2::new(0.0, 9000.0), 0.0), 0.0);
    let bad = VelocityField::Gyre {
        center_m: Vec2::ZERO,
        core_radius_m: 0.0,
        max_speed_m_per_s: 1.0,
    };
    assert!(bad.validate().is_err());
}

#[test]
fn envelope_switches_a_field_off_and_on() {
    // On for an hour, ramped off in 100 s, off for an hour, back on in 100 s.
    let envelope = Envelope::new(
        vec![0.0, 3600.0, 3700.0, 7200.0, 7300.0],
        vec![1.0, 1.0, 0.0, 0.0, 1.0],
    )
    .unwrap();
    let field = VelocityField::Uniform(Vec2::new(10.0, 0.0)).scaled(envelope.clone());
    field.validate().unwrap();
    let at = |t: f64| field.velocity(Vec2::ZERO, t);
    assert_eq!(at(-10.0), Vec2::new(10.0, 0.0));
    assert_eq!(at(1800.0), Vec2::new(10.0, 0.0));
    assert!((at(3650.0) - Vec2::new(5.0, 0.0)).length() < 1e-14);
    assert_eq!(at(5000.0), Vec2::ZERO);
    assert!((at(7225.0) - Vec2::new(2.5, 0.0)).length() < 1e-14);
    assert_eq!(at(1e6), Vec2::new(10.0, 0.0));
    assert_eq!(envelope.factor(3700.0), 0.0);

    // The floe feels no wind while it is off.
    let forcing = Forcing {
        wind: field,
        ..Forcing::default()
    };
    let (force, _) = forcing.force_and_torque(5000.0, &floe(1.0));
    assert_eq!(force, Vec2::ZERO);
    let (force, _) = forcing.force_and_torque(1000.0, &floe(1.0));
    assert!(force.x > 0.0);

    assert!(Envelope::new(vec![0.0, 1.0], vec![1.0]).is_err());
    assert!(Envelope::new(vec![1.0, 0.0], vec![1.0, 0.0]).is_err());
}

// ---------------------------------------------------------------------------
// (6) Rotational drag and the r^3 moment.

#[test]
fn rotational_drag_opposes_spin_and_scales_as_omega_squared() {
    let forcing = Forcing::default();
    let mut s = floe(1.0);
    let i3 = s.r3_moment_m5;
    let torque_at = |w: f64, s: &mut FloeDynamics| {
        s.angular_velocity = w;
        forcing.force_and_torque(0.0, s)
    };
    let w = 2e-4;
    let (force, t1) = torque_at(w, &mut s);
    assert_eq!(force, Vec2::ZERO); // spin alone gives no net force (phi = 0)
    assert!(t1 < 0.0);
    assert!((t1 + RHO_WATER * C_WATER * w * w * i3).abs() < 1e-14 * t1.abs());
    let (_, t2) = torque_at(2.0 * w, &mut s);
    assert!((t2 / t1 - 4.0).abs() < 1e-14);
    let (_, t3) = torque_at(10.0 * w, &mut s);
    assert!((t3 / t1 - 100.0).abs() < 1e-12);
    let (_, tn) = torque_at(-w, &mut s);
    assert_eq!(tn, -t1);
    let (_, t0) = torque_at(0.0, &mut s);
    assert_eq!(t0, 0.0);

    // Switched off: no torque.
    let off = Forcing {
        rotational_drag: false,
        ..forcing.clone()
    };
    s.angular_velocity = w;
    assert_eq!(off.force_and_torque(0.0, &s).1, 0.0);

    // Turning angle: only the tangential part cos(phi) of the stress has a moment.
    let turned = Forcing {
        ocean: DragParameters {
            turning_angle_deg: 25.0,
            ..DragParameters::ocean()
        },
        ..forcing.clone()
    };
    let (_, tt) = turned.force_and_torque(0.0, &s);
    assert!((tt / t1 - 25f64.to_radians().cos()).abs() < 1e-14);

    // Air drag relative to the ice adds its own rotational drag.
    let with_air = Forcing {
        air: DragParameters {
            relative_to_ice: true,
            ..DragParameters::air()
        },
        ..forcing.clone()
    };
    let (_, ta) = with_air.force_and_torque(0.0, &s);
    let expected = -(RHO_WATER * C_WATER + RHO_AIR * C_AIR) * w * w * i3;
    assert!((ta - expected).abs() < 1e-14 * expected.abs());

    // A floe co-rotating with the solid-body core of a gyre feels no torque;
    // at rest there, it is spun up in the gyre's sense.
    let (radius, speed) = (20_000.0, 0.3);
    let gyre = Forcing {
        current: VelocityField::Gyre {
            center_m: Vec2::ZERO,
            core_radius_m: radius,
            max_speed_m_per_s: speed,
        },
        ..forcing.clone()
    };
    s.angular_velocity = speed / radius;
    assert_eq!(gyre.force_and_torque(0.0, &s).1, 0.0);
    s.angular_velocity = 0.0;
    assert!(gyre.force_and_torque(0.0, &s).1 > 0.0);

    // Spin-down integrated explicitly: d omega/dt = T / J with the square's
    // moment of inertia J = m (2a)^2 / 6; for quadratic drag
    // omega(t) = omega0 / (1 + k omega0 t), k = rho C I3 / J.
    let a = 500.0;
    let j = s.mass_kg * (2.0 * a) * (2.0 * a) / 6.0;
    let k = RHO_WATER * C_WATER * i3 / j;
    let w0 = 1e-3;
    let (dt, steps) = (1.0, 20_000);
    let spin = |w: f64| {
        let mut st = s;
        st.angular_velocity = w;
        forcing.force_and_torque(0.0, &st).1 / j
    };
    let mut w = w0;
    for _ in 0..steps {
        let k1 = spin(w);
        let k2 = spin(w + 0.5 * dt * k1);
        let k3 = spin(w + 0.5 * dt * k2);
        let k4 = spin(w + dt * k3);
        w += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    let exact = w0 / (1.0 + k * w0 * dt * steps as f64);
    assert!((w - exact).abs() < 1e-9 * exact, "{w} vs {exact}");
}

/// Regular N-gon of circumradius `r`, counterclockwise, centred at the origin.
fn regular_polygon(n: usize, r: f64) -> Vec<Vec2> {
    (0..n)
        .map(|k| r * Vec2::from_angle(2.0 * PI * k as f64 / n as f64))
        .collect()
}

/// Independent reference: each fan triangle in polar coordinates,
/// `∫ ρ(θ)⁵/5 dθ` with `ρ(θ)` the distance to the edge line along `θ`,
/// by composite Simpson with `m` panels per edge. For a convex polygon
/// containing the origin.
fn r3_polar_simpson(vertices: &[Vec2], m: usize) -> f64 {
    let n = vertices.len();
    let mut total = 0.0;
    for i in 0..n {
        let (a, b) = (vertices[i], vertices[(i + 1) % n]);
        let (ta, mut tb) = (a.y.atan2(a.x), b.y.atan2(b.x));
        while tb < ta {
            tb += 2.0 * PI;
        }
        // Line through a and b: points p with p . nrm = d.
        let e = b - a;
        let nrm = Vec2::new(e.y, -e.x).normalize();
        let d = a.dot(nrm);
        let g = |t: f64| {
            let rho = d / Vec2::from_angle(t).dot(nrm);
            rho.powi(5) / 5.0
        };
        let h = (tb - ta) / m as f64;
        let mut s = g(ta) + g(tb);
        for k in 1..m {
            s += g(ta + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        total += s * h / 3.0;
    }
    total
}

#[test]
fn r3_moment_of_a_square_and_a_disc() {
    // Square of half-side a: a^5 (7 sqrt 2 + 3 ln(1 + sqrt 2)) / 5.
    for a in [1.0, 0.37, 250.0] {
        let sq = [
            Vec2::new(a, a),
            Vec2::new(-a, a),
            Vec2::new(-a, -a),
            Vec2::new(a, -a),
        ];
        let got = polygon_r3_moment(&sq);
        let want = square_r3(a);
        assert!(
            (got - want).abs() < 1e-14 * want,
            "a = {a}: {got} vs {want}"
        );
        // Clockwise order gives the same value.
        let mut cw = sq;
        cw.reverse();
        assert!((polygon_r3_moment(&cw) - want).abs() < 1e-14 * want);
    }
    // Numerically 2.50872314 a^5 (a 2000 x 2000 midpoint sum gives 2.5087220).
    assert!((square_r3(1.0) - 2.508_723_14).abs() < 1e-8);

    // Regular N-gon: exact value N (2 c^5 / 5) ∫_0^{π/N} sec^5, c the apothem.
    let r = 3.0;
    for n in [3, 4, 7, 64, 1000, 16_384] {
        let got = polygon_r3_moment(&regular_polygon(n, r));
        let alpha = PI / n as f64;
        let c = r * alpha.cos();
        let want = n as f64 * 2.0 * c.powi(5) / 5.0 * int_sec5(alpha);
        assert!(
            (got - want).abs() < 1e-12 * want,
            "N = {n}: {got} vs {want}"
        );
    }
    // Disc limit 2 pi R^5 / 5, with second-order convergence in 1/N.
    let disc = 2.0 * PI * r.powi(5) / 5.0;
    let err = |n: usize| (disc - polygon_r3_moment(&regular_polygon(n, r))) / disc;
    let (e1, e2) = (err(8192), err(16_384));
    assert!(e2 > 0.0 && e2 < 1e-7, "16384-gon vs disc: {e2:e}");
    assert!(
        (e1 / e2 - 4.0).abs() < 1e-3,
        "convergence ratio {}",
        e1 / e2
    );
}

#[test]
fn r3_moment_of_irregular_polygons() {
    // A convex pentagon about its area centroid, against polar Simpson.
    let raw = [
        Vec2::new(0.0, 0.0),
        Vec2::new(40.0, -5.0),
        Vec2::new(70.0, 20.0),
        Vec2::new(35.0, 60.0),
        Vec2::new(-10.0, 30.0),
    ];
    let mut area2 = 0.0;
    let mut cen = Vec2::ZERO;
    for i in 0..raw.len() {
        let (a, b) = (raw[i], raw[(i + 1) % raw.len()]);
        let cr = a.perp_dot(b);
        area2 += cr;
        cen += cr * (a + b);
    }
    let centroid = cen / (3.0 * area2);
    let rel: Vec<Vec2> = raw.iter().map(|&p| p - centroid).collect();
    let got = polygon_r3_moment(&rel);
    let want = r3_polar_simpson(&rel, 20_000);
    assert!((got - want).abs() < 1e-10 * want, "{got} vs {want}");

    // A triangle about one of its vertices (edges through the origin): the
    // right isosceles triangle (0,0), (a,0), (a,a) gives a^5/5 ∫_0^{π/4} sec^5.
    let a = 2.0;
    let tri = [Vec2::ZERO, Vec2::new(a, 0.0), Vec2::new(a, a)];
    let want = a.powi(5) / 5.0 * int_sec5(PI / 4.0);
    assert!((polygon_r3_moment(&tri) - want).abs() < 1e-14 * want);

    // Degenerate input.
    assert_eq!(polygon_r3_moment(&[]), 0.0);
    assert_eq!(polygon_r3_moment(&[Vec2::X, Vec2::Y]), 0.0);
}

// ---------------------------------------------------------------------------
// (7) Serde.

fn everything() -> Forcing {
    Forcing {
        wind: VelocityField::TimeSeries {
            times_s: vec![0.0, 3600.0, 7200.0],
            values: vec![
                Vec2::new(10.0, 0.0),
                Vec2::new(5.0, 5.0),
                Vec2::new(-2.5, 0.25),
            ],
        }
        .scaled(Envelope {
            times_s: vec![0.0, 100.0],
            factors: vec![0.0, 1.0],
        }),
        current: VelocityField::Gyre {
            center_m: Vec2::new(5000.0, -2500.0),
            core_radius_m: 10_000.0,
            max_speed_m_per_s: 0.125,
        },
        air: DragParameters {
            relative_to_ice: true,
            ..DragParameters::air()
        },
        ocean: DragParameters {
            turning_angle_deg: 25.0,
            ..DragParameters::ocean()
        },
        coriolis: Coriolis::LatitudeDeg(75.0),
        sea_surface_tilt: false,
        rotational_drag: true,
        sea_surface_height: None,
    }
}

#[test]
fn validate_rejects_bad_parameters() {
    assert!(everything().validate().is_ok());
    let cases = [
        Forcing {
            coriolis: Coriolis::LatitudeDeg(91.0),
            ..Forcing::default()
        },
        Forcing {
            ocean: DragParameters {
                turning_angle_deg: 90.0,
                ..DragParameters::ocean()
            },
            ..Forcing::default()
        },
        Forcing {
            air: DragParameters {
                drag_coefficient: -1e-3,
                ..DragParameters::air()
            },
            ..Forcing::default()
        },
        Forcing {
            wind: VelocityField::Uniform(Vec2::new(f64::NAN, 0.0)),
            ..Forcing::default()
        },
    ];
    for f in cases {
        assert!(
            matches!(f.validate(), Err(DemError::InvalidParameter { .. })),
            "{f:?}"
        );
    }
    // No steady state without ocean drag.
    let no_ocean = DragParameters {
        drag_coefficient: 0.0,
        ..DragParameters::ocean()
    };
    assert!(free_drift_velocity(
        Vec2::X,
        Vec2::ZERO,
        &DragParameters::air(),
        &no_ocean,
        0.0,
        RHO_ICE,
        true
    )
    .is_err());
}

// ---------------------------------------------------------------------------
// No allocation in the per-floe evaluation.

#[test]
fn force_and_torque_does_not_allocate() {
    let forcing = everything();
    let mut s = floe(1.0);
    let before = allocations();
    let mut acc = 0.0;
    for k in 0..20_000 {
        s.position = Vec2::new(k as f64, -0.5 * k as f64);
        s.velocity = Vec2::new(0.1, 0.05 * (k % 7) as f64);
        s.angular_velocity = 1e-5 * (k % 11) as f64 - 5e-5;
        let (f, t) = forcing.force_and_torque(0.37 * k as f64, &s);
        acc += f.x + f.y + t;
    }
    let after = allocations();
    assert!(acc.is_finite());
    assert_eq!(after - before, 0, "allocations in 20 000 evaluations");
}

#[test]
fn the_force_rates_are_the_derivatives_of_the_force() {
    // Every velocity-dependent term at once: ocean and air drag relative to
    // the ice with turning angles of both signs, Coriolis, tilt, rotational
    // drag in a sheared current; rates against central differences.
    let forcing = Forcing {
        wind: VelocityField::Uniform(Vec2::new(8.0, -3.0)),
        current: VelocityField::LinearShear {
            y_min_m: 0.0,
            y_max_m: 5000.0,
            velocity_at_y_min_m_per_s: Vec2::new(0.1, 0.05),
            velocity_at_y_max_m_per_s: Vec2::new(0.2, 0.05),
        },
        air: DragParameters {
            relative_to_ice: true,
            turning_angle_deg: -10.0,
            ..DragParameters::air()
        },
        ocean: DragParameters {
            turning_angle_deg: 25.0,
            ..DragParameters::ocean()
        },
        coriolis: Coriolis::LatitudeDeg(75.0),
        ..Forcing::default()
    };
    let mut state = floe(1.5);
    state.position = Vec2::new(300.0, 2000.0);
    state.velocity = Vec2::new(0.23, -0.11);
    state.angular_velocity = 3e-5;
    let (_, _, rates) = forcing.force_torque_and_rates(0.0, &state);
    let h = 1e-6;
    for j in 0..2 {
        let at = |dv: f64| {
            let mut s = state;
            if j == 0 {
                s.velocity.x += dv;
            } else {
                s.velocity.y += dv;
            }
            forcing.force_and_torque(0.0, &s).0
        };
        let d = (at(h) - at(-h)) / (2.0 * h);
        for (i, fd) in [d.x, d.y].into_iter().enumerate() {
            let analytic = rates.force_per_velocity[i][j];
            assert!(
                (analytic - fd).abs() < 1e-6 * analytic.abs().max(1.0),
                "dF{i}/du{j}: {analytic} vs {fd}"
            );
        }
    }
    let spin = |dw: f64| {
        let mut s = state;
        s.angular_velocity += dw;
        forcing.force_and_torque(0.0, &s).1
    };
    let hw = 1e-9;
    let fd = (spin(hw) - spin(-hw)) / (2.0 * hw);
    let analytic = rates.torque_per_angular_velocity;
    assert!(
        (analytic - fd).abs() < 1e-6 * analytic.abs(),
        "{analytic} vs {fd}"
    );
    assert!(analytic < 0.0, "rotational drag resists spin");
}
