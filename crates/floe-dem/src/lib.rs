//! # floe-dem
//!
//! A discrete-element model of sea-ice floes: convex polygons with
//! thickness, in contact through elastic overlap forces and a tangential
//! spring limited by a friction law from `floe-friction`, driven by wind and
//! ocean drag, Coriolis and boundaries. No I/O: the HDF5 writer and the
//! scenario files live in other crates.
//!
//! A step is four calls on a [`World`](world::World) (`drift`,
//! `detect_contacts`, `gather_forces`, `kick`); the stages, what each reads
//! and writes, and where to add a law, a forcing or a boundary are in
//! docs/dem.md ("Architecture"); the files of every crate are mapped once,
//! in README.md ("Layout").
#![deny(missing_docs)]

pub mod bond_kernel;
pub mod bonds;
pub mod cohesion;
pub mod contact_kernel;
pub mod contact_model;
pub mod contacts;
pub mod decomposition;
pub mod energy_ledger;
pub mod error;
pub mod exact_sum;
pub mod floes;
pub mod forcing;
pub mod fracture;
pub mod geometry;
pub mod load_point;
pub mod motion_schedule;
pub mod observables;
pub mod periodicity;
pub mod pipeline;
pub mod ridging;
pub mod run;
pub mod state;
pub mod stress_control;
pub mod tessellation;
pub mod welding;
pub mod world;

pub use error::DemError;

/// The 2-D vector type of the engine (glam's `DVec2`, as used by parry).
pub use parry2d_f64::math::Vector as Vec2;
