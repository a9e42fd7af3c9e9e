//! A scenario run into a run file: the scenario file in, an HDF5 file
//! (H5MD layout) out, with checkpoints to resume from, and a clean stop on
//! an interrupt or a numerical blow-up. The stepping loop is
//! [`floe_dem::run::drive()`]; the file is written by its observer, the
//! [`RunWriter`]. What the user sees (set-up lines, progress) and how a
//! run is interrupted come from the caller's [`RunHooks`].

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use floe_dem::forcing::ExternalForces;
use floe_dem::observables::Observables;
use floe_dem::run::{self, format_sim_time, Ending, Progress, RunObserver, Silent, Stepper};
use floe_dem::state::WorldState;
use floe_dem::world::{FractureEvent, PlannedRidge, Weld, World};
use floe_friction::{FrictionLaw, LawRegistry};
use floe_io::{DomainBox, InputRecord, IoError, OutputOptions, RunFile, RunMetadata, RunWriter};
use floe_scenario::Scenario;

use crate::error::Error;
use crate::same_file::refuse_overwriting_input;

/// What a run tells its caller as it goes, and how the caller stops it.
pub trait RunHooks: Sync {
    /// A line for the user: what was built, what is resumed.
    fn say(&self, line: &str);
    /// A progress reporter for steps `first_step..total_steps`, the run
    /// ending at simulated time `end_time_s`.
    fn progress(&self, first_step: u64, total_steps: u64, end_time_s: f64) -> Box<dyn Progress>;
    /// The flag that stops the run after the current step (set from a
    /// signal handler: Ctrl-C, a scheduler's SIGTERM).
    fn interrupt(&self) -> &AtomicBool;
}

/// Hooks that say nothing, show no progress and never interrupt (for
/// library use and tests).
pub struct Quiet;

static NEVER: AtomicBool = AtomicBool::new(false);

impl RunHooks for Quiet {
    fn say(&self, _line: &str) {}
    fn progress(&self, _: u64, _: u64, _: f64) -> Box<dyn Progress> {
        Box::new(Silent)
    }
    fn interrupt(&self) -> &AtomicBool {
        &NEVER
    }
}

/// Who made a run file, for its provenance record.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    /// The program's version.
    pub floe_version: String,
    /// The git commit it was built from (`unknown` outside a checkout).
    pub git_commit: String,
    /// The command line that started the run.
    pub command_line: Vec<String>,
    /// Who ran it.
    pub author: String,
}

impl Provenance {
    /// This library's version and the process's command line and user; the
    /// commit as the caller knows it.
    pub fn of_this_process(git_commit: &str) -> Self {
        Provenance {
            floe_version: env!("CARGO_PKG_VERSION").to_string(),
            git_commit: git_commit.to_string(),
            command_line: std::env::args().collect(),
            author: std::env::var("USER").unwrap_or_else(|_| "unknown".into()),
        }
    }
}

/// What to run.
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
    /// Most time steps the whole scenario may take: a longer one is
    /// refused before it starts ([`floe_scenario::MAX_RUN_STEPS`] by
    /// default).
    pub step_limit: f64,
    /// Who is running it.
    pub provenance: Provenance,
    /// The friction laws the scenario may name ([`LawRegistry::builtin`]
    /// and any the caller registered); a resume reads the stored scenario
    /// with them too.
    pub laws: LawRegistry,
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
    /// Threads used (per process).
    pub threads: usize,
    /// Processes (1 unless under `mpirun`).
    pub processes: usize,
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
            "{}: {state} at step {}/{} (t = {}), {} steps in {:.1} s ({:.1} steps/s, {})",
            output.display(),
            self.final_step,
            self.total_steps,
            format_sim_time(self.final_time_s),
            self.steps_taken,
            self.wall_s,
            self.steps_taken as f64 / self.wall_s.max(1e-9),
            if self.processes > 1 {
                format!("{} processes x {} threads", self.processes, self.threads)
            } else {
                format!("{} threads", self.threads)
            }
        )
    }
}

/// Runs (or resumes) a scenario to completion, or to the step budget.
pub fn run(args: &RunArgs, hooks: &dyn RunHooks) -> Result<RunSummary, Error> {
    if args.resume {
        if args.scenario.is_some() {
            return Err(Error::Usage(
                "--resume continues the scenario stored in the output file; do not give a scenario file".into(),
            ));
        }
        return resume(args, hooks);
    }
    let path = args.scenario.as_ref().ok_or_else(|| {
        Error::Usage("give a scenario file, or --resume to continue a run".into())
    })?;
    let scenario = Scenario::load_with(path, &args.laws)?.with_max_steps(args.step_limit);
    run_scenario(args, path, &scenario, hooks)
}

