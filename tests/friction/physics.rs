//! Physics of the contact laws: analytic solutions, limits, convergence and
//! stability of the spring-slider (the single contact of the DEM).

use floe_friction::experiments::{hold_test, late_oscillation_amplitude, velocity_step, Preset};
use floe_friction::protocol::{Protocol, Segment};
use floe_friction::rate_state::SOLVER_TREND;
use floe_friction::reference::friction_series;
use floe_friction::spring_slider::{Apparatus, SpringSlider};
use floe_friction::*;

const FORMS: [Form; 2] = [Form::Published, Form::Regularized];
const STATE_LAWS: [StateLaw; 2] = [StateLaw::Slip, StateLaw::Aging];

fn rate_state(p: RateStateParams, form: Form, state_law: StateLaw) -> Law {
    Law::RateState(RateState::new(p, form, state_law))
}

/// Steady-state mu of eq. 3 with theta at steady state, computed here from the
/// formulas (not through the crate).
fn mu_ss_formula(p: &RateStateParams, form: Form, v: f64) -> f64 {
    let theta = -p.b * (v / p.v_star_m_per_s).ln();
    match form {
        Form::Published => p.mu0 + theta + p.a * (v / p.v_star_m_per_s).ln(),
        Form::Regularized => {
            p.a * (v / (2.0 * p.v_star_m_per_s) * ((p.mu0 + theta) / p.a).exp()).asinh()
        }
    }
}

#[test]
fn steady_state_matches_the_physics_notes_values() {
    // Values of the notes (mu0 + (A - B) ln(V/V*) with Table 2).
    let p = RateStateParams::lishman_2011_lab();
    for (v, expected) in [
        (1e-4, 0.706214),
        (1e-3, 0.540428),
        (8e-3, 0.390708),
        (3e-2, 0.295542),
    ] {
        assert!((p.mu_steady_published(v) - expected).abs() < 5e-7, "v {v}");
    }
}

#[test]
fn sliding_relaxes_to_the_analytic_steady_state_for_every_form_and_state_law() {
    let p = RateStateParams::lishman_2011_lab();
    let apparatus = Preset::Lab.apparatus(1e-3);
    for form in FORMS {
        for state_law in STATE_LAWS {
            for v in [1e-4, 1e-3, 3e-2] {
                // Start in steady state at v/3, slide at v for 60 L.
                let mut slider =
                    SpringSlider::new(rate_state(p, form, state_law), apparatus, v / 3.0);
                let run = Protocol::new(vec![Segment::constant(v, 60.0 * p.critical_slip_m / v)])
                    .unwrap();
                slider.run(&run, |_| {});
                let s = slider.sample();
                let expected = mu_ss_formula(&p, form, v);
                assert!(
                    (s.mu - expected).abs() < 1e-8,
                    "{form:?} {state_law:?} v {v}: mu {} expected {expected}",
                    s.mu
                );
                assert!((s.slip_rate_m_per_s - v).abs() < 1e-8 * v);
                assert!((s.theta + p.b * (v / p.v_star_m_per_s).ln()).abs() < 1e-8);
            }
        }
    }
}

#[test]
fn rigid_velocity_step_jumps_by_a_ln_ratio_and_decays_over_l() {
    // A very stiff spring makes the slider follow the load point: the law's
    // rigid-limit response. Slip law, published form (as in the paper).
    let p = RateStateParams::lishman_2011_lab();
    let law = rate_state(p, Form::Published, StateLaw::Slip);
    let (v1, v2, n, dt) = (1e-4, 1e-3, 2e3, 1e-4);
    // k = 1e14 N/m: the spring takes up the jump of 1400 N in 1.4e-11 m.
    let apparatus = Apparatus::new(1e14, n, dt).unwrap();
    let mut slider = SpringSlider::new(law, apparatus, v1);
    let mu_ss1 = slider.sample().mu;
    let x0 = slider.sample().slider_m;
    let l = p.critical_slip_m;
    let run = Protocol::new(vec![Segment::constant(v2, 15.0 * l / v2)]).unwrap();
    let mut worst: f64 = 0.0;
    let mut first = None;
    slider.run(&run, |s| {
        // Exact rigid response at slip distance d after the step:
        // mu = mu_ss(V2) + B ln(V2/V1) exp(-d/L); at d -> 0 it is mu_ss1 + A ln(V2/V1).
        let d = s.slider_m - x0;
        let exact = p.mu_steady_published(v2) + p.b * (v2 / v1).ln() * (-d / l).exp();
        if first.is_some() {
            worst = worst.max((s.mu - exact).abs());
        }
        first.get_or_insert(s.mu);
    });
    // After the first step, the decay follows the rigid solution as a function
    // of slip (the state update is exact at constant V).
    assert!(
        worst < 1e-6,
        "max deviation from the rigid solution {worst}"
    );
    // The jump: A ln 10 = 0.7138 within what one step of slip (V2 dt = L/2000) evolves.
    let jump = first.unwrap() - mu_ss1;
    assert!((jump - p.a * 10f64.ln()).abs() < 1e-3, "jump {jump}");
    // New steady state shifted by (A - B) ln 10 = -0.1658.
    let shift = slider.sample().mu - mu_ss1;
    assert!(
        (shift - (p.a - p.b) * 10f64.ln()).abs() < 1e-6,
        "shift {shift}"
    );
    assert!((shift + 0.1658).abs() < 1e-4);
}

