//! What a distributed run (floe-parallel) needs of a world: which floes
//! are ghosts, and a floe's motion and forces to copy between processes.

use super::World;
use crate::error::DemError;
use crate::forcing::ExternalForces;
use crate::Vec2;

/// A floe's motion and the forces on it at the end of a step: what a
/// ghost copies from its owner ([`World::set_kinematics`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Centroid position, m.
    pub position: Vec2,
    /// Orientation, rad.
    pub angle: f64,
    /// Centroid velocity, m/s.
    pub velocity: Vec2,
    /// Angular velocity, rad/s.
    pub angular_velocity: f64,
    /// Total force, N.
    pub force: Vec2,
    /// Total torque, N m.
    pub torque: f64,
}

impl<F: ExternalForces> World<F> {
    /// Marks which floes are ghosts: copies of floes another process owns,
    /// stepped here for the contacts of this process's floes but left out
    /// of the energy sums (`ghost`, one per floe; empty: none). Adding or
    /// removing a floe clears the marks.
    pub fn set_ghosts(&mut self, ghost: Vec<bool>) -> Result<(), DemError> {
        if !ghost.is_empty() && ghost.len() != self.state.floes.len() {
            return Err(DemError::InvalidParameter {
                name: "ghost",
                value: ghost.len() as f64,
                reason: "one mark per floe expected",
            });
        }
        self.pipeline.ghost = ghost;
        Ok(())
    }

    /// Per floe, whether it is a ghost ([`World::set_ghosts`]; empty: none is).
    pub fn ghosts(&self) -> &[bool] {
        &self.pipeline.ghost
    }

    /// Floe `h`'s motion and the forces the next drift reads.
    pub fn kinematics(&self, h: usize) -> Kinematics {
        let s = &self.state;
        let f = s.floes.columns();
        Kinematics {
            position: f.position[h],
            angle: f.angle[h],
            velocity: f.velocity[h],
            angular_velocity: f.angular_velocity[h],
            force: s.force[h],
            torque: s.torque[h],
        }
    }

    /// Overwrites floe `h`'s motion and forces between steps with its
    /// owner's ([`World::kinematics`] there): a ghost then drifts as the
    /// owner's floe does. Refused inside a step.
    pub fn set_kinematics(&mut self, h: usize, k: &Kinematics) -> Result<(), DemError> {
        self.between_steps(self.state.floes.columns().id[h])?;
        let s = &mut self.state;
        let f = s.floes.columns_mut();
        f.position[h] = k.position;
        f.angle[h] = k.angle;
        f.velocity[h] = k.velocity;
        f.angular_velocity[h] = k.angular_velocity;
        s.force[h] = k.force;
        s.torque[h] = k.torque;
        let p = &mut self.pipeline;
        if p.trig.len() == s.floes.len() {
            p.trig[h] = k.angle.sin_cos();
        }
        p.moved_far |=
            p.broad_phase
                .moved_beyond_allowance(h, k.position, k.angle, self.periodicity);
        Ok(())
    }
}
