//! Running a world: the stepping loop with its output cadences, the
//! observer it reports to, the blow-up check and the clean stop on an
//! interrupt. The loop does no I/O itself: an observer writes (the HDF5
//! run writer of floe-io implements [`RunObserver`]), a [`Progress`]
//! reports, and an interrupt is a flag the caller raises (from a signal
//! handler, a scheduler's warning, a test).

pub mod cadence;
pub mod drive;
pub mod health;
pub mod sim_time;
pub mod stepper;

pub use cadence::{Cadence, CadenceWindow, Due};
pub use drive::{drive, start, Ending, Progress, RunObserver, Silent};
pub use health::{check_health, BlowUp, Fault, MAX_OVERLAP_FRACTION};
pub use sim_time::format_sim_time;
pub use stepper::{StepReport, Stepper};
