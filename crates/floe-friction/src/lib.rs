//! # floe-friction
//!
//! Friction laws for sea-ice contacts, after Lishman, Sammonds & Feltham
//! (2011), *A rate and state friction law for saline ice*, JGR 116, C05011.
//!
//! * [`law`]: the [`FrictionLaw`] trait and the per-contact [`ContactState`];
//!   [`any_law`]: the run-time choice of law, [`Law`];
//! * [`amontons`], [`rate_dependent`], [`rate_state`]: the three laws;
//!   [`state_evolution`]: slip and aging evolution of the state variable;
//! * [`params`]: parameter sets and the published presets;
//! * [`spring_slider`] and [`protocol`]: the paper's apparatus, driven by a
//!   load-point protocol; [`experiments`]: hold tests and velocity steps;
//! * [`registry`]: the laws files may name, with their parameter tables
//!   ([`law_table`]) and how a comparison matches each to the rate-and-state
//!   reference ([`reference_match`]);
//! * [`fit`]: least-squares fitting of law parameters to a measured series.
//!
//! The per-contact update ([`FrictionLaw::step`]) is the kernel the DEM
//! engine calls for every floe contact: it does not allocate and returns
//! finite numbers for any finite input.
#![deny(missing_docs)]

pub mod amontons;
pub mod any_law;
mod builtin_entries;
pub mod error;
pub mod fit;
pub mod law;
pub mod law_entry;
pub mod law_table;
pub mod params;
pub mod rate_dependent;
pub mod rate_state;
pub mod reference;
pub mod reference_match;
pub mod registry;
mod root;
pub mod state_evolution;

pub use amontons::Amontons;
pub use any_law::{CustomLaw, Law};
pub use error::FrictionError;
pub use law::{
    BatchItem, ContactLoad, ContactState, FrictionLaw, NumberStyle, StepOutcome, LAW_STATE_SLOTS,
};
pub use law_table::{LawContext, LawParams, ParamDefault, ParamKind, ParamSpec, ParamValue};
pub use params::RateStateParams;
pub use rate_dependent::RateDependent;
pub use rate_state::{Form, RateState};
pub use reference_match::{DerivedMatch, ReferenceMatch};
pub use registry::{LawEntry, LawParamError, LawRegistry};
pub use state_evolution::StateLaw;
pub mod experiments;
pub mod protocol;
pub mod spring_slider;
