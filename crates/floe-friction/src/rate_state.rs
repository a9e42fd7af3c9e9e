//! Rate-and-state friction (Lishman et al. 2011, eqs. 3a/3b) and its
//! per-contact update.
//!
//! # The update
//! Over a step `dt` the spring force and the state obey
//! `F_new = F + k (V_lp - V) dt` and `theta_new = Theta(theta, V, dt)` (the
//! exact constant-`V` solution of the evolution law, see
//! [`crate::state_evolution`]), and the law must hold at the end of the step:
//! `F_new / N = mu(V, theta_new)`. That is one scalar equation for the slip
//! rate `V`, solved by safeguarded Newton in a logarithmic unknown `w`
//! (`V = V* e^w` in the published form, `V = 2 V* sinh w` in the regularised
//! one), so that slip rates from 1e-300 to 1e3 m/s are equally well resolved.
//! The residual tends to `-inf`/`+inf` at the ends of the `w` axis, so a root
//! always exists; it is not always monotone (when `V dt > L` and `B > A`),
//! which is why the solver brackets. The scheme is first order in `dt`
//! (backward Euler in the slip) and L-stable: it does not blow up at low normal
//! load or large `dt`, where an explicit update needs `(k/N) V dt / A < 1`.

use serde::{Deserialize, Serialize};

use crate::amontons::sign;
use crate::law::{ContactLoad, ContactState, FrictionLaw, StepOutcome};
use crate::params::RateStateParams;
use crate::root::{solve, Eval};
use crate::state_evolution::{evolve, SlipMeasure, StateLaw};

/// How the friction coefficient relates to the slip rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Form {
    /// Eq. 4b as published: `V = V* exp((mu - mu0 - theta)/A)`. The slip rate is
    /// always positive, so the slider creeps forward even at zero or negative
    /// spring force; it cannot slide backwards.
    Published,
    /// Sign-consistent form `V = 2 V* exp(-(mu0 + theta)/A) sinh(mu/A)`: slip and
    /// friction share their sign and vanish together. Equal to the published form
    /// to relative order `exp(-2 mu/A)`, which for ice (`A = 0.31`) is not
    /// negligible: about 5 % in `mu` at 8 mm/s. Needed wherever force can vanish
    /// or reverse, as on every DEM contact.
    #[default]
    Regularized,
}

/// Relative Newton tolerance on the solver unknown.
const TOLERANCE: f64 = 1e-12;
/// Residual tolerance in units of `mu` (relative to the trial friction).
const RESIDUAL_TOLERANCE: f64 = 1e-13;
/// Above this `ln|y|`, `asinh(y)` is `ln(2|y|)` to within 1e-22.
const ASINH_LOG_SWITCH: f64 = 25.0;

/// The rate-and-state law: parameters, form and state-evolution law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateState {
    /// Law parameters.
    pub params: RateStateParams,
    /// Published (eq. 4b) or regularised form.
    pub form: Form,
    /// Slip (eq. 3b) or aging evolution of `theta`.
    pub state_law: StateLaw,
}

/// What an evaluation of the residual keeps: `theta` at the end of the step
/// and the slip rate.
#[derive(Debug, Clone, Copy)]
struct EndOfStep {
    theta: f64,
    v: f64,
}

impl RateState {
    /// A rate-and-state law from its three ingredients.
    pub fn new(params: RateStateParams, form: Form, state_law: StateLaw) -> Self {
        Self {
            params,
            form,
            state_law,
        }
    }

    /// The solver unknown `w` for slip rate `v` (m/s).
    pub fn unknown_for_slip_rate(&self, v: f64) -> f64 {
        let vs = self.params.v_star_m_per_s;
        match self.form {
            Form::Published => (v.abs() / vs).ln(),
            Form::Regularized => (0.5 * v / vs).asinh(),
        }
    }

    /// Instantaneous friction coefficient at slip rate `v` (m/s) and state `theta`
    /// (eq. 3a, or its regularised form).
    pub fn mu_at(&self, v: f64, theta: f64) -> f64 {
        let p = &self.params;
        match self.form {
            Form::Published => p.mu0 + theta + p.a * (v.abs() / p.v_star_m_per_s).ln(),
            Form::Regularized => {
                if v == 0.0 {
                    return 0.0;
                }
                let ln_y = (0.5 * v.abs() / p.v_star_m_per_s).ln() + (p.mu0 + theta) / p.a;
                sign(v) * p.a * asinh_of_exp(ln_y)
            }
        }
    }

