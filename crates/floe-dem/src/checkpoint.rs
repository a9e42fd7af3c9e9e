//! Checkpoints: the complete state of a [`World`](crate::world::World), from
//! which [`World::resume`](crate::world::World::resume) continues a run
//! bitwise as if it had never stopped.
//!
//! What is *not* in the state comes from the scenario: the contact model,
//! the forcing, the periodicity and `dt`. The broad-phase candidate list is
//! not saved either: it is rebuilt on the first step after a resume, and the
//! contacts found do not depend on when it was built (a candidate list only
//! has to contain every touching pair, and the contact list is sorted by
//! pair).

use crate::contacts::{BrokenContact, ContactRecord};
use crate::error::DemError;
use crate::floes::Floes;
use crate::world::EnergyLedger;
use crate::Vec2;

/// Everything a run needs to continue bitwise from the end of a step.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldState {
    /// The floes, including prescribed ones (walls) and ghosts.
    pub floes: Floes,
    /// Contacts at the end of the step, sorted by `(a, b)`, with their
    /// friction state and integrated energies.
    pub contacts: Vec<ContactRecord>,
    /// Recently broken contacts remembered by the model, sorted by `(a, b)`.
    pub broken: Vec<BrokenContact>,
    /// Simulated time, s.
    pub time_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Energy bookkeeping since the start.
    pub energy: EnergyLedger,
    /// Total force on each floe from the last evaluation, N. Saved rather
    /// than recomputed: it was evaluated at the half-step velocity.
    pub force: Vec<Vec2>,
    /// Total torque on each floe from the last evaluation, N m.
    pub torque: Vec<f64>,
    /// External (forcing) part of `force`, N; the next step's work integral
    /// starts from it.
    pub external_force: Vec<Vec2>,
    /// External part of `torque`, N m.
    pub external_torque: Vec<f64>,
}

impl WorldState {
    /// Checks that the arrays agree in length and the contacts refer to
    /// floes that exist, so a damaged checkpoint is refused, not stepped.
    pub fn validate(&self) -> Result<(), DemError> {
        let n = self.floes.len();
        let bad = |reason: String| Err(DemError::InvalidCheckpoint { reason });
        for (name, len) in [
            ("force", self.force.len()),
            ("torque", self.torque.len()),
            ("external_force", self.external_force.len()),
            ("external_torque", self.external_torque.len()),
        ] {
            if len != n {
                return bad(format!("{name} has {len} entries for {n} floes"));
            }
        }
        let sorted_valid = |pairs: &mut dyn Iterator<Item = (u32, u32)>| {
            let mut last = None;
            for (a, b) in pairs {
                // a < b: the force gathering relies on it (a floe's
                // contacts as `a` come after its contacts as `b`).
                if a as usize >= n || b as usize >= n || a >= b || last >= Some((a, b)) {
                    return false;
                }
                last = Some((a, b));
            }
            true
        };
        if !sorted_valid(&mut self.contacts.iter().map(|c| (c.a, c.b))) {
            return bad("contacts are not sorted pairs (a, b) of existing floes with a < b".into());
        }
        if !sorted_valid(&mut self.broken.iter().map(|c| (c.a, c.b))) {
            return bad(
                "broken contacts are not sorted pairs (a, b) of existing floes with a < b".into(),
            );
        }
        if !(self.time_s.is_finite()) {
            return bad(format!("time {} is not finite", self.time_s));
        }
        Ok(())
    }
}
