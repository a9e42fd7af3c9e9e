//! Velocity steps and holds read from friction series: a constructed
//! exponential, and the rate-and-state law's own rigid response on the
//! spring-slider, whose `a`, `a - b` and `L` are known.

use floe_analysis::step_response::{hold_healing, velocity_step};
use floe_analysis::AnalysisError;
use floe_friction::protocol::{Protocol, Segment};
use floe_friction::spring_slider::{Apparatus, SpringSlider};
use floe_friction::{Form, Law, RateState, RateStateParams, StateLaw};

/// `mu(s) = after + jump exp(-s / d)` on `n` samples up to `end`.
fn exponential(after: f64, jump: f64, d: f64, end: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let slip: Vec<f64> = (0..n).map(|i| end * i as f64 / (n - 1) as f64).collect();
    let mu = slip.iter().map(|s| after + jump * (-s / d).exp()).collect();
    (slip, mu)
}

#[test]
fn an_exponential_relaxation_gives_its_jump_change_and_length() {
    let ln = 3f64.ln();
    // Up: 0.50 -> peak 0.57 -> 0.52 over 200 m.
    let (slip, mu) = exponential(0.52, 0.05, 200.0, 4000.0, 2001);
    let r = velocity_step(&[0.5; 10], &slip, &mu, 0.5, ln).unwrap();
    assert!((r.before - 0.5).abs() < 1e-15);
    assert!((r.extreme - 0.57).abs() < 1e-15 && r.extreme_slip_m == 0.0);
    assert!((r.direct_per_ln - 0.07 / ln).abs() < 1e-12);
    // The steady window starts 10 lengths on: the tail is below 1e-5.
    assert!((r.steady_per_ln - 0.02 / ln).abs() < 1e-6);
    assert!((r.evolution_per_ln() - 0.05 / ln).abs() < 1e-6);
    assert!((r.decay_slip_m - 200.0).abs() < 0.1, "{}", r.decay_slip_m);
    // Down: 0.50 -> trough 0.40 -> 0.45 over 350 m.
    let (slip, mu) = exponential(0.45, -0.05, 350.0, 8000.0, 4001);
    let r = velocity_step(&[0.5; 3], &slip, &mu, 0.5, -ln).unwrap();
    assert!((r.extreme - 0.40).abs() < 1e-15);
    assert!((r.direct_per_ln - 0.10 / ln).abs() < 1e-12);
    assert!((r.steady_per_ln - 0.05 / ln).abs() < 1e-6);
    assert!((r.decay_slip_m - 350.0).abs() < 0.1, "{}", r.decay_slip_m);
}

#[test]
fn the_extreme_may_come_after_a_rise_and_the_fit_starts_there() {
    // A driver of finite stiffness: friction rises for 100 m, then decays
    // over 300 m from the peak.
    let (slip, mut mu): (Vec<f64>, Vec<f64>) = (0..6001)
        .map(|i| {
            let s = i as f64;
            let m = if s <= 100.0 {
                0.5 + 0.001 * s
            } else {
                0.55 + 0.05 * (-(s - 100.0) / 300.0).exp()
            };
            (s, m)
        })
        .unzip();
    mu[0] = 0.5;
    let r = velocity_step(&[0.5], &slip, &mu, 0.4, 1.0).unwrap();
    assert_eq!(r.extreme_slip_m, 100.0);
    assert!((r.decay_slip_m - 300.0).abs() < 0.1, "{}", r.decay_slip_m);
}

/// The law's rigid response to a tenfold step at `from`: the step read
/// from the slider's series, slip the load point's travel.
fn slider_step(
    from: f64,
    to: f64,
) -> (RateStateParams, floe_analysis::step_response::VelocityStep) {
    let p = RateStateParams::lishman_2011_lab();
    let law = Law::RateState(RateState::new(p, Form::Published, StateLaw::Slip));
    // Stiff enough that the slider follows the load point (as in
    // tests/friction/physics.rs).
    let apparatus = Apparatus::new(1e14, 2e3, 1e-4).unwrap();
    let mut slider = SpringSlider::new(law, apparatus, from);
    let before = slider.sample().mu;
    let l = p.critical_slip_m;
    let run = Protocol::new(vec![Segment::constant(to, 30.0 * l / to)]).unwrap();
    let samples = slider.record(&run, 0.01 * l / to);
    let (slip, mu): (Vec<f64>, Vec<f64>) = samples
        .iter()
        .filter(|s| s.t_s > 0.0)
        .map(|s| (s.load_point_m - samples[0].load_point_m, s.mu))
        .unzip();
    let r = velocity_step(&[before], &slip, &mu, 0.4, (to / from).ln()).unwrap();
    (p, r)
}

