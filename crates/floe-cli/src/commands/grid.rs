//! `floe grid`: a run's snapshots coarse-grained onto a regular grid.

use std::path::PathBuf;

use floe_study::cadence::Cadence;
use floe_study::grid_output::{self, GridArgs};

use super::values::positive;
use crate::CliError;

/// Coarse-grain a run's snapshots onto a regular grid (concentration,
/// thickness, velocity, stress, strain rates) and write CF NetCDF.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run's HDF5 file.
    pub file: PathBuf,
    /// Output NetCDF file.
    #[arg(long, short)]
    pub output: PathBuf,
    /// Largest cell size, m: the domain is split into whole cells of at most this.
    #[arg(long, value_name = "M")]
    pub cell_m: f64,
    /// Grid every K-th snapshot (default: every snapshot).
    #[arg(long, value_name = "K", conflicts_with = "interval_s")]
    pub every: Option<usize>,
    /// Grid the snapshot nearest to each multiple of T seconds (0, T,
    /// 2T, ...) that has one within T/2.
    #[arg(long, value_name = "T", value_parser = positive)]
    pub interval_s: Option<f64>,
    /// Replace an existing output.
    #[arg(long)]
    pub force: bool,
}

impl Args {
    /// Writes the gridded fields; returns where.
    pub fn run(self) -> Result<String, CliError> {
        let cadence = match (self.every, self.interval_s) {
            (Some(k), _) => Cadence::Every(k),
            (None, Some(t)) => Cadence::IntervalS(t),
            (None, None) => Cadence::All,
        };
        let path = grid_output::write_grid(&GridArgs {
            run: self.file,
            output: self.output,
            cell_m: self.cell_m,
            cadence,
            force: self.force,
        })?;
        Ok(format!("gridded fields: {}", path.display()))
    }
}
