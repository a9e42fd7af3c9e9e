//! The crate's one error type. Every message starts with the file's path and
//! says what is wrong with it.

use std::path::{Path, PathBuf};

/// Why reading or writing a run file failed.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The output file exists; floe never overwrites one.
    #[error("{}: already exists; floe does not overwrite output files (remove it first, or run with --force)", path.display())]
    AlreadyExists {
        /// The file.
        path: PathBuf,
    },
    /// The file does not exist.
    #[error("{}: no such file", path.display())]
    NotFound {
        /// The file.
        path: PathBuf,
    },
    /// The output file could not be created.
    #[error("{}: cannot create the output file: {reason}", path.display())]
    CannotCreate {
        /// The file.
        path: PathBuf,
        /// What stood in the way.
        reason: String,
    },
    /// The file exists but is not an HDF5 file.
    #[error("{}: not an HDF5 file (no HDF5 signature)", path.display())]
    NotHdf5 {
        /// The file.
        path: PathBuf,
    },
    /// An HDF5 file, but not one written by floe (or by a newer floe).
    #[error("{}: not a floe run file: {reason}", path.display())]
    NotFloeFile {
        /// The file.
        path: PathBuf,
        /// What is missing or unexpected.
        reason: String,
    },
    /// The file holds no checkpoint to resume from.
    #[error("{}: holds no valid checkpoint to resume from (the run was stopped before its first checkpoint)", path.display())]
    NoCheckpoint {
        /// The file.
        path: PathBuf,
    },
    /// A checkpoint failed its checks (checksum, format, consistency).
    #[error("{}: checkpoint {slot} is damaged: {reason}", path.display())]
    CorruptCheckpoint {
        /// The file.
        path: PathBuf,
        /// The slot, e.g. `/checkpoint/slot1`.
        slot: String,
        /// What failed.
        reason: String,
    },
    /// The file's content does not fit together, or a request does not fit
    /// the file (an index past the end, an unknown observable, a world with
    /// another floe count than the file's).
    #[error("{}: {reason}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        reason: String,
    },
    /// The HDF5 library refused an operation.
    #[error("{}: {what}: {source}", path.display())]
    Hdf5 {
        /// The file.
        path: PathBuf,
        /// What was being done, e.g. `reading /particles/floes/position/value`.
        what: String,
        /// The library's error.
        #[source]
        source: hdf5::Error,
    },
    /// An operating-system error outside HDF5.
    #[error("{}: {source}", path.display())]
    Os {
        /// The file.
        path: PathBuf,
        /// The error.
        #[source]
        source: std::io::Error,
    },
}

impl IoError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            IoError::AlreadyExists { path }
            | IoError::NotFound { path }
            | IoError::CannotCreate { path, .. }
            | IoError::NotHdf5 { path }
            | IoError::NotFloeFile { path, .. }
            | IoError::NoCheckpoint { path }
            | IoError::CorruptCheckpoint { path, .. }
            | IoError::Invalid { path, .. }
            | IoError::Hdf5 { path, .. }
            | IoError::Os { path, .. } => path,
        }
    }
}

/// Attaches the file and the operation to an HDF5 error.
pub(crate) trait Context<T> {
    /// `Err(e)` becomes [`IoError::Hdf5`] naming `path` and `what`.
    fn at(self, path: &Path, what: impl FnOnce() -> String) -> Result<T, IoError>;
}

impl<T> Context<T> for hdf5::Result<T> {
    fn at(self, path: &Path, what: impl FnOnce() -> String) -> Result<T, IoError> {
        self.map_err(|source| IoError::Hdf5 {
            path: path.to_path_buf(),
            what: what(),
            source,
        })
    }
}

/// An [`IoError::Invalid`] for `path`.
pub(crate) fn invalid(path: &Path, reason: impl Into<String>) -> IoError {
    IoError::Invalid {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}
