//! The `floe` command line, as a library so that its pieces (input files with
//! located errors, plots, CSV) can be tested and reused by the documentation
//! generators.
#![deny(missing_docs)]

pub mod cli;
pub mod compare;
pub mod error;
pub mod info;
pub mod input;
pub mod plot;
pub mod protocol_file;
pub mod render;
pub mod run;
pub mod scenario;
pub mod series_csv;
pub mod slider;
pub mod sweep;

pub use error::CliError;
