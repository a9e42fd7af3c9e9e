//! Parameter fitting (`floe_friction::fit`): recovery of known parameters
//! from synthetic noisy data, the section-5 model comparison, and rejection
//! of bad input.
//!
//! The synthetic series comes from the same forward model the fit uses, so
//! these tests check the optimiser, the parametrisation and the error
//! analysis, not the physics.

use floe_friction::fit::{
    compare_models, fit_constant, fit_rate_at_load_point, fit_rate_dependent, fit_rate_state,
    predict, Experiment, FitData, ModelFit,
};
use floe_friction::protocol::{Protocol, Segment};
use floe_friction::spring_slider::Apparatus;
use floe_friction::{
    Form, FrictionError, Law, RateDependent, RateState, RateStateParams, StateLaw,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Standard deviation of the synthetic measurement noise.
const SIGMA: f64 = 0.005;
/// Sampling interval of the synthetic series, s (50 steps of the apparatus).
const SAMPLE_EVERY_S: f64 = 0.05;
/// Relative tolerance on each recovered parameter. Chosen so that every
/// starting value (Lishman et al.'s) is outside it: recovery must move.
const REL_TOL: f64 = 0.05;

/// Truth for the synthetic data: deliberately not the published values.
fn truth() -> RateState {
    RateState::new(
        RateStateParams {
            mu0: 0.80,
            a: 0.25,
            b: 0.33,
            v_star_m_per_s: 1e-5,
            critical_slip_m: 0.5e-3,
        },
        Form::Regularized,
        StateLaw::Slip,
    )
}

/// Starting guess: Lishman et al. (2011) Table 2, laboratory L.
fn lishman_template() -> RateState {
    RateState::new(
        RateStateParams::lishman_2011_lab(),
        Form::Regularized,
        StateLaw::Slip,
    )
}

/// Lab apparatus (k = 20 MN/m, N = 2 kN, dt = 1 ms) and a 45 s protocol with
/// a step up, a step down, a hold and a ramp: transients that separate `A`
/// (direct effect), `B` (evolution) and `L` (decay length). About 45 000
/// steps, tens of milliseconds per simulation in release.
fn experiment() -> Experiment {
    let protocol = Protocol::new(vec![
        Segment::constant(1e-4, 10.0),
        Segment::constant(1e-3, 5.0),
        Segment::constant(1e-4, 10.0),
        Segment::hold(5.0),
        Segment::constant(1e-4, 10.0),
        Segment::ramp(1e-4, 5e-4, 5.0),
    ])
    .expect("valid protocol");
    let apparatus = Apparatus::new(20e6, 2e3, 1e-3).expect("valid apparatus");
    Experiment::new(protocol, apparatus, 1e-4).expect("valid experiment")
}

/// Sample times: every `SAMPLE_EVERY_S` from 0 to the end of the protocol,
/// offset by a third of a step so that they do not fall on step ends.
fn sample_times(experiment: &Experiment) -> Vec<f64> {
    let end = experiment.protocol().duration_s();
    let offset = experiment.apparatus().dt_s / 3.0;
    (0..)
        .map(|i| offset + i as f64 * SAMPLE_EVERY_S)
        .take_while(|&t| t <= end)
        .collect()
}

/// The truth's friction at the sample times plus seeded Gaussian noise.
fn synthetic_data(experiment: &Experiment, seed: u64) -> FitData {
    let t = sample_times(experiment);
    let clean = predict(&Law::RateState(truth()), experiment, &t).expect("forward model");
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let noise = Normal::new(0.0, SIGMA).expect("valid normal");
    let mu = clean.iter().map(|m| m + noise.sample(&mut rng)).collect();
    FitData::new(t, mu).expect("valid synthetic data")
}

fn value(fit: &ModelFit, name: &str) -> (f64, f64) {
    let p = fit
        .parameter(name)
        .unwrap_or_else(|| panic!("{} fit has no parameter {name}", fit.model));
    (p.value, p.std_error)
}

#[test]
fn rate_state_fit_recovers_known_parameters_from_noisy_data() {
    let experiment = experiment();
    let data = synthetic_data(&experiment, 20_110_511);
    let start = lishman_template().params;
    let truth = truth().params;
    let cases = [
        ("mu0", truth.mu0, start.mu0),
        ("a", truth.a, start.a),
        ("b", truth.b, start.b),
        (
            "critical_slip_m",
            truth.critical_slip_m,
            start.critical_slip_m,
        ),
    ];
    for (name, t, s) in cases {
        assert!(
            ((s - t) / t).abs() > REL_TOL,
            "the start {name} = {s} is already within {REL_TOL} of the truth {t}"
        );
    }

    let fit = fit_rate_state(&data, &experiment, &lishman_template()).expect("fit runs");
    println!(
        "rate-state fit: {}",
        serde_json::to_string(&fit).expect("serialisable")
    );
    assert!(fit.converged, "not converged: {}", fit.termination);
    assert_eq!(fit.n, data.len());
    for (name, t, _) in cases {
        let (v, se) = value(&fit, name);
        assert!(
            se.is_finite() && se > 0.0,
            "{name}: standard error {se} must be finite and > 0"
        );
        assert!(
            (v - t).abs() <= 4.0 * se,
            "{name} = {v} +- {se} is more than 4 standard errors from the truth {t}"
        );
        assert!(
            ((v - t) / t).abs() <= REL_TOL,
            "{name} = {v} is more than {REL_TOL} (relative) from the truth {t}"
        );
    }
    // The fixed parameters come from the template.
    match fit.law {
        Law::RateState(r) => {
            assert_eq!(r.params.v_star_m_per_s, start.v_star_m_per_s);
            assert_eq!(r.form, Form::Regularized);
            assert_eq!(r.state_law, StateLaw::Slip);
        }
        other => panic!("rate-state fit returned a {} law", other.name()),
    }
    // At the optimum the residuals are the noise: MSE ~ sigma^2 (with n ~ 900
    // its sampling spread is about 5 %).
    let ratio = fit.mse / (SIGMA * SIGMA);
    assert!(
        (ratio - 1.0).abs() < 0.3,
        "MSE {} is not close to sigma^2 = {} (ratio {ratio})",
        fit.mse,
        SIGMA * SIGMA
    );
    assert!((fit.mse - fit.ssr / fit.n as f64).abs() <= 1e-15);
}

/// Replicates in the standard-error calibration.
const REPLICATES: u64 = 16;

#[test]
fn standard_errors_match_the_scatter_over_noise_realisations() {
    // If the reported standard errors are right, z = (estimate - truth) / se
    // is roughly standard normal, so mean(z^2) over the replicates follows
    // chi^2_16 / 16: its 0.1 % and 99.9 % quantiles are 0.25 and 2.45. A
    // standard error off by a factor 2 (or a missing log-to-linear
    // conversion) moves mean(z^2) by a factor 4 or more.
    let experiment = experiment();
    let truth = truth().params;
    let names = ["mu0", "a", "b", "critical_slip_m"];
    let truths = [truth.mu0, truth.a, truth.b, truth.critical_slip_m];
    // Two threads: the machine has two cores and each fit is serial.
    let z2_sums: Vec<[f64; 4]> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..2)
            .map(|worker| {
                let experiment = &experiment;
                scope.spawn(move || {
                    let mut z2 = [0.0; 4];
                    for seed in (worker..REPLICATES).step_by(2) {
                        let data = synthetic_data(experiment, 1000 + seed);
                        let fit = fit_rate_state(&data, experiment, &lishman_template())
                            .expect("fit runs");
                        assert!(fit.converged, "seed {seed}: {}", fit.termination);
                        for (k, name) in names.iter().enumerate() {
                            let (v, se) = value(&fit, name);
                            z2[k] += ((v - truths[k]) / se).powi(2);
                        }
                    }
                    z2
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("worker"))
            .collect()
    });
    for (k, name) in names.iter().enumerate() {
        let mean_z2 = z2_sums.iter().map(|s| s[k]).sum::<f64>() / REPLICATES as f64;
        println!("{name}: mean z^2 = {mean_z2:.3}");
        assert!(
            (0.25..=2.45).contains(&mean_z2),
            "{name}: mean squared standardised error {mean_z2} over {REPLICATES} replicates; \
             the standard errors are miscalibrated"
        );
    }
}

#[test]
fn model_comparison_ranks_rate_state_first_on_rate_state_data() {
    let experiment = experiment();
    let data = synthetic_data(&experiment, 42);
    let comparison = compare_models(
        &data,
        &experiment,
        &lishman_template(),
        &RateDependent::lishman_2011(-0.072),
    )
    .expect("comparison runs");
    let (c, r, rs) = (
        &comparison.constant,
        &comparison.rate,
        &comparison.rate_state,
    );
    println!(
        "MSE: constant {}, rate {}, rate-state {}",
        c.mse, r.mse, rs.mse
    );

    // The constant model is the mean, and its MSE the variance about it.
    let n = data.len() as f64;
    let mean = data.mu().iter().sum::<f64>() / n;
    let variance = data.mu().iter().map(|m| (m - mean).powi(2)).sum::<f64>() / n;
    let (mu, _) = value(c, "mu");
    assert!((mu - mean).abs() <= 1e-12);
    assert!((c.mse - variance).abs() <= 1e-12 * variance);

    // Guaranteed by construction: the rate model (eq. 2 at the load-point
    // speed, linear least squares with an intercept) contains the constant
    // model as C1 = 0.
    assert!(
        r.ssr <= c.ssr * (1.0 + 1e-12),
        "rate SSR {} exceeds constant SSR {}",
        r.ssr,
        c.ssr
    );
    // Not guaranteed by construction (the rate model is not a special case
    // of the rate-and-state one, nor the reverse), but the data
    // come from a rate-and-state law, whose fit reaches the noise floor; the
    // rate model misses the transients by far more than the noise.
    assert!(rs.converged, "rate-state: {}", rs.termination);
    assert!(
        rs.mse < 1.3 * SIGMA * SIGMA,
        "rate-state MSE {} above the noise floor",
        rs.mse
    );
    assert!(
        rs.mse < 0.5 * r.mse,
        "rate-state MSE {} not clearly below rate MSE {}",
        rs.mse,
        r.mse
    );

    // A CLI prints this as JSON.
    let json = serde_json::to_value(&comparison).expect("serialisable");
    for model in ["constant", "rate", "rate_state"] {
        assert!(
            json[model]["mse"].is_number(),
            "{model} has no numeric mse in {json}"
        );
    }
    assert_eq!(
        json["rate_state"]["parameters"].as_array().map(Vec::len),
        Some(4)
    );
}

#[test]
fn rate_fit_from_a_poor_start_is_still_no_worse_than_constant() {
    let experiment = experiment();
    let data = synthetic_data(&experiment, 7);
    // Strongly velocity weakening: violent stick-slip on this stiff spring.
    let poor = RateDependent {
        mu0: 1.5,
        c1: -0.3,
        ..RateDependent::lishman_2011(-0.072)
    };
    let rate = fit_rate_dependent(&data, &experiment, &poor).expect("fit runs");
    let constant = fit_constant(&data);
    assert!(
        rate.ssr <= constant.ssr * (1.0 + 1e-12),
        "rate SSR {} exceeds constant SSR {}",
        rate.ssr,
        constant.ssr
    );
    for p in &rate.parameters {
        assert!(p.value.is_finite(), "{} = {}", p.name, p.value);
    }
}

#[test]
fn predictions_interpolate_linearly_between_step_ends() {
    let experiment = experiment();
    let law = Law::RateState(truth());
    // Inside the velocity step up at t = 10 s, where mu changes fastest.
    let dt = experiment.apparatus().dt_s;
    let (t0, t1) = (10.0 + 3.0 * dt, 10.0 + 4.0 * dt);
    let at = predict(&law, &experiment, &[t0, t0 + 0.25 * dt, t1]).expect("predict");
    assert!(
        (at[2] - at[0]).abs() > 1e-4,
        "mu barely changes over the step: {at:?}"
    );
    let expected = 0.75 * at[0] + 0.25 * at[2];
    assert!(
        (at[1] - expected).abs() <= 1e-9,
        "{} is not the linear interpolation {expected}",
        at[1]
    );
    // Start and end of the protocol are valid times.
    let end = experiment.protocol().duration_s();
    let ends = predict(&law, &experiment, &[0.0, end]).expect("predict at the ends");
    assert!(ends.iter().all(|m| m.is_finite()));
}

#[test]
fn bad_data_are_errors_not_panics() {
    let is_fit_error = |r: Result<FitData, FrictionError>| matches!(r, Err(FrictionError::Fit(_)));
    assert!(is_fit_error(FitData::new(
        vec![0.0, 1.0, 2.0],
        vec![0.5, 0.5]
    )));
    assert!(is_fit_error(FitData::new(vec![0.0, 1.0], vec![0.5, 0.5])));
    assert!(is_fit_error(FitData::new(vec![], vec![])));
    assert!(is_fit_error(FitData::new(
        vec![0.0, 1.0, 1.0],
        vec![0.5, 0.5, 0.5]
    )));
    assert!(is_fit_error(FitData::new(
        vec![0.0, 2.0, 1.0],
        vec![0.5, 0.5, 0.5]
    )));
    assert!(is_fit_error(FitData::new(
        vec![0.0, 1.0, 2.0],
        vec![0.5, f64::NAN, 0.5]
    )));
    assert!(is_fit_error(FitData::new(
        vec![0.0, f64::INFINITY, 2.0],
        vec![0.5, 0.5, 0.5]
    )));
    assert!(is_fit_error(FitData::new(
        vec![f64::NAN, 1.0, 2.0],
        vec![0.5, 0.5, 0.5]
    )));

    let experiment = experiment();
    let rate = RateDependent::lishman_2011(-0.072);
    // Times beyond the end of the protocol (45 s).
    let late = FitData::new(vec![0.0, 20.0, 40.0, 50.0, 60.0], vec![0.6; 5]).expect("valid");
    assert!(fit_rate_state(&late, &experiment, &lishman_template()).is_err());
    assert!(fit_rate_dependent(&late, &experiment, &rate).is_err());
    assert!(compare_models(&late, &experiment, &lishman_template(), &rate).is_err());
    assert!(predict(&Law::RateState(truth()), &experiment, late.t_s()).is_err());
    // Negative or decreasing prediction times.
    assert!(predict(&Law::RateState(truth()), &experiment, &[-1.0, 2.0]).is_err());
    assert!(predict(&Law::RateState(truth()), &experiment, &[2.0, 1.0]).is_err());

    // Four points cannot determine four parameters.
    let four = FitData::new(vec![0.0, 1.0, 2.0, 3.0], vec![0.6, 0.7, 0.6, 0.5]).expect("valid");
    assert!(fit_rate_state(&four, &experiment, &lishman_template()).is_err());

    // Invalid templates.
    let ok = FitData::new(vec![0.0, 1.0, 2.0, 3.0, 4.0], vec![0.6; 5]).expect("valid");
    let mut bad_template = lishman_template();
    bad_template.params.critical_slip_m = -1e-3;
    assert!(fit_rate_state(&ok, &experiment, &bad_template).is_err());
    bad_template.params = RateStateParams {
        a: f64::NAN,
        ..RateStateParams::lishman_2011_lab()
    };
    assert!(fit_rate_state(&ok, &experiment, &bad_template).is_err());
    let bad_rate = RateDependent {
        v_floor_m_per_s: 0.0,
        ..rate
    };
    assert!(fit_rate_dependent(&ok, &experiment, &bad_rate).is_err());

    // Invalid experiments.
    let protocol = experiment.protocol().clone();
    let zero_stiffness = Apparatus {
        stiffness_n_per_m: 0.0,
        normal_load_n: 2e3,
        dt_s: 1e-3,
    };
    assert!(Experiment::new(protocol.clone(), zero_stiffness, 1e-4).is_err());
    assert!(Experiment::new(protocol, *experiment.apparatus(), f64::NAN).is_err());
}

#[test]
fn rate_model_recovers_eq_2_exactly_from_a_curve_of_the_imposed_speed() {
    // Data made by eq. 2 at the load-point speed of each sample (holds at the
    // floor speed): the linear fit must return mu0 and C1 to round-off.
    let experiment = experiment();
    let template = RateDependent::lishman_2011(-0.072);
    let (mu0, c1) = (0.91, -0.085);
    let t = sample_times(&experiment);
    let mu: Vec<f64> = t
        .iter()
        .map(|&t| {
            let v = experiment
                .protocol()
                .velocity_at(t)
                .abs()
                .max(template.v_floor_m_per_s);
            mu0 + c1 * (v / template.v_star_m_per_s).ln()
        })
        .collect();
    let data = FitData::new(t, mu).unwrap();
    let fit = fit_rate_at_load_point(&data, &experiment, &template).unwrap();
    let (got_mu0, _) = value(&fit, "mu0");
    let (got_c1, se) = value(&fit, "c1");
    assert!(
        (got_mu0 - mu0).abs() < 1e-12 && (got_c1 - c1).abs() < 1e-12,
        "{got_mu0} {got_c1}"
    );
    assert!(fit.mse < 1e-25 && se < 1e-10, "mse {} se {se}", fit.mse);
}
