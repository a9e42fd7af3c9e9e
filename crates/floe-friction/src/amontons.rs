//! Amontons's law (eq. 1): a constant friction coefficient.

use serde::{Deserialize, Serialize};

use crate::law::NumberStyle;
use crate::law::{released, sign, ContactLoad, ContactState, FrictionLaw, StepOutcome};
use crate::law_table::{LawParams, ParamDefault, ParamKind, ParamSpec};

/// The law's parameters, as the registry publishes them.
pub const PARAMS: &[ParamSpec] = &[ParamSpec {
    key: "mu",
    unit: "",
    kind: ParamKind::FRICTION_COEFFICIENT,
    default: ParamDefault::Required,
    meaning: "constant friction coefficient",
}];

/// Constant friction coefficient, applied as Coulomb friction on a tangential
/// spring: the contact sticks while `|F| <= mu N` and slides at `|F| = mu N`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Amontons {
    /// Friction coefficient (dimensionless), >= 0.
    pub mu: f64,
}

impl Amontons {
    /// The law from its checked parameters ([`PARAMS`]).
    pub fn from_params(p: &LawParams) -> Self {
        Amontons { mu: p.number("mu") }
    }
}

impl FrictionLaw for Amontons {
    fn mu_steady(&self, _v: f64) -> f64 {
        self.mu
    }

    fn steady_state(&self, v: f64, n: f64) -> ContactState {
        ContactState {
            tangential_force_n: self.mu * n.max(0.0) * sign(v),
            ..ContactState::default()
        }
    }

    fn state_slots(&self) -> usize {
        0
    }

    fn describe(&self, style: &NumberStyle) -> Option<String> {
        Some(format!("Amontons mu = {}", (style.parameter)(self.mu)))
    }

    #[inline]
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt: f64) -> StepOutcome {
        let n = load.normal_load_n;
        if n <= 0.0 || n.is_nan() {
            let v = released(state, load);
            return StepOutcome {
                slip_rate_m_per_s: v,
                mu: self.mu * sign(v),
                iterations: 0,
            };
        }
        let kdt = load.stiffness_n_per_m * dt;
        // Elastic predictor, plastic corrector: the backward-Euler update of a
        // Coulomb contact, exact for any dt.
        let trial = state.tangential_force_n + kdt * load.load_point_velocity_m_per_s;
        let cap = self.mu * n;
        let (force, v) = if trial.abs() <= cap {
            (trial, 0.0)
        } else {
            let f = cap.copysign(trial);
            (f, (trial - f) / kdt)
        };
        state.tangential_force_n = force;
        StepOutcome {
            slip_rate_m_per_s: v,
            mu: force / n,
            iterations: 0,
        }
    }
}
