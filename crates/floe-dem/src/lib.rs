//! # floe-dem
//!
//! A discrete-element model of sea-ice floes: convex polygons with
//! thickness, in contact through elastic overlap forces and a tangential
//! spring limited by a friction law from `floe-friction`, driven by wind and
//! ocean drag, Coriolis and boundaries. No I/O: the HDF5 writer and the
//! scenario files live in other crates.
#![deny(missing_docs)]

pub mod error;
pub mod forcing;
pub mod tessellation;

pub use error::DemError;

/// The 2-D vector type of the engine (glam's `DVec2`, as used by parry).
pub use parry2d_f64::math::Vector as Vec2;
pub mod broad_phase;
pub mod checkpoint;
pub mod contact_kernel;
pub mod contacts;
pub mod floes;
pub mod geometry;
pub mod observables;
pub mod world;
