//! Property tests of the per-contact update over the whole range the DEM can
//! throw at it: dt 1 us - 10 s, normal load 0 and 1 mN - 1 GN, slip rates
//! 1e-15 - 10 m/s either way, reversals.

use crate::proptest_settings;
use floe_friction::rate_state::{SOLVER_GUESS, SOLVER_TREND, THETA};
use floe_friction::*;
use proptest::prelude::*;

fn law_strategy() -> impl Strategy<Value = Law> {
    let rate_state = (
        any::<bool>(),
        any::<bool>(),
        prop_oneof![Just(2e-4), Just(5e-3), 1e-6..1.0f64],
    )
        .prop_map(|(published, aging, l)| {
            Law::RateState(RateState::new(
                RateStateParams::lishman_2011(l),
                if published {
                    Form::Published
                } else {
                    Form::Regularized
                },
                if aging {
                    StateLaw::Aging
                } else {
                    StateLaw::Slip
                },
            ))
        });
    prop_oneof![
        6 => rate_state,
        1 => (0.0..1.5f64).prop_map(|mu| Law::Amontons(Amontons { mu })),
        1 => prop_oneof![Just(-0.072), Just(-0.10), Just(-0.16), Just(0.02)]
            .prop_map(|c1| Law::RateDependent(RateDependent::lishman_2011(c1))),
    ]
}

/// log-uniform magnitude with a random sign, or exactly zero.
fn signed_log(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        8 => (lo.log10()..hi.log10(), any::<bool>()).prop_map(|(e, neg)| {
            let m = 10f64.powf(e);
            if neg { -m } else { m }
        }),
    ]
}

fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..hi.log10()).prop_map(|e| 10f64.powf(e))
}

fn normal_load() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 9 => log_uniform(1e-3, 1e9)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..proptest_settings::default() })]

    #[test]
    fn every_step_is_finite_and_satisfies_the_law(
        law in law_strategy(),
        dt in log_uniform(1e-6, 10.0),
        n in normal_load(),
        k in log_uniform(1e2, 1e12),
        v0 in signed_log(1e-15, 10.0),
        velocities in prop::collection::vec(signed_log(1e-15, 10.0), 1..6),
        guess in -50.0..50.0f64,
    ) {
        let mut state = law.steady_state(v0, n);
        state.law_state[SOLVER_GUESS] += guess * 0.1;
        for &v in &velocities {
            let load = ContactLoad { load_point_velocity_m_per_s: v, stiffness_n_per_m: k, normal_load_n: n };
            let before = state;
            let out = law.step(&mut state, &load, dt);
            prop_assert!(out.mu.is_finite() && out.slip_rate_m_per_s.is_finite(), "{out:?}");
            prop_assert!(state.tangential_force_n.is_finite() && state.law_state[THETA].is_finite() && state.law_state[SOLVER_GUESS].is_finite(), "{state:?}");
            if n > 0.0 {
                // The spring: F_new = F + k (V_lp - V) dt, to round-off of the larger term.
                let spring = before.tangential_force_n + k * (v - out.slip_rate_m_per_s) * dt;
                let scale = before.tangential_force_n.abs() + (k * v * dt).abs() + (k * out.slip_rate_m_per_s * dt).abs() + n;
                prop_assert!((state.tangential_force_n - spring).abs() <= 1e-9 * scale, "{state:?} vs {spring}");
                // The law holds at the end of the step.
                if let Law::RateState(rs) = law {
                    let law_mu = rs.mu_at(out.slip_rate_m_per_s, state.law_state[THETA]);
                    let tol = 1e-8 * (1.0 + law_mu.abs()) + 1e-9 * scale / n;
                    // Below ~1e-290 m/s the reported V is subnormal and its log loses
                    // digits (the solver itself works with ln V and is exact).
                    if out.slip_rate_m_per_s.abs() > 1e-290 && law_mu.is_finite() {
                        prop_assert!((law_mu - out.mu).abs() <= tol, "law {law_mu} vs F/N {} ({rs:?})", out.mu);
                    }
                }
                // Coulomb-type laws never exceed their cap.
                if let Law::Amontons(a) = law {
                    prop_assert!(out.mu.abs() <= a.mu * (1.0 + 1e-12));
                }
            } else {
                prop_assert_eq!(state.tangential_force_n, 0.0);
            }
        }
    }

    #[test]
    fn reversed_loading_reverses_the_regularised_friction(
        steps in 200usize..2000,
        n in log_uniform(1.0, 1e7),
        v in log_uniform(1e-6, 1e-1),
    ) {
        // Slide forward in steady state, then drive backwards by 15 L plus the
        // spring's reload distance: friction and slip must both turn negative.
        let p = RateStateParams::lishman_2011_lab();
        let law = Law::RateState(RateState::new(p, Form::Regularized, StateLaw::Slip));
        let k = 20e6 * n / 2e3;
        let distance = 15.0 * p.critical_slip_m + 2.0 * 1.5 * n / k;
        let dt = distance / (v * steps as f64);
        let mut state = law.steady_state(v, n);
        let load = ContactLoad { load_point_velocity_m_per_s: -v, stiffness_n_per_m: k, normal_load_n: n };
        let mut last = law.step(&mut state, &load, dt);
        for _ in 1..steps { last = law.step(&mut state, &load, dt); }
        prop_assert!(last.mu < 0.0 && last.slip_rate_m_per_s < 0.0, "{last:?} dt {dt}");
    }
}

