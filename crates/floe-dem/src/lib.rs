//! # floe-dem
//!
//! A discrete-element model of sea-ice floes: convex polygons with
//! thickness, in contact through elastic overlap forces and a tangential
//! spring limited by a friction law from `floe-friction`, driven by wind and
//! ocean drag, Coriolis and boundaries. No I/O: the HDF5 writer and the
//! scenario files live in other crates.
//!
//! * [`world`]: the [`World`](world::World): state, stages, edits;
//! * [`state`]: what a checkpoint holds; [`floes`], [`contacts`],
//!   [`energy_ledger`]: its parts;
//! * [`pipeline`]: the stages of a step (broad phase, narrow phase,
//!   friction, force gathering, integrator, energy accounting);
//! * [`contact_model`], [`contact_kernel`]: the contact's parameters and
//!   force formulas; [`forcing`]: wind, ocean, Coriolis;
//!   [`periodicity`]: periodic axes; [`motion_schedule`]: prescribed
//!   floes whose velocity follows segments in time; [`load_point`]: free
//!   floes driven through a spring from a moving point; [`stress_control`]:
//!   walls that hold a normal stress; [`geometry`], [`tessellation`]: floe
//!   shapes and how to make a pack of them; [`observables`]: assembly
//!   diagnostics; [`run`]: the stepping loop with its observer and cadences;
//!   [`exact_sum`]: sums of `f64` that do not depend on the order of the
//!   terms nor on how threads or ranks split them.
#![deny(missing_docs)]

pub mod contact_kernel;
pub mod contact_model;
pub mod contacts;
pub mod decomposition;
pub mod energy_ledger;
pub mod error;
pub mod exact_sum;
pub mod floes;
pub mod forcing;
pub mod geometry;
pub mod load_point;
pub mod motion_schedule;
pub mod observables;
pub mod periodicity;
pub mod pipeline;
pub mod run;
pub mod state;
pub mod stress_control;
pub mod tessellation;
pub mod world;

pub use error::DemError;

/// The 2-D vector type of the engine (glam's `DVec2`, as used by parry).
pub use parry2d_f64::math::Vector as Vec2;
