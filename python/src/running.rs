//! `floe._floe.run` and `resume`: a run on floe's run-loop library in a
//! thread of its own, the Python thread waiting without the GIL. Every
//! 100 ms it takes the GIL to check for Ctrl-C (which asks the run to stop
//! after the current step, with a final snapshot and checkpoint, as the
//! command line does) and to report progress and set-up lines to the
//! callbacks the Python side gives (a tqdm bar).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use floe_dem::run::Progress;
use floe_friction::LawRegistry;
use floe_run::run_file::{self, Provenance, RunArgs, RunHooks, RunSummary};
use floe_run::Error;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::run_error;
use crate::scenario::Scenario;

/// Where the run's progress is, written by the stepping loop and read by
/// the waiting Python thread.
#[derive(Default)]
struct Shared {
    first_step: AtomicU64,
    step: AtomicU64,
    total_steps: AtomicU64,
    time_bits: AtomicU64,
    end_time_bits: AtomicU64,
}

/// The stepping loop's progress reporter: atomics only.
struct SharedProgress(Arc<Shared>);

impl Progress for SharedProgress {
    fn update(&mut self, step: u64, total_steps: u64, time_s: f64) {
        self.0.step.store(step, Ordering::Relaxed);
        self.0.total_steps.store(total_steps, Ordering::Relaxed);
        self.0.time_bits.store(time_s.to_bits(), Ordering::Relaxed);
    }
    fn finish(&mut self) {}
}

/// The run's hooks: lines kept for the Python thread, progress in atomics,
/// the interrupt flag raised by the Python thread.
#[derive(Default)]
struct PythonHooks {
    lines: Mutex<Vec<String>>,
    shared: Arc<Shared>,
    interrupt: AtomicBool,
}

impl RunHooks for PythonHooks {
    fn say(&self, line: &str) {
        self.lines
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(line.to_string());
    }

    fn progress(&self, first_step: u64, total_steps: u64, end_time_s: f64) -> Box<dyn Progress> {
        let s = &self.shared;
        s.first_step.store(first_step, Ordering::Relaxed);
        s.step.store(first_step, Ordering::Relaxed);
        s.total_steps.store(total_steps, Ordering::Relaxed);
        s.end_time_bits
            .store(end_time_s.to_bits(), Ordering::Relaxed);
        Box::new(SharedProgress(Arc::clone(s)))
    }

    fn interrupt(&self) -> &AtomicBool {
        &self.interrupt
    }
}

/// The Python callbacks: `on_line(str)` and
/// `on_progress(first_step, step, total_steps, time_s, end_time_s)`.
pub struct Callbacks {
    /// Called with each line the run says.
    pub on_line: Option<Py<PyAny>>,
    /// Called with the run's progress.
    pub on_progress: Option<Py<PyAny>>,
}

impl Callbacks {
    /// Passes on what the run said and how far it is; an exception in a
    /// callback stops the run like Ctrl-C (and is raised afterwards).
    fn report(&self, py: Python<'_>, hooks: &PythonHooks) -> PyResult<()> {
        let lines = std::mem::take(&mut *hooks.lines.lock().unwrap_or_else(|e| e.into_inner()));
        if let Some(f) = &self.on_line {
            for line in lines {
                f.call1(py, (line,))?;
            }
        }
        let s = &hooks.shared;
        let total = s.total_steps.load(Ordering::Relaxed);
        if let (Some(f), true) = (&self.on_progress, total > 0) {
            f.call1(
                py,
                (
                    s.first_step.load(Ordering::Relaxed),
                    s.step.load(Ordering::Relaxed),
                    total,
                    f64::from_bits(s.time_bits.load(Ordering::Relaxed)),
                    f64::from_bits(s.end_time_bits.load(Ordering::Relaxed)),
                ),
            )?;
        }
        Ok(())
    }
}

