//! The floe life cycle's fracture: when a floe's stress breaks it
//! ([`criteria`]).

pub mod criteria;
