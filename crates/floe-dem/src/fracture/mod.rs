//! The floe life cycle's fracture: when a floe's stress breaks it
//! ([`criteria`]) and the pieces it breaks into ([`split`]).

pub mod criteria;
pub mod split;
