//! The `floe` command line, as a library so that its pieces (input files with
//! located errors, plots, CSV) can be tested and reused by the documentation
//! generators.
#![deny(missing_docs)]

pub mod cli;
pub mod error;
// TEMP (until floe-io lands): pub mod info;
pub mod input;
pub mod plot;
pub mod protocol_file;
// TEMP (until floe-io lands): pub mod render;
// TEMP (until floe-io lands): pub mod run;
pub mod scenario;
pub mod series_csv;
pub mod slider;

pub use error::CliError;
