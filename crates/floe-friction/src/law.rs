//! The friction-law trait and the per-contact data every law works on.
//!
//! A contact is a spring-slider: a tangential spring of stiffness `k` whose far
//! end (the "load point") moves at an imposed velocity, and whose near end (the
//! slider) slips at a rate the friction law decides. In the laboratory this is
//! the apparatus of Lishman et al. (2011), eq. 4a; in the DEM it is the
//! tangential spring between two floes, the load-point velocity being their
//! relative tangential velocity at the contact.

use serde::{Deserialize, Serialize};

use crate::amontons::Amontons;
use crate::rate_dependent::RateDependent;
use crate::rate_state::RateState;

/// What persists on a contact between steps. 32 bytes, `Copy`, no heap.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ContactState {
    /// Tangential spring force in N (signed: positive resists positive slip).
    pub tangential_force_n: f64,
    /// Rate-and-state state variable `theta` (dimensionless, Lishman's log-state).
    /// Unused by the laws without state.
    pub theta: f64,
    /// The solver's unknown `q = ln(|V|/V*)` at the end of the last step
    /// (rate-and-state and rate-dependent laws).
    pub solver_guess: f64,
    /// How much the rate-and-state solver's unknown changed over the last
    /// step, limited to `±1` (a factor `e` in slip rate): the next step
    /// starts its iteration at `solver_guess + solver_trend`. A contact's
    /// slip rate changes smoothly from step to step, so this linear
    /// extrapolation starts the solve about ten times closer to the root
    /// than the last root does, and the solve then mostly takes a single
    /// evaluation (docs/performance.md). Zero for a new contact and after a
    /// step without a solve. It steers only where the solve starts, not
    /// what it converges to.
    pub solver_trend: f64,
}

/// What is imposed on a contact over one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLoad {
    /// Velocity of the load point (the spring's far end) relative to the
    /// opposite surface, m/s, signed.
    pub load_point_velocity_m_per_s: f64,
    /// Tangential spring stiffness, N/m; must be finite and > 0.
    pub stiffness_n_per_m: f64,
    /// Normal load on the sliding interface, N. Zero or negative means the
    /// contact carries no friction (see [`FrictionLaw::step`]).
    pub normal_load_n: f64,
}

/// What one step produced, besides the updated [`ContactState`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutcome {
    /// Slip rate of the slider over the step, m/s, signed (backward Euler: the
    /// slip over the step is `slip_rate * dt`).
    pub slip_rate_m_per_s: f64,
    /// Friction coefficient at the end of the step, `F / N`; at zero normal load,
    /// the coefficient the law gives for the slip rate and state.
    pub mu: f64,
    /// Residual evaluations the solve took (0 for closed-form updates).
    pub iterations: u32,
}

/// One contact of a batch update ([`Law::step_batch`]): its state, advanced
/// in place, the load over the step, and what the step produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchItem {
    /// Contact state, advanced in place.
    pub state: ContactState,
    /// Load over the step.
    pub load: ContactLoad,
    /// Written by the step.
    pub outcome: StepOutcome,
}

/// A friction law that can advance a contact.
///
/// Every implementation is allocation-free and returns finite numbers for
/// finite inputs with `dt > 0` and stiffness `> 0`.
pub trait FrictionLaw {
    /// Steady-state friction coefficient at constant slip rate `|v|` (m/s).
    fn mu_steady(&self, slip_rate_m_per_s: f64) -> f64;

    /// Contact state in steady sliding at slip rate `v` (m/s, signed) under
    /// normal load `N` (N): spring force `mu_ss(v) N sign(v)`, steady `theta`.
    fn steady_state(&self, slip_rate_m_per_s: f64, normal_load_n: f64) -> ContactState;

    /// Advances `state` over `dt_s` seconds under `load` and reports the slip.
    ///
    /// The spring force obeys `F_new = F + k (V_lp - V) dt` with `V` the slip
    /// rate at the end of the step (backward Euler), and the friction law is
    /// satisfied at the end of the step. At zero or negative normal load the
    /// spring is released (`F_new = 0`), the slider follows the load point and
    /// the state evolves at that slip rate.
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt_s: f64) -> StepOutcome;
}

/// Any of the crate's laws, chosen at run time (e.g. from a scenario file).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
}

impl FrictionLaw for Law {
    fn mu_steady(&self, v: f64) -> f64 {
        match self {
            Law::Amontons(l) => l.mu_steady(v),
            Law::RateDependent(l) => l.mu_steady(v),
            Law::RateState(l) => l.mu_steady(v),
        }
    }

    fn steady_state(&self, v: f64, n: f64) -> ContactState {
        match self {
            Law::Amontons(l) => l.steady_state(v, n),
            Law::RateDependent(l) => l.steady_state(v, n),
            Law::RateState(l) => l.steady_state(v, n),
        }
    }

    #[inline]
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt_s: f64) -> StepOutcome {
        match self {
            Law::Amontons(l) => l.step(state, load, dt_s),
            Law::RateDependent(l) => l.step(state, load, dt_s),
            Law::RateState(l) => l.step(state, load, dt_s),
        }
    }
}

impl Law {
    /// Advances every item over `dt_s`: bitwise what [`FrictionLaw::step`]
    /// gives each item in turn. The rate-and-state law iterates several
    /// contacts' solves side by side ([`RateState::step_batch`]); the
    /// others, which need at most a cheap solve, step one by one.
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

    /// Short name used on the command line and in file names:
    /// `amontons`, `rate` or `rate-state`.
    pub fn name(&self) -> &'static str {
        match self {
            Law::Amontons(_) => "amontons",
            Law::RateDependent(_) => "rate",
            Law::RateState(_) => "rate-state",
        }
    }
}

/// Released contact: no normal load, no spring force; the slider follows the load point.
#[inline]
pub(crate) fn released(state: &mut ContactState, load: &ContactLoad) -> f64 {
    state.tangential_force_n = 0.0;
    load.load_point_velocity_m_per_s
}
