//! The forcing as the engine calls it: a force and a torque on each free
//! floe at each step, from wind, ocean, Coriolis or anything else.

use crate::floes::FloeColumns;
use crate::forcing::{FloeDynamics, Forcing};
use crate::Vec2;

/// Forces on floes from outside the floe assembly (wind, ocean, Coriolis).
/// Called for every free floe once per step, from several threads.
pub trait ExternalForces: Sync {
    /// Force (N) and torque (N m) on floe `i` at time `t_s`.
    fn force_and_torque(&self, t_s: f64, floes: &FloeColumns, i: usize) -> (Vec2, f64);
}

/// No external forcing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoForcing;

impl ExternalForces for NoForcing {
    fn force_and_torque(&self, _t: f64, _floes: &FloeColumns, _i: usize) -> (Vec2, f64) {
        (Vec2::ZERO, 0.0)
    }
}

impl ExternalForces for Forcing {
    fn force_and_torque(&self, t_s: f64, floes: &FloeColumns, i: usize) -> (Vec2, f64) {
        let dynamics = FloeDynamics {
            position: floes.position[i],
            velocity: floes.velocity[i],
            angular_velocity: floes.angular_velocity[i],
            area_m2: floes.area_m2[i],
            mass_kg: floes.mass_kg[i],
            r3_moment_m5: floes.r3_moment_m5[i],
        };
        Forcing::force_and_torque(self, t_s, &dynamics)
    }
}
