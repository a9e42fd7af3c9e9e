//! Rate-dependent friction (eq. 2): `mu = mu0 + C1 ln(V/V*)`, no memory.

use serde::{Deserialize, Serialize};

use crate::law::NumberStyle;
use crate::law::{
    released, sign, ContactLoad, ContactState, FrictionLaw, StepOutcome, LAW_STATE_SLOTS,
};
use crate::law_table::{LawParams, ParamDefault, ParamKind, ParamSpec};
use crate::params::{LISHMAN_A, LISHMAN_B, LISHMAN_MU0, LISHMAN_V_STAR_M_PER_S};
use crate::rate_state::SOLVER_GUESS;

/// The law's parameters, as the registry publishes them (defaults:
/// Lishman et al. 2011).
pub const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        key: "mu0",
        unit: "",
        kind: ParamKind::FRICTION_COEFFICIENT,
        default: ParamDefault::Number(LISHMAN_MU0),
        meaning: "friction coefficient at V = V*",
    },
    ParamSpec {
        key: "c1",
        unit: "",
        kind: ParamKind::FRICTION_RATE,
        default: ParamDefault::Number(LISHMAN_A - LISHMAN_B),
        meaning: "slope of mu in ln V (A - B of the rate-and-state law)",
    },
    ParamSpec {
        key: "v_star_m_per_s",
        unit: "m/s",
        kind: ParamKind::POSITIVE,
        default: ParamDefault::Number(LISHMAN_V_STAR_M_PER_S),
        meaning: "reference slip rate V*",
    },
    ParamSpec {
        key: "v_floor_m_per_s",
        unit: "m/s",
        kind: ParamKind::POSITIVE,
        default: ParamDefault::Number(LISHMAN_V_STAR_M_PER_S),
        meaning: "slip rate below which mu is held at mu(floor): static friction",
    },
];
use crate::root::{solve, Eval};

/// Rate-dependent friction on a tangential spring.
///
/// Eq. 2 with `C1 < 0` gives infinite friction at rest and, taken literally on
/// a spring, an ill-posed slider (velocity weakening with no direct effect:
/// Rice & Ruina 1983). It is made usable the way Coulomb friction is: below
/// the floor speed `v_floor` the coefficient is frozen at `mu(v_floor)`, which
/// acts as static friction (the contact sticks while `|F| < mu(v_floor) N`),
/// and `mu` is clipped at zero for very fast slip (with the paper's
/// `C1 = -0.072` that happens above 1.8 m/s). The default floor is `V*` =
/// 1e-5 m/s, below which the paper notes (section 3, after Kennedy et al.
/// 2000 and Fortt & Schulson 2009) friction stops decreasing with speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateDependent {
    /// Friction at `V = V*` (dimensionless).
    pub mu0: f64,
    /// Rate coefficient `C1` (dimensionless; `A - B` of the rate-and-state law).
    pub c1: f64,
    /// Reference slip rate `V*`, m/s.
    pub v_star_m_per_s: f64,
    /// Slip rate below which `mu` is held at `mu(v_floor)`, m/s.
    pub v_floor_m_per_s: f64,
}

impl RateDependent {
    /// Eq. 2 with Lishman et al.'s `mu0 = 0.872`, `V* = 1e-5 m/s`, floor at `V*`
    /// and the given `C1`.
    pub fn lishman_2011(c1: f64) -> Self {
        Self {
            mu0: crate::params::LISHMAN_MU0,
            c1,
            v_star_m_per_s: crate::params::LISHMAN_V_STAR_M_PER_S,
            v_floor_m_per_s: crate::params::LISHMAN_V_STAR_M_PER_S,
        }
    }

    /// The law from its checked parameters ([`PARAMS`]).
    pub fn from_params(p: &LawParams) -> Self {
        RateDependent {
            mu0: p.number("mu0"),
            c1: p.number("c1"),
            v_star_m_per_s: p.number("v_star_m_per_s"),
            v_floor_m_per_s: p.number("v_floor_m_per_s"),
        }
    }

