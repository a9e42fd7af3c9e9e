//! The floe-size distribution of a power law: the number of floes larger
//! than `d` falls as `N(>d) ∝ d^−α` between a smallest and a largest size
//! (number density `∝ d^−α−1`), the form fitted to observed sea-ice floe
//! sizes (Rothrock & Thorndike 1984; Stern et al. 2018 review exponents of
//! about 1.5 to 3). Here the size of a floe is `d = sqrt(area)`.
//!
//! [`PowerLawSizes::quantile`] draws sizes by the inverse of the truncated
//! law's distribution function; [`fit_power_law`] is the maximum-likelihood
//! estimate of `α` for sizes known to lie between two bounds (the
//! truncated Pareto estimator of Aban, Meerschaert & Panorska 2006), with
//! its standard error from the Fisher information.

use crate::error::DemError;

/// A power law `N(>d) ∝ d^−α` truncated to `[min_m, max_m]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerLawSizes {
    /// The exponent `α` of the exceedance count, > 0.
    pub exponent: f64,
    /// The smallest size, m, > 0.
    pub min_m: f64,
    /// The largest size, m, > `min_m`.
    pub max_m: f64,
}

/// Largest exponent accepted: beyond it every floe is within a few percent
/// of the smallest size (and `(min/max)^α` underflows for wide ranges).
pub const MAX_POWER_LAW_EXPONENT: f64 = 20.0;

impl PowerLawSizes {
    /// Checks `0 < α ≤` [`MAX_POWER_LAW_EXPONENT`] and `0 < min < max`,
    /// all finite.
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] naming the parameter.
    pub fn validate(&self) -> Result<(), DemError> {
        let bad = crate::error::invalid_parameter;
        if !(self.exponent.is_finite()
            && self.exponent > 0.0
            && self.exponent <= MAX_POWER_LAW_EXPONENT)
        {
            return bad("exponent", self.exponent, "must be in (0, 20]");
        }
        if !(self.min_m.is_finite() && self.min_m > 0.0) {
            return bad("min_m", self.min_m, "must be finite and > 0");
        }
        if !(self.max_m.is_finite() && self.max_m > self.min_m) {
            return bad("max_m", self.max_m, "must be finite and > min_m");
        }
        Ok(())
    }

    /// `1 − (min/max)^α`: the probability mass the untruncated law puts
    /// between `min` and `max` (accurate for small `α` too).
    fn mass(&self) -> f64 {
        -(-self.exponent * (self.max_m / self.min_m).ln()).exp_m1()
    }

    /// The size with exceedance probability `1 − u` (inverse distribution
    /// function), for `u ∈ [0, 1]`: `min` at `u = 0`, `max` at `u = 1`.
    pub fn quantile(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        // P(D > d) = ((min/d)^α − r) / (1 − r), r = (min/max)^α, so
        // d = min (1 − u (1 − r))^(−1/α), in logarithms for small α.
        let log_exceed = (-u * self.mass()).ln_1p();
        (self.min_m * (-log_exceed / self.exponent).exp()).clamp(self.min_m, self.max_m)
    }

    /// The mean of `d²` (the mean floe area, m²).
    pub fn mean_square_m2(&self) -> f64 {
        let (a, alpha) = (self.min_m, self.exponent);
        let log_ratio = (self.max_m / a).ln();
        // ∫ d² α a^α d^(−α−1) dd / (1 − r) over [a, b]
        //   = α a² (R^(2−α) − 1) / ((2 − α)(1 − r)),  R = b / a.
        let x = (2.0 - alpha) * log_ratio;
        let integral = if x.abs() < 1e-12 {
            log_ratio
        } else {
            x.exp_m1() / (2.0 - alpha)
        };
        alpha * a * a * integral / self.mass()
    }

    /// The expected number of floes of this law that cover `area_m2`.
    pub fn expected_count(&self, area_m2: f64) -> f64 {
        area_m2 / self.mean_square_m2()
    }
}

/// A maximum-likelihood fit of the exponent of a truncated power law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerLawFit {
    /// The fitted exponent `α̂`.
    pub exponent: f64,
    /// Its standard error, `1 / sqrt(n I(α̂))`.
    pub std_error: f64,
    /// Sizes used (those in `[min_m, max_m]`).
    pub used: usize,
}

/// The mean of `ln(d/min)` under the law of exponent `alpha` on
/// `[min, R min]`, `ln_r = ln R`; decreasing in `alpha`.
fn mean_log(alpha: f64, ln_r: f64) -> f64 {
    // 1/α − ln R / (R^α − 1)
    let x = alpha * ln_r;
    1.0 / alpha - ln_r / x.exp_m1()
}

/// The variance of `ln(d/min)` (the Fisher information of one size).
fn variance_log(alpha: f64, ln_r: f64) -> f64 {
    let x = alpha * ln_r;
    let e = x.exp_m1();
    // 1/α² − (ln R)² R^α / (R^α − 1)²
    1.0 / (alpha * alpha) - ln_r * ln_r * (e + 1.0) / (e * e)
}

