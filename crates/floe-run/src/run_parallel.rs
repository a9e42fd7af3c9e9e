//! A scenario run spread over the processes of a communicator (`mpirun -np
//! K floe run`): process 0 builds the whole world from the scenario (or
//! reads the checkpoint) and hands each process its subdomain
//! ([`DistributedWorld::from_root`]); every process reads the scenario for
//! the model and the forcing; process 0 writes the one run file, in the
//! layout a single process writes, from the world gathered at each output.
//!
//! Errors before the first step are agreed: if any process fails, every
//! process stops, process 0 says why once, and all exit with its code.
//! A failure of process 0's writer during the run ends the whole job
//! ([`Communicator::abort`]): the other processes are waiting for it.

use std::path::PathBuf;

use floe_dem::run;
use floe_io::RunWriter;
use floe_parallel::{Communicator, DistributedWorld, Settings};
use floe_scenario::Scenario;

use crate::error::Error;
use crate::run_file::{
    advance, check_output, create_writer, pool, reopen, scenario_from_text, stored_scenario,
    thread_count, RootWriter, RunArgs, RunHooks, RunSummary,
};
use crate::same_file::refuse_overwriting_input;

/// Hooks of a process other than 0: silent, interrupted as process 0 is.
struct Quiet<'a>(&'a dyn RunHooks);

impl RunHooks for Quiet<'_> {
    fn say(&self, _: &str) {}
    fn progress(&self, _: u64, _: u64, _: f64) -> Box<dyn floe_dem::run::Progress> {
        Box::new(floe_dem::run::Silent)
    }
    fn interrupt(&self) -> &std::sync::atomic::AtomicBool {
        self.0.interrupt()
    }
}

/// Runs (or resumes) a scenario over the processes of `comm`; the result
/// is bitwise the single process's.
pub fn run_parallel<C: Communicator + Sync>(
    args: &RunArgs,
    hooks: &dyn RunHooks,
    comm: &C,
    settings: Settings,
) -> Result<RunSummary, Error> {
    let root = comm.rank() == 0;
    let quiet = Quiet(hooks);
    let hooks: &dyn RunHooks = if root { hooks } else { &quiet };
    match run_inner(args, hooks, comm, settings) {
        Ok(summary) => Ok(summary),
        Err(e) => {
            // Every process is here (the failure was agreed, or the run
            // ended so on all): process 0 says why before any exits, for
            // mpirun ends the job, and its output, at the first non-zero
            // exit.
            let code = e.exit_code();
            if root {
                hooks.say(&format!("error: {e}"));
            }
            comm.max_f64(&mut [0.0]);
            Err(Error::ReportedByRoot { code })
        }
    }
}

/// What every process has before the first step.
struct Prepared {
    scenario: Scenario,
    /// The whole world's state, on process 0.
    state: Option<floe_dem::state::WorldState>,
    writer: Option<RunWriter>,
    fresh: bool,
}

