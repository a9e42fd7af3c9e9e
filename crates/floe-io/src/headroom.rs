//! Room claimed ahead of the writer. HDF5 1.10 does not survive a write
//! that fails inside a flush: it has already written a superblock whose
//! end-of-file covers data that never arrived, and no reader opens the
//! file again ("truncated file"). So before each batch of writes the bytes
//! it may take are allocated past the end of the file (`fallocate`, or
//! zeros written where the filesystem has no `fallocate`): a full disk, a
//! quota or a file-size limit then fails here, before HDF5 has written
//! anything, and the file stays as its last flush left it.
//!
//! Bytes past HDF5's end of allocation are allowed (HDF5 refuses only a
//! file shorter than it recorded) and are overwritten as the file grows.
//! Copy-on-write filesystems (btrfs, ZFS) allocate again on overwrite, so
//! there the claim narrows the window rather than closing it.

use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::Path;

use crate::error::IoError;

/// The least room claimed before a batch, bytes.
const MIN_CLAIM_BYTES: u64 = 1 << 20;

/// Keeps room past the end of a run file.
#[derive(Debug)]
pub(crate) struct Headroom {
    file: File,
    /// HDF5's end of the file at the last claim.
    last_end: u64,
    /// The most the file grew between two claims.
    largest_growth: u64,
}

impl Headroom {
    /// Opens `path` (a run file HDF5 has open) to claim room in it.
    pub(crate) fn open(path: &Path, hdf5_end: u64) -> Result<Self, IoError> {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|source| os(path, source))?;
        Ok(Self {
            file,
            last_end: hdf5_end,
            largest_growth: 0,
        })
    }

    /// Makes sure at least `estimate` bytes (and twice the largest growth
    /// seen between two claims, and at least 1 MiB) lie allocated past
    /// `hdf5_end`, the end of HDF5's allocation.
    pub(crate) fn claim(
        &mut self,
        path: &Path,
        hdf5_end: u64,
        estimate: u64,
    ) -> Result<(), IoError> {
        let on_disk = self.file.metadata().map_err(|e| os(path, e))?.len();
        self.largest_growth = self
            .largest_growth
            .max(hdf5_end.saturating_sub(self.last_end));
        self.last_end = hdf5_end;
        let want = hdf5_end + estimate.max(2 * self.largest_growth).max(MIN_CLAIM_BYTES);
        if on_disk >= want {
            return Ok(());
        }
        self.fill(on_disk, want).map_err(|source| {
            // Give the bytes back, so the file is as HDF5 left it.
            let _ = self.file.set_len(on_disk);
            match source.raw_os_error() {
                // ENOSPC, EDQUOT, EFBIG: the file cannot grow.
                Some(28 | 122 | 27) => no_room(path, source),
                _ => os(path, source),
            }
        })
    }

    /// Gives back the room past `hdf5_end` (when the writer is done and
    /// HDF5 has flushed: no byte of its lies past its end).
    pub(crate) fn give_back(&mut self, hdf5_end: u64) {
        if self.file.metadata().is_ok_and(|m| m.len() > hdf5_end) {
            let _ = self.file.set_len(hdf5_end);
        }
    }

    /// Allocates `[from, to)`, past the last byte HDF5 wrote: with
    /// `fallocate` (no data written), else by writing zeros and syncing
    /// them (NFS reports a full disk only when written data reaches it).
    fn fill(&mut self, from: u64, to: u64) -> std::io::Result<()> {
        use rustix::fs::{fallocate, FallocateFlags};
        match fallocate(&self.file, FallocateFlags::empty(), from, to - from) {
            Ok(()) => return Ok(()),
            Err(e) if e == rustix::io::Errno::OPNOTSUPP || e == rustix::io::Errno::NOSYS => {}
            Err(e) => return Err(e.into()),
        }
        const BLOCK: usize = 1 << 16;
        let zeros = [0u8; BLOCK];
        self.file.seek(SeekFrom::Start(from))?;
        let mut left = to - from;
        while left > 0 {
            let n = left.min(BLOCK as u64) as usize;
            self.file.write_all(&zeros[..n])?;
            left -= n as u64;
        }
        self.file.sync_data()
    }
}

fn os(path: &Path, source: std::io::Error) -> IoError {
    IoError::Os {
        path: path.to_path_buf(),
        source,
    }
}

fn no_room(path: &Path, source: std::io::Error) -> IoError {
    let errno = source.raw_os_error().unwrap_or(0);
    let reason = format!("{} (errno {errno})", plain(&source));
    IoError::NoSpace {
        path: path.to_path_buf(),
        what: "making room for the next write".to_string(),
        reason,
    }
}

/// The OS's message without Rust's ` (os error N)` suffix.
fn plain(e: &std::io::Error) -> String {
    let text = e.to_string();
    match text.find(" (os error") {
        Some(i) => text[..i].to_string(),
        None => text,
    }
}
