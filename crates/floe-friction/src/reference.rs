//! An independent solution of the spring-slider, for validation: the ODE of
//! eqs. 4a-4c in `(mu, theta)` integrated by the adaptive 8th-order
//! Dormand-Prince method of `ode_solvers` at tight tolerance. It shares no
//! code with the per-contact update (no backward Euler, no exact state
//! update, no Newton solve), so agreement between the two is evidence for
//! both. Slow: for tests and documentation, not for production runs.

use ode_solvers::{Dop853, System, Vector2};

use crate::error::FrictionError;
use crate::law::FrictionLaw;
use crate::rate_state::{Form, RateState};
use crate::state_evolution::StateLaw;

struct SliderOde {
    law: RateState,
    k_over_n: f64,
    v_lp: f64,
}

impl SliderOde {
    /// Slip rate from friction and state: eq. 4b or its regularised inverse.
    fn slip_rate(&self, mu: f64, theta: f64) -> f64 {
        let p = &self.law.params;
        match self.law.form {
            Form::Published => p.v_star_m_per_s * ((mu - p.mu0 - theta) / p.a).exp(),
            Form::Regularized => {
                2.0 * p.v_star_m_per_s * (-(p.mu0 + theta) / p.a).exp() * (mu / p.a).sinh()
            }
        }
    }
}

impl System<f64, Vector2<f64>> for SliderOde {
    fn system(&self, _t: f64, y: &Vector2<f64>, dy: &mut Vector2<f64>) {
        let p = &self.law.params;
        let v = self.slip_rate(y[0], y[1]).abs();
        dy[0] = self.k_over_n * (self.v_lp - self.slip_rate(y[0], y[1]));
        dy[1] = match self.law.state_law {
            StateLaw::Slip => -(v / p.critical_slip_m) * (y[1] + p.b * (v / p.v_star_m_per_s).ln()),
            StateLaw::Aging => {
                (p.b * p.v_star_m_per_s / p.critical_slip_m) * (-y[1] / p.b).exp()
                    - p.b * v / p.critical_slip_m
            }
        };
    }
}

/// Friction every `every_s` seconds (starting with `t = 0`) for a slider that
/// starts in steady sliding at `v0` and is driven through constant-velocity
/// `segments` of `(velocity m/s, duration s)`, with spring-to-load ratio
/// `k_over_n` (1/m). The integrator restarts at every output time, so
/// velocity jumps fall on its end points. Durations must be multiples of
/// `every_s`.
pub fn friction_series(
    law: &RateState,
    k_over_n: f64,
    segments: &[(f64, f64)],
    v0: f64,
    every_s: f64,
) -> Result<Vec<f64>, FrictionError> {
    let mut y = Vector2::new(law.mu_steady(v0), law.params.theta_steady(v0));
    let mut out = vec![y[0]];
    let mut t = 0.0;
    for &(v_lp, duration) in segments {
        let intervals = (duration / every_s).round() as usize;
        for _ in 0..intervals {
            let ode = SliderOde {
                law: *law,
                k_over_n,
                v_lp,
            };
            let mut solver = Dop853::new(ode, t, t + every_s, 0.0, y, 1e-13, 1e-15);
            solver.integrate().map_err(|e| {
                FrictionError::Fit(format!("reference integration failed at t = {t} s: {e:?}"))
            })?;
            y = *solver
                .y_out()
                .last()
                .expect("the integrator reports its end point");
            out.push(y[0]);
            t += every_s;
        }
    }
    Ok(out)
}