/// Runs a scenario already read (from `path`, or made from text whose
/// relative inputs are found beside `path`: the Python package's edited
/// scenarios) into `args.output`; `args.scenario` and `args.resume` are
/// not read. The file records `path` as where the scenario came from.
pub fn run_scenario(
    args: &RunArgs,
    path: &Path,
    scenario: &Scenario,
    hooks: &dyn RunHooks,
) -> Result<RunSummary, Error> {
    refuse_overwriting_input(path, "scenario file", [args.output.as_path()])?;
    check_output(args)?;
    let threads = thread_count(args.threads.or(scenario.threads()))?;
    let pool = pool(threads)?;
    pool.install(|| {
        let setup = scenario.build()?;
        for line in &setup.report {
            hooks.say(line);
        }
        let mut writer = create_writer(args, path, scenario, &setup, (threads, 1))?;
        let mut world = setup.world;
        run::start(&mut world, &mut writer, scenario.domain().area_m2())?;
        advance(
            scenario,
            &mut world,
            Some(&mut writer),
            args,
            (threads, 1),
            hooks,
        )
    })
}

fn resume(args: &RunArgs, hooks: &dyn RunHooks) -> Result<RunSummary, Error> {
    let scenario = stored_scenario(args)?.1;
    let threads = thread_count(args.threads.or(scenario.threads()))?;
    let pool = pool(threads)?;
    pool.install(|| {
        let parts = scenario.engine_parts();
        let (mut writer, state) = reopen(args, &scenario, hooks)?;
        let mut world = World::resume(state, parts.model, parts.forcing, parts.periodicity)?;
        world.set_fracturing(scenario.fracturing(world.dt_s()))?;
        world.set_cohesion(scenario.cohesion())?;
        world.set_ridging(scenario.ridging())?;
        advance(
            &scenario,
            &mut world,
            Some(&mut writer),
            args,
            (threads, 1),
            hooks,
        )
    })
}

/// Refuses an output file that exists (without `--force`) or is not a
/// regular file: `--force` replaces a run file, never a device, a
/// directory or a pipe.
pub(crate) fn check_output(args: &RunArgs) -> Result<(), Error> {
    if args.output.exists() && !args.force {
        return Err(Error::WouldOverwrite(args.output.clone()));
    }
    if args.output.exists() && !args.output.is_file() {
        return Err(Error::Usage(format!(
            "-o {}: exists and is not a regular file; a run is written to a new file \
             or replaces a regular one",
            args.output.display()
        )));
    }
    Ok(())
}

/// A fresh run's file: its metadata (scenario, provenance, inputs), the
/// floes, the land marks, status running.
pub(crate) fn create_writer(
    args: &RunArgs,
    path: &Path,
    scenario: &Scenario,
    setup: &floe_scenario::Setup,
    (threads, processes): (usize, usize),
) -> Result<RunWriter, Error> {
    if args.force && args.output.exists() {
        std::fs::remove_file(&args.output).map_err(|e| Error::io(&args.output, e))?;
    }
    let domain = scenario.domain();
    let p = &args.provenance;
    let metadata = RunMetadata {
        scenario_toml: scenario.text().to_string(),
        // Absolute: a resume finds relative input files from it.
        scenario_path: std::path::absolute(path)
            .unwrap_or_else(|_| path.to_path_buf())
            .display()
            .to_string(),
        floe_version: p.floe_version.clone(),
        git_commit: p.git_commit.clone(),
        command_line: p.command_line.clone(),
        threads,
        processes,
        author: p.author.clone(),
        domain: DomainBox {
            min_m: [domain.min_m.x, domain.min_m.y],
            size_m: [domain.size_m.x, domain.size_m.y],
            periodic: domain.periodic,
        },
        inputs: input_records(scenario)?,
    };
    // The output's directory is made if missing, as `-o out/run.h5` suggests.
    if let Some(parent) = args.output.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| Error::io(&args.output, e))?;
    }
    let mut writer = RunWriter::create(
        &args.output,
        &metadata,
        setup.world.floes(),
        &OutputOptions {
            floe_stress: setup.world.stress_filter().is_some(),
            bonds: setup.world.cohesion().is_some(),
            ridging: setup.world.ridging().is_some(),
            ..OutputOptions::default()
        },
    )?;
    if !setup.land_floe_ids.is_empty() {
        writer.mark_land(&setup.land_floe_ids)?;
    }
    writer.set_status(&floe_io::run_status::running())?;
    Ok(writer)
}

