//! `floe compare`: one scenario under several friction laws.

use std::path::PathBuf;

use floe_friction::LawRegistry;
use floe_study::compare::{self, CompareArgs};

use super::options::{parse_laws, MatchingArgs, MetricArgs, StepLimit, Workers};
use crate::hooks::{provenance, TerminalHooks};
use crate::CliError;

/// Run one scenario under several friction laws and report the differences.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scenario file.
    pub scenario: PathBuf,
    /// Laws to compare, comma-separated.
    #[arg(long, default_value = "amontons,rate,rate-state")]
    pub laws: String,
    /// Output directory: LAW.h5, LAW.toml, LAW/ maps, report.md and figures (LAW each law's name).
    #[arg(long, short)]
    pub output: PathBuf,
    /// Amontons' mu.
    #[command(flatten)]
    pub matching: MatchingArgs,
    /// Threads and --force.
    #[command(flatten)]
    pub workers: Workers,
    /// No progress bars.
    #[arg(long, short)]
    pub quiet: bool,
    /// Metric options.
    #[command(flatten)]
    pub metrics: MetricArgs,
    /// Most time steps each run may take.
    #[command(flatten)]
    pub step_limit: StepLimit,
}

impl Args {
    /// Runs the scenario under each law; returns where the report is.
    pub fn run(self) -> Result<String, CliError> {
        let args = CompareArgs {
            scenario: self.scenario,
            laws: parse_laws(&self.laws)?,
            out_dir: self.output,
            threads: self.workers.threads,
            force: self.workers.force,
            matching: self.matching.matching(),
            metrics: self.metrics.options(),
            provenance: provenance(),
            registry: LawRegistry::builtin(),
            step_limit: self.step_limit.step_limit,
        };
        let hooks = TerminalHooks {
            progress: !self.quiet,
        };
        let report = compare::compare(&args, &hooks)?.report;
        Ok(format!("report: {}", report.display()))
    }
}
