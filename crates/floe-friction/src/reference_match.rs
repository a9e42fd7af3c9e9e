//! How a comparison (`floe compare`, `floe rheology`) matches a law to its
//! rate-and-state reference: each registry entry says how its parameters
//! follow from the reference ([`crate::LawEntry::reference_match`]).

pub use crate::law::NumberStyle;
use crate::rate_state::RateState;

/// How a law is matched to the rate-and-state reference of a comparison.
#[derive(Debug, Clone, Copy)]
pub enum ReferenceMatch {
    /// The law takes no part in comparisons.
    Unmatched,
    /// The law is the reference: its variant is the reference's own
    /// `[friction]` table.
    Reference,
    /// The law's parameters are derived from the reference.
    Derived(DerivedMatch),
}

/// A law's parameters derived from the rate-and-state reference.
#[derive(Debug, Clone, Copy)]
pub struct DerivedMatch {
    /// The parameters (keys of the law's table, in the order the variant's
    /// `[friction]` table lists them) from the reference and the reference
    /// slip speed, m/s.
    pub params: fn(&RateState, f64) -> Vec<(&'static str, f64)>,
    /// One sentence for the comparison's notes on how they were chosen,
    /// from the same two.
    pub note: fn(&RateState, f64, &NumberStyle) -> String,
}