#[test]
fn velocity_step_experiment_reaches_the_new_steady_state() {
    for form in FORMS {
        let law = rate_state(Preset::Lab.params(), form, StateLaw::Slip);
        let r = velocity_step(law.clone(), Preset::Lab.apparatus(1e-3), 1e-4, 1e-3);
        assert!(
            (r.mu_ss_after - r.mu_ss_after_analytic).abs() < 1e-6,
            "{form:?} {r:?}"
        );
        assert!(
            r.mu_peak > r.mu_ss_before + 0.4,
            "{form:?}: direct effect visible: {r:?}"
        );
        let down = velocity_step(law, Preset::Lab.apparatus(1e-3), 1e-3, 1e-4);
        assert!(
            down.mu_peak < down.mu_ss_before - 0.4,
            "{form:?}: dip on a down-step: {down:?}"
        );
    }
}

#[test]
fn fixed_step_update_converges_at_first_order_to_a_tight_stiff_solution() {
    let p = RateStateParams::lishman_2011_lab();
    // Step up, step down, hold, reslide: every transient the paper uses.
    let segments = [(1e-3, 1.0), (1e-4, 2.0), (0.0, 2.0), (1e-4, 3.0)];
    let every = 0.1;
    for form in FORMS {
        let reference = friction_series(
            &RateState::new(p, form, StateLaw::Slip),
            20e6 / 2e3,
            &segments,
            1e-4,
            every,
        )
        .unwrap();
        let protocol = Protocol::new(
            segments
                .iter()
                .map(|&(v, d)| Segment::constant(v, d))
                .collect(),
        )
        .unwrap();
        let dts = [1e-2, 5e-3, 2.5e-3, 1.25e-3, 6.25e-4];
        let errors: Vec<f64> = dts
            .iter()
            .map(|&dt| {
                let apparatus = Apparatus::new(20e6, 2e3, dt).unwrap();
                let mut slider =
                    SpringSlider::new(rate_state(p, form, StateLaw::Slip), apparatus, 1e-4);
                let series = slider.record(&protocol, every);
                assert_eq!(series.len(), reference.len(), "{form:?} dt {dt}");
                series
                    .iter()
                    .zip(&reference)
                    .map(|(s, r)| (s.mu - r).abs())
                    .fold(0.0, f64::max)
            })
            .collect();
        let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        eprintln!("{form:?}: max |mu - reference| {errors:?}, observed orders {orders:?}");
        for order in &orders[1..] {
            assert!(
                (0.85..1.3).contains(order),
                "{form:?}: order {order} (errors {errors:?})"
            );
        }
        // At the paper's dt = 1 ms the error is a few 1e-3 at most.
        assert!(errors[3] < 1e-2, "{form:?}: error at 1.25 ms {}", errors[3]);
    }
}

#[test]
fn stick_slip_below_critical_stiffness_and_steady_sliding_above() {
    let p = RateStateParams::lishman_2011_lab();
    let n = 2e3;
    let k_c = p.critical_stiffness_n_per_m(n);
    assert!((k_c - 0.72e6).abs() < 1.0, "k_c {k_c}");
    for form in FORMS {
        let law = rate_state(p, form, StateLaw::Slip);
        let amplitude = |ratio: f64| {
            let apparatus = Apparatus::new(ratio * k_c, n, 1e-3).unwrap();
            late_oscillation_amplitude(law.clone(), apparatus, 1e-4, 600.0)
        };
        let (unstable, stable) = (amplitude(0.7), amplitude(1.5));
        eprintln!("{form:?}: amplitude at 0.7 k_c {unstable:.3e}, at 1.5 k_c {stable:.3e}");
        assert!(
            unstable > 0.05,
            "{form:?}: expected stick-slip at 0.7 k_c, amplitude {unstable}"
        );
        assert!(
            stable < 1e-6,
            "{form:?}: expected steady sliding at 1.5 k_c, amplitude {stable}"
        );
    }
}

