//! floe-scenario: the shipped scenario files, located errors for bad ones,
//! ice from gridded fields, land, stress-controlled walls, law variants
//! and sweep settings.

mod bad_input;
mod custom_law;
#[path = "../../crates/floe-scenario/examples/custom_law.rs"]
mod custom_law_example;
mod files;
mod grid_support;
mod ice_grid;
mod land;
mod law_variants;
#[path = "../support/pool.rs"]
mod pool_support;
mod settings;
mod stress_wall;
