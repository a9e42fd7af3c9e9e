//! Motion schedules: a prescribed floe (a wall, a pusher, a fixed block)
//! whose velocity and rotation rate follow piecewise-linear segments in
//! time: constant speeds, ramps, holds (zero), reversals.
//!
//! The boundary-motion stage (`pipeline/boundary_motion.rs`) sets
//! each scheduled floe's velocity, at the start of every step, to its mean
//! over the step, so the drift moves it by exactly the schedule's
//! displacement (to the rounding of the sum): a step that straddles the end
//! of a segment moves the floe as the two segments say. Schedules are part
//! of the [`WorldState`](crate::state::WorldState) and its checkpoint, so
//! a run resumed in the middle of one continues bitwise.

use crate::error::DemError;
use crate::Vec2;

/// One piece of a schedule: over `duration_s` the velocity and the angular
/// velocity go linearly from their start to their end values (equal: a
/// constant speed; zero: a hold).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MotionSegment {
    /// How long the segment lasts, s (> 0).
    pub duration_s: f64,
    /// Velocity at the segment's start, m/s.
    pub velocity_start: Vec2,
    /// Velocity at its end, m/s.
    pub velocity_end: Vec2,
    /// Angular velocity at the start, rad/s (counter-clockwise).
    pub angular_velocity_start: f64,
    /// Angular velocity at the end, rad/s.
    pub angular_velocity_end: f64,
}

impl MotionSegment {
    /// A segment at constant velocity, without rotation.
    pub fn constant(duration_s: f64, velocity: Vec2) -> Self {
        Self::ramp(duration_s, velocity, velocity)
    }

    /// A segment whose velocity goes linearly from `from` to `to`.
    pub fn ramp(duration_s: f64, from: Vec2, to: Vec2) -> Self {
        MotionSegment {
            duration_s,
            velocity_start: from,
            velocity_end: to,
            angular_velocity_start: 0.0,
            angular_velocity_end: 0.0,
        }
    }

    /// Displacement and rotation over the first `t` seconds of the segment
    /// (`0 <= t <= duration_s`).
    fn travel(&self, t: f64) -> (Vec2, f64) {
        let f = t / self.duration_s;
        // Integral of a linear ramp: t (v0 + (v1 - v0) t / (2 T)).
        let v = self.velocity_start + (self.velocity_end - self.velocity_start) * (0.5 * f);
        let w = self.angular_velocity_start
            + (self.angular_velocity_end - self.angular_velocity_start) * (0.5 * f);
        (v * t, w * t)
    }
}

/// A floe's piecewise-linear velocity from `t = 0`; after the last segment
/// its end velocity continues.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MotionSchedule {
    segments: Vec<MotionSegment>,
    /// Start time of each segment, s (`starts[0] = 0`).
    starts: Vec<f64>,
    /// Displacement and rotation at each segment's start (summed in order).
    travel_at_start: Vec<(Vec2, f64)>,
}

impl MotionSchedule {
    /// A schedule of `segments` (at least one), each of finite velocities
    /// and a finite duration > 0.
    pub fn new(segments: Vec<MotionSegment>) -> Result<Self, DemError> {
        if segments.is_empty() {
            return Err(DemError::InvalidParameter {
                name: "motion schedule",
                value: 0.0,
                reason: "needs at least one segment",
            });
        }
        let mut starts = Vec::with_capacity(segments.len());
        let mut travel_at_start = Vec::with_capacity(segments.len());
        let (mut x, mut a) = (Vec2::ZERO, 0.0);
        let mut t = 0.0;
        for s in &segments {
            let finite = s.velocity_start.is_finite()
                && s.velocity_end.is_finite()
                && s.angular_velocity_start.is_finite()
                && s.angular_velocity_end.is_finite();
            if !(s.duration_s.is_finite() && s.duration_s > 0.0 && finite) {
                return Err(DemError::InvalidParameter {
                    name: "motion segment",
                    value: s.duration_s,
                    reason: "needs a finite duration > 0 and finite velocities",
                });
            }
            starts.push(t);
            travel_at_start.push((x, a));
            t += s.duration_s;
            let (dx, da) = s.travel(s.duration_s);
            x += dx;
            a += da;
        }
        Ok(MotionSchedule {
            segments,
            starts,
            travel_at_start,
        })
    }

    /// The segments, in order.
    pub fn segments(&self) -> &[MotionSegment] {
        &self.segments
    }

    /// When the last segment ends, s.
    pub fn end_s(&self) -> f64 {
        let last = self.segments.len() - 1;
        self.starts[last] + self.segments[last].duration_s
    }

    /// Velocity (m/s) and angular velocity (rad/s) at time `t_s`.
    pub fn velocity_at(&self, t_s: f64) -> (Vec2, f64) {
        let k = self.segment_at(t_s);
        let s = &self.segments[k];
        let f = ((t_s - self.starts[k]) / s.duration_s).clamp(0.0, 1.0);
        (
            s.velocity_start + (s.velocity_end - s.velocity_start) * f,
            s.angular_velocity_start + (s.angular_velocity_end - s.angular_velocity_start) * f,
        )
    }

    /// Displacement (m) and rotation (rad) from time 0 to `t_s` (>= 0).
    pub fn travel_to(&self, t_s: f64) -> (Vec2, f64) {
        let k = self.segment_at(t_s);
        let (x, a) = self.travel_at_start[k];
        let s = &self.segments[k];
        let into = t_s - self.starts[k];
        let (dx, da) = if into <= s.duration_s {
            s.travel(into.max(0.0))
        } else {
            // Past the end: the last end velocity continues.
            let (dx, da) = s.travel(s.duration_s);
            let extra = into - s.duration_s;
            (
                dx + s.velocity_end * extra,
                da + s.angular_velocity_end * extra,
            )
        };
        (x + dx, a + da)
    }

