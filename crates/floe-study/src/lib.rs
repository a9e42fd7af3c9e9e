//! # floe-study
//!
//! What a study does with the runs of `floe-run`: runs one scenario under
//! several friction laws and reports them side by side ([`compare`]), runs
//! the cartesian product of settings ([`sweep`]), measures runs
//! ([`compare::metrics`]), and draws them ([`render`], [`plot`]). The
//! `floe` command line is a thin layer over this crate and `floe-run`;
//! study scripts (`examples/`) use them directly.
#![deny(missing_docs)]

pub mod cadence;
mod cell_study;
pub mod compare;
pub mod double_shear_protocol;
pub mod floe_sizes;
pub mod grid_output;
pub mod pack_friction;
pub mod partial_file;
pub mod plot;
pub mod render;
pub mod rheology;
mod side_by_side;
pub mod sweep;
pub mod ticks;

/// The error type of runs, which studies report too (`floe-run`).
pub use floe_run::Error;
