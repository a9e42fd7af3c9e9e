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
    #[error("{}: {what}: {}", path.display(), condensed(source))]
    Hdf5 {
        /// The file.
        path: PathBuf,
        /// What was being done, e.g. `reading /particles/floes/position/value`.
        what: String,
        /// The library's error.
        #[source]
        source: hdf5::Error,
    },
    /// The file cannot grow: the device is full, a quota is reached, or the
    /// file-size limit (`ulimit -f`).
    #[error("{}: {reason} ({what}); what was flushed before stays readable, and if the file holds a checkpoint the run resumes from it once there is room: `floe run --resume -o {}`", path.display(), path.display())]
    NoSpace {
        /// The file.
        path: PathBuf,
        /// What was being done.
        what: String,
        /// The system's reason, e.g. `No space left on device (errno 28)`.
        reason: String,
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
            | IoError::NoSpace { path, .. }
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
        self.map_err(|source| {
            // ENOSPC, EDQUOT, EFBIG: the file cannot grow.
            let text = source.to_string();
            if let Some((message, errno @ (28 | 122 | 27))) = system_error(&text) {
                IoError::NoSpace {
                    path: path.to_path_buf(),
                    what: what(),
                    reason: format!("{message} (errno {errno})"),
                }
            } else {
                IoError::Hdf5 {
                    path: path.to_path_buf(),
                    what: what(),
                    source,
                }
            }
        })
    }
}

/// An HDF5 error on one line: a failed system call as its error message
/// and errno (HDF5 adds the buffer address, sizes and a timestamp).
fn condensed(e: &hdf5::Error) -> String {
    let text = e.to_string();
    match system_error(&text) {
        Some((message, errno)) => {
            let head = text.split(": time = ").next().unwrap_or("");
            format!("{head}: {message} (errno {errno})")
        }
        None => text.split_whitespace().collect::<Vec<_>>().join(" "),
    }
}

/// The message and errno of a failed system call in an HDF5 error
/// (`..., errno = 28, error message = 'No space left on device', ...`).
fn system_error(text: &str) -> Option<(&str, i32)> {
    let errno = text
        .split("errno = ")
        .nth(1)?
        .split(',')
        .next()?
        .trim()
        .parse()
        .ok()?;
    let message = text.split("error message = '").nth(1)?.split('\'').next()?;
    Some((message, errno))
}

/// An [`IoError::Invalid`] for `path`.
pub(crate) fn invalid(path: &Path, reason: impl Into<String>) -> IoError {
    IoError::Invalid {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What HDF5 1.10 says when a write hits a full disk.
    const FULL: &str =
        "H5F__accum_write(): file write failed: file write failed: time = Wed Nov 25 \
        18:41:59 2026\n, filename = '/tmp/tiny/s.h5', file descriptor = 3, errno = 28, error \
        message = 'No space left on device', buf = 0x7f11f085d753, total write size = 23372, bytes \
        this sub-write = 23372, bytes actually written = 18446744073709551615, offset = 0";

    #[test]
    fn a_full_disk_is_one_line_without_hdf5_internals() {
        let e: hdf5::Result<()> = Err(hdf5::Error::from(FULL));
        let message = e
            .at(Path::new("run.h5"), || "flushing".into())
            .unwrap_err()
            .to_string();
        assert!(
            message.starts_with("run.h5: No space left on device (errno 28) (flushing)"),
            "{message}"
        );
        assert!(
            !message.contains('\n') && !message.contains("18446744073709551615"),
            "{message}"
        );
        assert!(message.contains("floe run --resume -o run.h5"), "{message}");
    }

    #[test]
    fn other_system_errors_are_condensed_and_the_rest_kept() {
        let text = FULL
            .replace("errno = 28", "errno = 5")
            .replace("No space left on device", "Input/output error");
        let message = Err::<(), _>(hdf5::Error::from(text.as_str()))
            .at(Path::new("run.h5"), || "flushing".into())
            .unwrap_err()
            .to_string();
        assert_eq!(
            message,
            "run.h5: flushing: H5F__accum_write(): file write failed: file write failed: Input/output error (errno 5)"
        );
        let plain = Err::<(), _>(hdf5::Error::from("H5Dread(): can't read\n  data"))
            .at(Path::new("run.h5"), || "reading".into())
            .unwrap_err()
            .to_string();
        assert_eq!(plain, "run.h5: reading: H5Dread(): can't read data");
    }
}
