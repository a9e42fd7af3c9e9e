//! `floe rheology`: mu(I) of a sheared constant-pressure cell.

use std::path::PathBuf;

use floe_friction::LawRegistry;
use floe_scenario::settings::parse_setting;
use floe_study::rheology::{self, RheologyArgs};

use super::options::{parse_laws, MatchingArgs, StepLimit, Workers};
use crate::hooks::{provenance, TerminalHooks};
use crate::CliError;

/// Shear a constant-pressure cell at several wall speeds under several
/// laws; report mu = tau/P and the solid fraction against the inertial
/// number, with a fit of mu(I).
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("threads", |a| a.help("Total thread budget; runs go side by side, one thread each")),
    mut_arg("step_limit", |a| a.help("Most time steps each run may take (default 1e9)")),
)]
pub struct Args {
    /// Shear-cell scenario (periodic along x; bottom wall; top wall
    /// holding normal_stress_n_per_m), e.g. scenarios/shear_cell.toml.
    pub scenario: PathBuf,
    /// KEY=VALUE: a dotted scenario key set before the runs are made
    /// (repeatable; one value each), e.g. contact.youngs_modulus_pa=6e7 or
    /// dt_s=0.25.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Laws, comma-separated.
    #[arg(long, default_value = "amontons,rate-state")]
    pub laws: String,
    /// The top wall's speeds along x, m/s, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "0.005,0.02,0.1,0.5,2")]
    pub speeds: Vec<f64>,
    /// Seeds, comma-separated: every law and speed is run once per seed
    /// (the scenario's `seed`, which draws the tessellation); runs are
    /// named LAW_vSPEED_sSEED and the report gives the mean over seeds
    /// with its 95 % confidence interval. Default: the scenario's seed.
    #[arg(long, value_delimiter = ',')]
    pub seeds: Vec<u64>,
    /// Shear strain of each run (its duration is strain x domain height / speed).
    #[arg(long, default_value_t = 6.0)]
    pub strain: f64,
    /// Snapshots per run (the samples measured).
    #[arg(long, default_value_t = 300)]
    pub snapshots: usize,
    /// Fraction of each run left out of the means (start-up).
    #[arg(long, default_value_t = 1.0 / 3.0)]
    pub transient: f64,
    /// Output directory: LAW_vSPEED[_sSEED].{toml,h5}, results.csv,
    /// over_seeds.csv (with --seeds), report.md, rheology.png.
    #[arg(long, short)]
    pub output: PathBuf,
    /// Amontons' mu.
    #[command(flatten)]
    pub matching: MatchingArgs,
    /// Threads and --force.
    #[command(flatten)]
    pub workers: Workers,
    /// How the free floes start: `linear` (the simple-shear profile
    /// from the fixed wall to the moving one, so that the flow need not
    /// diffuse across the layer from the moving wall first) or `rest`.
    #[arg(long, value_parser = ["linear", "rest"], default_value = "linear")]
    pub initial_profile: String,
    /// Only write the runs' scenario files (LAW_vSPEED[_sSEED].toml), for a job array.
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
    /// Runs, emits or gathers the shear runs; returns what was written.
    pub fn run(self) -> Result<String, CliError> {
        let mode = rheology::Mode::from_flags(self.emit, self.gather);
        let settings = self
            .set
            .iter()
            .map(|s| parse_setting(s))
            .collect::<Result<Vec<_>, _>>()?;
        let args = RheologyArgs {
            scenario: self.scenario,
            settings,
            laws: parse_laws(&self.laws)?,
            speeds_m_per_s: self.speeds,
            seeds: self.seeds,
            strain: self.strain,
            snapshots: self.snapshots,
            transient_fraction: self.transient,
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
        let path = rheology::rheology(&args, &TerminalHooks { progress: false })?;
        Ok(match mode {
            rheology::Mode::Emit => format!(
                "scenario files written to {}; run each LAW_vSPEED[_sSEED].toml with `floe run ... -o LAW_vSPEED[_sSEED].h5`, then the same command with --gather",
                path.display()
            ),
            _ => format!("report: {}", path.display()),
        })
    }
}
