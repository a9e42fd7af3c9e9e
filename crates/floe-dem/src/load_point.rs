//! A load point: a free floe driven through a linear spring whose far end
//! moves on a schedule, the apparatus of the paper's experiments (a lab
//! stiffness of 20 MN/m, a tank one of 2 MN/m) acting on a DEM block.
//!
//! The spring joins the load point to the floe's centroid with zero rest
//! length, `F = k (x_lp(t) - x)`, with `x_lp(t) = anchor + travel(t)` from
//! the schedule; across a periodic axis the nearest image of the load point
//! counts. It is an external force: it enters the force gathering
//! (`pipeline/boundary_motion.rs`) and its work is counted as forcing work.
//! Load points are part of the [`WorldState`](crate::state::WorldState) and
//! its checkpoint.

use crate::error::DemError;
use crate::motion_schedule::MotionSchedule;
use crate::periodicity::Periodicity;
use crate::Vec2;

/// A spring from a moving point to a free floe's centroid.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LoadPoint {
    /// Global id of the floe it drives (a free one).
    pub floe_id: u64,
    /// Spring stiffness, N/m (> 0).
    pub stiffness_n_per_m: f64,
    /// Where the load point is at `t = 0`, m.
    pub anchor: Vec2,
    /// The load point's motion (translation only: the angular velocities
    /// of its segments are not used).
    pub schedule: MotionSchedule,
}

impl LoadPoint {
    /// A load point for floe `floe_id`; refuses a stiffness that is not a
    /// finite number > 0 or an anchor that is not finite.
    pub fn new(
        floe_id: u64,
        stiffness_n_per_m: f64,
        anchor: Vec2,
        schedule: MotionSchedule,
    ) -> Result<Self, DemError> {
        if !(stiffness_n_per_m.is_finite() && stiffness_n_per_m > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "stiffness_n_per_m",
                value: stiffness_n_per_m,
                reason: "must be a finite number > 0",
            });
        }
        if !anchor.is_finite() {
            return Err(DemError::InvalidParameter {
                name: "anchor",
                value: anchor.x,
                reason: "must be finite",
            });
        }
        Ok(LoadPoint {
            floe_id,
            stiffness_n_per_m,
            anchor,
            schedule,
        })
    }

    /// Where the load point is at time `t_s`, m.
    pub fn position(&self, t_s: f64) -> Vec2 {
        self.anchor + self.schedule.travel_to(t_s).0
    }

    /// The spring's force on a floe whose centroid is at `position`, at
    /// time `t_s`, N.
    pub fn force(&self, t_s: f64, position: Vec2, periodicity: Periodicity) -> Vec2 {
        let lp = self.position(t_s);
        let lp = lp + periodicity.nearest_image(position, lp);
        (lp - position) * self.stiffness_n_per_m
    }
}