/// The scenario a run file stores, read from where it was, after checking
/// that its inputs and domain are those the run began with; with the
/// file's metadata.
pub(crate) fn stored_scenario(args: &RunArgs) -> Result<(RunMetadata, Scenario), Error> {
    let metadata = RunFile::open(&args.output)?.metadata()?;
    let scenario = scenario_from_text(args, &metadata.scenario_toml, &metadata.scenario_path)?;
    check_inputs_unchanged(&metadata.inputs, &scenario, &args.output)?;
    let d = scenario.domain();
    let recorded = &metadata.domain;
    if [d.min_m.x, d.min_m.y] != recorded.min_m
        || [d.size_m.x, d.size_m.y] != recorded.size_m
        || d.periodic != recorded.periodic
    {
        return Err(Error::Output(floe_io::IoError::Invalid {
            path: args.output.clone(),
            reason: "the stored scenario's domain is not the one the run began in \
                     (/parameters/domain): the scenario was changed after the run began, \
                     and a run resumes only with the scenario it started with"
                .into(),
        }));
    }
    Ok((metadata, scenario))
}

/// A stored scenario's text, its relative input files found from where
/// the scenario file was (`scenario_path`).
pub(crate) fn scenario_from_text(
    args: &RunArgs,
    toml: &str,
    scenario_path: &str,
) -> Result<Scenario, Error> {
    let origin = PathBuf::from(format!(
        "{scenario_path} (scenario stored in {})",
        args.output.display()
    ));
    let base_dir = Path::new(scenario_path)
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    Ok(Scenario::from_text_in(
        toml, &origin, &base_dir, &args.laws,
    )?)
}

/// The run file reopened to continue, its last checkpoint's state, status
/// running.
pub(crate) fn reopen(
    args: &RunArgs,
    scenario: &Scenario,
    hooks: &dyn RunHooks,
) -> Result<(RunWriter, WorldState), Error> {
    // Checkpoints of format 3 hold the time step; older ones take the
    // scenario's, found by building its floes.
    let (mut writer, state, info) = RunWriter::reopen_for_resume(
        &args.output,
        || scenario.time_step().ok(),
        scenario.engine_parts().model.law.state_slots(),
    )?;
    hooks.say(&format!(
        "resuming {} from step {} (t = {})",
        args.output.display(),
        info.step,
        format_sim_time(info.time_s)
    ));
    writer.set_status(&floe_io::run_status::running())?;
    Ok((writer, state))
}

/// The run writer on the process that writes (`None` on the others of a
/// distributed run, which never get a world to write), and whether it logs
/// ridging events (`[output] ridging_log`).
pub(crate) struct RootWriter<'a>(pub(crate) Option<&'a mut RunWriter>, pub(crate) bool);

impl<F: ExternalForces> RunObserver<F> for RootWriter<'_> {
    type Error = IoError;

    fn snapshot(&mut self, world: &World<F>) -> Result<(), IoError> {
        match &mut self.0 {
            Some(w) => RunObserver::<F>::snapshot(*w, world),
            None => Ok(()),
        }
    }

    fn observables(&mut self, step: u64, observables: &Observables) -> Result<(), IoError> {
        match &mut self.0 {
            Some(w) => RunObserver::<F>::observables(*w, step, observables),
            None => Ok(()),
        }
    }

    fn checkpoint(&mut self, state: &WorldState, law_state_slots: usize) -> Result<(), IoError> {
        match &mut self.0 {
            Some(w) => RunObserver::<F>::checkpoint(*w, state, law_state_slots),
            None => Ok(()),
        }
    }

    fn fractures(&mut self, events: &[FractureEvent]) -> Result<(), IoError> {
        match &mut self.0 {
            Some(w) => RunObserver::<F>::fractures(*w, events),
            None => Ok(()),
        }
    }

    fn ridges(&mut self, time_s: f64, events: &[PlannedRidge]) -> Result<(), IoError> {
        match &mut self.0 {
            Some(w) if self.1 => RunObserver::<F>::ridges(*w, time_s, events),
            _ => Ok(()),
        }
    }

    fn welds(&mut self, welds: &[Weld]) -> Result<(), IoError> {
        match &mut self.0 {
            Some(w) => RunObserver::<F>::welds(*w, welds),
            None => Ok(()),
        }
    }
}

