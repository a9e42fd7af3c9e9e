//! The run writer as the stepping loop's observer
//! ([`floe_dem::run::RunObserver`]): snapshots, observables and
//! checkpoints go to the run file as the loop hands them over.

use floe_dem::forcing::ExternalForces;
use floe_dem::observables::Observables;
use floe_dem::run::RunObserver;
use floe_dem::state::WorldState;
use floe_dem::world::{FractureEvent, PlannedRidge, Weld, World};

use crate::error::IoError;
use crate::writer::RunWriter;

impl<F: ExternalForces> RunObserver<F> for RunWriter {
    type Error = IoError;

    fn snapshot(&mut self, world: &World<F>) -> Result<(), IoError> {
        self.write_snapshot(world)
    }

    fn observables(&mut self, step: u64, observables: &Observables) -> Result<(), IoError> {
        self.write_observables(step, observables)
    }

    fn checkpoint(&mut self, state: &WorldState, law_state_slots: usize) -> Result<(), IoError> {
        self.write_checkpoint(state, law_state_slots)
    }

    fn fractures(&mut self, events: &[FractureEvent]) -> Result<(), IoError> {
        self.write_fractures(events)
    }

    fn ridges(&mut self, time_s: f64, events: &[PlannedRidge]) -> Result<(), IoError> {
        self.write_ridges(time_s, events)
    }

    fn welds(&mut self, welds: &[Weld]) -> Result<(), IoError> {
        self.write_welds(welds)
    }
}
