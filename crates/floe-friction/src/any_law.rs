//! [`Law`]: any of the crate's friction laws, chosen at run time (from a
//! scenario or protocol file), or one defined elsewhere ([`CustomLaw`]).

use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::amontons::Amontons;
use crate::law::{BatchItem, ContactLoad, ContactState, FrictionLaw, StepOutcome};
use crate::rate_dependent::RateDependent;
use crate::rate_state::RateState;

/// A friction law defined outside this crate, behind [`Law::Custom`]:
/// any [`FrictionLaw`] that can be shared between threads, with a name for
/// messages and file names.
#[derive(Clone)]
pub struct CustomLaw {
    name: &'static str,
    law: Arc<dyn FrictionLaw + Send + Sync>,
}

impl CustomLaw {
    /// Wraps `law` under `name` (as in the law registry).
    pub fn new(name: &'static str, law: impl FrictionLaw + Send + Sync + 'static) -> Self {
        CustomLaw {
            name,
            law: Arc::new(law),
        }
    }

    /// The law.
    pub fn law(&self) -> &(dyn FrictionLaw + Send + Sync) {
        &*self.law
    }
}

impl fmt::Debug for CustomLaw {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CustomLaw({})", self.name)
    }
}

impl PartialEq for CustomLaw {
    /// The same law object (a clone of it): custom laws have no value
    /// equality.
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && Arc::ptr_eq(&self.law, &other.law)
    }
}

/// Any of the crate's laws, chosen at run time (e.g. from a scenario file),
/// or one defined elsewhere ([`Law::Custom`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Law {
    /// Constant friction coefficient (Coulomb with a tangential spring).
    Amontons(Amontons),
    /// Rate-dependent friction, eq. 2.
    #[serde(rename = "rate")]
    RateDependent(RateDependent),
    /// Rate-and-state friction, eqs. 3a/3b.
    #[serde(rename = "rate-state")]
    RateState(RateState),
    /// A law defined outside this crate (see the law registry).
    #[serde(skip)]
    Custom(CustomLaw),
}

impl FrictionLaw for Law {
    fn mu_steady(&self, v: f64) -> f64 {
        match self {
            Law::Amontons(l) => l.mu_steady(v),
            Law::RateDependent(l) => l.mu_steady(v),
            Law::RateState(l) => l.mu_steady(v),
            Law::Custom(l) => l.law().mu_steady(v),
        }
    }

    fn steady_state(&self, v: f64, n: f64) -> ContactState {
        match self {
            Law::Amontons(l) => l.steady_state(v, n),
            Law::RateDependent(l) => l.steady_state(v, n),
            Law::RateState(l) => l.steady_state(v, n),
            Law::Custom(l) => l.law().steady_state(v, n),
        }
    }

    #[inline]
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt_s: f64) -> StepOutcome {
        match self {
            Law::Amontons(l) => l.step(state, load, dt_s),
            Law::RateDependent(l) => l.step(state, load, dt_s),
            Law::RateState(l) => l.step(state, load, dt_s),
            Law::Custom(l) => l.law().step(state, load, dt_s),
        }
    }

    fn state_slots(&self) -> usize {
        match self {
            Law::Amontons(l) => l.state_slots(),
            Law::RateDependent(l) => l.state_slots(),
            Law::RateState(l) => l.state_slots(),
            Law::Custom(l) => l.law().state_slots(),
        }
    }

    #[inline]
    fn theta(&self, state: &ContactState) -> f64 {
        match self {
            Law::Amontons(l) => l.theta(state),
            Law::RateDependent(l) => l.theta(state),
            Law::RateState(l) => l.theta(state),
            Law::Custom(l) => l.law().theta(state),
        }
    }

    fn reformed(&self, remembered: &ContactState, fresh: ContactState) -> ContactState {
        match self {
            Law::Amontons(l) => l.reformed(remembered, fresh),
            Law::RateDependent(l) => l.reformed(remembered, fresh),
            Law::RateState(l) => l.reformed(remembered, fresh),
            Law::Custom(l) => l.law().reformed(remembered, fresh),
        }
    }
}

impl Law {
    /// A law defined outside this crate, under `name`.
    pub fn custom(name: &'static str, law: impl FrictionLaw + Send + Sync + 'static) -> Self {
        Law::Custom(CustomLaw::new(name, law))
    }

    /// Advances every item over `dt_s`: bitwise what [`FrictionLaw::step`]
    /// gives each item in turn. The rate-and-state law iterates several
    /// contacts' solves side by side ([`RateState::step_batch`]); the
    /// others step one by one.
    pub fn step_batch(&self, items: &mut [BatchItem], dt_s: f64) {
        match self {
            Law::RateState(l) => l.step_batch(items, dt_s),
            _ => {
                for item in items {
                    item.outcome = self.step(&mut item.state, &item.load, dt_s);
                }
            }
        }
    }

    /// Short name used on the command line, in scenario files and in file
    /// names: `amontons`, `rate`, `rate-state`, or a custom law's name.
    pub fn name(&self) -> &'static str {
        match self {
            Law::Amontons(_) => "amontons",
            Law::RateDependent(_) => "rate",
            Law::RateState(_) => "rate-state",
            Law::Custom(l) => l.name,
        }
    }
}