    /// Residual `mu_law(w, theta_new(w)) - F_new(w)/N` and its derivative.
    #[inline(always)]
    fn residual(&self, w: f64, theta: f64, trial_mu: f64, kappa: f64, dt: f64) -> Eval<EndOfStep> {
        let p = &self.params;
        let vs = p.v_star_m_per_s;
        let dt_over_l = dt / p.critical_slip_m;
        match self.form {
            Form::Published => {
                let v = vs * w.exp();
                let slip = SlipMeasure {
                    q: w,
                    x: v * dt_over_l,
                    g: 1.0,
                };
                let (theta_new, dtheta) = evolve(self.state_law, p.b, theta, slip, vs * dt_over_l);
                let mu = p.mu0 + theta_new + p.a * w;
                Eval {
                    r: mu - trial_mu + kappa * v,
                    dr: p.a + dtheta + kappa * v,
                    payload: EndOfStep {
                        theta: theta_new,
                        v,
                    },
                }
            }
            Form::Regularized => {
                let sgn = sign(w);
                let em1 = w.abs().exp_m1();
                let sinh = 0.5 * em1 * (2.0 + em1) / (1.0 + em1); // |sinh w|, exact near 0
                let cosh = 1.0 + 0.5 * em1 * em1 / (1.0 + em1);
                let speed = 2.0 * vs * sinh;
                let q = (2.0 * sinh).ln();
                let slip = SlipMeasure {
                    q,
                    x: speed * dt_over_l,
                    g: sgn * cosh / sinh,
                };
                let (theta_new, dtheta) = evolve(self.state_law, p.b, theta, slip, vs * dt_over_l);
                let c = (p.mu0 + theta_new) / p.a;
                let (mu, dmu) = if q - std::f64::consts::LN_2 + c > ASINH_LOG_SWITCH {
                    // asinh(y) = ln(2|y|): exactly the published form, without overflow.
                    (sgn * p.a * (q + c), p.a * slip.g * sgn + sgn * dtheta)
                } else {
                    let ec = c.exp();
                    let y = sgn * sinh * ec;
                    (
                        p.a * y.asinh(),
                        (p.a * cosh * ec + y * dtheta) / (1.0 + y * y).sqrt(),
                    )
                };
                let v = sgn * speed;
                Eval {
                    r: mu - trial_mu + kappa * v,
                    dr: dmu + kappa * 2.0 * vs * cosh,
                    payload: EndOfStep {
                        theta: theta_new,
                        v,
                    },
                }
            }
        }
    }

    /// `theta` after `dt` of slip at the imposed rate `v` (no spring involved).
    fn evolve_at(&self, theta: f64, v: f64, dt: f64) -> f64 {
        let p = &self.params;
        let dt_over_l = dt / p.critical_slip_m;
        let speed = v.abs();
        let slip = SlipMeasure {
            q: (speed / p.v_star_m_per_s).ln(),
            x: speed * dt_over_l,
            g: 1.0,
        };
        evolve(
            self.state_law,
            p.b,
            theta,
            slip,
            p.v_star_m_per_s * dt_over_l,
        )
        .0
    }
}

impl FrictionLaw for RateState {
    fn mu_steady(&self, v: f64) -> f64 {
        match self.form {
            Form::Published => self.params.mu_steady_published(v),
            Form::Regularized => self.mu_at(v.abs(), self.params.theta_steady(v)),
        }
    }

    fn steady_state(&self, v: f64, n: f64) -> ContactState {
        if v == 0.0 {
            // No steady state at rest (theta_ss is infinite): take the state of
            // steady sliding at V*, unloaded.
            return ContactState {
                tangential_force_n: 0.0,
                theta: 0.0,
                solver_guess: self.unknown_for_slip_rate(self.params.v_star_m_per_s),
            };
        }
        let dir = match self.form {
            Form::Published => 1.0,
            Form::Regularized => sign(v),
        };
        ContactState {
            tangential_force_n: dir * self.mu_steady(v) * n.max(0.0),
            theta: self.params.theta_steady(v),
            solver_guess: self.unknown_for_slip_rate(dir * v.abs()),
        }
    }

    #[inline]
    fn step(&self, state: &mut ContactState, load: &ContactLoad, dt: f64) -> StepOutcome {
        let n = load.normal_load_n;
        let v_lp = load.load_point_velocity_m_per_s;
        if n <= 0.0 || n.is_nan() {
            let v = match self.form {
                Form::Published => v_lp.abs(),
                Form::Regularized => v_lp,
            };
            state.tangential_force_n = 0.0;
            state.theta = self.evolve_at(state.theta, v, dt);
            if v != 0.0 {
                state.solver_guess = self.unknown_for_slip_rate(v);
            }
            // At rest and unloaded there is no friction to report (the
            // published form's ln V would give -inf).
            let mu = if v == 0.0 {
                0.0
            } else {
                self.mu_at(v, state.theta)
            };
            return StepOutcome {
                slip_rate_m_per_s: v,
                mu,
                iterations: 0,
            };
        }
        let kdt = load.stiffness_n_per_m * dt;
        let trial_force = state.tangential_force_n + kdt * v_lp;
        let (trial_mu, kappa) = (trial_force / n, kdt / n);
        let theta = state.theta;
        let root = solve(
            |w| self.residual(w, theta, trial_mu, kappa, dt),
            state.solver_guess,
            TOLERANCE,
            RESIDUAL_TOLERANCE * (1.0 + trial_mu.abs()),
        );
        let end = root.payload;
        state.tangential_force_n = trial_force - kdt * end.v;
        state.theta = end.theta;
        state.solver_guess = root.x;
        StepOutcome {
            slip_rate_m_per_s: end.v,
            mu: state.tangential_force_n / n,
            iterations: root.evaluations,
        }
    }
}

/// `asinh(exp(z))` without overflow for large `z`.
#[inline]
fn asinh_of_exp(z: f64) -> f64 {
    if z > ASINH_LOG_SWITCH {
        z + std::f64::consts::LN_2
    } else {
        z.exp().asinh()
    }
}
