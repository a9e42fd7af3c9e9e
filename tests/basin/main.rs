//! floe-basin: land from GeoJSON, its convex decomposition checked exactly
//! on generated coastlines.

mod land;
mod land_support;
