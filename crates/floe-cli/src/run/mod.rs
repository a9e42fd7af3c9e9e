//! `floe run`: a scenario file in, an HDF5 file (H5MD layout) out, with
//! checkpoints to resume from, progress on long runs, and a clean stop on
//! Ctrl-C or a numerical blow-up.

pub mod driver;
pub mod health;
pub mod interrupt;
pub mod progress;

use std::path::{Path, PathBuf};
use std::time::Instant;

use floe_dem::forcing::Forcing;
use floe_dem::observables::Observables;
use floe_dem::state::WorldState;
use floe_dem::world::World;
use floe_io::{DomainBox, OutputOptions, RunFile, RunMetadata, RunWriter};

use crate::error::CliError;
use crate::scenario::Scenario;
use driver::{Cadence, Ending, RunObserver};
use progress::{format_sim_time, RunProgress};

/// The HDF5 writer is the run's observer.
impl RunObserver<Forcing> for RunWriter {
    type Error = floe_io::IoError;

    fn snapshot(&mut self, world: &World<Forcing>) -> Result<(), Self::Error> {
        self.write_snapshot(world)
    }

    fn observables(&mut self, step: u64, observables: &Observables) -> Result<(), Self::Error> {
        self.write_observables(step, observables)
    }

    fn checkpoint(
        &mut self,
        state: &WorldState,
        law_state_slots: usize,
    ) -> Result<(), Self::Error> {
        self.write_checkpoint(state, law_state_slots)
    }
}

/// What `floe run` was asked to do.
#[derive(Debug, Clone)]
pub struct RunArgs {
    /// The scenario file (absent with `resume`).
    pub scenario: Option<PathBuf>,
    /// The HDF5 output file.
    pub output: PathBuf,
    /// Worker threads (default: the scenario's `threads`, else all cores).
    pub threads: Option<usize>,
    /// Replace an existing output file.
    pub force: bool,
    /// Continue the run in `output` from its last checkpoint.
    pub resume: bool,
    /// Take at most this many steps in this invocation, then write a
    /// checkpoint and stop (continue with `resume`): for batch jobs with a
    /// wall-clock limit, and for tests of resuming.
    pub max_steps: Option<u64>,
    /// Show progress on standard error.
    pub progress: bool,
}

/// What a finished run did.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Steps taken by this invocation.
    pub steps_taken: u64,
    /// The run's step count at the end.
    pub final_step: u64,
    /// The step the scenario ends at.
    pub total_steps: u64,
    /// Simulated time at the end, s.
    pub final_time_s: f64,
    /// Wall-clock time of the stepping loop, s.
    pub wall_s: f64,
    /// Threads used.
    pub threads: usize,
}

impl RunSummary {
    /// One line for the terminal.
    pub fn describe(&self, output: &Path) -> String {
        let state = if self.final_step >= self.total_steps {
            "completed".to_string()
        } else {
            format!(
                "paused; continue with `floe run --resume {}`",
                output.display()
            )
        };
        format!(
            "{}: {state} at step {}/{} (t = {}), {} steps in {:.1} s ({:.1} steps/s, {} threads)",
            output.display(),
            self.final_step,
            self.total_steps,
            format_sim_time(self.final_time_s),
            self.steps_taken,
            self.wall_s,
            self.steps_taken as f64 / self.wall_s.max(1e-9),
            self.threads
        )
    }
}

/// Runs (or resumes) a scenario to completion.
pub fn run(args: &RunArgs) -> Result<RunSummary, CliError> {
    if args.resume {
        if args.scenario.is_some() {
            return Err(CliError::Usage(
                "--resume continues the scenario stored in the output file; do not give a scenario file".into(),
            ));
        }
        return resume(args);
    }
    let path = args.scenario.as_ref().ok_or_else(|| {
        CliError::Usage("give a scenario file, or --resume to continue a run".into())
    })?;
    let scenario = Scenario::load(path)?;
    if args.output.exists() && !args.force {
        return Err(CliError::WouldOverwrite(args.output.clone()));
    }
    let threads = thread_count(args.threads.or(scenario.threads()))?;
    let pool = pool(threads)?;
    pool.install(|| {
        let setup = scenario.build()?;
        for line in &setup.report {
            eprintln!("{line}");
        }
        if args.force && args.output.exists() {
            std::fs::remove_file(&args.output).map_err(|e| CliError::io(&args.output, e))?;
        }
        let domain = scenario.domain();
        let metadata = RunMetadata {
            scenario_toml: scenario.text().to_string(),
            scenario_path: path.display().to_string(),
            floe_version: env!("CARGO_PKG_VERSION").to_string(),
            git_commit: env!("FLOE_GIT_COMMIT").to_string(),
            command_line: std::env::args().collect(),
            threads,
            author: std::env::var("USER").unwrap_or_else(|_| "unknown".into()),
            domain: DomainBox {
                min_m: [domain.min_m.x, domain.min_m.y],
                size_m: [domain.size_m.x, domain.size_m.y],
                periodic: domain.periodic,
            },
        };
        // The output's directory is made if missing, as `-o out/run.h5` suggests.
        if let Some(parent) = args.output.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(|e| CliError::io(&args.output, e))?;
        }
        let mut writer = RunWriter::create(
            &args.output,
            &metadata,
            setup.world.floes(),
            &OutputOptions::default(),
        )?;
        writer.set_status("running")?;
        let mut world = setup.world;
        driver::start(&world, &mut writer, domain.area_m2())?;
        advance(&scenario, &mut world, &mut writer, args, threads)
    })
}

