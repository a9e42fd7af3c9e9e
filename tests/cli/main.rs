//! floe-cli: the `floe` binary end to end (runs, pauses and resumes, bad
//! input, fuzzing, compare and sweep, slider, the documented commands, MPI)
//! and the workspace's module structure.

mod bad_input;
mod compare;
mod documented_commands;
mod fuzz;
mod fuzz_support;
#[cfg(feature = "mpi")]
mod mpi_run;
mod robustness;
mod run;
mod run_support;
mod slider;
mod workspace_modules;
