//! NetCDF files and the programs tests start (python, ffmpeg, ffprobe): a
//! started program inherits every file the test process has open, with its
//! HDF5 file lock, and holds the lock for its lifetime, so a test opening
//! that file again fails (NetCDF: HDF error). Tests that open NetCDF files
//! hold [`netcdf_files`]; tests that start programs hold
//! [`starting_programs`], which waits until no NetCDF file is open.

use std::sync::{RwLock, RwLockReadGuard, RwLockWriteGuard};

static OPEN_NETCDF: RwLock<()> = RwLock::new(());

/// Held while a test has NetCDF files open (shared between such tests).
pub fn netcdf_files() -> RwLockReadGuard<'static, ()> {
    OPEN_NETCDF.read().unwrap_or_else(|e| e.into_inner())
}

/// Held while a test starts programs (alone).
pub fn starting_programs() -> RwLockWriteGuard<'static, ()> {
    OPEN_NETCDF.write().unwrap_or_else(|e| e.into_inner())
}
