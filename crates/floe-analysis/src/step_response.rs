//! A friction series' answer to a change of the driving speed, read as a
//! rock-mechanics laboratory reads a velocity step or a slide-hold-slide
//! (Marone 1998): the direct effect `a`, the steady-state change `a - b`
//! and the slip distance over which friction evolves, `D_c`; and the
//! healing of a hold, the peak on reslide over the friction before it.
//!
//! Slip is the driver's displacement from the step on (the load point's,
//! or a shear cell's moving wall): the quantity a laboratory plots against.

use crate::error::AnalysisError;

/// The answer to a velocity step `V0 -> V1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityStep {
    /// Friction before the step (the mean of the steady window given).
    pub before: f64,
    /// The extreme after the step: the largest friction after a step up,
    /// the smallest after a step down.
    pub extreme: f64,
    /// Slip from the step to the extreme, m.
    pub extreme_slip_m: f64,
    /// The new steady friction: the mean over the last part of the window.
    pub after: f64,
    /// Direct effect per e-fold of speed, `(extreme - before) / ln(V1/V0)`:
    /// the law's `a` on a stiff driver.
    pub direct_per_ln: f64,
    /// Steady-state change per e-fold, `(after - before) / ln(V1/V0)`:
    /// `a - b`.
    pub steady_per_ln: f64,
    /// Slip over which friction relaxes from the extreme to the new steady
    /// state: `D` of the least-squares fit `mu = after + c exp(-(s - s_x) /
    /// D)` from the extreme on. For a slip law on a stiff driver, `L`; NaN
    /// where the series does not relax (flat, or no decay within ten
    /// windows).
    pub decay_slip_m: f64,
}

impl VelocityStep {
    /// The evolution effect per e-fold, `b = a - (a - b)`.
    pub fn evolution_per_ln(&self) -> f64 {
        self.direct_per_ln - self.steady_per_ln
    }
}

/// Reads a velocity step. `before`: friction samples of the steady sliding
/// before the step; `slip_m`, `mu`: the samples from the step to the end of
/// the new speed's window, slip from the step (increasing); the last
/// `steady_fraction` of that slip is the new steady state; `ln_ratio =
/// ln(V1/V0)`, not zero.
pub fn velocity_step(
    before: &[f64],
    slip_m: &[f64],
    mu: &[f64],
    steady_fraction: f64,
    ln_ratio: f64,
) -> Result<VelocityStep, AnalysisError> {
    if before.is_empty() {
        return Err(AnalysisError::NotEnoughData(
            "no friction sample before the step",
        ));
    }
    check_finite("friction before", before)?;
    check_after(slip_m, mu)?;
    if !(steady_fraction > 0.0 && steady_fraction < 1.0) {
        return Err(AnalysisError::InvalidParameter {
            name: "steady_fraction",
            value: steady_fraction,
            reason: "must be in (0, 1)",
        });
    }
    if !(ln_ratio.is_finite() && ln_ratio != 0.0) {
        return Err(AnalysisError::InvalidParameter {
            name: "ln(V1/V0)",
            value: ln_ratio,
            reason: "the speed must change (finite, not 0)",
        });
    }
    let before_mean = mean(before);
    let end = slip_m[slip_m.len() - 1];
    let steady_from = end * (1.0 - steady_fraction);
    let transient = slip_m.partition_point(|&s| s < steady_from);
    let steady = &mu[transient..];
    if transient == 0 || steady.is_empty() {
        return Err(AnalysisError::NotEnoughData(
            "the window after the step needs samples both in its transient and in its steady part",
        ));
    }
    let after = mean(steady);
    // The extreme of the transient part, the first one where it repeats.
    let up = ln_ratio > 0.0;
    let mut k = 0;
    for i in 1..transient {
        if (up && mu[i] > mu[k]) || (!up && mu[i] < mu[k]) {
            k = i;
        }
    }
    let decay = decay_length(&slip_m[k..transient], &mu[k..transient], after);
    Ok(VelocityStep {
        before: before_mean,
        extreme: mu[k],
        extreme_slip_m: slip_m[k],
        after,
        direct_per_ln: (mu[k] - before_mean) / ln_ratio,
        steady_per_ln: (after - before_mean) / ln_ratio,
        decay_slip_m: decay,
    })
}

