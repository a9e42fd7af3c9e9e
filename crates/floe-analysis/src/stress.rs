//! The assembly's stress history: components in the channel frame,
//! invariants, and the peak-to-steady ratio of a loading curve.
//!
//! floe writes the mean stress as `[xx, xy, yx, yy]`, vertically integrated
//! (N/m), tension positive (see floe-dem's `Observables`). Here compression
//! is reported positive, as sea-ice rheology does: pressure
//! `p = -(σxx + σyy)/2`, channel-normal stress `-σyy`.

use crate::time_mean::time_mean;
use crate::AnalysisError;

/// Stress in the frame of a channel along x, walls across y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelStress {
    /// Shear stress `(σxy + σyx)/2`, N/m.
    pub shear_n_per_m: f64,
    /// Normal stress across the channel, compression positive, `-σyy`, N/m.
    pub normal_n_per_m: f64,
}

/// The channel-frame components of `[xx, xy, yx, yy]`.
pub fn channel_stress(s: [f64; 4]) -> ChannelStress {
    ChannelStress {
        shear_n_per_m: 0.5 * (s[1] + s[2]),
        normal_n_per_m: -s[3],
    }
}

/// Frame-independent measures of a 2-D stress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressInvariants {
    /// Pressure, compression positive, `-(σxx + σyy)/2`, N/m.
    pub pressure_n_per_m: f64,
    /// Maximum shear stress, `sqrt(((σxx - σyy)/2)² + σxy²)` of the
    /// symmetric part, N/m.
    pub max_shear_n_per_m: f64,
}

/// The invariants of `[xx, xy, yx, yy]` (the antisymmetric part, a torque
/// density that vanishes in equilibrium, is left out).
pub fn invariants(s: [f64; 4]) -> StressInvariants {
    let half_diff = 0.5 * (s[0] - s[3]);
    let xy = 0.5 * (s[1] + s[2]);
    StressInvariants {
        pressure_n_per_m: -0.5 * (s[0] + s[3]),
        max_shear_n_per_m: half_diff.hypot(xy),
    }
}

/// The peak of a loading curve against its late-time level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeakToSteady {
    /// The value of largest magnitude.
    pub peak: f64,
    /// When it occurred, s.
    pub peak_at_s: f64,
    /// Mean over the steady window (the last `steady_fraction` of the
    /// span), each sample weighted by the time it stands for.
    pub steady: f64,
    /// `peak / steady`.
    pub ratio: f64,
}

/// Peak-to-steady ratio of `value(time_s)`. The steady level is the mean
/// over time ([`time_mean`]) of the samples in the last `steady_fraction`
/// of the time span (0 < f <= 1), which must not be empty or average to zero.
pub fn peak_to_steady(
    time_s: &[f64],
    value: &[f64],
    steady_fraction: f64,
) -> Result<PeakToSteady, AnalysisError> {
    if time_s.len() != value.len() {
        return Err(AnalysisError::LengthMismatch {
            what: "times and values",
            left: time_s.len(),
            right: value.len(),
        });
    }
    if !(steady_fraction > 0.0 && steady_fraction <= 1.0) {
        return Err(AnalysisError::InvalidParameter {
            name: "steady_fraction",
            value: steady_fraction,
            reason: "must be in (0, 1]",
        });
    }
    if value.is_empty() {
        return Err(AnalysisError::NotEnoughData("an empty series has no peak"));
    }
    let (t0, t1) = (time_s[0], time_s[time_s.len() - 1]);
    let from = t1 - steady_fraction * (t1 - t0);
    let steady = time_mean(time_s, value, (from, f64::INFINITY)).unwrap_or(f64::NAN);
    if steady == 0.0 || !steady.is_finite() {
        return Err(AnalysisError::NotEnoughData(
            "the steady level is zero: no peak-to-steady ratio",
        ));
    }
    let k = (0..value.len())
        .max_by(|&i, &j| value[i].abs().total_cmp(&value[j].abs()))
        .expect("non-empty");
    Ok(PeakToSteady {
        peak: value[k],
        peak_at_s: time_s[k],
        steady,
        ratio: value[k] / steady,
    })
}

/// How a loading curve answers a restart of the forcing after a pause.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestartResponse {
    /// Mean |value| over the window before the pause began ([`time_mean`]).
    pub before: f64,
    /// Largest |value| within the window after the restart.
    pub peak: f64,
    /// From the restart to that peak, s.
    pub peak_delay_s: f64,
    /// `peak / before`: above 1, the restart overshoots the earlier level.
    pub ratio: f64,
}

/// The response of `value(time_s)` to forcing that pauses at `pause_s` and
/// restarts at `restart_s`: the level over `window_s` before the pause
/// against the peak within `window_s` after the restart.
pub fn restart_response(
    time_s: &[f64],
    value: &[f64],
    pause_s: f64,
    restart_s: f64,
    window_s: f64,
) -> Result<RestartResponse, AnalysisError> {
    if time_s.len() != value.len() {
        return Err(AnalysisError::LengthMismatch {
            what: "times and values",
            left: time_s.len(),
            right: value.len(),
        });
    }
    if window_s.is_nan() || window_s <= 0.0 || restart_s < pause_s {
        return Err(AnalysisError::InvalidParameter {
            name: "window_s",
            value: window_s,
            reason: "needs a positive window and a restart after the pause",
        });
    }
    let magnitude: Vec<f64> = value.iter().map(|v| v.abs()).collect();
    let Some(before) = time_mean(time_s, &magnitude, (pause_s - window_s, pause_s)) else {
        return Err(AnalysisError::NotEnoughData(
            "no samples in the window before the pause",
        ));
    };
    let mut peak: Option<(f64, f64)> = None;
    for (&t, &v) in time_s.iter().zip(&magnitude) {
        if t >= restart_s && t <= restart_s + window_s && peak.is_none_or(|(_, p)| v > p) {
            peak = Some((t, v));
        }
    }
    let Some((peak_at, peak)) = peak else {
        return Err(AnalysisError::NotEnoughData(
            "no samples in the window after the restart",
        ));
    };
    Ok(RestartResponse {
        before,
        peak,
        peak_delay_s: peak_at - restart_s,
        ratio: peak / before,
    })
}