fn resume(args: &RunArgs) -> Result<RunSummary, CliError> {
    let metadata = RunFile::open(&args.output)?.metadata()?;
    let origin = PathBuf::from(format!(
        "{} (scenario stored in {})",
        metadata.scenario_path,
        args.output.display()
    ));
    let scenario = Scenario::from_text(&metadata.scenario_toml, &origin)?;
    let threads = thread_count(args.threads.or(scenario.threads()))?;
    let pool = pool(threads)?;
    pool.install(|| {
        let parts = scenario.engine_parts();
        // Checkpoints of format 3 hold the time step; older ones take the
        // scenario's, found by building its floes.
        let (mut writer, state, info) =
            RunWriter::reopen_for_resume(&args.output, || scenario.time_step().ok())?;
        eprintln!(
            "resuming {} from step {} (t = {})",
            args.output.display(),
            info.step,
            format_sim_time(info.time_s)
        );
        let mut world = World::resume(state, parts.model, parts.forcing, parts.periodicity)?;
        writer.set_status("running")?;
        advance(&scenario, &mut world, &mut writer, args, threads)
    })
}

/// The stepping loop and the status it leaves in the file.
fn advance(
    scenario: &Scenario,
    world: &mut World<Forcing>,
    writer: &mut RunWriter,
    args: &RunArgs,
    threads: usize,
) -> Result<RunSummary, CliError> {
    let dt = world.dt_s();
    let total_steps = ((scenario.duration_s() / dt).round() as u64).max(1);
    let out = scenario.output();
    let cadence = Cadence::from_seconds(
        out.snapshot_every_s,
        out.observables_every_s,
        out.checkpoint_every_s,
        dt,
    );
    let first_step = world.steps();
    let pause_at = args.max_steps.map(|n| first_step.saturating_add(n));
    let mut progress = RunProgress::new(
        first_step,
        total_steps,
        total_steps as f64 * dt,
        args.progress,
    );
    let started = Instant::now();
    let ending = driver::drive(
        world,
        total_steps,
        pause_at,
        cadence,
        scenario.domain().area_m2(),
        writer,
        interrupt::flag(),
        &mut progress,
    )?;
    let summary = RunSummary {
        steps_taken: world.steps() - first_step,
        final_step: world.steps(),
        total_steps,
        final_time_s: world.time_s(),
        wall_s: started.elapsed().as_secs_f64(),
        threads,
    };
    match ending {
        Ending::Completed => {
            writer.set_status("completed")?;
            writer.flush()?;
            Ok(summary)
        }
        Ending::Interrupted { step } => {
            writer.set_status(&format!("interrupted at step {step}"))?;
            writer.flush()?;
            Err(CliError::Interrupted {
                output: args.output.clone(),
                step,
            })
        }
        Ending::Paused { step } => {
            writer.set_status(&format!("paused at step {step}"))?;
            writer.flush()?;
            Ok(summary)
        }
        Ending::BlewUp(blow_up) => {
            writer.set_status(&format!("stopped: {blow_up}"))?;
            writer.flush()?;
            Err(CliError::BlowUp {
                output: args.output.clone(),
                message: blow_up.to_string(),
            })
        }
    }
}

fn thread_count(requested: Option<usize>) -> Result<usize, CliError> {
    match requested {
        Some(0) => Err(CliError::Usage("--threads must be at least 1".into())),
        Some(n) => Ok(n),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

fn pool(threads: usize) -> Result<rayon::ThreadPool, CliError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::Usage(format!("cannot start {threads} threads: {e}")))
}
