//! The friction-law trait and the per-contact data every law works on.
//!
//! A contact is a spring-slider: a tangential spring of stiffness `k` whose far
//! end (the "load point") moves at an imposed velocity, and whose near end (the
//! slider) slips at a rate the friction law decides. In the laboratory this is
//! the apparatus of Lishman et al. (2011), eq. 4a; in the DEM it is the
//! tangential spring between two floes, the load-point velocity being their
//! relative tangential velocity at the contact.

use serde::{Deserialize, Serialize};

/// Slots of law state a [`ContactState`] holds. A law uses the first
/// [`FrictionLaw::state_slots`] of them (LAMMPS's `size_history`); run
/// files and checkpoints store that many per contact, length-prefixed, so a
/// law with more state needs this raised, not a new file format.
pub const LAW_STATE_SLOTS: usize = 3;

/// What persists on a contact between steps. 32 bytes, `Copy`, no heap.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ContactState {
    /// Tangential spring force in N (signed: positive resists positive slip).
    pub tangential_force_n: f64,
    /// The law's own state, in the slots it declares
    /// ([`FrictionLaw::state_slots`]); the rest stay zero. The
    /// rate-and-state law keeps `theta`, the solver's last root and its
    /// last change ([`crate::rate_state::THETA`] and the constants beside
    /// it).
    pub law_state: [f64; LAW_STATE_SLOTS],
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

/// One contact of a batch update ([`crate::Law::step_batch`]): its state, advanced
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
    /// normal load `N` (N): spring force `mu_ss(v) N sign(v)`, steady state.
    fn steady_state(&self, slip_rate_m_per_s: f64, normal_load_n: f64) -> ContactState;

    /// Advances `state` over `dt_s` seconds under `load` and reports the slip.
    ///
    /// The spring force obeys `F_new = F + k (V_lp - V) dt` with `V` the slip
    /// rate at the end of the step (backward Euler), and the friction law is
    /// satisfied at the end of the step. At zero or negative normal load the
    /// spring is released (`F_new = 0`), the slider follows the load point and
    /// the state evolves at that slip rate.
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt_s: f64) -> StepOutcome;

    /// How many slots of [`ContactState::law_state`] the law uses (at most
    /// [`LAW_STATE_SLOTS`]).
    fn state_slots(&self) -> usize;

    /// The state variable `theta` of a contact, for output (the run files'
    /// `theta`); 0 for laws without one.
    fn theta(&self, _state: &ContactState) -> f64 {
        0.0
    }

    /// The state of a contact that forms again within the contact memory:
    /// `fresh` is a new contact's state, `remembered` the state the pair had
    /// when it broke. By default the remembered law state with the fresh
    /// (unloaded) spring.
    fn reformed(&self, remembered: &ContactState, fresh: ContactState) -> ContactState {
        ContactState {
            law_state: remembered.law_state,
            ..fresh
        }
    }

    /// Advances every item over `dt_s`: bitwise what [`FrictionLaw::step`]
    /// gives each item in turn (by default, one by one).
    fn step_batch(&self, items: &mut [BatchItem], dt_s: f64) {
        for item in items {
            item.outcome = self.step(&mut item.state, &item.load, dt_s);
        }
    }

    /// The law and its parameters in one line, as the build report prints
    /// it after `friction: ` (`Amontons mu = 0.5`), numbers written in
    /// `style`; `None` (the default) lets the caller name the law.
    fn describe(&self, _style: &NumberStyle) -> Option<String> {
        None
    }

    /// Critical spring stiffness (N/m) under normal load `N` (N): steady
    /// sliding on a softer spring is unstable (stick-slip). For
    /// rate-and-state `N (B - A) / L`, from the characteristic slip length
    /// `L`; zero or negative when the law strengthens with speed. `None`
    /// (the default) for a law without a characteristic slip length.
    fn critical_stiffness_n_per_m(&self, _normal_load_n: f64) -> Option<f64> {
        None
    }
}

/// Released contact: no normal load, no spring force; the slider follows the load point.
#[inline]
pub(crate) fn released(state: &mut ContactState, load: &ContactLoad) -> f64 {
    state.tangential_force_n = 0.0;
    load.load_point_velocity_m_per_s
}

/// `+1`, `-1` or `0` (unlike `f64::signum`, which gives `+1` for `+0`).
#[inline]
pub(crate) fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// How numbers are written in text a law writes about itself (the caller's
/// choice: floe-scenario's `numbers`).
#[derive(Debug, Clone, Copy)]
pub struct NumberStyle {
    /// A parameter (floe's reports: six significant digits).
    pub parameter: fn(f64) -> String,
    /// A derived or measured value (floe's reports: four significant digits).
    pub measured: fn(f64) -> String,
}