/// The maximum-likelihood exponent of `sizes` under a power law truncated
/// to `[min_m, max_m]` (sizes outside are left out). `None` with fewer
/// than two sizes inside, or when the likelihood has no maximum at a
/// positive exponent up to [`MAX_POWER_LAW_EXPONENT`] (sizes weighted
/// towards the large end: `α ≤ 0`).
///
/// The score equation `E_α[ln(d/min)] = mean ln(d/min)` has one root, as
/// the left side decreases with `α`; it is found by bisection to 1e-12.
pub fn fit_power_law(sizes: &[f64], min_m: f64, max_m: f64) -> Option<PowerLawFit> {
    if !(min_m > 0.0 && max_m > min_m && max_m.is_finite()) {
        return None;
    }
    let (mut n, mut sum) = (0usize, 0.0);
    for &d in sizes {
        if d >= min_m && d <= max_m {
            n += 1;
            sum += (d / min_m).ln();
        }
    }
    if n < 2 {
        return None;
    }
    let target = sum / n as f64;
    let ln_r = (max_m / min_m).ln();
    let (mut lo, mut hi) = (1e-9, MAX_POWER_LAW_EXPONENT);
    if mean_log(lo, ln_r) < target || mean_log(hi, ln_r) > target {
        return None;
    }
    while hi - lo > 1e-12 * hi {
        let mid = 0.5 * (lo + hi);
        if mean_log(mid, ln_r) > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let alpha = 0.5 * (lo + hi);
    let info = variance_log(alpha, ln_r).max(f64::MIN_POSITIVE);
    Some(PowerLawFit {
        exponent: alpha,
        std_error: 1.0 / (n as f64 * info).sqrt(),
        used: n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_spans_the_bounds_and_inverts_the_exceedance() {
        let law = PowerLawSizes {
            exponent: 1.5,
            min_m: 100.0,
            max_m: 2000.0,
        };
        assert_eq!(law.quantile(0.0), 100.0);
        assert!((law.quantile(1.0) - 2000.0).abs() < 1e-9);
        // P(D > d) at d = quantile(u) is 1 − u.
        let r = (0.05f64).powf(1.5);
        // A vanishing exponent is log-uniform: the median is the geometric mean.
        let flat = PowerLawSizes {
            exponent: 1e-300,
            ..law
        };
        assert!((flat.quantile(0.5) - (100.0f64 * 2000.0).sqrt()).abs() < 1e-9);
        assert!(
            (flat.mean_square_m2() - (2000.0f64.powi(2) - 1e4) / (2.0 * 20f64.ln())).abs() < 1e-3
        );
        for u in [0.1, 0.5, 0.9] {
            let d = law.quantile(u);
            let exceed = ((100.0 / d).powf(1.5) - r) / (1.0 - r);
            assert!((exceed - (1.0 - u)).abs() < 1e-12, "{u}: {exceed}");
        }
    }

    #[test]
    fn mean_square_matches_quadrature_including_alpha_two() {
        for alpha in [0.5, 1.5, 2.0, 2.5, 4.0] {
            let law = PowerLawSizes {
                exponent: alpha,
                min_m: 10.0,
                max_m: 500.0,
            };
            // Midpoint rule in u: E[d²] = ∫0^1 quantile(u)² du.
            let n = 200_000;
            let q: f64 = (0..n)
                .map(|k| law.quantile((k as f64 + 0.5) / n as f64).powi(2))
                .sum::<f64>()
                / n as f64;
            let m = law.mean_square_m2();
            // The midpoint rule loses accuracy where the quantile steepens (u near 1).
            assert!((q / m - 1.0).abs() < 1e-3, "alpha {alpha}: {q} vs {m}");
        }
    }

    #[test]
    fn the_fit_recovers_the_exponent_of_exact_quantiles() {
        for alpha in [0.7, 1.5, 2.5, 5.0] {
            let law = PowerLawSizes {
                exponent: alpha,
                min_m: 50.0,
                max_m: 5000.0,
            };
            let n = 100_000;
            let sizes: Vec<f64> = (0..n)
                .map(|k| law.quantile((k as f64 + 0.5) / n as f64))
                .collect();
            let fit = fit_power_law(&sizes, 50.0, 5000.0).unwrap();
            assert!((fit.exponent - alpha).abs() < 1e-3 * alpha, "{fit:?}");
            assert_eq!(fit.used, n);
            // Asymptotic 1/sqrt(n I): about alpha/sqrt(n) for wide ranges.
            assert!(fit.std_error > 0.5 * alpha / (n as f64).sqrt());
            assert!(fit.std_error < 2.0 * alpha / (n as f64).sqrt());
        }
    }

    #[test]
    fn no_fit_without_data_or_for_sizes_heavy_at_the_top() {
        assert!(fit_power_law(&[100.0], 50.0, 500.0).is_none());
        assert!(fit_power_law(&[490.0, 495.0, 499.0], 50.0, 500.0).is_none());
        assert!(fit_power_law(&[60.0, 70.0], 50.0, 50.0).is_none());
    }

    #[test]
    fn validation_names_the_parameter() {
        let ok = PowerLawSizes {
            exponent: 2.0,
            min_m: 1.0,
            max_m: 2.0,
        };
        assert!(ok.validate().is_ok());
        for (bad, name) in [
            (
                PowerLawSizes {
                    exponent: 0.0,
                    ..ok
                },
                "exponent",
            ),
            (
                PowerLawSizes {
                    exponent: 21.0,
                    ..ok
                },
                "exponent",
            ),
            (PowerLawSizes { min_m: -1.0, ..ok }, "min_m"),
            (PowerLawSizes { max_m: 1.0, ..ok }, "max_m"),
        ] {
            let e = bad.validate().unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
    }
}
