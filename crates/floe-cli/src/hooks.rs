//! What runs started from the command line show and how they stop: set-up
//! lines on standard error, a progress bar (or log lines), and Ctrl-C or
//! SIGTERM as the interrupt.

use std::sync::atomic::AtomicBool;

use floe_dem::run::Progress;
use floe_run::run_file::{Provenance, RunHooks};

use crate::interrupt;
use crate::progress_bar::RunProgress;

/// The command line's [`RunHooks`].
pub struct TerminalHooks {
    /// Show progress (`--quiet` turns it off).
    pub progress: bool,
}

impl RunHooks for TerminalHooks {
    fn say(&self, line: &str) {
        crate::stderr::line(line);
    }

    fn progress(&self, first_step: u64, total_steps: u64, end_time_s: f64) -> Box<dyn Progress> {
        Box::new(RunProgress::new(
            first_step,
            total_steps,
            end_time_s,
            self.progress,
        ))
    }

    fn interrupt(&self) -> &AtomicBool {
        interrupt::flag()
    }
}

/// This program's provenance for the run files it writes: its version,
/// the commit it was built from, the command line and the user.
pub fn provenance() -> Provenance {
    Provenance {
        floe_version: env!("CARGO_PKG_VERSION").to_string(),
        ..Provenance::of_this_process(env!("FLOE_GIT_COMMIT"))
    }
}
