//! The one error type of the command line: every failure becomes one message
//! and an exit code, never a panic.

use std::path::PathBuf;

use thiserror::Error;

/// Everything `floe` can report to its user.
#[derive(Debug, Error)]
pub enum CliError {
    /// A problem in a file the user wrote, located to line and column.
    #[error("{file}:{line}:{column}: {}{message}", key.as_ref().map(|k| format!("`{k}`: ")).unwrap_or_default())]
    Input {
        /// The input file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The key (dotted path) the problem is about, when there is one.
        key: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A bad command-line value.
    #[error("{0}")]
    Usage(String),
    /// A file that would be overwritten without `--force`.
    #[error("{0}: already exists; pass --force to overwrite it")]
    WouldOverwrite(PathBuf),
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// Drawing a plot failed.
    #[error("{path}: could not draw the plot: {message}")]
    Plot {
        /// The image file.
        path: PathBuf,
        /// What the plotting library said.
        message: String,
    },
    /// The friction library refused a parameter or a fit failed.
    #[error("{0}")]
    Friction(#[from] floe_friction::FrictionError),
    /// The DEM engine refused its input (outside a scenario file, e.g. a
    /// damaged checkpoint).
    #[error("{0}")]
    Engine(#[from] floe_dem::DemError),
    // TEMP (until floe-io lands):
    // /// Writing or reading a run's HDF5 file failed.
    // #[error("{0}")]
    // Output(#[from] floe_io::IoError),
    /// The run was interrupted (Ctrl-C, SIGTERM) and stopped cleanly.
    #[error("interrupted at step {step}; final snapshot and checkpoint written to {}; continue with `floe run --resume {}`", output.display(), output.display())]
    Interrupted {
        /// The run's output file.
        output: PathBuf,
        /// The step it stopped at.
        step: u64,
    },
    /// The state went non-finite or floes overlapped beyond reason.
    #[error("{message}; last snapshot written to {}, its checkpoint holds the last good state", output.display())]
    BlowUp {
        /// The run's output file.
        output: PathBuf,
        /// What happened, where, and the suggested time step.
        message: String,
    },
}

impl CliError {
    /// Process exit code: 2 for bad input (files or flags), 130 for an
    /// interrupted run, 1 for everything else.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Input { .. } | CliError::Usage(_) | CliError::WouldOverwrite(_) => 2,
            // 128 + SIGINT, as a shell reports a process stopped by Ctrl-C.
            CliError::Interrupted { .. } => 130,
            _ => 1,
        }
    }

    /// An [`CliError::Io`] for `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        CliError::Io {
            path: path.into(),
            source,
        }
    }
}
