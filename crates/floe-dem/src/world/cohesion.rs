//! Cohesion on the world: bonds between floes frozen together
//! ([`crate::cohesion`]), formed and broken in the contact detection.

use super::World;
use crate::bonds::Bond;
use crate::cohesion::Cohesion;
use crate::error::DemError;
use crate::forcing::ExternalForces;
use crate::pipeline::cohesion::{update_bonds, CohesionInput};

impl<F: ExternalForces> World<F> {
    /// Forms and breaks bonds from the next step on (`Some`), or stops
    /// (`None`: every bond and candidate is dropped, as if melted, with
    /// no energy counted). Bonds already held (a resumed state's) go on.
    pub fn set_cohesion(&mut self, cohesion: Option<Cohesion>) -> Result<(), DemError> {
        match &cohesion {
            Some(c) => c.check()?,
            None => self.state.bonds.clear(),
        }
        self.cohesion = cohesion;
        Ok(())
    }

    /// The cohesion parameters, if on.
    pub fn cohesion(&self) -> Option<Cohesion> {
        self.cohesion
    }

    /// The bonds and the quiet pairs on their way to one, sorted by pair.
    pub fn bonds(&self) -> &[Bond] {
        &self.state.bonds
    }

    /// Bonds broken since the world was made or resumed (a diagnostic, not
    /// state: a distributed run's processes each count their own, from
    /// their last migration).
    pub fn bonds_broken(&self) -> u64 {
        self.pipeline.bonds_broken
    }

    /// The cohesion stage, after the narrow phase.
    pub(super) fn update_bonds(&mut self) {
        let Some(cohesion) = &self.cohesion else {
            return;
        };
        let s = &mut self.state;
        let p = &mut self.pipeline;
        let input = CohesionInput {
            cohesion,
            model: &self.model,
            damping_ratio: self.damping_ratio,
            floes: s.floes.columns(),
            trig: &p.trig,
            periodicity: self.periodicity,
            contacts: &s.contacts,
            time_s: s.time_s,
            ghost: &p.ghost,
        };
        let broken = update_bonds(
            &input,
            &mut s.bonds,
            &mut p.bond_fresh,
            &mut p.accounting.bonds,
        );
        p.bonds_broken += broken as u64;
    }
}