/// The answer to a hold: friction before it, the peak on reslide and the
/// healing, their difference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoldHealing {
    /// Mean friction of the steady sliding before the hold.
    pub before: f64,
    /// Largest friction in the reslide window.
    pub peak: f64,
    /// `peak - before`.
    pub healing: f64,
}

/// Reads a slide-hold-slide: `before`, the samples of the steady sliding
/// before the hold; `reslide`, those of the window after sliding resumes.
pub fn hold_healing(before: &[f64], reslide: &[f64]) -> Result<HoldHealing, AnalysisError> {
    if before.is_empty() || reslide.is_empty() {
        return Err(AnalysisError::NotEnoughData(
            "a hold needs samples before it and after sliding resumes",
        ));
    }
    check_finite("friction before", before)?;
    check_finite("friction on reslide", reslide)?;
    let before = mean(before);
    let peak = reslide.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(HoldHealing {
        before,
        peak,
        healing: peak - before,
    })
}

fn check_after(slip_m: &[f64], mu: &[f64]) -> Result<(), AnalysisError> {
    if slip_m.len() != mu.len() {
        return Err(AnalysisError::LengthMismatch {
            what: "slip and friction",
            left: slip_m.len(),
            right: mu.len(),
        });
    }
    if slip_m.len() < 4 {
        return Err(AnalysisError::NotEnoughData(
            "at least 4 samples after the step",
        ));
    }
    check_finite("slip", slip_m)?;
    check_finite("friction after", mu)?;
    if let Some(w) = slip_m.windows(2).find(|w| w[1] <= w[0]) {
        return Err(AnalysisError::InvalidParameter {
            name: "slip",
            value: w[1],
            reason: "must increase from sample to sample",
        });
    }
    Ok(())
}

fn check_finite(name: &'static str, values: &[f64]) -> Result<(), AnalysisError> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(&value) => Err(AnalysisError::InvalidParameter {
            name,
            value,
            reason: "must be finite",
        }),
        None => Ok(()),
    }
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// `D` of the least-squares fit `mu - after = c exp(-(s - s_0) / D)`, `c`
/// solved for each `D` in closed form and `ln D` by golden section between
/// a tenth of the first spacing and ten times the window. NaN where there
/// is no relaxation to measure: fewer than three samples, no departure
/// from `after`, a fitted `c` of the other sign than the first sample's
/// departure, or a best `D` at either end of the range searched.
fn decay_length(slip_m: &[f64], mu: &[f64], after: f64) -> f64 {
    if slip_m.len() < 3 {
        return f64::NAN;
    }
    let s0 = slip_m[0];
    if mu[0] == after {
        return f64::NAN;
    }
    let amplitude = |d: f64| {
        let (mut se, mut ee) = (0.0, 0.0);
        for (&s, &m) in slip_m.iter().zip(mu) {
            let e = (-(s - s0) / d).exp();
            se += (m - after) * e;
            ee += e * e;
        }
        se / ee
    };
    let residual = |ln_d: f64| {
        let d = ln_d.exp();
        let c = amplitude(d);
        slip_m
            .iter()
            .zip(mu)
            .map(|(&s, &m)| (m - after - c * (-(s - s0) / d).exp()).powi(2))
            .sum::<f64>()
    };
    let span = slip_m[slip_m.len() - 1] - s0;
    let range = ((0.1 * (slip_m[1] - s0)).ln(), (10.0 * span).ln());
    let (mut lo, mut hi) = range;
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (residual(x1), residual(x2));
    while hi - lo > 1e-10 {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = residual(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = residual(x2);
        }
    }
    let best = 0.5 * (lo + hi);
    let at_an_end = (best - range.0).abs() < 1e-6 || (range.1 - best).abs() < 1e-6;
    let d = best.exp();
    if at_an_end || amplitude(d) * (mu[0] - after) <= 0.0 {
        return f64::NAN;
    }
    d
}
