//! The `floe` command line: the grammar ([`cli`]), one module per command
//! ([`commands`]: its flags and what it prints), [`progress_bar`] and the process's signals
//! ([`interrupt`]), and MPI when run under `mpirun` ([`processes`]). The work is done by the libraries: floe-scenario (files),
//! floe-dem (the engine and its run loop), floe-io (run files), floe-study
//! (runs, comparisons, sweeps, pictures).
#![deny(missing_docs)]

pub mod cli;
pub mod commands;
pub mod hooks;
pub mod interrupt;
pub mod processes;
pub mod progress_bar;
pub mod stderr;

/// Every failure of the command line: the libraries' errors, one message
/// and an exit code each.
pub type CliError = floe_run::Error;
