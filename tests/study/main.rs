//! floe-study: double-shear protocols against the spring-slider, rheology,
//! gridded output read back (and by xarray), pictures and movies.

mod double_shear_protocols;
mod grid_output;
mod grid_xarray;
mod inherited_locks;
mod movie;
mod pack_friction;
mod picture_text;
#[path = "../support/pool.rs"]
mod pool_support;
mod render_land;
mod rheology;
#[path = "../support/study.rs"]
mod study_support;
mod table;
#[path = "../support/union.rs"]
mod union_support;
