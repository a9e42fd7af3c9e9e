//! Evolution of the state variable `theta` over one step at constant slip rate.
//!
//! Both evolution laws are linear ODEs in a suitable variable when the slip
//! rate `V` is held fixed over the step, so they are integrated exactly for
//! that `V` rather than by an explicit formula that would blow up when
//! `V dt / L` is large:
//!
//! * slip (Ruina) law, eq. 3b: `dtheta/dt = -(|V|/L)(theta - theta_ss)`, so
//!   `theta_new = theta_ss + (theta - theta_ss) exp(-|V| dt / L)`;
//! * aging (Dieterich) law in Lishman's log-state,
//!   `dtheta/dt = (B V*/L) exp(-theta/B) - B |V|/L`: with `phi = exp(theta/B)`,
//!   `dphi/dt = V*/L - (|V|/L) phi`, so
//!   `phi_new = phi exp(-x) + (V* dt/L) (1 - exp(-x))/x`, `x = |V| dt / L`,
//!   evaluated in log space so long holds cannot overflow.
//!
//! `theta_ss = -B ln(|V|/V*)` in both. `evolve` also returns the
//! derivatives of `theta_new` with respect to the solver's unknown
//! `q = ln(|V|/V*)` (note `dx/dq = x`): the first for both laws, the second
//! and third for the slip law (the solver's Halley steps and its
//! fourth-order last correction, `crate::root`).

use serde::{Deserialize, Serialize};

/// Which evolution law drives the state variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StateLaw {
    /// Ruina's slip law, eq. 3b as published: state changes only while slipping.
    #[default]
    Slip,
    /// Dieterich's aging law: the contact heals at rest (log of hold time).
    Aging,
}

/// Slip velocity over the step, described for the state update.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SlipMeasure {
    /// `ln(|V|/V*)`; `-inf` when `V = 0`.
    pub q: f64,
    /// `|V| dt / L`, the slip over the step in units of `L`.
    pub x: f64,
}

/// `theta` at the end of a step and its derivatives with respect to `q`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Evolved {
    /// `theta` at the end of the step.
    pub theta: f64,
    /// `d theta / dq`.
    pub d1: f64,
    /// `d2 theta / dq2`; NaN for the aging law, whose solve takes Newton
    /// steps.
    pub d2: f64,
    /// `d3 theta / dq3`; NaN for the aging law.
    pub d3: f64,
}

