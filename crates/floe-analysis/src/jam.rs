//! Jam or flow: whether a driven pack has stopped moving by the end of a run.
//!
//! A pack is *jammed* when, over the last `final_fraction` of the run, its
//! kinetic energy averages below `energy_fraction` of its peak **and** its
//! free floes' mean speed is below `speed_fraction` of a reference speed
//! (the free-drift speed of the forcing). Both: the energy alone cannot
//! tell a stopped pack from one that was never set moving, and a speed
//! alone depends on the choice of reference. Alongside, the frictional
//! dissipation rate over that window against its peak over any window of
//! the same length, and the time since which the kinetic energy has stayed
//! below the threshold.

use crate::error::AnalysisError;

/// Thresholds of the jam criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JamRule {
    /// Final kinetic energy below this fraction of the peak.
    pub energy_fraction: f64,
    /// Final mean speed below this fraction of the reference speed.
    pub speed_fraction: f64,
    /// The final window, as a fraction of the time span (0 < f <= 1).
    pub final_fraction: f64,
}

impl Default for JamRule {
    fn default() -> Self {
        Self {
            energy_fraction: 0.01,
            speed_fraction: 0.01,
            final_fraction: 0.1,
        }
    }
}

/// What [`jam_state`] finds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JamState {
    /// Largest kinetic energy sample, J.
    pub peak_kinetic_j: f64,
    /// Mean kinetic energy over the final window, J.
    pub final_kinetic_j: f64,
    /// `final_kinetic_j / peak_kinetic_j`.
    pub kinetic_ratio: f64,
    /// The final mean speed over the reference speed.
    pub speed_ratio: f64,
    /// Mean dissipation rate over the final window over its largest value
    /// over any window of that length (0 when nothing was ever dissipated).
    pub dissipation_rate_ratio: f64,
    /// The earliest time after which the kinetic energy stays below
    /// `energy_fraction` of its peak (only after the peak); `None` when
    /// the last sample is above it.
    pub below_since_s: Option<f64>,
    /// Both criteria met.
    pub jammed: bool,
}

/// Assesses a run from its kinetic energy and cumulative frictional
/// dissipation histories (same sample times, increasing), the free floes'
/// mean speed at the end and the reference speed (both m/s).
pub fn jam_state(
    time_s: &[f64],
    kinetic_j: &[f64],
    dissipation_j: &[f64],
    final_mean_speed: f64,
    reference_speed: f64,
    rule: &JamRule,
) -> Result<JamState, AnalysisError> {
    for (len, what) in [
        (kinetic_j.len(), "times and kinetic energies"),
        (dissipation_j.len(), "times and dissipation"),
    ] {
        if len != time_s.len() {
            return Err(AnalysisError::LengthMismatch {
                what,
                left: time_s.len(),
                right: len,
            });
        }
    }
    let positive = |name, value: f64| {
        if value > 0.0 && value.is_finite() {
            Ok(())
        } else {
            Err(AnalysisError::InvalidParameter {
                name,
                value,
                reason: "must be positive and finite",
            })
        }
    };
    positive("reference_speed", reference_speed)?;
    positive("energy_fraction", rule.energy_fraction)?;
    positive("speed_fraction", rule.speed_fraction)?;
    if !(rule.final_fraction > 0.0 && rule.final_fraction <= 1.0) {
        return Err(AnalysisError::InvalidParameter {
            name: "final_fraction",
            value: rule.final_fraction,
            reason: "must be in (0, 1]",
        });
    }
    if time_s.len() < 2 {
        return Err(AnalysisError::NotEnoughData(
            "a jam needs at least two samples",
        ));
    }
    let n = time_s.len();
    let (t0, t1) = (time_s[0], time_s[n - 1]);
    let window = rule.final_fraction * (t1 - t0);
    let from = t1 - window;
    let first = time_s.iter().position(|&t| t >= from).expect("t1 >= from");
    let final_kinetic_j = kinetic_j[first..].iter().sum::<f64>() / (n - first) as f64;
    let peak = (0..n)
        .max_by(|&i, &j| kinetic_j[i].total_cmp(&kinetic_j[j]))
        .expect("non-empty");
    let peak_kinetic_j = kinetic_j[peak];
    if peak_kinetic_j <= 0.0 {
        return Err(AnalysisError::NotEnoughData(
            "the kinetic energy is never positive: nothing moved",
        ));
    }
    let threshold = rule.energy_fraction * peak_kinetic_j;
    let below_since_s = match (peak..n).rev().find(|&i| kinetic_j[i] >= threshold) {
        Some(i) if i == n - 1 => None,
        Some(i) => Some(time_s[i + 1]),
        None => Some(time_s[peak]),
    };

    // Rate over [t - window, t] for every sample a whole window in.
    let rate_at = |i: usize| {
        let j = time_s.partition_point(|&t| t <= time_s[i] - window);
        let j = j.saturating_sub(1).min(i);
        let dt = time_s[i] - time_s[j];
        if dt > 0.0 {
            (dissipation_j[i] - dissipation_j[j]) / dt
        } else {
            0.0
        }
    };
    let peak_rate = (0..n)
        .filter(|&i| time_s[i] - t0 >= window)
        .map(rate_at)
        .fold(0.0, f64::max);
    let final_rate = rate_at(n - 1);
    let dissipation_rate_ratio = if peak_rate > 0.0 {
        final_rate / peak_rate
    } else {
        0.0
    };
    let kinetic_ratio = final_kinetic_j / peak_kinetic_j;
    let speed_ratio = final_mean_speed / reference_speed;
    Ok(JamState {
        peak_kinetic_j,
        final_kinetic_j,
        kinetic_ratio,
        speed_ratio,
        dissipation_rate_ratio,
        below_since_s,
        jammed: kinetic_ratio < rule.energy_fraction && speed_ratio < rule.speed_fraction,
    })
}
