//! # floe-scenario
//!
//! The files a floe user writes, read into engine objects with every
//! problem reported as one message at its file, line, column and key:
//!
//! * scenario files for DEM runs ([`Scenario`], every key in
//!   docs/scenarios.md): [`spec`] (the file as written), [`resolve`]
//!   (defaults and single-value checks), [`checks`] (values together),
//!   [`build`] (floes, walls, contact model, forcing, time step);
//! * spring-slider protocol files ([`protocol_file`]);
//! * friction-law tables in either, read through the law registry
//!   ([`law_table`]);
//! * edits of scenario text that keep it a valid file: `--set` settings
//!   ([`settings`]) and law variants for comparisons ([`law_variants`]).
//!
//! Depends on the engine, the friction laws and floe-basin (NetCDF and
//! GeoJSON inputs) only: no command-line,
//! plotting or terminal crates. Nothing here panics on input.
#![deny(missing_docs)]

pub mod build;
pub mod built_floes;
pub mod checks;
mod describe;
pub mod domain;
pub mod error;
pub mod exact;
mod extent;
pub mod gridded_inputs;
mod ice_grid;
pub mod ice_grid_keys;
pub mod input_paths;
mod land_build;
pub mod law_table;
pub mod law_variants;
mod length_limit;
mod motion_segments;
pub mod numbers;
pub mod output_cadence;
mod piece;
pub mod protocol_file;
pub mod resolve;
pub mod scenario;
pub mod settings;
mod size_distribution;
pub mod source_file;
pub mod spec;
pub mod start_time;
pub mod stress_wall;
mod tessellation;
pub mod value_ranges;

pub use domain::Domain;
pub use error::ScenarioError;
pub use gridded_inputs::InputFile;
pub use output_cadence::{OutputCadence, OutputWindow};
pub use resolve::{
    AUTO_DT_FRACTION, DEFAULT_ICE_DENSITY_KG_PER_M3, DEFAULT_MIN_AREA_FRACTION,
    DEFAULT_THICKNESS_M, MAX_LENGTH_M, MAX_OUTPUT_WINDOWS, MAX_RUN_STEPS, MAX_THICKNESS_M,
};
pub use scenario::{EngineParts, Scenario, Setup};
pub use source_file::SourceFile;
