//! The stepping loop: advances a world to a given step, hands snapshots,
//! observables and checkpoints to an observer at their cadences, stops
//! cleanly on an interrupt or a numerical blow-up.
//!
//! Cadences ([`Cadence`]) are counted in absolute steps, never from the
//! start of this process, so a resumed run writes exactly where the
//! uninterrupted run would have.

use std::sync::atomic::AtomicBool;

use crate::forcing::ExternalForces;
use crate::observables::Observables;
use crate::state::WorldState;
use crate::world::{FractureEvent, PlannedRidge, Weld, World};

use floe_friction::FrictionLaw;

use super::cadence::{Cadence, Due, NextDue};
use super::health::BlowUp;
use super::stepper::Stepper;

/// What the loop reports to: the HDF5 run writer of floe-io is one, tests
/// use an in-memory one.
pub trait RunObserver<F: ExternalForces> {
    /// The error type of the sink.
    type Error;
    /// A snapshot of the world (floes and contacts).
    fn snapshot(&mut self, world: &World<F>) -> Result<(), Self::Error>;
    /// One sample of the assembly observables at step `step`.
    fn observables(&mut self, step: u64, observables: &Observables) -> Result<(), Self::Error>;
    /// A checkpoint from which the run can continue bitwise; each contact's
    /// friction state has `law_state_slots` slots of law state.
    fn checkpoint(&mut self, state: &WorldState, law_state_slots: usize)
        -> Result<(), Self::Error>;
    /// Floes that broke after the step just taken (every process calls
    /// it with the same events; the default records nothing).
    fn fractures(&mut self, events: &[FractureEvent]) -> Result<(), Self::Error> {
        let _ = events;
        Ok(())
    }
    /// Floes that ridging cut after the step just taken, at simulated time
    /// `time_s` (every process calls it with the same events, by loser id;
    /// the default records nothing).
    fn ridges(&mut self, time_s: f64, events: &[PlannedRidge]) -> Result<(), Self::Error> {
        let _ = (time_s, events);
        Ok(())
    }
    /// Pairs welded after the step just taken (every process calls it
    /// with the same welds, by pair; the default records nothing).
    fn welds(&mut self, welds: &[Weld]) -> Result<(), Self::Error> {
        let _ = welds;
        Ok(())
    }
}

/// How a call to [`drive`] ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Ending {
    /// The last step was reached; everything was written.
    Completed,
    /// The interrupt flag was raised; the step in progress was finished and
    /// a checkpoint and final snapshot written (see `finish_interrupted`).
    Interrupted {
        /// The step the run stopped at.
        step: u64,
    },
    /// The state went bad; a last snapshot was written, the last checkpoint
    /// is the last good state.
    BlewUp(BlowUp),
    /// The forcing could not be evaluated for the step after `step` (a
    /// gridded field's time, grid or missing values): nothing of that step
    /// was written; the last checkpoint is the last good state.
    ForcingFailed {
        /// The last step written.
        step: u64,
        /// What went wrong, naming the file.
        message: String,
    },
    /// The step budget of this invocation was used up before the end; a
    /// checkpoint (and a snapshot) was written as for an interrupt.
    Paused {
        /// The step the run paused at.
        step: u64,
    },
}

/// Progress reports, one per step (implementations throttle themselves).
pub trait Progress {
    /// Called after each step with the steps done and the total.
    fn update(&mut self, step: u64, total_steps: u64, time_s: f64);
    /// Called once when the loop ends.
    fn finish(&mut self);
}

/// No progress output.
pub struct Silent;

impl Progress for Silent {
    fn update(&mut self, _: u64, _: u64, _: f64) {}
    fn finish(&mut self) {}
}

