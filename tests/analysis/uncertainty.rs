//! Errors of means against analytic answers: the blocked standard error of
//! an AR(1) series against its exact variance of the mean, and the seeds'
//! 95 % interval against its coverage.

use floe_analysis::uncertainty::{blocked_mean, blocked_ratio, seed_mean, t975};

/// A small counter-based generator (splitmix64) and Box-Muller normals:
/// the series are the same on every machine.
struct Normals(u64);

impl Normals {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
    /// `n` samples of `x_k = phi x_{k-1} + e_k`, unit innovations, started
    /// in the stationary distribution.
    fn ar1(&mut self, phi: f64, n: usize) -> Vec<f64> {
        let mut x = self.normal() / (1.0 - phi * phi).sqrt();
        (0..n)
            .map(|_| {
                x = phi * x + self.normal();
                x
            })
            .collect()
    }
}

/// The exact standard deviation of the mean of `n` stationary AR(1)
/// samples with unit innovations.
fn ar1_error_of_mean(phi: f64, n: usize) -> f64 {
    let var = 1.0 / (1.0 - phi * phi);
    let nf = n as f64;
    let sum: f64 = (1..n)
        .map(|k| 2.0 * (nf - k as f64) * phi.powi(k as i32))
        .sum();
    (var * (nf + sum)).sqrt() / nf
}

#[test]
fn blocked_error_of_a_correlated_series_matches_the_exact_variance_of_its_mean() {
    let (phi, n, trials) = (0.9, 4096, 300);
    let exact = ar1_error_of_mean(phi, n);
    let mut rng = Normals(7);
    let (mut estimates, mut means, mut naive) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..trials {
        let x = rng.ar1(phi, n);
        let e = blocked_mean(&x);
        estimates.push(e.error);
        means.push(e.mean);
        let m = e.mean;
        let var = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1) as f64;
        naive.push((var / n as f64).sqrt());
    }
    let avg = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    // The estimate is right on average (levels with 16+ blocks: about 18 %
    // noise each, so the average of 300 is good to a few per cent).
    let ratio = avg(&estimates) / exact;
    assert!((0.9..1.15).contains(&ratio), "blocked / exact = {ratio}");
    // A second, independent measure of the same thing: the scatter of the
    // trials' means.
    let spread = (means.iter().map(|m| m * m).sum::<f64>() / trials as f64).sqrt();
    assert!(
        (0.85..1.15).contains(&(spread / exact)),
        "scatter of means / exact = {}",
        spread / exact
    );
    // The naive error is too small by about sqrt((1 + phi) / (1 - phi)).
    let naive_ratio = avg(&naive) / exact;
    assert!(naive_ratio < 0.3, "naive / exact = {naive_ratio}");
}

#[test]
fn blocked_error_of_independent_samples_is_the_naive_one() {
    let mut rng = Normals(3);
    let x: Vec<f64> = (0..1000).map(|_| rng.normal()).collect();
    let e = blocked_mean(&x);
    let exact = 1.0 / (1000f64).sqrt();
    assert!((e.error / exact - 1.0).abs() < 0.3, "{} {exact}", e.error);
    assert!(e.converged);
}

#[test]
fn a_series_far_shorter_than_its_correlation_time_is_not_converged() {
    let mut rng = Normals(5);
    let x = rng.ar1(0.999, 256);
    let e = blocked_mean(&x);
    assert!(!e.converged, "{e:?}");
    assert!(e.error < ar1_error_of_mean(0.999, 256));
}

#[test]
fn blocked_ratio_of_proportional_series_has_no_error() {
    // tau = 0.4 P exactly: the ratio of means is 0.4 with no uncertainty,
    // however much P itself fluctuates.
    let mut rng = Normals(11);
    let p: Vec<f64> = rng.ar1(0.8, 500).iter().map(|x| 100.0 + x).collect();
    let tau: Vec<f64> = p.iter().map(|p| 0.4 * p).collect();
    let r = blocked_ratio(&tau, &p);
    assert!((r.mean - 0.4).abs() < 1e-14);
    assert!(r.error < 1e-14, "{r:?}");
}

#[test]
fn seed_interval_covers_the_true_mean_95_times_in_100() {
    // Five normal repetitions per experiment, 4000 experiments: the
    // t-interval's coverage is 0.95 within its binomial noise (0.0034).
    let mut rng = Normals(13);
    let trials = 4000;
    let covered = (0..trials)
        .filter(|_| {
            let x: Vec<f64> = (0..5).map(|_| 2.0 + 0.5 * rng.normal()).collect();
            let s = seed_mean(&x);
            (s.mean - 2.0).abs() <= s.ci95
        })
        .count();
    let coverage = covered as f64 / trials as f64;
    assert!((0.935..0.965).contains(&coverage), "coverage {coverage}");
}

#[test]
fn t_quantiles_meet_the_normal_one() {
    assert!((t975(4) - 2.7764).abs() < 1e-4);
    // The series beyond the table continues it smoothly.
    assert!((t975(31) - 2.0395).abs() < 2e-4, "{}", t975(31));
    assert!((t975(120) - 1.9799).abs() < 2e-4, "{}", t975(120));
    assert!((t975(100_000) - 1.96).abs() < 1e-3);
    assert!(t975(0).is_nan());
}
