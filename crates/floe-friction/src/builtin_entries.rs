//! The built-in laws' registry entries: name, parameter table, how to build
//! the law and how a comparison matches it to the rate-and-state reference.
//! Kept apart from the laws' files so that a law's kernel does not depend
//! on the enum of all laws ([`Law`]) that holds it.

use crate::amontons::{self, Amontons};
use crate::any_law::Law;
use crate::law::{FrictionLaw, NumberStyle};
use crate::law_entry::LawEntry;
use crate::rate_dependent::{self, RateDependent};
use crate::rate_state::{self, RateState};
use crate::reference_match::{DerivedMatch, ReferenceMatch};

/// Amontons' registry entry. In a comparison its `mu` is the reference's
/// steady state at the reference slip speed.
pub const AMONTONS: LawEntry = LawEntry {
    name: "amontons",
    summary: "constant friction coefficient (Coulomb on a tangential spring)",
    params: amontons::PARAMS,
    build: |p| Ok(Law::Amontons(Amontons::from_params(p))),
    reference_match: ReferenceMatch::Derived(DerivedMatch {
        params: |reference, v| vec![("mu", reference.mu_steady(v))],
        note: amontons_note,
    }),
};

fn amontons_note(reference: &RateState, v: f64, style: &NumberStyle) -> String {
    format!(
        "Amontons: mu = {}, the rate-and-state steady state at the reference slip speed {} m/s (`--reference-slip-speed`).",
        (style.parameter)(reference.mu_steady(v)),
        (style.parameter)(v)
    )
}

/// The rate law's registry entry. In a comparison it takes the reference's
/// `mu0` and `V*` with `C1 = A - B`: the same steady state as the
/// published form, without memory.
pub const RATE_DEPENDENT: LawEntry = LawEntry {
    name: "rate",
    summary: "rate-dependent friction, eq. 2: mu = mu0 + c1 ln(V/V*)",
    params: rate_dependent::PARAMS,
    build: |p| Ok(Law::RateDependent(RateDependent::from_params(p))),
    reference_match: ReferenceMatch::Derived(DerivedMatch {
        params: |reference, _| {
            let p = reference.params;
            vec![
                ("mu0", p.mu0),
                ("c1", p.a - p.b),
                ("v_star_m_per_s", p.v_star_m_per_s),
            ]
        },
        note: rate_note,
    }),
};

fn rate_note(reference: &RateState, v: f64, style: &NumberStyle) -> String {
    let p = reference.params;
    format!(
        "Rate law: the rate-and-state mu0 = {} and V* = {} m/s, with C1 = A - B = {}: the steady state of the published form, without memory. At the reference slip speed {} m/s it gives mu = {}; the rate-and-state law used here ({:?} form) gives {} in steady state.",
        (style.parameter)(p.mu0),
        (style.parameter)(p.v_star_m_per_s),
        (style.parameter)(p.a - p.b),
        (style.parameter)(v),
        (style.measured)(p.mu_steady_published(v)),
        reference.form,
        (style.measured)(reference.mu_steady(v))
    )
}

/// Rate-and-state's registry entry; in a comparison it is the reference.
pub const RATE_STATE: LawEntry = LawEntry {
    name: "rate-state",
    summary: "rate-and-state friction, eqs. 3a/3b",
    params: rate_state::PARAMS,
    build: |p| Ok(Law::RateState(RateState::from_params(p))),
    reference_match: ReferenceMatch::Reference,
};
