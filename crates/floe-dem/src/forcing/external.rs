//! The forcing as the engine calls it: a force and a torque on each free
//! floe at each step, from wind, ocean, Coriolis or anything else.

use crate::floes::FloeColumns;
use crate::forcing::gridded::ForcingFailure;
use crate::forcing::{FloeDynamics, Forcing};
use crate::Vec2;

/// How a floe's external force and torque change with its own velocity
/// and angular velocity: what makes the second half kick implicit in them
/// (second order in time). Zero: explicit.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ForceRates {
    /// `∂F/∂u`, N s/m, row by row: `[[∂F_x/∂u_x, ∂F_x/∂u_y], [∂F_y/∂u_x,
    /// ∂F_y/∂u_y]]`.
    pub force_per_velocity: [[f64; 2]; 2],
    /// `∂T/∂ω`, N m s.
    pub torque_per_angular_velocity: f64,
}

impl ForceRates {
    /// No dependence on the floe's motion.
    pub const ZERO: ForceRates = ForceRates {
        force_per_velocity: [[0.0; 2]; 2],
        torque_per_angular_velocity: 0.0,
    };
}

/// Forces on floes from outside the floe assembly (wind, ocean, Coriolis).
/// Called for every free floe once per step, from several threads.
pub trait ExternalForces: Sync {
    /// Called once before the forces of each step are gathered, at the
    /// time they are evaluated, from one thread: a forcing read from files
    /// loads the time slices it needs here and checks the floes are on its
    /// grid. The default does nothing.
    ///
    /// # Errors
    /// Why the forcing cannot be evaluated (the world records the first
    /// failure; the run loop stops on it).
    fn prepare(&mut self, _t_s: f64, _floes: &FloeColumns) -> Result<(), ForcingFailure> {
        Ok(())
    }

    /// Force (N) and torque (N m) on floe `i` at time `t_s`.
    fn force_and_torque(&self, t_s: f64, floes: &FloeColumns, i: usize) -> (Vec2, f64);

    /// Force, torque and their rates with the floe's velocity (the step
    /// calls this one). The default has zero rates: a forcing that depends
    /// on the floe's velocity is then first order in time, as an explicit
    /// force is.
    fn force_torque_and_rates(
        &self,
        t_s: f64,
        floes: &FloeColumns,
        i: usize,
    ) -> (Vec2, f64, ForceRates) {
        let (force, torque) = self.force_and_torque(t_s, floes, i);
        (force, torque, ForceRates::ZERO)
    }
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
    fn prepare(&mut self, t_s: f64, floes: &FloeColumns) -> Result<(), ForcingFailure> {
        Forcing::prepare(self, t_s, floes)
    }

    fn force_and_torque(&self, t_s: f64, floes: &FloeColumns, i: usize) -> (Vec2, f64) {
        Forcing::force_and_torque(self, t_s, &dynamics(floes, i))
    }

    fn force_torque_and_rates(
        &self,
        t_s: f64,
        floes: &FloeColumns,
        i: usize,
    ) -> (Vec2, f64, ForceRates) {
        Forcing::force_torque_and_rates(self, t_s, &dynamics(floes, i))
    }
}

fn dynamics(floes: &FloeColumns, i: usize) -> FloeDynamics {
    FloeDynamics {
        position: floes.position[i],
        velocity: floes.velocity[i],
        angular_velocity: floes.angular_velocity[i],
        area_m2: floes.area_m2[i],
        mass_kg: floes.mass_kg[i],
        r3_moment_m5: floes.r3_moment_m5[i],
    }
}
