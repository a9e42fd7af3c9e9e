//! Ctrl-C and SIGTERM: the first asks the run to stop after the current step
//! (with a final snapshot and checkpoint); a second one aborts at once.
//! SIGTERM counts because batch schedulers (Slurm at a job's time limit)
//! send it before killing a job. SIGUSR1 asks the same, and only that (a
//! repeat does not abort): Open MPI's `mpirun` passes it to every process
//! at once, where it holds SIGTERM back and then kills (docs/hpc.md).

use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The run file, named in the second interrupt's message.
static RUN_FILE: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();

/// Names the run file that the second interrupt's message tells how to
/// resume (the first name given is kept).
pub fn set_run_file(path: &std::path::Path) {
    let _ = RUN_FILE.set(path.to_path_buf());
}

/// The flag the stepping loop polls. Installs the signal handler on first
/// use; if it cannot be installed (another handler owns the signal), runs
/// go on without one and say so.
pub fn flag() -> &'static AtomicBool {
    static INSTALL: std::sync::Once = std::sync::Once::new();
    INSTALL.call_once(|| {
        let installed = ctrlc::set_handler(|| {
            if INTERRUPTED.swap(true, Ordering::SeqCst) {
                crate::stderr::line(&format!(
                    "\nsecond interrupt: stopping now; the last checkpoint stays valid \
                     (resume with `floe run --resume {}`)",
                    RUN_FILE
                        .get()
                        .map_or("OUT.h5".into(), |p| p.display().to_string())
                ));
                stop_now();
            }
            // Under mpirun every process is signalled; process 0 speaks.
            if !crate::processes::is_other_than_first() {
                crate::stderr::line(
                    "\ninterrupt: finishing this step and writing a final snapshot and checkpoint \
                     (interrupt again to stop at once)",
                );
            }
        });
        if let Err(e) = installed {
            crate::stderr::line(&format!(
                "warning: no interrupt handler ({e}); Ctrl-C will stop without a final snapshot"
            ));
        }
        on_user_signal_1();
    });
    &INTERRUPTED
}

/// Makes SIGUSR1 raise the flag.
#[allow(unsafe_code)]
fn on_user_signal_1() {
    extern "C" fn raise_flag(_: libc::c_int) {
        // An atomic store: async-signal-safe.
        INTERRUPTED.store(true, Ordering::SeqCst);
    }
    // SAFETY: installs a handler that only stores to an atomic; the
    // function pointer lives for the program's life.
    unsafe {
        libc::signal(
            libc::SIGUSR1,
            raise_flag as extern "C" fn(libc::c_int) as libc::sighandler_t,
        );
    }
}

/// Ends the process at once, as kill -9 would: no exit handlers, so the
/// HDF5 library's own (which would flush the run file while the stepping
/// thread may be half-way through a write) never run. The file is left as
/// the last flush made it, which is what resuming relies on.
#[allow(unsafe_code)]
fn stop_now() -> ! {
    // SAFETY: _exit takes no pointers, touches no Rust state and is
    // async-signal-safe.
    unsafe { libc::_exit(130) }
}

/// A file-size limit (`ulimit -f`) raises SIGXFSZ, whose default ends the
/// process without a word; ignored, the write fails with EFBIG instead and
/// the run stops with its one-line message, the file intact.
#[allow(unsafe_code)]
pub fn ignore_file_size_signal() {
    // SAFETY: installs the predefined SIG_IGN disposition; no handler code.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}
