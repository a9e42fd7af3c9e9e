//! `floe sweep`: a scenario over the cartesian product of `--set` values.

use std::path::PathBuf;

use floe_friction::LawRegistry;
use floe_scenario::settings::parse_setting;
use floe_study::sweep::{self, SweepArgs};

use super::options::{MetricArgs, StepLimit, Workers};
use crate::hooks::{provenance, TerminalHooks};
use crate::CliError;

/// Run a scenario over the cartesian product of --set values and tabulate metrics.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("threads", |a| a.help("Total thread budget; variants run in parallel")),
    mut_arg("force", |a| a.help("Replace existing files")),
)]
pub struct Args {
    /// Scenario file (omit with --gather).
    #[arg(required_unless_present = "gather")]
    pub scenario: Option<PathBuf>,
    /// KEY=V1,V2,...: a dotted scenario key and its values (repeat for more keys).
    #[arg(long = "set", value_name = "KEY=VALUES")]
    pub set: Vec<String>,
    /// Sweep directory.
    #[arg(long, short)]
    pub output: PathBuf,
    /// Only write one scenario file per variant, the manifest and two
    /// Slurm job-array scripts (array.slurm: a node per variant;
    /// mpi.slurm: an MPI run over several nodes per variant).
    #[arg(long)]
    pub emit: bool,
    /// Tabulate the outputs already in the sweep directory.
    #[arg(long, conflicts_with_all = ["emit", "set"])]
    pub gather: bool,
    /// Threads and --force.
    #[command(flatten)]
    pub workers: Workers,
    /// Metric options.
    #[command(flatten)]
    pub metrics: MetricArgs,
    /// Most time steps each run may take.
    #[command(flatten)]
    pub step_limit: StepLimit,
}

impl Args {
    /// Runs, emits or gathers the variants; returns what was written.
    pub fn run(self) -> Result<String, CliError> {
        if self.gather {
            let table = sweep::gather(&self.output, &self.metrics.options())?;
            return Ok(format!("results: {}", table.display()));
        }
        let settings = self
            .set
            .iter()
            .map(|s| parse_setting(s))
            .collect::<Result<Vec<_>, _>>()?;
        let args = SweepArgs {
            scenario: self.scenario.expect("clap requires it without --gather"),
            settings,
            out_dir: self.output,
            threads: self.workers.threads,
            force: self.workers.force,
            emit_only: self.emit,
            metrics: self.metrics.options(),
            provenance: provenance(),
            laws: LawRegistry::builtin(),
            step_limit: self.step_limit.step_limit,
        };
        let path = sweep::sweep(&args, &TerminalHooks { progress: false })?;
        Ok(if self.emit {
            format!("variants written; manifest: {} (run each variant_NNN.toml with `floe run`: sbatch array.slurm, or mpi.slurm for one MPI run per variant; then `floe sweep --gather`)", path.display())
        } else {
            format!("results: {}", path.display())
        })
    }
}
