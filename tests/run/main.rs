//! floe-run: scenarios run into run files, with gridded NetCDF forcing and
//! with a friction law registered outside floe-friction.

mod basin_forcing;
mod custom_law;
#[path = "../../crates/floe-scenario/examples/custom_law.rs"]
#[allow(dead_code)] // these tests use the law and its registration only
mod custom_law_example;
#[path = "../support/study.rs"]
mod study_support;