/// `theta` at the end of the step and its derivatives with respect to `q`
/// (see [`Evolved`]). `ln_vstar_dt_over_l` is `ln(V* dt / L)` (used by the
/// aging law only).
#[inline(always)]
pub(crate) fn evolve(
    law: StateLaw,
    b: f64,
    theta: f64,
    slip: SlipMeasure,
    ln_vstar_dt_over_l: f64,
) -> Evolved {
    let SlipMeasure { q, x } = slip;
    match law {
        StateLaw::Slip => {
            if x == 0.0 {
                return Evolved {
                    theta,
                    d1: 0.0,
                    d2: 0.0,
                    d3: 0.0,
                };
            }
            let one_minus_e = -(-x).exp_m1();
            let e = 1.0 - one_minus_e;
            let theta_ss = -b * q;
            let theta_new = theta + (theta_ss - theta) * one_minus_e;
            // With dx/dq = x, de/dq = -e x and d(theta - theta_ss)/dq = b:
            // d(e x)/dq = e x (1 - x), d(e x (1 - x))/dq = e x ((1 - x)^2 - x).
            let gap = theta - theta_ss;
            let ex = e * x;
            let one_minus_x = 1.0 - x;
            Evolved {
                theta: theta_new,
                d1: -(b * one_minus_e + gap * ex),
                d2: -(2.0 * b * ex + gap * ex * one_minus_x),
                d3: -(3.0 * b * ex * one_minus_x + gap * ex * (one_minus_x * one_minus_x - x)),
            }
        }
        StateLaw::Aging => {
            if b == 0.0 {
                return Evolved {
                    theta,
                    d1: 0.0,
                    d2: f64::NAN,
                    d3: f64::NAN,
                };
            }
            // ln of the two terms of phi_new, and x h'(x)/h(x) with h = (1-e^-x)/x.
            let (ln_h, x_dlnh) = if x < 1e-8 {
                (-0.5 * x, -0.5 * x)
            } else {
                let one_minus_e = -(-x).exp_m1();
                (
                    (one_minus_e / x).ln(),
                    (1.0 - one_minus_e) * x / one_minus_e - 1.0,
                )
            };
            let a1 = theta / b - x;
            let a2 = ln_vstar_dt_over_l + ln_h;
            // theta_new = B ln(e^a1 + e^a2), evaluated as max + ln(1 + e^(min - max)).
            let (m, small) = if a1 >= a2 {
                (a1, a2 - a1)
            } else {
                (a2, a1 - a2)
            };
            let e_small = small.exp();
            let theta_new = b * (m + e_small.ln_1p());
            let (w1, w2) = if a1 >= a2 {
                (1.0, e_small)
            } else {
                (e_small, 1.0)
            };
            Evolved {
                theta: theta_new,
                d1: b * (w2 * x_dlnh - w1 * x) / (1.0 + e_small),
                d2: f64::NAN,
                d3: f64::NAN,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integrates dtheta/dt with many small RK4 steps at fixed V.
    fn rk4(law: StateLaw, b: f64, l: f64, vstar: f64, v: f64, theta: f64, dt: f64) -> f64 {
        let rhs = |th: f64| match law {
            StateLaw::Slip => -(v / l) * (th + b * (v / vstar).ln()),
            StateLaw::Aging => (b * vstar / l) * (-th / b).exp() - b * v / l,
        };
        let n = 20_000;
        let h = dt / n as f64;
        let mut th = theta;
        for _ in 0..n {
            let k1 = rhs(th);
            let k2 = rhs(th + 0.5 * h * k1);
            let k3 = rhs(th + 0.5 * h * k2);
            let k4 = rhs(th + h * k3);
            th += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        th
    }

    #[test]
    fn exact_updates_match_fine_rk4_integration() {
        let (b, l, vstar) = (0.382, 2e-4, 1e-5);
        for law in [StateLaw::Slip, StateLaw::Aging] {
            for &(v, theta, dt) in &[(1e-4_f64, 0.3, 1.0), (1e-3, -0.5, 0.05), (1e-6, 1.0, 10.0)] {
                let slip = SlipMeasure {
                    q: (v / vstar).ln(),
                    x: v * dt / l,
                };
                let exact = evolve(law, b, theta, slip, (vstar * dt / l).ln()).theta;
                let reference = rk4(law, b, l, vstar, v, theta, dt);
                assert!(
                    (exact - reference).abs() < 1e-9,
                    "{law:?} v {v}: {exact} vs {reference}"
                );
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        // Each derivative against a central difference of the one below it,
        // for slips per step x = V dt / L from 1e-13 to 160 (through x = 1
        // and 3, where the factors 1 - x and (1 - x)^2 - x change sign).
        let (b, l, vstar, dt, theta) = (0.382, 2e-4, 1e-5, 1e-3, 0.2);
        for law in [StateLaw::Slip, StateLaw::Aging] {
            for w in [-20.0, -3.0, 0.5, 2.3, 9.0, 10.0, 11.0, 12.0, 15.0] {
                let at = |w: f64| {
                    let v = vstar * f64::exp(w);
                    let slip = SlipMeasure {
                        q: w,
                        x: v * dt / l,
                    };
                    evolve(law, b, theta, slip, (vstar * dt / l).ln())
                };
                let h = 1e-6;
                let (up, down, here) = (at(w + h), at(w - h), at(w));
                let close = |fd: f64, d: f64| (fd - d).abs() <= 1e-6 * (1.0 + d.abs());
                let fd = (up.theta - down.theta) / (2.0 * h);
                assert!(close(fd, here.d1), "{law:?} w {w}: {} vs {fd}", here.d1);
                if law == StateLaw::Slip {
                    let fd2 = (up.d1 - down.d1) / (2.0 * h);
                    assert!(
                        close(fd2, here.d2),
                        "{law:?} w {w}: second derivative {} vs {fd2}",
                        here.d2
                    );
                    let fd3 = (up.d2 - down.d2) / (2.0 * h);
                    assert!(
                        close(fd3, here.d3),
                        "{law:?} w {w}: third derivative {} vs {fd3}",
                        here.d3
                    );
                } else {
                    assert!(here.d2.is_nan() && here.d3.is_nan());
                }
            }
        }
    }

    #[test]
    fn aging_heals_logarithmically_at_rest_and_slip_law_does_not() {
        let (b, l, vstar) = (0.382, 2e-4, 1e-5);
        let at_rest = SlipMeasure {
            q: f64::NEG_INFINITY,
            x: 0.0,
        };
        let slip_theta = evolve(StateLaw::Slip, b, 0.1, at_rest, 0.0).theta;
        assert_eq!(slip_theta, 0.1);
        // phi = e^{theta/B} grows by V* t / L: theta -> B ln(e^{theta/B} + V* t/L).
        let t = 1000.0;
        let aged = evolve(StateLaw::Aging, b, 0.1, at_rest, f64::ln(vstar * t / l)).theta;
        let expected = b * ((0.1 / b).exp() + vstar * t / l).ln();
        assert!((aged - expected).abs() < 1e-12);
    }
}
