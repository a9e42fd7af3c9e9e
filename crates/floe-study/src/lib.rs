//! # floe-study
//!
//! What a study does with floe beyond stepping a world: runs a scenario
//! into a run file and resumes it ([`run_file`]), runs one scenario under
//! several friction laws and reports them side by side ([`compare`]), runs
//! the cartesian product of settings ([`sweep`]), measures runs
//! ([`compare::metrics`]), and draws them ([`render`], [`plot`]). The
//! `floe` command line is a thin layer over this crate; study scripts
//! (`examples/`) use it directly.
#![deny(missing_docs)]

pub mod cadence;
pub mod compare;
pub mod double_shear_protocol;
pub mod error;
pub mod grid_output;
pub mod partial_file;
pub mod plot;
pub mod render;
pub mod rheology;
pub mod run_file;
pub mod run_parallel;
pub mod same_file;
mod side_by_side;
pub mod sweep;
pub mod ticks;

pub use error::Error;