/// The stepping loop and the status it leaves in the file (written by the
/// process holding `writer`).
pub(crate) fn advance<S: Stepper>(
    scenario: &Scenario,
    world: &mut S,
    mut writer: Option<&mut RunWriter>,
    args: &RunArgs,
    (threads, processes): (usize, usize),
    hooks: &dyn RunHooks,
) -> Result<RunSummary, Error> {
    let dt = world.dt_s();
    let total_steps = ((scenario.duration_s() / dt).round() as u64).max(1);
    let cadence = scenario.output().in_steps(dt);
    let first_step = world.steps();
    let pause_at = args.max_steps.map(|n| first_step.saturating_add(n));
    let mut progress = hooks.progress(first_step, total_steps, total_steps as f64 * dt);
    let started = Instant::now();
    let ending = run::drive(
        world,
        total_steps,
        pause_at,
        &cadence,
        scenario.domain().area_m2(),
        &mut RootWriter(writer.as_deref_mut(), scenario.output().ridging_log),
        hooks.interrupt(),
        progress.as_mut(),
    )?;
    let mut set_status = |status: &str| -> Result<(), Error> {
        if let Some(w) = writer.as_deref_mut() {
            w.set_status(status)?;
            w.flush()?;
        }
        Ok(())
    };
    let summary = RunSummary {
        steps_taken: world.steps() - first_step,
        final_step: world.steps(),
        total_steps,
        final_time_s: world.time_s(),
        wall_s: started.elapsed().as_secs_f64(),
        threads,
        processes,
    };
    match ending {
        Ending::Completed => {
            set_status("completed")?;
            Ok(summary)
        }
        Ending::Interrupted { step } => {
            set_status(&format!("interrupted at step {step}"))?;
            Err(Error::Interrupted {
                output: args.output.clone(),
                step,
            })
        }
        Ending::Paused { step } => {
            set_status(&format!("paused at step {step}"))?;
            Ok(summary)
        }
        Ending::ForcingFailed { step, message } => {
            set_status(&format!("stopped after step {step}: {message}"))?;
            // Located at the key of the field's file.
            let message = scenario.locate_forcing_failure(&message);
            Err(Error::Forcing {
                output: args.output.clone(),
                step,
                message,
            })
        }
        Ending::BlewUp(blow_up) => {
            set_status(&format!("stopped: {blow_up}"))?;
            Err(Error::BlowUp {
                output: args.output.clone(),
                message: blow_up.to_string(),
            })
        }
    }
}

/// The scenario's input files with their SHA-256, for the provenance.
fn input_records(scenario: &Scenario) -> Result<Vec<InputRecord>, Error> {
    scenario
        .input_files()
        .iter()
        .map(|i| {
            Ok(InputRecord {
                role: i.role.clone(),
                path: i.path.display().to_string(),
                sha256: floe_basin::checksum::sha256_file(&i.path)
                    .map_err(|e| Error::Usage(e.to_string()))?,
            })
        })
        .collect()
}

/// A resume continues the same run only if the input files are the ones
/// it began with.
fn check_inputs_unchanged(
    recorded: &[InputRecord],
    scenario: &Scenario,
    output: &Path,
) -> Result<(), Error> {
    let now = input_records(scenario)?;
    for (was, is) in recorded.iter().zip(&now) {
        if was.sha256 != is.sha256 {
            return Err(Error::Usage(format!(
                "{}: input {} ({}) has changed since the run began (sha256 {} then, {} now); \
                 a run resumes only with the files it started with",
                output.display(),
                is.role,
                is.path,
                was.sha256,
                is.sha256
            )));
        }
    }
    if recorded.len() != now.len() && !recorded.is_empty() {
        return Err(Error::Usage(format!(
            "{}: the run recorded {} input files, its scenario now reads {}",
            output.display(),
            recorded.len(),
            now.len()
        )));
    }
    Ok(())
}

/// The scenario file at `path`, with its relative input files (`file`
/// keys) made absolute so that variants written elsewhere still find them.
pub fn read_anchored(path: &Path) -> Result<String, Error> {
    let text = floe_scenario::SourceFile::read(path)?.text;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Ok(floe_scenario::input_paths::anchor_input_paths(&text, dir))
}

/// The worker threads a run gets: `requested` (1 to
/// [`floe_scenario::resolve::MAX_THREADS`]), else all cores.
pub fn thread_count(requested: Option<usize>) -> Result<usize, Error> {
    let most = floe_scenario::resolve::MAX_THREADS as usize;
    match requested {
        Some(0) => Err(Error::Usage("--threads must be at least 1".into())),
        Some(n) if n > most => Err(Error::Usage(format!(
            "--threads {n}: at most {most} threads"
        ))),
        Some(n) => Ok(n),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

pub(crate) fn pool(threads: usize) -> Result<rayon::ThreadPool, Error> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Usage(format!("cannot start {threads} threads: {e}")))
}
