//! Energy accounting: the work of forcing and walls and the dissipation of
//! friction and dashpots over a step, summed into the
//! [`EnergyLedger`].
//!
//! Every sum runs over fixed blocks (`ENERGY_CHUNK`) in parallel, then
//! over the blocks in order: the same sums for any thread count. The
//! contacts' powers depend on the contact list alone (not on how the
//! narrow phase cut its work), so a resumed run sums them as the
//! uninterrupted one did.

use rayon::prelude::*;

use crate::contact_kernel::force_and_torques;
use crate::contacts::ContactRecord;
use crate::energy_ledger::EnergyLedger;
use crate::floes::FloeColumns;
use crate::Vec2;

/// Contacts (or floes) per block of the energy sums.
pub(crate) const ENERGY_CHUNK: usize = 4096;

/// Power of a set of contacts over a step.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct ContactPower {
    /// Dissipated by friction, W.
    friction_w: f64,
    /// Dissipated by normal damping, W.
    damping_w: f64,
    /// Put in by walls (floes with prescribed motion), W.
    boundary_w: f64,
}

impl ContactPower {
    /// Adds a contact whose step is complete.
    #[inline]
    fn add(&mut self, c: &ContactRecord, f: &FloeColumns) {
        self.friction_w += c.friction_power_w;
        self.damping_w += c.damping_power_w;
        // Work done by a wall on the floe it touches: the force the wall
        // exerts (the opposite of the force on it) times its velocity.
        // Only wall contacts need the force.
        let (a, b) = (c.a as usize, c.b as usize);
        if f.is_free(a) && f.is_free(b) {
            return;
        }
        let (fb, _, _) = force_and_torques(c, f.position[a], f.position[b] + c.image_offset);
        if !f.is_free(a) {
            self.boundary_w += fb.dot(f.velocity[a]);
        }
        if !f.is_free(b) {
            self.boundary_w += (-fb).dot(f.velocity[b]);
        }
    }
}

/// What the accounting keeps between the stages of a step (reused every step).
#[derive(Debug, Default)]
pub(crate) struct EnergyAccounting {
    /// Per block of contacts, the sums of their powers.
    contact_partials: Vec<ContactPower>,
    /// Per block of floes, the power of the external forces.
    pub(crate) forcing_partials: Vec<f64>,
    /// The external forces at the start of the step, N, for the work
    /// integral (trapezoidal in the force).
    pub(crate) previous_external_force: Vec<Vec2>,
    /// The external torques at the start of the step, N m.
    pub(crate) previous_external_torque: Vec<f64>,
}

impl EnergyAccounting {
    /// Keeps this step's starting external forces: swaps them with the
    /// buffers the force gathering fills next.
    pub(crate) fn begin_step(
        &mut self,
        external_force: &mut Vec<Vec2>,
        external_torque: &mut Vec<f64>,
    ) {
        let n = external_force.len();
        self.previous_external_force.resize(n, Vec2::ZERO);
        self.previous_external_torque.resize(n, 0.0);
        std::mem::swap(external_force, &mut self.previous_external_force);
        std::mem::swap(external_torque, &mut self.previous_external_torque);
    }

    /// Sums the contacts' powers over fixed blocks of the list, in
    /// parallel. The velocities it reads are the walls', which the kick
    /// leaves alone, so it may run beside the force gathering.
    pub(crate) fn sum_contact_power(&mut self, contacts: &[ContactRecord], f: &FloeColumns) {
        contacts
            .par_chunks(ENERGY_CHUNK)
            .map(|block| {
                let mut power = ContactPower::default();
                for c in block {
                    power.add(c, f);
                }
                power
            })
            .collect_into_vec(&mut self.contact_partials);
    }

    /// Adds the step's work and dissipation to `ledger`, block by block in
    /// order: the forcing power the kick summed, then the contacts'.
    pub(crate) fn finish_step(&self, ledger: &mut EnergyLedger, dt: f64) {
        for p in &self.forcing_partials {
            ledger.forcing_work_j += dt * p;
        }
        let mut power = ContactPower::default();
        for p in &self.contact_partials {
            power.friction_w += p.friction_w;
            power.damping_w += p.damping_w;
            power.boundary_w += p.boundary_w;
        }
        ledger.friction_dissipation_j += dt * power.friction_w;
        ledger.damping_dissipation_j += dt * power.damping_w;
        ledger.boundary_work_j += dt * power.boundary_w;
    }
}

/// Power of the external forcing on a free floe over the step, W:
/// trapezoidal in the force (`previous` at the start, `now` at the end),
/// with the half-step velocity, as the contacts' powers are. With the
/// velocity after the kick instead, each step would add `dt^2/2m F_ext .
/// F`, a bias that grows with the run (a spring-driven block gained 30 %
/// of its kinetic energy in 10 s); with the half-step velocity the
/// difference from the kinetic energy's change telescopes and stays
/// `O(dt^2)` (`tests/dem_load_point.rs`).
#[inline(always)]
pub(crate) fn forcing_power(
    (previous_force, previous_torque): (Vec2, f64),
    (force, torque): (Vec2, f64),
    velocity: Vec2,
    angular_velocity: f64,
) -> f64 {
    let mean_f = 0.5 * (previous_force + force);
    let mean_t = 0.5 * (previous_torque + torque);
    mean_f.dot(velocity) + mean_t * angular_velocity
}
