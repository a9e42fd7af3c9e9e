//! Outputs written under a temporary name beside their target and renamed
//! onto it when complete: a failure, an error or a Ctrl-C never leaves a
//! half file under the target's name.

use std::path::{Path, PathBuf};

use floe_run::Error;

/// A file being written as `TARGET.partial`, renamed to `TARGET` by
/// [`PartialFile::commit`]; dropped without a commit, it is removed.
#[derive(Debug)]
pub struct PartialFile {
    partial: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl PartialFile {
    /// A partial file for `target`, with any left over from an earlier
    /// attempt (a killed process) removed.
    pub fn new(target: &Path) -> Self {
        let mut name = target
            .file_name()
            .map(|n| n.to_os_string())
            .unwrap_or_default();
        name.push(".partial");
        let partial = target.with_file_name(name);
        let _ = std::fs::remove_file(&partial);
        Self {
            partial,
            target: target.to_path_buf(),
            committed: false,
        }
    }

    /// Where to write.
    pub fn path(&self) -> &Path {
        &self.partial
    }

    /// Creates the (empty) partial file, so that a missing or read-only
    /// directory is reported by the system for the target, before any
    /// library (HDF5, NetCDF, ffmpeg) writes into it.
    pub fn create(&self) -> Result<std::fs::File, Error> {
        std::fs::File::create_new(&self.partial).map_err(|e| Error::io(&self.target, e))
    }

    /// The file it becomes.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Renames the finished file onto the target; returns the target.
    pub fn commit(mut self) -> Result<PathBuf, Error> {
        std::fs::rename(&self.partial, &self.target).map_err(|e| Error::io(&self.target, e))?;
        self.committed = true;
        Ok(self.target.clone())
    }
}

impl Drop for PartialFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.partial);
        }
    }
}