fn run_inner<C: Communicator + Sync>(
    args: &RunArgs,
    hooks: &dyn RunHooks,
    comm: &C,
    settings: Settings,
) -> Result<RunSummary, Error> {
    if args.resume && args.scenario.is_some() {
        return Err(Error::Usage(
            "--resume continues the scenario stored in the output file; do not give a scenario file".into(),
        ));
    }
    let source = if args.resume {
        Source::Resumed(Box::new(prepare_resume(args, hooks, comm)?))
    } else {
        Source::Fresh(Box::new(load_fresh(args, comm)?))
    };
    let scenario_threads = match &source {
        Source::Resumed(p) => p.scenario.threads(),
        Source::Fresh(f) => f.1.threads(),
    };
    let threads = agree(
        comm,
        thread_count(Some(
            args.threads
                .or(scenario_threads)
                .unwrap_or_else(|| threads_per_process(comm.size())),
        )),
    )?;
    let pool = agree(comm, pool(threads))?;
    pool.install(|| {
        let Prepared {
            scenario,
            state,
            mut writer,
            fresh,
        } = match source {
            Source::Resumed(p) => *p,
            Source::Fresh(f) => build_fresh(args, hooks, comm, f.0, f.1)?,
        };
        let parts = scenario.engine_parts();
        let mut world = DistributedWorld::from_root(
            state,
            parts.model,
            parts.forcing,
            parts.periodicity,
            comm,
            settings,
        )?;
        let dt_s = world.local().dt_s();
        world.set_fracturing(scenario.fracturing(dt_s))?;
        world.set_cohesion(scenario.cohesion())?;
        world.set_ridging(scenario.ridging())?;
        world.set_welding(scenario.welding())?;
        let stats = world.stats();
        hooks.say(&format!(
            "{} processes x {threads} threads; process 0 owns {} floes and holds {} ghosts",
            comm.size(),
            stats.owned,
            stats.ghosts
        ));
        if fresh {
            run::start(
                &mut world,
                &mut RootWriter(writer.as_mut(), scenario.output().ridging_log),
                scenario.domain().area_m2(),
            )
            .map_err(|e| abort_with(comm, e.into()))?;
        }
        let (first_step, before) = (world.local().steps(), comm.traffic());
        let result = advance(
            &scenario,
            &mut world,
            writer.as_mut(),
            args,
            (threads, comm.size()),
            hooks,
        );
        let (stats, after) = (world.stats(), comm.traffic());
        let steps = (world.local().steps() - first_step).max(1);
        hooks.say(&format!(
            "decomposition: {} migrations, {} rebalances; process 0 sent {:.1} kB in {:.1} messages \
             per step, spent {:.2} s gathering and writing {} outputs",
            stats.migrations,
            stats.rebalances,
            (after.bytes - before.bytes) as f64 / steps as f64 / 1e3,
            (after.messages - before.messages) as f64 / steps as f64,
            stats.output_s,
            stats.gathers
        ));
        result.map_err(|e| match e {
            // The others wait in a collective for process 0: end the job.
            Error::Output(_) | Error::Io { .. } => abort_with(comm, e),
            other => other,
        })
    })
}

/// Where the run starts from.
enum Source {
    /// A scenario file (its path) not yet built.
    Fresh(Box<(PathBuf, Scenario)>),
    /// A run file's checkpoint.
    Resumed(Box<Prepared>),
}

/// Threads per process when neither `--threads` nor the scenario says:
/// the node's cores shared among the processes on it (`mpirun` and Slurm
/// say how many), at least one.
fn threads_per_process(processes: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let local = [
        "OMPI_COMM_WORLD_LOCAL_SIZE",
        "MPI_LOCALNRANKS",
        "SLURM_NTASKS_PER_NODE",
    ]
    .iter()
    .find_map(|v| std::env::var(v).ok()?.trim().parse::<usize>().ok())
    .unwrap_or(processes)
    .max(1);
    (cores / local).max(1)
}

/// Says `e` and ends every process with its exit code.
fn abort_with<C: Communicator>(comm: &C, e: Error) -> Error {
    eprintln!("error: process {} of {}: {e}", comm.rank(), comm.size());
    comm.abort(i32::from(e.exit_code()))
}

/// Every process learns whether any failed; the first failure's message
/// goes to process 0, the others stop with its code.
fn agree<T, C: Communicator>(comm: &C, result: Result<T, Error>) -> Result<T, Error> {
    let mine = match &result {
        Ok(_) => Vec::new(),
        Err(e) => {
            let mut bytes = vec![e.exit_code()];
            bytes.extend_from_slice(e.to_string().as_bytes());
            bytes
        }
    };
    let all = comm.all_to_all(vec![mine; comm.size()]);
    let Some((rank, failure)) = all.iter().enumerate().find(|(_, m)| !m.is_empty()) else {
        return result;
    };
    if rank == comm.rank() {
        return result;
    }
    let _ = result;
    Err(Error::OnProcess {
        rank,
        processes: comm.size(),
        code: failure[0],
        message: String::from_utf8_lossy(&failure[1..]).into_owned(),
    })
}

/// A fresh run's scenario, read by every process; process 0 checks the
/// output file can be written.
fn load_fresh<C: Communicator>(args: &RunArgs, comm: &C) -> Result<(PathBuf, Scenario), Error> {
    let loaded = (|| {
        let path = args.scenario.as_ref().ok_or_else(|| {
            Error::Usage("give a scenario file, or --resume to continue a run".into())
        })?;
        refuse_overwriting_input(path, "scenario file", [args.output.as_path()])?;
        let scenario = Scenario::load_with(path, &args.laws)?.with_max_steps(args.step_limit);
        if comm.rank() == 0 {
            check_output(args)?;
        }
        Ok((path.clone(), scenario))
    })();
    agree(comm, loaded)
}

