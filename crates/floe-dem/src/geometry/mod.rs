//! Floe geometry: shapes and their mass properties ([`shape`],
//! [`r3_moment`]), the overlap of two convex floes ([`clip`]), and a lower
//! bound on their distance for the broad phase ([`separation`]).

pub mod clip;
pub mod r3_moment;
pub mod separation;
pub mod shape;

pub use clip::{
    overlap, overlap_cached, ClipScratch, Oriented, Overlap, Placed, PlacedPolygon, SeparatingEdge,
};
pub use r3_moment::polygon_r3_moment;
pub use separation::separation_lower_bound;
pub use shape::FloeShape;

use crate::Vec2;

/// Most vertices a floe may have: the clipper's fixed buffers are sized
/// for it.
pub const MAX_VERTICES: usize = 32;

/// Counter-clockwise rotation of `v` by the angle whose cosine and sine are given.
#[inline(always)]
pub fn rotate(v: Vec2, cos: f64, sin: f64) -> Vec2 {
    Vec2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y)
}

/// `v` turned by +90 degrees.
#[inline(always)]
pub fn perp(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// z-component of the cross product `a x b`.
#[inline(always)]
pub fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}
