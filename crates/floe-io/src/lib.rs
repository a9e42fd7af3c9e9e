//! # floe-io
//!
//! HDF5 output of floe runs in the H5MD 1.1 layout, readable with h5py
//! without floe (docs/output.md describes every group and dataset):
//! snapshots of the floes and their contacts, assembly observables, the
//! run's provenance, and checkpoints that a run resumes from bitwise.
//!
//! [`RunWriter`] creates and appends to a file (and is the stepping loop's
//! observer, [`observer`]); [`RunFile`] reads one.
//! Checkpoints live in two slots written alternately, with the valid one
//! switched only after the new one is flushed, so a process killed at any
//! moment leaves a file that [`RunWriter::reopen_for_resume`] continues.
#![deny(missing_docs)]

mod appendable;
pub mod checkpoint;
mod element;
pub mod error;
mod event_log;
mod floe_group;
pub mod fracture_log;
mod h5;
mod headroom;
pub mod layout;
pub mod metadata;
pub mod observer;
pub mod reader;
pub mod ridging_log;
pub mod run_status;
pub mod welding_log;
pub mod writer;
pub mod xdmf;

pub use error::IoError;
pub use metadata::{CheckpointInfo, DomainBox, InputRecord, OutputOptions, RunMetadata};
pub use reader::{ContactSnapshot, RunFile, Series, Snapshot, StaticFloes};
pub use writer::RunWriter;
