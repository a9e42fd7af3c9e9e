//! `floe pack-friction`: the shear cell's wall on a schedule of velocity
//! steps and holds; the pack's own a, b, slip distance and healing.

use std::path::PathBuf;

use floe_friction::LawRegistry;
use floe_scenario::settings::parse_setting;
use floe_study::pack_friction::Mode;
use floe_study::pack_friction::{self, PackFrictionArgs};

use super::options::{parse_laws, MatchingArgs, StepLimit, Workers};
use crate::hooks::{provenance, TerminalHooks};
use crate::CliError;

/// Drive a shear cell's top wall through its schedule of velocity steps
/// and holds under several laws and seeds; read the pack's friction as a
/// laboratory reads a sample's: the direct effect a, a - b, the slip
/// distance of the transient and the healing of each hold.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("threads", |a| a.help("Total thread budget; runs go side by side, one thread each")),
    mut_arg("step_limit", |a| a.help("Most time steps each run may take (default 1e9)")),
)]
pub struct Args {
    /// Shear-cell scenario whose top wall follows [[wall.segment]] tables
    /// of constant speeds along x and holds, e.g.
    /// scenarios/shear_cell_wide_steps.toml.
    pub scenario: PathBuf,
    /// KEY=VALUE: a dotted scenario key set before the runs are made
    /// (repeatable; one value each), e.g. contact.youngs_modulus_pa=6e7.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Laws, comma-separated.
    #[arg(long, default_value = "amontons,rate-state")]
    pub laws: String,
    /// Seeds, comma-separated: every law is run once per seed (runs
    /// LAW_sSEED).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3,4,5")]
    pub seeds: Vec<u64>,
    /// Spacing of the friction samples (the runs' observables), s.
    #[arg(long, default_value_t = 10.0)]
    pub sample_every: f64,
    /// Output directory: LAW_sSEED.{toml,h5}, events.csv, series.csv,
    /// report.md, pack_friction.png.
    #[arg(long, short)]
    pub output: PathBuf,
    /// Amontons' mu.
    #[command(flatten)]
    pub matching: MatchingArgs,
    /// Threads and --force.
    #[command(flatten)]
    pub workers: Workers,
    /// How the free floes start: `linear` (the simple-shear profile of the
    /// first segment's speed) or `rest`.
    #[arg(long, value_parser = ["linear", "rest"], default_value = "linear")]
    pub initial_profile: String,
    /// Only write the runs' scenario files (LAW_sSEED.toml), for a job array.
    #[arg(long)]
    pub emit: bool,
    /// Only measure the runs already in the output directory (same flags as the run).
    #[arg(long, conflicts_with = "emit")]
    pub gather: bool,
    /// Most time steps each run may take.
    #[command(flatten)]
    pub step_limit: StepLimit,
}

impl Args {
    /// Runs, emits or gathers the cells; returns what was written.
    pub fn run(self) -> Result<String, CliError> {
        let mode = Mode::from_flags(self.emit, self.gather);
        let settings = self
            .set
            .iter()
            .map(|s| parse_setting(s))
            .collect::<Result<Vec<_>, _>>()?;
        let args = PackFrictionArgs {
            scenario: self.scenario,
            settings,
            laws: parse_laws(&self.laws)?,
            seeds: self.seeds,
            sample_every_s: self.sample_every,
            out_dir: self.output,
            threads: self.workers.threads,
            force: self.workers.force,
            mode,
            matching: self.matching.matching(),
            provenance: provenance(),
            registry: LawRegistry::builtin(),
            step_limit: self.step_limit.step_limit,
            linear_start: self.initial_profile == "linear",
        };
        let path = pack_friction::pack_friction(&args, &TerminalHooks { progress: false })?;
        Ok(match mode {
            Mode::Emit => format!(
                "scenario files written to {}; run each LAW_sSEED.toml with `floe run ... -o LAW_sSEED.h5`, then the same command with --gather",
                path.display()
            ),
            _ => format!("report: {}", path.display()),
        })
    }
}
