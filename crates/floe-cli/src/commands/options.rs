//! Options several commands share, flattened into each command's `Args`.
//! A command whose help words an option differently says so with
//! `#[command(mut_arg(NAME, |a| a.help(...)))]`.

use floe_friction::LawRegistry;
use floe_scenario::law_variants::{LawChoice, Matching};
use floe_study::compare::metrics::MetricOptions;

use super::values::{
    above_one, friction_coefficient, load_point_speed, positive, profile_bins, step_count,
};
use crate::CliError;

/// `--threads` and `--force` of the commands that run scenarios.
#[derive(Debug, Clone, clap::Args)]
pub struct Workers {
    /// Worker threads per run.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Replace existing outputs.
    #[arg(long)]
    pub force: bool,
}

/// `--step-limit` of the commands that run scenarios.
#[derive(Debug, Clone, clap::Args)]
pub struct StepLimit {
    /// Most time steps each run may take (default 1e9); a longer one is
    /// refused before anything runs.
    #[arg(long, value_name = "N", default_value_t = floe_scenario::MAX_RUN_STEPS, value_parser = step_count)]
    pub step_limit: f64,
}

/// How Amontons' mu is matched to rate-and-state (`floe compare`, `floe rheology`).
#[derive(Debug, Clone, clap::Args)]
pub struct MatchingArgs {
    /// Slip speed at which Amontons' mu equals the rate-and-state steady state, m/s.
    #[arg(long, default_value_t = 1e-2, value_name = "M_PER_S", value_parser = load_point_speed)]
    pub reference_slip_speed: f64,
    /// Give Amontons' mu explicitly instead.
    #[arg(long, value_name = "MU", value_parser = friction_coefficient, conflicts_with = "reference_slip_speed")]
    pub amontons_mu: Option<f64>,
}

impl MatchingArgs {
    /// The matching the flags ask for.
    pub fn matching(&self) -> Matching {
        Matching {
            reference_slip_m_per_s: self.reference_slip_speed,
            amontons_mu: self.amontons_mu,
        }
    }
}

/// The laws of a comma-separated `--laws` list, from the built-in registry.
pub fn parse_laws(laws: &str) -> Result<Vec<LawChoice>, CliError> {
    Ok(LawChoice::parse_list(laws, &LawRegistry::builtin())?)
}

/// `floe compare` / `floe sweep` metric options shared by both.
#[derive(Debug, Clone, clap::Args)]
pub struct MetricArgs {
    /// Bins across the channel for the velocity profile.
    #[arg(long, default_value_t = 25, value_parser = profile_bins)]
    pub profile_bins: usize,
    /// A slip event: the slip rate jumps by at least this factor between snapshots...
    #[arg(long, default_value_t = 10.0, value_parser = above_one)]
    pub slip_jump: f64,
    /// ...to at least this slip rate, m/s.
    #[arg(long, default_value_t = 1e-3, value_parser = positive)]
    pub slip_min_rate: f64,
}

impl MetricArgs {
    /// The metrics' options.
    pub fn options(&self) -> MetricOptions {
        MetricOptions {
            profile_bins: self.profile_bins,
            slip: floe_analysis::slip_events::SlipEventRule {
                jump_factor: self.slip_jump,
                min_rate_m_per_s: self.slip_min_rate,
            },
            ..Default::default()
        }
    }
}
