//! # floe-basin
//!
//! What a run over a real basin needs beyond the engine: forcing read from
//! gridded CF NetCDF files (wind, ocean current, sea-surface height),
//! coastlines and islands from GeoJSON as fixed bodies, initial ice placed
//! from concentration and thickness grids, and the map projection that
//! puts longitude and latitude onto the model plane.
//!
//! Land: [`coastline`] reads the polygons of a GeoJSON file onto the model
//! plane, checked simple by [`simple_ring`] (a sweep line,
//! [`ring_crossing`]); [`convex_pieces`] cuts each exactly into convex
//! pieces of at most a given size (from a triangulation,
//! [`ring_triangulation`]); [`land`] holds the pieces with a grid for
//! overlap queries.
//!
//! Forcing: [`cf_file`] reads CF NetCDF (a damaged file is an error naming
//! it, never a crash: [`classic_header`], [`native_guard`]);
//! [`netcdf_source`] samples its variables onto the model plane, refusing
//! values beyond a [`value_limit`].
#![deny(missing_docs)]

pub mod coastline;
pub mod convex_pieces;
pub mod error;
pub mod land;
pub mod planar;
pub mod projection;
pub mod ring_crossing;
pub mod ring_triangulation;
pub mod simple_ring;

pub use coastline::{read_land, Coordinates, LandPolygon};
pub use error::BasinError;
pub use land::Land;
pub use projection::MapProjection;
pub mod cf_file;
pub mod cf_time;
pub mod checksum;
pub mod classic_header;
pub mod ice_fields;
pub mod native_guard;
pub mod netcdf_source;
pub mod scalar_grid;
pub mod value_limit;

pub use ice_fields::{open_concentration, open_thickness, ConcentrationGrid, ConcentrationUnits};
pub use netcdf_source::{FieldRequest, NetcdfSource};
pub use scalar_grid::{ScalarGrid, ScalarRequest};
pub use value_limit::ValueLimit;