#[test]
fn regularized_form_reduces_to_published_where_mu_over_a_is_large() {
    // Friction at a given slip rate and state: the two forms differ by
    // A (ln 2X - asinh X) ~ A / (4 X^2) with X = exp(mu/A) / 2.
    let p = RateStateParams::lishman_2011_lab();
    let published = RateState::new(p, Form::Published, StateLaw::Slip);
    let regularized = RateState::new(p, Form::Regularized, StateLaw::Slip);
    let mut previous = f64::INFINITY;
    for v in [1e-6, 1e-5, 1e-4, 1e-3, 1e-2] {
        let theta = -0.3;
        let (mp, mr) = (published.mu_at(v, theta), regularized.mu_at(v, theta));
        let bound = p.a * (-2.0 * mp / p.a).exp();
        assert!(
            (mp - mr).abs() <= bound,
            "v {v}: {mp} vs {mr}, bound {bound}"
        );
        assert!(
            (mp - mr).abs() < previous,
            "difference shrinks as mu/A grows"
        );
        previous = (mp - mr).abs();
    }
    // A rock-like law (A = 0.01, mu/A ~ 60): whole spring-slider runs agree.
    let rock = RateStateParams {
        mu0: 0.6,
        a: 0.01,
        b: 0.015,
        v_star_m_per_s: 1e-6,
        critical_slip_m: 1e-5,
    };
    let protocol = Protocol::new(vec![
        Segment::constant(1e-5, 5.0),
        Segment::hold(20.0),
        Segment::constant(1e-4, 2.0),
    ])
    .unwrap();
    let apparatus = Apparatus::new(1e8, 1e3, 1e-3).unwrap();
    let run = |form| {
        SpringSlider::new(rate_state(rock, form, StateLaw::Slip), apparatus, 1e-5)
            .record(&protocol, 0.5)
    };
    for (a, b) in run(Form::Published).iter().zip(&run(Form::Regularized)) {
        assert!(
            (a.mu - b.mu).abs() < 1e-12,
            "t {}: {} vs {}",
            a.t_s,
            a.mu,
            b.mu
        );
    }
}

#[test]
fn hold_tests_show_what_each_form_and_state_law_predicts() {
    let preset = Preset::Lab;
    let holds = preset.paper_hold_times_s();
    let run = |form, state_law| -> Vec<f64> {
        let law = rate_state(preset.params(), form, state_law);
        holds
            .iter()
            .map(|&h| {
                hold_test(
                    law.clone(),
                    preset.apparatus(1e-3),
                    preset.speed_m_per_s(),
                    h,
                )
                .delta_mu
            })
            .collect()
    };
    let published_slip = run(Form::Published, StateLaw::Slip);
    let regularized_slip = run(Form::Regularized, StateLaw::Slip);
    let aging = run(Form::Published, StateLaw::Aging);
    // Published form: the slider creeps through the hold, so peaks keep growing.
    assert!(
        published_slip.windows(2).all(|w| w[1] > w[0] + 0.1),
        "{published_slip:?}"
    );
    // Regularised slip law heals only while creeping: strengthening saturates.
    assert!(
        (regularized_slip[3] - regularized_slip[2]).abs() < 1e-3,
        "{regularized_slip:?}"
    );
    assert!(regularized_slip[1] > regularized_slip[0]);
    // Aging law heals as B ln(t_hold) at long holds.
    let per_decade = aging[3] - aging[2];
    let expected = preset.params().b * 10f64.ln();
    assert!(
        (per_decade - expected).abs() < 0.03 * expected,
        "{per_decade} vs {expected}"
    );
}

#[test]
fn amontons_sticks_in_a_hold_and_slides_at_constant_mu() {
    let law = Law::Amontons(Amontons { mu: 0.5 });
    let apparatus = Apparatus::new(1e6, 1e3, 1e-3).unwrap();
    let mut slider = SpringSlider::new(law, apparatus, 1e-3);
    let protocol = Protocol::new(vec![Segment::constant(1e-3, 1.0), Segment::hold(10.0)]).unwrap();
    let series = slider.record(&protocol, 0.5);
    for s in &series {
        assert!((s.mu - 0.5).abs() < 1e-12, "t {} mu {}", s.t_s, s.mu);
    }
    // No creep in a hold: the slider stops with the load point.
    assert_eq!(series.last().unwrap().slip_rate_m_per_s, 0.0);
}

