//! # floe-run
//!
//! A scenario run into a run file: [`run_file`] builds the world from a
//! scenario file, steps it and writes the HDF5 run file with its
//! checkpoints, resumes it, and stops cleanly on an interrupt or a
//! blow-up; [`run_parallel`] does the same over the processes of a
//! communicator (`mpirun`), bitwise as one process. [`Error`] is the one
//! error type of runs and of the studies built on them (`floe-study`),
//! with the exit code a command line gives each failure.
#![deny(missing_docs)]

pub mod error;
pub mod run_file;
pub mod run_parallel;
pub mod same_file;

pub use error::Error;