/// Writes what `due` asks for at the world's current step (on the process
/// that writes; every process takes part in gathering the world).
fn write_due<S: Stepper, O: RunObserver<S::Whole>>(
    world: &mut S,
    observer: &mut O,
    due: Due,
    domain_area_m2: f64,
) -> Result<(), O::Error> {
    if !(due.observables || due.snapshot || due.checkpoint) {
        return Ok(());
    }
    world
        .with_whole(|whole| {
            if due.observables {
                observer.observables(whole.steps(), &whole.observables(domain_area_m2))?;
            }
            if due.snapshot {
                observer.snapshot(whole)?;
            }
            // The checkpoint comes last: whatever it records as written is written.
            if due.checkpoint {
                observer.checkpoint(whole.state(), whole.model().law.state_slots())?;
            }
            Ok(())
        })
        .unwrap_or(Ok(()))
}

/// Writes the initial output of a fresh run (step 0: observables, snapshot, checkpoint).
pub fn start<S: Stepper, O: RunObserver<S::Whole>>(
    world: &mut S,
    observer: &mut O,
    domain_area_m2: f64,
) -> Result<(), O::Error> {
    write_due(world, observer, Due::ALL, domain_area_m2)
}

/// Steps `world` until `total_steps`, or until `pause_at` if that comes
/// first, writing at the cadences. Checks the interrupt flag and the
/// state's health after every step.
#[allow(clippy::too_many_arguments)] // one call site; a struct would only rename them
pub fn drive<S: Stepper, O: RunObserver<S::Whole>>(
    world: &mut S,
    total_steps: u64,
    pause_at: Option<u64>,
    cadence: &Cadence,
    domain_area_m2: f64,
    observer: &mut O,
    interrupt: &AtomicBool,
    progress: &mut dyn Progress,
) -> Result<Ending, O::Error> {
    let mut next = NextDue::after(cadence, world.steps());
    while world.steps() < total_steps {
        let before = world.steps();
        let report = world.step(interrupt);
        if let Some(message) = report.forcing_failure {
            progress.finish();
            return Ok(Ending::ForcingFailed {
                step: before,
                message,
            });
        }
        progress.update(world.steps(), total_steps, world.time_s());
        // In the order they were made: ridging, then fracture.
        if !report.ridges.is_empty() {
            observer.ridges(world.time_s(), &report.ridges)?;
        }
        if !report.welds.is_empty() {
            observer.welds(&report.welds)?;
        }
        if !report.fractures.is_empty() {
            observer.fractures(&report.fractures)?;
        }
        if let Some(blow_up) = report.blow_up {
            // The bad state is shown (it is what one needs to see), but the
            // checkpoint is left at the last good state.
            let bad_state = Due {
                observables: true,
                snapshot: true,
                checkpoint: false,
            };
            write_due(world, observer, bad_state, domain_area_m2)?;
            progress.finish();
            return Ok(Ending::BlewUp(blow_up));
        }
        let last = world.steps() == total_steps;
        let due = next.take(cadence, world.steps());
        write_due(
            world,
            observer,
            if last { Due::ALL } else { due },
            domain_area_m2,
        )?;
        if report.interrupted && !last {
            finish_interrupted(world, observer, due, domain_area_m2)?;
            progress.finish();
            return Ok(Ending::Interrupted {
                step: world.steps(),
            });
        }
        if pause_at == Some(world.steps()) && !last {
            finish_interrupted(world, observer, due, domain_area_m2)?;
            progress.finish();
            return Ok(Ending::Paused {
                step: world.steps(),
            });
        }
    }
    progress.finish();
    Ok(Ending::Completed)
}

/// After an interrupt: a checkpoint at this step, then the observables and
/// snapshot the cadence did not already write (`written`). The checkpoint
/// comes before those extras, so it does not count them and a resume drops
/// them: the resumed file then holds exactly the uninterrupted run's output.
fn finish_interrupted<S: Stepper, O: RunObserver<S::Whole>>(
    world: &mut S,
    observer: &mut O,
    written: Due,
    domain_area_m2: f64,
) -> Result<(), O::Error> {
    let checkpoint = Due {
        observables: false,
        snapshot: false,
        checkpoint: !written.checkpoint,
    };
    write_due(world, observer, checkpoint, domain_area_m2)?;
    let extra = Due {
        observables: !written.observables,
        snapshot: !written.snapshot,
        checkpoint: false,
    };
    write_due(world, observer, extra, domain_area_m2)
}
