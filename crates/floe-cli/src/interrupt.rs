//! Ctrl-C and SIGTERM: the first asks the run to stop after the current step
//! (with a final snapshot and checkpoint); a second one aborts at once.
//! SIGTERM counts because batch schedulers (Slurm at a job's time limit)
//! send it before killing a job.

use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The flag the stepping loop polls. Installs the signal handler on first
/// use; if it cannot be installed (another handler owns the signal), runs
/// go on without one and say so.
pub fn flag() -> &'static AtomicBool {
    static INSTALL: std::sync::Once = std::sync::Once::new();
    INSTALL.call_once(|| {
        let installed = ctrlc::set_handler(|| {
            if INTERRUPTED.swap(true, Ordering::SeqCst) {
                eprintln!("\nsecond interrupt: stopping now; the last checkpoint stays valid");
                std::process::exit(130);
            }
            eprintln!(
                "\ninterrupt: finishing this step and writing a final snapshot and checkpoint \
                 (interrupt again to stop at once)"
            );
        });
        if let Err(e) = installed {
            eprintln!(
                "warning: no interrupt handler ({e}); Ctrl-C will stop without a final snapshot"
            );
        }
    });
    &INTERRUPTED
}
