//! Boundary motion, the first thing a step does: each scheduled floe's
//! velocity and rotation rate become their mean over the coming step
//! ([`MotionSchedule::mean_velocity`](crate::motion_schedule::MotionSchedule::mean_velocity)),
//! so the drift moves it by the schedule's displacement. And the load
//! points' springs, added to the gathered forces.

use crate::floes::{Floes, Motion};
use crate::load_point::LoadPoint;
use crate::motion_schedule::ScheduledMotion;
use crate::periodicity::Periodicity;
use crate::stress_control::StressControl;
use crate::Vec2;

/// Sets the velocities of the floes in `schedules` for the step from
/// `t0_s` to `t0_s + dt_s`.
pub(crate) fn apply(floes: &mut Floes, schedules: &[ScheduledMotion], t0_s: f64, dt_s: f64) {
    for s in schedules {
        // WorldState::validate and the world's edits keep every id present.
        if let Some(h) = floes.handle_of(s.floe_id) {
            let (velocity, angular_velocity) = s.schedule.mean_velocity(t0_s, dt_s);
            floes.set_motion(h, Motion::Prescribed { velocity });
            floes.set_velocity(h, velocity, angular_velocity);
        }
    }
}

/// Adds each load point's spring force at time `t_s` to its floe's total
/// and external force, in floe-id order.
pub(crate) fn add_load_point_forces(
    floes: &Floes,
    load_points: &[LoadPoint],
    periodicity: Periodicity,
    t_s: f64,
    (force, external_force): (&mut [Vec2], &mut [Vec2]),
) {
    for l in load_points {
        // WorldState::validate and the world's edits keep every id present.
        if let Some(h) = floes.handle_of(l.floe_id) {
            let f = l.force(t_s, floes.position[h], periodicity);
            force[h] += f;
            external_force[h] += f;
        }
    }
}

/// Sets the normal velocity of each stress-controlled wall's pieces for
/// the step of `dt_s` from the stress the last force gathering measured on
/// it (`force`, per floe), keeping their velocity along the wall; a servo
/// wall's state moves on.
pub(crate) fn apply_stress_controls(
    floes: &mut Floes,
    force: &[Vec2],
    controls: &mut [StressControl],
    dt_s: f64,
) {
    for c in controls {
        let stress = wall_stress(floes, force, c);
        let v_n = c.advance(stress, dt_s);
        for &id in &c.floe_ids {
            if let Some(h) = floes.handle_of(id) {
                let velocity = with_normal_speed(floes.velocity[h], c.inward_normal, v_n);
                floes.set_motion(h, Motion::Prescribed { velocity });
                let w = floes.angular_velocity[h];
                floes.set_velocity(h, velocity, w);
            }
        }
    }
}

/// The stress the forces on control `c`'s pieces (`force`, per floe of
/// `floes`) make on it, N/m.
pub(crate) fn wall_stress(floes: &Floes, force: &[Vec2], c: &StressControl) -> f64 {
    c.stress(|id| floes.handle_of(id).map_or(Vec2::ZERO, |h| force[h]))
}

/// Velocity `v` with its component along the unit normal `n` made `v_n`.
#[inline]
pub(crate) fn with_normal_speed(v: Vec2, n: Vec2, v_n: f64) -> Vec2 {
    v - n * v.dot(n) + n * v_n
}