#[test]
fn rate_dependent_law_follows_eq_2_on_a_rigid_spring_and_sticks_in_a_hold() {
    let law = Law::RateDependent(RateDependent::lishman_2011(-0.072));
    let apparatus = Apparatus::new(1e14, 2e3, 1e-3).unwrap();
    let mut slider = SpringSlider::new(law, apparatus, 1e-4);
    let protocol = Protocol::new(vec![
        Segment::constant(1e-3, 2.0),
        Segment::hold(5.0),
        Segment::constant(1e-3, 2.0),
    ])
    .unwrap();
    let series = slider.record(&protocol, 0.01);
    let at = |t: f64| series.iter().find(|s| (s.t_s - t).abs() < 1e-9).unwrap();
    let eq2 = 0.872 - 0.072 * (1e-3f64 / 1e-5).ln();
    assert!((at(2.0).mu - eq2).abs() < 1e-6, "{} vs {eq2}", at(2.0).mu);
    assert_eq!(at(6.0).slip_rate_m_per_s, 0.0);
    assert!((at(9.0).mu - eq2).abs() < 1e-6);
}

#[test]
fn rate_dependent_law_stick_slips_on_a_soft_spring() {
    // Velocity weakening with no direct effect: steady sliding on a spring is
    // unstable (dV/dt = k (V_lp - V) / (N dmu/dV) with dmu/dV < 0), so the lab
    // apparatus stick-slips between static friction mu(V*) = mu0 and below.
    let law = Law::RateDependent(RateDependent::lishman_2011(-0.072));
    let mut slider = SpringSlider::new(law, Preset::Lab.apparatus(1e-3), 1e-3);
    let protocol = Protocol::new(vec![Segment::constant(1e-3, 30.0)]).unwrap();
    let series = slider.record(&protocol, 1e-3);
    let late = &series[series.len() / 2..];
    let max = late.iter().map(|s| s.mu).fold(f64::NEG_INFINITY, f64::max);
    let min = late.iter().map(|s| s.mu).fold(f64::INFINITY, f64::min);
    let stuck = late.iter().filter(|s| s.slip_rate_m_per_s == 0.0).count();
    // The spring loads by k V dt / N = 0.01 in mu per step while stuck.
    assert!(
        max <= 0.872 + 1e-12 && max > 0.872 - 0.0101,
        "peaks at static friction: {max}"
    );
    assert!(max - min > 0.1, "stick-slip amplitude {}", max - min);
    assert!(
        stuck > late.len() / 10,
        "sticks part of the time: {stuck} of {}",
        late.len()
    );
}

#[test]
fn the_extrapolated_start_saves_evaluations_and_changes_no_result() {
    // The paper's velocity steps at its dt = 1 ms, up and down, through
    // transients that last ~L / V (hundreds of steps): the slip rate
    // changes smoothly, and starting each solve from the last root plus its
    // last change (`solver_trend`) should take one evaluation in most
    // steps. The same run with the trend zeroed before every step starts
    // from the last root alone: it must give the same friction to the
    // solver's tolerance, in more evaluations.
    let p = Preset::Lab.params();
    let apparatus = Preset::Lab.apparatus(1e-3);
    let segments = [(1e-4, 2.0), (1e-3, 1.0), (1e-4, 2.0), (3e-3, 0.5)];
    for form in FORMS {
        let law = rate_state(p, form, StateLaw::Slip);
        let run = |extrapolate: bool| {
            let mut state = law.steady_state(1e-4, apparatus.normal_load_n);
            let (mut mu, mut evaluations) = (Vec::new(), 0u64);
            for &(v, duration) in &segments {
                let load = ContactLoad {
                    load_point_velocity_m_per_s: v,
                    stiffness_n_per_m: apparatus.stiffness_n_per_m,
                    normal_load_n: apparatus.normal_load_n,
                };
                for _ in 0..(duration / apparatus.dt_s).round() as usize {
                    if !extrapolate {
                        state.law_state[SOLVER_TREND] = 0.0;
                    }
                    let out = law.step(&mut state, &load, apparatus.dt_s);
                    mu.push(out.mu);
                    evaluations += u64::from(out.iterations);
                }
            }
            let mean = evaluations as f64 / mu.len() as f64;
            (mu, mean)
        };
        let ((with, mean_with), (without, mean_without)) = (run(true), run(false));
        let worst = with
            .iter()
            .zip(&without)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{form:?}: {mean_with:.3} evaluations per step extrapolated, \
             {mean_without:.3} from the last root; results differ by {worst:.1e}"
        );
        assert!(worst < 1e-10, "{form:?}: results differ by {worst}");
        assert!(
            mean_with < 1.1,
            "{form:?}: {mean_with} evaluations per step"
        );
        assert!(
            mean_with < mean_without - 0.1,
            "{form:?}: {mean_with} against {mean_without}"
        );
    }
}
