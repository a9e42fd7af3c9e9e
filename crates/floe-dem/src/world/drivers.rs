//! Driven floes: prescribed floes on a motion schedule, free floes pulled
//! by a load point, walls that hold a normal stress.

use super::World;
use crate::error::DemError;
use crate::forcing::ExternalForces;
use crate::load_point::LoadPoint;
use crate::motion_schedule::{MotionSchedule, ScheduledMotion};
use crate::stress_control::StressControl;
use crate::Vec2;

impl<F: ExternalForces> World<F> {
    /// Makes prescribed floe `id` follow `schedule` from the next step on
    /// (replacing any schedule it had). The schedule's time is the world's
    /// clock: `t = 0` at the start of the run.
    pub fn set_schedule(&mut self, id: u64, schedule: MotionSchedule) -> Result<(), DemError> {
        let h = self.handle(id)?;
        if self.state.floes.is_free(h) {
            return Err(DemError::FloeEdit {
                id,
                reason: "only a prescribed floe follows a motion schedule".into(),
            });
        }
        let schedules = &mut self.state.schedules;
        let entry = ScheduledMotion {
            floe_id: id,
            schedule,
        };
        match schedules.binary_search_by_key(&id, |s| s.floe_id) {
            Ok(k) => schedules[k] = entry,
            Err(k) => schedules.insert(k, entry),
        }
        Ok(())
    }

    /// The prescribed floes that follow a schedule, sorted by floe id.
    pub fn schedules(&self) -> &[ScheduledMotion] {
        &self.state.schedules
    }

    /// Drives free floe `load_point.floe_id` through `load_point`'s spring
    /// (replacing any load point it had). The spring's force at the
    /// current time joins the floe's force at once, so the next half kick
    /// feels it.
    pub fn set_load_point(&mut self, load_point: LoadPoint) -> Result<(), DemError> {
        let id = load_point.floe_id;
        let h = self.handle(id)?;
        if !self.state.floes.is_free(h) {
            return Err(DemError::FloeEdit {
                id,
                reason: "a load point drives a free floe".into(),
            });
        }
        let s = &mut self.state;
        let new = load_point.force(s.time_s, s.floes.position[h], self.periodicity);
        let list = &mut s.load_points;
        let old = match list.binary_search_by_key(&id, |l| l.floe_id) {
            Ok(k) => {
                let old = list[k].force(s.time_s, s.floes.position[h], self.periodicity);
                list[k] = load_point;
                old
            }
            Err(k) => {
                list.insert(k, load_point);
                Vec2::ZERO
            }
        };
        s.force[h] += new - old;
        s.external_force[h] += new - old;
        Ok(())
    }

    /// The load points, sorted by floe id.
    pub fn load_points(&self) -> &[LoadPoint] {
        &self.state.load_points
    }

    /// Makes the prescribed floes of `control` (a wall) hold its normal
    /// stress from the next step on; a floe already in a control is
    /// refused.
    pub fn add_stress_control(&mut self, control: StressControl) -> Result<(), DemError> {
        for &id in &control.floe_ids {
            let h = self.handle(id)?;
            if self.state.floes.is_free(h) {
                return Err(DemError::FloeEdit {
                    id,
                    reason: "a stress-controlled wall is made of prescribed floes".into(),
                });
            }
            if self.stress_control_of(id).is_some() {
                return Err(DemError::FloeEdit {
                    id,
                    reason: "already in a stress-controlled wall".into(),
                });
            }
        }
        self.state.stress_controls.push(control);
        Ok(())
    }

    /// The stress-controlled walls.
    pub fn stress_controls(&self) -> &[StressControl] {
        &self.state.stress_controls
    }

    /// The stress control floe `id` belongs to, if any.
    fn stress_control_of(&self, id: u64) -> Option<usize> {
        self.state
            .stress_controls
            .iter()
            .position(|c| c.floe_ids.binary_search(&id).is_ok())
    }

    /// Takes floe `id` out of its stress-controlled wall; a wall left with
    /// no floe goes.
    pub(super) fn leave_stress_control(&mut self, id: u64) {
        let controls = &mut self.state.stress_controls;
        for c in controls.iter_mut() {
            c.floe_ids.retain(|&f| f != id);
        }
        controls.retain(|c| !c.floe_ids.is_empty());
    }
}
