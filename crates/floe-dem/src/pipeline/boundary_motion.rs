//! Boundary motion, the first thing a step does: each scheduled floe's
//! velocity and rotation rate become their mean over the coming step
//! ([`MotionSchedule::mean_velocity`](crate::motion_schedule::MotionSchedule::mean_velocity)),
//! so the drift moves it by the schedule's displacement.

use crate::floes::{Floes, Motion};
use crate::motion_schedule::ScheduledMotion;

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