#[test]
fn the_rate_and_state_slider_gives_back_a_b_and_l() {
    for (from, to) in [(1e-4, 1e-3), (1e-3, 1e-4)] {
        let (p, r) = slider_step(from, to);
        // The first sample is 0.01 L after the step: the direct effect is
        // read 1 % of the way into the decay, B (1 - e^-0.01) / A low.
        assert!(
            (r.direct_per_ln - p.a).abs() < 0.015 * p.a,
            "{from}: a {}",
            r.direct_per_ln
        );
        assert!(
            (r.steady_per_ln - (p.a - p.b)).abs() < 1e-6,
            "{from}: a-b {}",
            r.steady_per_ln
        );
        assert!((r.evolution_per_ln() - p.b).abs() < 0.015 * p.b);
        let l = p.critical_slip_m;
        assert!(
            (r.decay_slip_m - l).abs() < 1e-3 * l,
            "{from}: L {} against {l}",
            r.decay_slip_m
        );
    }
}

#[test]
fn a_hold_heals_by_its_peak_over_the_sliding_before() {
    let r = hold_healing(&[0.4, 0.42, 0.41, 0.41], &[0.3, 0.5, 0.45, 0.41]).unwrap();
    assert!((r.before - 0.41).abs() < 1e-15);
    assert_eq!(r.peak, 0.5);
    assert!((r.healing - 0.09).abs() < 1e-15);
}

#[test]
fn bad_series_are_refused_not_read() {
    let slip = [0.0, 1.0, 2.0, 3.0];
    let mu = [0.5; 4];
    assert!(matches!(
        velocity_step(&[], &slip, &mu, 0.5, 1.0),
        Err(AnalysisError::NotEnoughData(_))
    ));
    assert!(matches!(
        velocity_step(&[0.5], &slip, &mu[..3], 0.5, 1.0),
        Err(AnalysisError::LengthMismatch { .. })
    ));
    assert!(velocity_step(&[0.5], &[0.0, 1.0, 1.0, 2.0], &mu, 0.5, 1.0).is_err());
    assert!(velocity_step(&[0.5], &slip, &[0.5, f64::NAN, 0.5, 0.5], 0.5, 1.0).is_err());
    assert!(velocity_step(&[0.5], &slip, &mu, 1.0, 1.0).is_err());
    assert!(velocity_step(&[0.5], &slip, &mu, 0.5, 0.0).is_err());
    assert!(hold_healing(&[0.5], &[]).is_err());
}

#[test]
fn a_series_that_does_not_relax_has_no_slip_distance() {
    let slip: Vec<f64> = (0..400).map(f64::from).collect();
    // Flat after the step: nothing relaxes.
    let flat = vec![0.52; 400];
    let r = velocity_step(&[0.5], &slip, &flat, 0.5, 1.0).unwrap();
    assert!(r.decay_slip_m.is_nan() && (r.steady_per_ln - 0.02).abs() < 1e-12);
    // A rise to the new level (no overshoot to relax from) and a slow
    // drift that the window cannot resolve: no length either.
    let drift: Vec<f64> = slip.iter().map(|s| 0.5 + 1e-5 * s).collect();
    let r = velocity_step(&[0.5], &slip, &drift, 0.5, 1.0).unwrap();
    assert!(r.decay_slip_m.is_nan(), "{}", r.decay_slip_m);
    // Too short a window: no transient part before the steady one.
    assert!(velocity_step(&[0.5], &[10.0, 11.0, 12.0, 13.0], &[0.5; 4], 0.99, 1.0).is_err());
    assert!(velocity_step(&[f64::NAN], &slip, &flat, 0.5, 1.0).is_err());
    assert!(hold_healing(&[0.5], &[0.4, f64::NAN]).is_err());
}
