//! A law as the registry knows it ([`LawEntry`]); the built-in laws'
//! entries are in `builtin_entries.rs`.

use crate::any_law::Law;
use crate::law_table::{LawParams, ParamSpec};
use crate::reference_match::ReferenceMatch;

/// A law as the registry knows it: its name, its parameter table and how
/// to build it.
#[derive(Debug, Clone, Copy)]
pub struct LawEntry {
    /// The name files and the command line choose it by (`rate-state`).
    pub name: &'static str,
    /// One line on what the law is.
    pub summary: &'static str,
    /// Its parameters.
    pub params: &'static [ParamSpec],
    /// The law from checked parameters; an error names what is wrong
    /// beyond single values (none of the built-in laws has such checks).
    pub build: fn(&LawParams) -> Result<Law, String>,
    /// How a comparison matches the law to its rate-and-state reference.
    pub reference_match: ReferenceMatch,
}
