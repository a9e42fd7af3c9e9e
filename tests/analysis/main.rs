//! floe-analysis: metrics on constructed cases with known answers, and
//! gridded fields of overlapping floes against independent references.

mod grid_overlaps;
mod metrics;
#[path = "../support/proptest_settings.rs"]
mod proptest_settings;
mod step_response;
mod uncertainty;
#[path = "../support/union.rs"]
mod union_support;
