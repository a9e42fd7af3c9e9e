//! Floe geometry: shapes and their mass properties ([`shape`]), and the
//! overlap of two convex floes ([`clip`]).

pub mod clip;
pub mod shape;

pub use clip::{overlap, overlap_cached, ClipScratch, Overlap, Placed, SeparatingEdge};
pub use shape::FloeShape;

use crate::Vec2;

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
