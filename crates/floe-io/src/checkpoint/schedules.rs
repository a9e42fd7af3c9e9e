//! Motion schedules of prescribed floes (from version 4) and load points
//! on free floes (from version 5); older versions read as none.

use super::bytes::{ReadResult, Reader, Writer};
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::{MotionSchedule, MotionSegment, ScheduledMotion};

/// The segments: per segment its duration, start and end velocity, start
/// and end angular velocity.
fn write_segments(w: &mut Writer, schedule: &MotionSchedule) {
    let segments = schedule.segments();
    w.len(segments.len());
    for g in segments {
        let MotionSegment {
            duration_s,
            velocity_start,
            velocity_end,
            angular_velocity_start,
            angular_velocity_end,
        } = *g;
        w.f64(duration_s);
        w.v2(velocity_start);
        w.v2(velocity_end);
        w.f64(angular_velocity_start);
        w.f64(angular_velocity_end);
    }
}

/// [`write_segments`], checked as the schedule of floe `floe_id`.
fn read_segments(r: &mut Reader, floe_id: u64) -> ReadResult<MotionSchedule> {
    let segments = r.vec(56, |r| {
        Ok(MotionSegment {
            duration_s: r.f64()?,
            velocity_start: r.v2()?,
            velocity_end: r.v2()?,
            angular_velocity_start: r.f64()?,
            angular_velocity_end: r.f64()?,
        })
    })?;
    MotionSchedule::new(segments).map_err(|e| format!("the schedule of floe {floe_id}: {e}"))
}

/// Per scheduled floe its id, then its segments.
pub(super) fn write_schedules(w: &mut Writer, schedules: &[ScheduledMotion]) {
    w.len(schedules.len());
    for s in schedules {
        let ScheduledMotion { floe_id, schedule } = s;
        w.u64(*floe_id);
        write_segments(w, schedule);
    }
}

/// [`write_schedules`]; none before version 4.
pub(super) fn read_schedules(r: &mut Reader) -> ReadResult<Vec<ScheduledMotion>> {
    if r.version < 4 {
        return Ok(Vec::new());
    }
    r.vec(16, |r| {
        let floe_id = r.u64()?;
        let schedule = read_segments(r, floe_id)?;
        Ok(ScheduledMotion { floe_id, schedule })
    })
}

/// Per load point its floe's id, stiffness, anchor, then the anchor's
/// segments.
pub(super) fn write_load_points(w: &mut Writer, load_points: &[LoadPoint]) {
    w.len(load_points.len());
    for l in load_points {
        let LoadPoint {
            floe_id,
            stiffness_n_per_m,
            anchor,
            schedule,
        } = l;
        w.u64(*floe_id);
        w.f64(*stiffness_n_per_m);
        w.v2(*anchor);
        write_segments(w, schedule);
    }
}

/// [`write_load_points`]; none before version 5.
pub(super) fn read_load_points(r: &mut Reader) -> ReadResult<Vec<LoadPoint>> {
    if r.version < 5 {
        return Ok(Vec::new());
    }
    r.vec(40, |r| {
        let floe_id = r.u64()?;
        let (k, anchor) = (r.f64()?, r.v2()?);
        let schedule = read_segments(r, floe_id)?;
        LoadPoint::new(floe_id, k, anchor, schedule)
            .map_err(|e| format!("the load point of floe {floe_id}: {e}"))
    })
}
