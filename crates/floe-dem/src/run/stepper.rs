//! What the stepping loop steps: one [`World`], or a world spread over
//! processes (floe-parallel's distributed world), behind one trait so that
//! the loop, its cadences and its endings are written once.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::forcing::ExternalForces;
use crate::world::{FractureEvent, PlannedRidge, Weld, World};

use super::health::{check_health, BlowUp};

/// What a step found that ends the run, agreed by every process.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepReport {
    /// The forcing could not be evaluated for the step: why.
    pub forcing_failure: Option<String>,
    /// The state went bad.
    pub blow_up: Option<BlowUp>,
    /// The interrupt flag was raised (on any process).
    pub interrupted: bool,
    /// Floes the fracture after the step broke (every process's, by
    /// parent id; empty without fracture).
    pub fractures: Vec<FractureEvent>,
    /// Floes ridging after the step cut (every process's, by loser id;
    /// empty without ridging).
    pub ridges: Vec<PlannedRidge>,
    /// Pairs welded after the step (every process's, by pair; empty
    /// without welding).
    pub welds: Vec<Weld>,
}

/// A simulation the loop can step and write.
pub trait Stepper {
    /// The forcing type of the whole world handed to the observer.
    type Whole: ExternalForces;
    /// Takes one step and reports what ends the run; `interrupt` is the
    /// flag a signal handler raises. Every process calls it together.
    fn step(&mut self, interrupt: &AtomicBool) -> StepReport;
    /// Steps taken.
    fn steps(&self) -> u64;
    /// Simulated time, s.
    fn time_s(&self) -> f64;
    /// The time step, s.
    fn dt_s(&self) -> f64;
    /// Calls `write` with the whole world on the process that writes the
    /// run file and returns its result there (`None` elsewhere). Every
    /// process calls it together.
    fn with_whole<R>(&mut self, write: impl FnOnce(&World<Self::Whole>) -> R) -> Option<R>;
}

impl<F: ExternalForces> Stepper for World<F> {
    type Whole = F;

    fn step(&mut self, interrupt: &AtomicBool) -> StepReport {
        World::step(self);
        let mut report = StepReport {
            forcing_failure: self.forcing_failure().map(ToString::to_string),
            blow_up: check_health(self),
            interrupted: interrupt.load(Ordering::SeqCst),
            fractures: Vec::new(),
            ridges: Vec::new(),
            welds: Vec::new(),
        };
        if let (None, None) = (&report.forcing_failure, &report.blow_up) {
            report.ridges = self
                .ridge()
                .unwrap_or_else(|e| panic!("ridging after step {}: {e}", self.steps()));
            report.welds = self
                .weld()
                .unwrap_or_else(|e| panic!("welding after step {}: {e}", self.steps()));
        }
        if let (Some(f), None, None) = (self.fracturing(), &report.forcing_failure, &report.blow_up)
        {
            report.fractures = self
                .fracture(&f.rule, f.domain_area_m2)
                .unwrap_or_else(|e| panic!("fracture after step {}: {e}", self.steps()));
        }
        report
    }

    fn steps(&self) -> u64 {
        World::steps(self)
    }

    fn time_s(&self) -> f64 {
        World::time_s(self)
    }

    fn dt_s(&self) -> f64 {
        World::dt_s(self)
    }

    fn with_whole<R>(&mut self, write: impl FnOnce(&World<F>) -> R) -> Option<R> {
        Some(write(self))
    }
}