/// Process 0 builds the whole world and makes the file (the others get
/// their floes from it).
fn build_fresh<C: Communicator>(
    args: &RunArgs,
    hooks: &dyn RunHooks,
    comm: &C,
    path: PathBuf,
    scenario: Scenario,
) -> Result<Prepared, Error> {
    let setup = if comm.rank() == 0 {
        Some(scenario.build().map_err(Error::from))
    } else {
        None
    };
    let setup = agree(comm, setup.transpose())?;
    let writer = setup.as_ref().map(|setup| {
        for line in &setup.report {
            hooks.say(line);
        }
        create_writer(
            args,
            &path,
            &scenario,
            setup,
            (rayon::current_num_threads(), comm.size()),
        )
    });
    let writer = agree(comm, writer.transpose())?;
    let state = setup.map(|setup| setup.world.into_parts().0);
    Ok(Prepared {
        scenario,
        state,
        writer,
        fresh: true,
    })
}

/// A resumed run: process 0 reads the file and its last checkpoint (only
/// it opens the file) and sends the stored scenario to the others; the
/// run may resume on another number of processes.
fn prepare_resume<C: Communicator>(
    args: &RunArgs,
    hooks: &dyn RunHooks,
    comm: &C,
) -> Result<Prepared, Error> {
    let opened = if comm.rank() == 0 {
        open_for_resume(args, hooks).map(Some)
    } else {
        Ok(None)
    };
    let opened = agree(comm, opened)?;
    // The stored scenario and where it was (its input files are found from there).
    let payload = match &opened {
        Some(o) => encode_strings(&[&o.scenario_toml, &o.scenario_path]),
        None => Vec::new(),
    };
    let payload = comm.broadcast_from_root(payload);
    let received = (|| {
        let parts = split_parts(&payload)
            .filter(|p| p.len() == 2)
            .ok_or_else(|| Error::Usage("a message from process 0 was cut short".into()))?;
        let text = |k: usize| String::from_utf8_lossy(parts[k]).into_owned();
        scenario_from_text(args, &text(0), &text(1))
    })();
    let scenario = agree(comm, received)?;
    let (state, writer) = match opened {
        Some(o) => (Some(o.state), Some(o.writer)),
        None => (None, None),
    };
    Ok(Prepared {
        scenario,
        state,
        writer,
        fresh: false,
    })
}

/// `parts` as one message of length-prefixed parts.
fn encode_strings(parts: &[&str]) -> Vec<u8> {
    let mut bytes = Vec::new();
    for part in parts {
        bytes.extend_from_slice(&(part.len() as u64).to_le_bytes());
        bytes.extend_from_slice(part.as_bytes());
    }
    bytes
}

/// The parts of a message of length-prefixed parts.
fn split_parts(mut bytes: &[u8]) -> Option<Vec<&[u8]>> {
    let mut parts = Vec::new();
    while !bytes.is_empty() {
        let n = u64::from_le_bytes(bytes.get(..8)?.try_into().ok()?) as usize;
        parts.push(bytes.get(8..8 + n)?);
        bytes = &bytes[8 + n..];
    }
    Some(parts)
}

/// What process 0 reads to resume.
struct Opened {
    /// The stored scenario's text.
    scenario_toml: String,
    /// Where the scenario file was.
    scenario_path: String,
    /// The last checkpoint's state.
    state: floe_dem::state::WorldState,
    /// The file, reopened.
    writer: RunWriter,
}

fn open_for_resume(args: &RunArgs, hooks: &dyn RunHooks) -> Result<Opened, Error> {
    let (metadata, scenario) = stored_scenario(args)?;
    let (writer, state) = reopen(args, &scenario, hooks)?;
    Ok(Opened {
        scenario_toml: metadata.scenario_toml,
        scenario_path: metadata.scenario_path,
        state,
        writer,
    })
}
