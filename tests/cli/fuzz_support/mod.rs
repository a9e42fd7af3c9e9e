//! The seeded fuzz test of `tests/cli/fuzz.rs`: its base inputs, the
//! mutations of files and command lines, the cases a seed draws, running a
//! case, checking its outcome and reporting failures.
//!
//! Modules, each using only those listed before it:
//! - `text`: small text helpers;
//! - `base_inputs`: the valid inputs, from `tests/data/fuzz/`;
//! - `toml_scan`: statements, numbers and arrays of an input found by scanning;
//! - `file_mutations`: mutations of an input file;
//! - `basin_files`: mutations of the basin scenario's NetCDF and GeoJSON
//!   files and of the keys naming them;
//! - `templates`: the valid command lines;
//! - `command_lines`: mutations of a command line;
//! - `cases`: the cases of a seed;
//! - `runner`: running one case;
//! - `outcome`: checking one case's outcome;
//! - `report`: failures and the summary;
//! - `pool`: running all cases, a few at a time.

mod base_inputs;
mod basin_files;
mod cases;
mod command_lines;
mod file_mutations;
mod outcome;
mod pool;
mod report;
mod runner;
mod templates;
mod text;
mod toml_scan;

pub use cases::{all_cases, seed, Case};
pub use pool::run_all;
pub use runner::fixtures;

/// What a case's exit must be, beyond the contract every case obeys.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Expect {
    /// Any of 0, 1, 2 (with the matching messages).
    Anything,
    /// Exit 0: an unmutated base input.
    Success,
    /// Exit 2: the input can never be valid.
    Refusal,
    /// Exit 1 or 2: a missing or wrong file.
    Failure,
}
