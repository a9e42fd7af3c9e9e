//! `floe run`: a scenario into a run file, alone or under mpirun.

use std::path::PathBuf;

use floe_friction::LawRegistry;
use floe_parallel::Settings;
use floe_run::run_file::{self, RunArgs};

use super::options::{StepLimit, Workers};
use super::values::{positive_fraction, whole_steps};
use crate::hooks::{provenance, TerminalHooks};
use crate::CliError;

/// Run a DEM scenario (TOML, see docs/scenarios.md) into an HDF5 file
/// (H5MD layout, see docs/output.md).
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("threads", |a| a.help("Worker threads (default: the scenario's `threads`, else every core). Results are bitwise identical for any count")),
    mut_arg("force", |a| a.help("Replace an existing output file")),
    mut_arg("step_limit", |a| a.help("Most time steps the scenario may take (default 1e9): a run longer than this is refused before it starts, naming dt_s or duration_s")),
)]
pub struct Args {
    /// Scenario file (omit with --resume).
    #[arg(required_unless_present = "resume")]
    pub scenario: Option<PathBuf>,
    /// Output HDF5 file (with --resume: the file to continue, given
    /// either way).
    #[arg(long, short, required_unless_present = "resume")]
    pub output: Option<PathBuf>,
    /// Threads and --force.
    #[command(flatten)]
    pub workers: Workers,
    /// Continue the run in FILE (or in --output) from its last
    /// checkpoint: `floe run --resume OUT.h5`.
    #[arg(long, value_name = "FILE", num_args = 0..=1)]
    pub resume: Option<Option<PathBuf>>,
    /// Take at most this many steps, then write a checkpoint and stop
    /// (continue with --resume; for batch jobs with a time limit).
    #[arg(long, value_name = "STEPS", value_parser = whole_steps)]
    pub max_steps: Option<u64>,
    /// Most time steps the scenario may take.
    #[command(flatten)]
    pub step_limit: StepLimit,
    /// No progress bar or progress lines.
    #[arg(long, short)]
    pub quiet: bool,
    /// When the run stops (completed or paused), describe the run file
    /// for ParaView as `floe export --xdmf` does: OUT.xdmf and
    /// OUT.xdmf.h5 beside it, replaced if there.
    #[arg(long)]
    pub xdmf: bool,
    /// Under mpirun: cut the domain anew when the busiest process's
    /// work (floes plus contacts) exceeds the mean by this fraction.
    #[arg(long, value_name = "FRACTION", default_value_t = Settings::default().rebalance_threshold, value_parser = positive_fraction)]
    pub rebalance_threshold: f64,
    /// Under mpirun: the ghosts' reach beyond contact, as a fraction of
    /// the largest floe's bounding radius; floes migrate when one has
    /// moved half of it.
    #[arg(long, value_name = "FRACTION", default_value_t = Settings::default().skin_fraction, value_parser = positive_fraction)]
    pub halo_skin: f64,
}

/// The run's output file and whether it resumes, from `-o FILE` and
/// `--resume [FILE]`: a file given to both must be the same one.
pub fn run_output(
    output: Option<PathBuf>,
    resume: Option<Option<PathBuf>>,
) -> Result<(PathBuf, bool), CliError> {
    match (output, resume) {
        (Some(o), None) => Ok((o, false)),
        (Some(o), Some(None)) | (None, Some(Some(o))) => Ok((o, true)),
        (Some(o), Some(Some(r))) if o == r => Ok((o, true)),
        (Some(o), Some(Some(r))) => Err(floe_run::Error::Usage(format!(
            "--resume {} and --output {} name two files; give the run file once: `floe run --resume {}`",
            r.display(),
            o.display(),
            r.display()
        ))),
        (None, None | Some(None)) => Err(floe_run::Error::Usage(
            "--resume needs the run file: `floe run --resume OUT.h5`".into(),
        )),
    }
}

impl Args {
    /// Runs the scenario (across the processes of an MPI job when there
    /// are several); returns the summary to print.
    pub fn run(self) -> Result<String, CliError> {
        let (output, resume) = run_output(self.output, self.resume)?;
        crate::interrupt::set_run_file(&output);
        let args = RunArgs {
            scenario: self.scenario,
            output,
            threads: self.workers.threads,
            force: self.workers.force,
            resume,
            max_steps: self.max_steps,
            step_limit: self.step_limit.step_limit,
            provenance: provenance(),
            laws: LawRegistry::builtin(),
        };
        let hooks = TerminalHooks {
            progress: !self.quiet,
        };
        let settings = Settings {
            skin_fraction: self.halo_skin,
            rebalance_threshold: self.rebalance_threshold,
        };
        let mpi = crate::processes::start()?;
        #[cfg(feature = "mpi")]
        if let Some(mpi) = &mpi {
            let comm = mpi.world();
            if floe_parallel::Communicator::size(&comm) > 1 {
                let summary = floe_run::run_parallel::run_parallel(&args, &hooks, &comm, settings)?;
                return Ok(if floe_parallel::Communicator::rank(&comm) == 0 {
                    summary.describe(&args.output) + &export_xdmf(self.xdmf, &args.output)?
                } else {
                    String::new()
                });
            }
        }
        let _ = (mpi, settings);
        let summary = run_file::run(&args, &hooks)?;
        Ok(summary.describe(&args.output) + &export_xdmf(self.xdmf, &args.output)?)
    }
}

/// With `--xdmf`, the run file's XDMF description beside it; the line
/// that says so.
fn export_xdmf(wanted: bool, output: &std::path::Path) -> Result<String, CliError> {
    if !wanted {
        return Ok(String::new());
    }
    let done = floe_io::xdmf::write_xdmf(output, &output.with_extension("xdmf"), true)?;
    Ok(format!("\nParaView: {}", done.xdmf.display()))
}