/// Runs `work` in a thread of its own while this thread, without the GIL,
/// checks for signals and reports progress every 100 ms.
pub fn drive_with<T: Send>(
    py: Python<'_>,
    callbacks: Callbacks,
    work: impl FnOnce(&dyn RunHooks) -> Result<T, Error> + Send,
) -> PyResult<T> {
    let hooks = PythonHooks::default();
    let (outcome, pending) = py.detach(|| {
        std::thread::scope(|scope| {
            let (tx, rx) = mpsc::channel();
            let hooks = &hooks;
            let worker = scope.spawn(move || {
                let _ = tx.send(work(hooks));
            });
            let mut pending: Option<PyErr> = None;
            let mut tick = |final_report: bool| {
                Python::attach(|py| {
                    let checked = if final_report {
                        Ok(())
                    } else {
                        py.check_signals()
                    };
                    if let Err(e) = checked.and_then(|()| callbacks.report(py, hooks)) {
                        hooks.interrupt.store(true, Ordering::SeqCst);
                        pending.get_or_insert(e);
                    }
                });
            };
            let outcome = loop {
                match rx.recv_timeout(Duration::from_millis(100)) {
                    Ok(outcome) => break Some(outcome),
                    Err(mpsc::RecvTimeoutError::Timeout) => tick(false),
                    Err(mpsc::RecvTimeoutError::Disconnected) => break None,
                }
            };
            tick(true);
            let outcome = match (outcome, worker.join()) {
                (Some(outcome), _) => Ok(outcome),
                (None, Err(panic)) => Err(panic_message(panic.as_ref())),
                (None, Ok(())) => Err("the run ended without a result".to_string()),
            };
            (outcome, pending)
        })
    });
    match outcome {
        // A Ctrl-C or a callback's exception that came as the run ended:
        // the run is whole, and the exception is raised all the same.
        Ok(Ok(done)) => match pending {
            Some(e) => Err(e),
            None => Ok(done),
        },
        Ok(Err(e @ Error::Interrupted { .. })) => match pending {
            Some(p) if !p.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => Err(p),
            _ => Err(run_error(e)),
        },
        Ok(Err(e)) => Err(run_error(e)),
        Err(message) => Err(crate::errors::internal_error(format!(
            "the run stopped on an internal error: {message} (please report it)"
        ))),
    }
}

fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".into())
}

pub fn provenance(command_line: Option<Vec<String>>) -> Provenance {
    let mut p = Provenance::of_this_process(env!("FLOE_GIT_COMMIT"));
    if let Some(c) = command_line {
        p.command_line = c;
    }
    p
}

fn summary_dict<'py>(
    py: Python<'py>,
    s: &RunSummary,
    output: &PathBuf,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("output", output)?;
    d.set_item(
        "status",
        if s.final_step >= s.total_steps {
            "completed"
        } else {
            "paused"
        },
    )?;
    d.set_item("steps_taken", s.steps_taken)?;
    d.set_item("final_step", s.final_step)?;
    d.set_item("total_steps", s.total_steps)?;
    d.set_item("final_time_s", s.final_time_s)?;
    d.set_item("wall_s", s.wall_s)?;
    d.set_item("threads", s.threads)?;
    d.set_item("processes", s.processes)?;
    d.set_item("summary", s.describe(output))?;
    Ok(d)
}

/// `max_steps`, if given, is at least 1 (as `floe run --max-steps`).
fn check_max_steps(max_steps: Option<u64>) -> PyResult<()> {
    match max_steps {
        Some(0) => Err(pyo3::exceptions::PyValueError::new_err(
            "max_steps=0: the steps to take before pausing, at least 1 (None: to the end)",
        )),
        _ => Ok(()),
    }
}

/// Runs `scenario` into the run file `output` (see ``floe.run``).
#[pyfunction]
#[pyo3(signature = (scenario, output, *, threads=None, force=false, max_steps=None, on_line=None, on_progress=None, command_line=None))]
#[allow(clippy::too_many_arguments)]
pub fn run<'py>(
    py: Python<'py>,
    scenario: Scenario,
    output: PathBuf,
    threads: Option<usize>,
    force: bool,
    max_steps: Option<u64>,
    on_line: Option<Py<PyAny>>,
    on_progress: Option<Py<PyAny>>,
    command_line: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyDict>> {
    check_max_steps(max_steps)?;
    let parsed = scenario.parsed()?;
    let args = RunArgs {
        scenario: None,
        output: output.clone(),
        threads,
        force,
        resume: false,
        max_steps,
        step_limit: floe_scenario::MAX_RUN_STEPS,
        provenance: provenance(command_line),
        laws: LawRegistry::builtin(),
    };
    let parsed = parsed.with_max_steps(args.step_limit);
    let path = scenario.recorded_path();
    let callbacks = Callbacks {
        on_line,
        on_progress,
    };
    let summary = drive_with(py, callbacks, |hooks| {
        run_file::run_scenario(&args, &path, &parsed, hooks)
    })?;
    summary_dict(py, &summary, &output)
}

/// Continues the run in `output` from its last checkpoint (see
/// ``floe.resume``).
#[pyfunction]
#[pyo3(signature = (output, *, threads=None, max_steps=None, on_line=None, on_progress=None, command_line=None))]
pub fn resume<'py>(
    py: Python<'py>,
    output: PathBuf,
    threads: Option<usize>,
    max_steps: Option<u64>,
    on_line: Option<Py<PyAny>>,
    on_progress: Option<Py<PyAny>>,
    command_line: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyDict>> {
    crate::errors::existing(&output)?;
    check_max_steps(max_steps)?;
    let args = RunArgs {
        scenario: None,
        output: output.clone(),
        threads,
        force: false,
        resume: true,
        max_steps,
        step_limit: floe_scenario::MAX_RUN_STEPS,
        provenance: provenance(command_line),
        laws: LawRegistry::builtin(),
    };
    let callbacks = Callbacks {
        on_line,
        on_progress,
    };
    let summary = drive_with(py, callbacks, |hooks| run_file::run(&args, hooks))?;
    summary_dict(py, &summary, &output)
}
