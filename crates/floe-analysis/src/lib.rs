//! # floe-analysis
//!
//! The metrics `floe compare` reports, as pure functions on arrays read from
//! a run's output: velocity profiles and shear-band width across a channel
//! ([`profile`]), slip events on contacts ([`slip_events`]), the stress
//! history of the assembly ([`stress`]) and of each floe ([`love_weber`]),
//! floes coarse-grained onto a grid
//! ([`grid_fields`]), the rheology of a shear cell
//! ([`rheology`]), whether a driven pack has jammed ([`jam`]), the ice area through a
//! gate across a strait ([`gate_flux`]), means
//! over time of series sampled unevenly ([`time_mean`]), and the errors of
//! means of correlated series and over seeds ([`uncertainty`]), and a
//! friction series' answer to velocity steps and holds ([`step_response`]).
//! No I/O and no engine types, so each
//! metric can be checked on a constructed case with a known answer.
#![deny(missing_docs)]

pub mod error;
pub mod gate_flux;
pub mod grid_fields;
pub mod jam;
pub mod love_weber;
mod polygon;
mod polygon_overlaps;
pub mod profile;
pub mod rheology;
pub mod slip_events;
pub mod step_response;
pub mod stress;
pub mod time_mean;
pub mod uncertainty;

pub use error::AnalysisError;