    /// Friction coefficient at slip rate `|v|` (m/s).
    pub fn mu_at(&self, v: f64) -> f64 {
        let s = v.abs().max(self.v_floor_m_per_s);
        (self.mu0 + self.c1 * (s / self.v_star_m_per_s).ln()).max(0.0)
    }
}

impl FrictionLaw for RateDependent {
    fn mu_steady(&self, v: f64) -> f64 {
        self.mu_at(v)
    }

    fn steady_state(&self, v: f64, n: f64) -> ContactState {
        let mut law_state = [0.0; LAW_STATE_SLOTS];
        law_state[SOLVER_GUESS] = (v.abs().max(self.v_floor_m_per_s) / self.v_star_m_per_s).ln();
        ContactState {
            tangential_force_n: self.mu_at(v) * n.max(0.0) * sign(v),
            law_state,
        }
    }

    /// The solver's last root, in the rate-and-state law's slot for it
    /// (slot 0 unused), so that both laws' checkpoints of format 2 map
    /// onto the slots unchanged.
    fn state_slots(&self) -> usize {
        SOLVER_GUESS + 1
    }

    fn describe(&self, style: &NumberStyle) -> Option<String> {
        let p = style.parameter;
        Some(format!(
            "rate-dependent mu0 = {}, c1 = {}, V* = {} m/s",
            p(self.mu0),
            p(self.c1),
            p(self.v_star_m_per_s)
        ))
    }

    #[inline]
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt: f64) -> StepOutcome {
        let n = load.normal_load_n;
        if n <= 0.0 || n.is_nan() {
            let v = released(state, load);
            return StepOutcome {
                slip_rate_m_per_s: v,
                mu: self.mu_at(v) * sign(v),
                iterations: 0,
            };
        }
        let kdt = load.stiffness_n_per_m * dt;
        let trial = state.tangential_force_n + kdt * load.load_point_velocity_m_per_s;
        let static_cap = self.mu_at(0.0) * n;
        if trial.abs() <= static_cap {
            state.tangential_force_n = trial;
            return StepOutcome {
                slip_rate_m_per_s: 0.0,
                mu: trial / n,
                iterations: 0,
            };
        }
        // Sliding: |F_new| = mu(s) N with s = (|trial| - |F_new|)/(k dt), solved
        // for z = ln(s/V*). G(-inf) = mu_static N - |trial| < 0 and
        // G(s_max = |trial|/(k dt)) = mu N >= 0. Velocity weakening can give
        // several roots; starting from s_max picks the largest, the one on the
        // branch where dG/ds > 0 (a small extra push gives a little more slip),
        // so the choice does not depend on history.
        let (vs, floor_z) = (
            self.v_star_m_per_s,
            (self.v_floor_m_per_s / self.v_star_m_per_s).ln(),
        );
        let trial_abs = trial.abs();
        let root = solve(
            |z| {
                let s = vs * z.exp();
                let mu = self.mu_at(s);
                let dmu = if z > floor_z && mu > 0.0 {
                    self.c1
                } else {
                    0.0
                };
                Eval {
                    r: mu * n + kdt * s - trial_abs,
                    dr: dmu * n + kdt * s,
                    d2r: f64::NAN,
                    d3r: f64::NAN,
                    payload: s,
                }
            },
            // s = V* e^z: ds = s dz to first order.
            |s, dz| s + s * dz,
            (trial_abs / (kdt * vs)).ln(),
            1e-12,
            1e-13 * trial_abs,
        );
        let s = root.payload;
        state.tangential_force_n = sign(trial) * (trial_abs - kdt * s);
        state.law_state[SOLVER_GUESS] = root.x;
        StepOutcome {
            slip_rate_m_per_s: sign(trial) * s,
            mu: state.tangential_force_n / n,
            iterations: root.evaluations,
        }
    }
}
