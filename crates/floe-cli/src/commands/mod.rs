//! One module per `floe` command, each an `Args` (its flags, clap derive)
//! with a `run()` that returns what to print; [`options`] holds the flags
//! several commands share, [`values`] what each flag's value may be.

pub mod compare;
pub mod export;
pub mod grid;
pub mod info;
pub mod options;
pub mod pack_friction;
pub mod render;
pub mod rheology;
pub mod run;
pub mod slider;
pub mod sweep;
pub mod values;