    /// Mean velocity and angular velocity over `[t0_s, t0_s + dt_s]`: what
    /// moves the floe by the schedule's displacement in one step.
    pub fn mean_velocity(&self, t0_s: f64, dt_s: f64) -> (Vec2, f64) {
        let (k0, t1) = (self.segment_at(t0_s), t0_s + dt_s);
        let end = self.starts[k0] + self.segments[k0].duration_s;
        // Within one segment (or both past the last one's end) the mean of
        // a linear ramp is its midpoint; a step across the last segment's
        // end is not.
        if self.segment_at(t1) == k0 && (t1 <= end || t0_s >= end) {
            return self.velocity_at(t0_s + 0.5 * dt_s);
        }
        let (x0, a0) = self.travel_to(t0_s);
        let (x1, a1) = self.travel_to(t0_s + dt_s);
        ((x1 - x0) / dt_s, (a1 - a0) / dt_s)
    }

    /// The most a floe following this schedule can be from where it
    /// started over `[0, duration_s]`, m: bounded by the integral of its
    /// speed.
    pub fn most_travel_m(&self, duration_s: f64) -> f64 {
        let mut total = 0.0;
        for (s, &start) in self.segments.iter().zip(&self.starts) {
            if start >= duration_s {
                return total;
            }
            let t = s.duration_s.min(duration_s - start);
            total += s.velocity_start.length().max(s.velocity_end.length()) * t;
        }
        let last = self.segments[self.segments.len() - 1];
        total + last.velocity_end.length() * (duration_s - self.end_s()).max(0.0)
    }

    /// The segment in force at `t_s`: the last whose start is at or before
    /// it (the first for `t_s < 0`).
    fn segment_at(&self, t_s: f64) -> usize {
        self.starts.partition_point(|&s| s <= t_s).saturating_sub(1)
    }
}

/// A schedule and the floe that follows it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ScheduledMotion {
    /// Global id of the floe (a prescribed one).
    pub floe_id: u64,
    /// Its schedule.
    pub schedule: MotionSchedule,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 10 s at 1 m/s, a ramp to -1 m/s over 4 s, a 5 s hold, then 2 m/s on.
    fn schedule() -> MotionSchedule {
        let x = |v: f64| Vec2::new(v, 0.0);
        MotionSchedule::new(vec![
            MotionSegment::constant(10.0, x(1.0)),
            MotionSegment::ramp(4.0, x(1.0), x(-1.0)),
            MotionSegment::constant(5.0, Vec2::ZERO),
            MotionSegment::constant(1.0, x(2.0)),
        ])
        .unwrap()
    }

    #[test]
    fn travel_is_the_integral_of_the_piecewise_linear_velocity() {
        let s = schedule();
        let x = |t: f64| s.travel_to(t).0.x;
        // Hand integrals: 10; the ramp crosses zero at 12 s (+1, then -1).
        for (t, expected) in [
            (5.0, 5.0),
            (10.0, 10.0),
            (12.0, 11.0),
            (14.0, 10.0),
            (16.0, 10.0),
            (19.0, 10.0),
            (20.0, 12.0),
            (23.0, 18.0), // past the end: 2 m/s continues
        ] {
            assert!(
                (x(t) - expected).abs() < 1e-12,
                "t {t}: {} vs {expected}",
                x(t)
            );
        }
        assert_eq!(s.end_s(), 20.0);
        assert_eq!(s.velocity_at(13.0).0.x, -0.5);
        assert_eq!(s.velocity_at(25.0).0.x, 2.0);
    }

    #[test]
    fn the_mean_velocity_over_a_step_moves_by_the_schedule_even_across_segments() {
        let s = schedule();
        let dt = 0.7; // steps straddle every boundary somewhere
        let mut x = 0.0;
        let mut t = 0.0;
        for _ in 0..40 {
            x += s.mean_velocity(t, dt).0.x * dt;
            t += dt;
            assert!((x - s.travel_to(t).0.x).abs() < 1e-12, "t {t}");
        }
    }

    #[test]
    fn a_step_across_the_end_of_a_final_ramp_moves_by_the_schedule() {
        let s = MotionSchedule::new(vec![MotionSegment::ramp(
            1.0,
            Vec2::ZERO,
            Vec2::new(1.0, 0.0),
        )])
        .unwrap();
        // 0.9 .. 1.1 s: 0.095 m of ramp then 0.1 m at 1 m/s.
        assert!((s.mean_velocity(0.9, 0.2).0.x - 0.975).abs() < 1e-12);
        // Stepping by the mean velocity, against the hand integral.
        let (mut x, dt) = (0.0, 0.3);
        for k in 0..10 {
            x += s.mean_velocity(k as f64 * dt, dt).0.x * dt;
        }
        let t = 10.0 * dt;
        assert!((x - (0.5 + (t - 1.0))).abs() < 1e-12, "{x}");
    }

    #[test]
    fn bad_segments_are_refused() {
        assert!(MotionSchedule::new(vec![]).is_err());
        for d in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(MotionSchedule::new(vec![MotionSegment::constant(d, Vec2::ZERO)]).is_err());
        }
        let nan = MotionSegment::constant(1.0, Vec2::new(f64::NAN, 0.0));
        assert!(MotionSchedule::new(vec![nan]).is_err());
    }

    #[test]
    fn the_travel_bound_covers_every_displacement() {
        let s = schedule();
        let bound = s.most_travel_m(30.0);
        assert!((bound - (10.0 + 4.0 + 0.0 + 11.0 * 2.0)).abs() < 1e-12);
        for k in 0..300 {
            let t = 0.1 * k as f64;
            assert!(s.travel_to(t).0.length() <= bound + 1e-12);
        }
    }
}
