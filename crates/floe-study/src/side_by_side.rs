//! Runs several scenario files side by side, one thread each, as many at
//! a time as the thread budget allows (`floe sweep`, `floe rheology`).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use floe_dem::run::{Progress, Silent};

use floe_friction::LawRegistry;
use floe_run::Error;

use floe_run::run_file::{run, Provenance, RunArgs, RunHooks};

/// The caller's hooks without progress reports: runs go side by side.
struct WithoutProgress<'a>(&'a dyn RunHooks);

impl RunHooks for WithoutProgress<'_> {
    fn say(&self, line: &str) {
        self.0.say(line);
    }
    fn progress(&self, _: u64, _: u64, _: f64) -> Box<dyn Progress> {
        Box::new(Silent)
    }
    fn interrupt(&self) -> &AtomicBool {
        self.0.interrupt()
    }
}

/// What the runs of a batch share.
pub(crate) struct Batch<'a> {
    /// Replace existing outputs.
    pub force: bool,
    /// Most time steps a run may take.
    pub step_limit: f64,
    /// Who runs them.
    pub provenance: &'a Provenance,
    /// The friction laws the scenarios may name.
    pub laws: &'a LawRegistry,
}

/// Runs each fresh `(scenario, output)` of `jobs` with the settings of
/// `batch`, `budget` threads in all; `tag` starts each line said. Returns
/// the scenario file names of the runs that failed; an interrupt leaves the
/// rest unstarted.
pub(crate) fn run_side_by_side(
    jobs: &[(PathBuf, PathBuf)],
    budget: usize,
    batch: &Batch,
    tag: &str,
    hooks: &dyn RunHooks,
) -> Vec<String> {
    let workers = budget.min(jobs.len()).max(1);
    let per_job = (budget / workers).max(1);
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some((scenario, output)) = jobs.get(k) else {
                    break;
                };
                let name = scenario
                    .file_stem()
                    .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
                let result = run(
                    &RunArgs {
                        scenario: Some(scenario.clone()),
                        output: output.clone(),
                        threads: Some(per_job),
                        force: batch.force,
                        resume: false,
                        max_steps: None,
                        step_limit: batch.step_limit,
                        provenance: batch.provenance.clone(),
                        laws: batch.laws.clone(),
                    },
                    &WithoutProgress(hooks),
                );
                match result {
                    Ok(summary) => hooks.say(&format!("{tag}: {}", summary.describe(output))),
                    Err(e) => {
                        hooks.say(&format!("{tag}: {name}: {e}"));
                        failures.lock().expect("no panics").push(name);
                        if matches!(e, Error::Interrupted { .. }) {
                            next.store(usize::MAX / 2, Ordering::SeqCst);
                        }
                    }
                }
            });
        }
    });
    let mut failed = failures.into_inner().expect("no panics");
    failed.sort();
    failed
}
