//! The one error type of runs, comparisons and sweeps: every failure is one
//! message for the user, with the exit code a command line gives it.

use std::path::PathBuf;

use thiserror::Error;

/// Everything a run, comparison or sweep can report to its user.
#[derive(Debug, Error)]
pub enum Error {
    /// A problem in a scenario or protocol file (located to line, column
    /// and key) or in a setting.
    #[error("{0}")]
    Scenario(#[from] floe_scenario::ScenarioError),
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
    /// Writing or reading a NetCDF file failed.
    #[error("{}: NetCDF: {message}", path.display())]
    NetCdf {
        /// The file.
        path: PathBuf,
        /// What the NetCDF library said.
        message: String,
    },
    /// Encoding a movie failed (ffmpeg or the GIF encoder).
    #[error("{}: could not write the movie: {message}", path.display())]
    Encode {
        /// The movie file.
        path: PathBuf,
        /// What went wrong.
        message: String,
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
    /// Writing or reading a run's HDF5 file failed.
    #[error("{0}")]
    Output(#[from] floe_io::IoError),
    /// A metric could not be computed from a run's output: floe-analysis's
    /// error, boxed so that running does not depend on the analysis crate
    /// (made by [`Error::analysis`]).
    #[error("{0}")]
    Analysis(#[source] Box<dyn std::error::Error + Send + Sync>),
    /// A distributed run could not be spread over its processes.
    #[error("{0}")]
    Parallel(#[from] floe_parallel::ParallelError),
    /// Another process of a distributed run failed; process 0 reports it.
    #[error("process {rank} of {processes}: {message}")]
    OnProcess {
        /// The process that failed.
        rank: usize,
        /// The number of processes.
        processes: usize,
        /// Its exit code.
        code: u8,
        /// What it said.
        message: String,
    },
    /// Process 0 of a distributed run reports this error; this process
    /// says nothing and exits with `code`.
    #[error("")]
    ReportedByRoot {
        /// The exit code.
        code: u8,
    },
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
    /// The gridded forcing stopped the run (a floe left its grid or
    /// reached missing values, a slice could not be read): the run had
    /// started, so, as a blow-up, exit code 1 (what the files are seen not
    /// to fit before the first step is a located scenario error, exit 2).
    #[error("{message}; the run stopped after step {step} of {}, whose checkpoint holds the last good state", output.display())]
    Forcing {
        /// The run's output file.
        output: PathBuf,
        /// The last step written.
        step: u64,
        /// What went wrong, naming the file.
        message: String,
    },
    /// Some variants of a sweep did not complete (each row says why).
    #[error("{failed} of {total} variants did not complete ({names}); their rows in {} say why", table.display())]
    VariantsFailed {
        /// How many failed.
        failed: usize,
        /// How many there were.
        total: usize,
        /// Their names.
        names: String,
        /// The results table.
        table: PathBuf,
    },
}

impl Error {
    /// Process exit code: 2 for bad input (files or flags), 130 for an
    /// interrupted run, 1 for everything else.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Scenario(e) if e.is_input() => 2,
            Error::Usage(_) | Error::WouldOverwrite(_) => 2,
            // A run file that is not there, or not a floe run file: bad input.
            Error::Output(
                floe_io::IoError::NotFound { .. }
                | floe_io::IoError::NotHdf5 { .. }
                | floe_io::IoError::NotFloeFile { .. }
                | floe_io::IoError::AlreadyExists { .. },
            ) => 2,
            // 128 + SIGINT, as a shell reports a process stopped by Ctrl-C.
            Error::Interrupted { .. } => 130,
            Error::OnProcess { code, .. } | Error::ReportedByRoot { code } => *code,
            // More processes than floes, subdomains narrower than a floe:
            // the command line asked for it.
            Error::Parallel(
                floe_parallel::ParallelError::MoreProcessesThanFloes { .. }
                | floe_parallel::ParallelError::SubdomainTooSmall { .. },
            ) => 2,
            _ => 1,
        }
    }

    /// An [`Error::Analysis`] carrying `e` (floe-analysis's error) as it is.
    pub fn analysis(e: impl std::error::Error + Send + Sync + 'static) -> Self {
        Error::Analysis(Box::new(e))
    }

    /// An [`Error::Io`] for `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
