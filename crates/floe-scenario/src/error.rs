//! The one error type of scenario and protocol files: a problem located in
//! the file (line, column, key), or the file unreadable.

use std::path::PathBuf;

use thiserror::Error;

/// What can go wrong reading or building a scenario or protocol file.
#[derive(Debug, Error)]
pub enum ScenarioError {
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
    /// A bad value from the command line (a `--set` setting, a law list),
    /// naming the flag.
    #[error("{0}")]
    Usage(String),
    /// Reading the file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The DEM engine refused what the file built (a check the file's own
    /// checks did not anticipate).
    #[error("{0}")]
    Engine(#[from] floe_dem::DemError),
    /// The friction library refused a value outside a file's keys.
    #[error("{0}")]
    Friction(#[from] floe_friction::FrictionError),
}

impl ScenarioError {
    /// A [`ScenarioError::Io`] for `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        ScenarioError::Io {
            path: path.into(),
            source,
        }
    }

    /// Whether the file is at fault (a located input error), as opposed to
    /// the system or the engine.
    pub fn is_input(&self) -> bool {
        match self {
            ScenarioError::Input { .. } | ScenarioError::Usage(_) => true,
            // A file named that is not there, or is a directory, is a bad
            // argument; other read errors (permissions, I/O) are not.
            ScenarioError::Io { source, .. } => matches!(
                source.kind(),
                std::io::ErrorKind::NotFound | std::io::ErrorKind::IsADirectory
            ),
            _ => false,
        }
    }
}
