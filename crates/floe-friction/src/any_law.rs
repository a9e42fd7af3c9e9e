//! [`Law`]: any of the crate's friction laws, chosen at run time (from a
//! scenario or protocol file), or one defined elsewhere ([`CustomLaw`]).

use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::amontons::Amontons;
use crate::law::{BatchItem, ContactLoad, ContactState, FrictionLaw, NumberStyle, StepOutcome};
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

/// The built-in laws, each once: `Variant(Type) = "name"` with its doc.
/// This makes [`Law`] (the name is also its `kind` in serialized form),
/// [`Law::name`] and [`Law`]'s [`FrictionLaw`] implementation, which hands
/// every method to the law inside.
macro_rules! builtin_laws {
    ($($(#[doc = $doc:expr])* $variant:ident($law:ty) = $name:literal,)*) => {
        /// Any of the crate's laws, chosen at run time (e.g. from a scenario
        /// file), or one defined elsewhere ([`Law::Custom`]).
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "kind", deny_unknown_fields)]
        pub enum Law {
            $($(#[doc = $doc])* #[serde(rename = $name)] $variant($law),)*
            /// A law defined outside this crate (see the law registry).
            #[serde(skip)]
            Custom(CustomLaw),
        }

        /// `$call` with `$l` bound to the law inside `$self_`.
        macro_rules! dispatch {
            ($self_:expr, $l:ident => $call:expr) => {
                match $self_ {
                    $(Law::$variant($l) => $call,)*
                    Law::Custom(custom) => {
                        let $l = custom.law();
                        $call
                    }
                }
            };
        }

        impl Law {
            /// Short name used on the command line, in scenario files and in
            /// file names (the registry's name): `amontons`, `rate`,
            /// `rate-state`, or a custom law's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Law::$variant(_) => $name,)*
                    Law::Custom(l) => l.name,
                }
            }
        }
    };
}

builtin_laws! {
    /// Constant friction coefficient (Coulomb with a tangential spring).
    Amontons(Amontons) = "amontons",
    /// Rate-dependent friction, eq. 2.
    RateDependent(RateDependent) = "rate",
    /// Rate-and-state friction, eqs. 3a/3b.
    RateState(RateState) = "rate-state",
}

impl FrictionLaw for Law {
    fn mu_steady(&self, v: f64) -> f64 {
        dispatch!(self, l => l.mu_steady(v))
    }

    fn steady_state(&self, v: f64, n: f64) -> ContactState {
        dispatch!(self, l => l.steady_state(v, n))
    }

    #[inline]
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt_s: f64) -> StepOutcome {
        dispatch!(self, l => l.step(state, load, dt_s))
    }

    fn state_slots(&self) -> usize {
        dispatch!(self, l => l.state_slots())
    }

    #[inline]
    fn theta(&self, state: &ContactState) -> f64 {
        dispatch!(self, l => l.theta(state))
    }

    fn reformed(&self, remembered: &ContactState, fresh: ContactState) -> ContactState {
        dispatch!(self, l => l.reformed(remembered, fresh))
    }

    fn step_batch(&self, items: &mut [BatchItem], dt_s: f64) {
        dispatch!(self, l => FrictionLaw::step_batch(l, items, dt_s))
    }

    fn describe(&self, style: &NumberStyle) -> Option<String> {
        dispatch!(self, l => l.describe(style))
    }

    fn critical_stiffness_n_per_m(&self, normal_load_n: f64) -> Option<f64> {
        dispatch!(self, l => l.critical_stiffness_n_per_m(normal_load_n))
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
        FrictionLaw::step_batch(self, items, dt_s)
    }

    /// The law in one line, as the build report prints it after
    /// `friction: `: its [`FrictionLaw::describe`], or for a law that does
    /// not describe itself, "custom law" and its name.
    pub fn description(&self, style: &NumberStyle) -> String {
        self.describe(style)
            .unwrap_or_else(|| format!("custom law `{}`", self.name()))
    }
}