/// One contact of a batch: its starting state and the load of the step.
fn batch_contact(law: Law) -> impl Strategy<Value = (ContactState, ContactLoad)> {
    (
        normal_load(),
        log_uniform(1e2, 1e12),
        signed_log(1e-15, 10.0),
        signed_log(1e-15, 10.0),
        -50.0..50.0f64,
        -1.0..1.0f64,
    )
        .prop_map(move |(n, k, v0, v, guess, trend)| {
            let mut state = law.steady_state(v0, n);
            state.law_state[SOLVER_GUESS] += guess * 0.1;
            state.law_state[SOLVER_TREND] = trend;
            let load = ContactLoad {
                load_point_velocity_m_per_s: v,
                stiffness_n_per_m: k,
                normal_load_n: n,
            };
            (state, load)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..proptest_settings::default() })]

    /// `Law::step_batch` iterates several contacts' solves side by side, each
    /// lane taking a new contact when its own converges: every contact must
    /// come out bitwise as `FrictionLaw::step` leaves it, whatever its
    /// neighbours in the batch (which need different numbers of iterations,
    /// or none).
    #[test]
    fn a_batch_step_is_bitwise_the_steps_one_by_one(
        (law, contacts) in law_strategy().prop_flat_map(|law| {
            (Just(law.clone()), prop::collection::vec(batch_contact(law), 0..40))
        }),
        dt in log_uniform(1e-6, 10.0),
    ) {
        let mut items: Vec<BatchItem> = contacts
            .iter()
            .map(|&(state, load)| BatchItem {
                state,
                load,
                outcome: StepOutcome { slip_rate_m_per_s: f64::NAN, mu: f64::NAN, iterations: u32::MAX },
            })
            .collect();
        law.step_batch(&mut items, dt);
        for (item, &(state, load)) in items.iter().zip(&contacts) {
            let mut alone = state;
            let out = law.step(&mut alone, &load, dt);
            let bits = |s: &ContactState| {
                [s.tangential_force_n, s.law_state[THETA], s.law_state[SOLVER_GUESS], s.law_state[SOLVER_TREND]].map(f64::to_bits)
            };
            prop_assert_eq!(bits(&item.state), bits(&alone));
            prop_assert_eq!(item.outcome.slip_rate_m_per_s.to_bits(), out.slip_rate_m_per_s.to_bits());
            prop_assert_eq!(item.outcome.mu.to_bits(), out.mu.to_bits());
            prop_assert_eq!(item.outcome.iterations, out.iterations);
        }
    }
}
