//! Shear localisation across a channel: the binned profile of the
//! along-channel velocity, and the width of the band in which it changes.
//!
//! Two widths are reported, because neither alone describes a band:
//! * the *equivalent width* `|Δu| / max|du/dy|`, the width a linear profile
//!   with the same jump and the same peak shear rate would have (a uniform
//!   shear across the channel gives the channel; a tanh band
//!   `u = U tanh(y/δ)` gives `2δ`);
//! * the *10-90 width*, the distance over which the velocity goes from 10 %
//!   to 90 % of its jump (uniform shear: 0.8 of the channel; tanh band:
//!   `2 atanh(0.8) δ ≈ 2.197 δ`).
//!
//! Both are measured between bin centres, so a profile sampled in `n` bins
//! of a channel `W` wide spans `W (1 - 1/n)`: a uniform shear gives an
//! equivalent width of `W (1 - 1/n)`, not `W`.

use crate::AnalysisError;

/// Area-weighted mean velocity in bins across the channel. Empty bins are
/// left out.
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityProfile {
    /// Bin centres across the channel, m, increasing.
    pub centre_m: Vec<f64>,
    /// Weighted mean along-channel velocity in each bin, m/s.
    pub velocity_m_per_s: Vec<f64>,
    /// Total weight (e.g. floe area, m²) in each bin.
    pub weight: Vec<f64>,
}

/// Bins floes by their across-channel coordinate `across_m` (e.g. the
/// centroid's y) into `bins` equal bins on `[min_m, max_m)` and averages
/// their along-channel velocity weighted by `weight` (use floe area or mass:
/// the profile of momentum, not of floe count). Floes outside the range are
/// ignored.
pub fn velocity_profile(
    across_m: &[f64],
    velocity_m_per_s: &[f64],
    weight: &[f64],
    min_m: f64,
    max_m: f64,
    bins: usize,
) -> Result<VelocityProfile, AnalysisError> {
    if across_m.len() != velocity_m_per_s.len() {
        return Err(AnalysisError::LengthMismatch {
            what: "positions and velocities",
            left: across_m.len(),
            right: velocity_m_per_s.len(),
        });
    }
    if across_m.len() != weight.len() {
        return Err(AnalysisError::LengthMismatch {
            what: "positions and weights",
            left: across_m.len(),
            right: weight.len(),
        });
    }
    if bins == 0 {
        return Err(AnalysisError::InvalidParameter {
            name: "bins",
            value: 0.0,
            reason: "need at least one bin",
        });
    }
    if !(min_m.is_finite() && max_m.is_finite() && max_m > min_m) {
        return Err(AnalysisError::InvalidParameter {
            name: "max_m - min_m",
            value: max_m - min_m,
            reason: "the channel must have a finite, positive width",
        });
    }
    let h = (max_m - min_m) / bins as f64;
    let mut sum_w = vec![0.0; bins];
    let mut sum_wu = vec![0.0; bins];
    for ((&y, &u), &w) in across_m.iter().zip(velocity_m_per_s).zip(weight) {
        let counted = (min_m..max_m).contains(&y) && u.is_finite() && w > 0.0;
        if !counted {
            continue;
        }
        let k = (((y - min_m) / h) as usize).min(bins - 1);
        sum_w[k] += w;
        sum_wu[k] += w * u;
    }
    let mut profile = VelocityProfile {
        centre_m: Vec::new(),
        velocity_m_per_s: Vec::new(),
        weight: Vec::new(),
    };
    for k in 0..bins {
        if sum_w[k] > 0.0 {
            profile.centre_m.push(min_m + (k as f64 + 0.5) * h);
            profile.velocity_m_per_s.push(sum_wu[k] / sum_w[k]);
            profile.weight.push(sum_w[k]);
        }
    }
    Ok(profile)
}

/// Where and how wide the velocity changes across the channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearBand {
    /// Velocity of the last bin minus that of the first, m/s.
    pub velocity_jump_m_per_s: f64,
    /// Largest |du/dy| between neighbouring bins, 1/s.
    pub peak_shear_rate_per_s: f64,
    /// Where the peak shear rate is (midpoint of the two bins), m.
    pub peak_at_m: f64,
    /// `|Δu| / max|du/dy|`, m.
    pub equivalent_width_m: f64,
    /// Distance between the first crossings of 10 % and 90 % of the jump
    /// (linear interpolation between bin centres), m.
    pub width_10_90_m: f64,
}

/// The shear band of a profile (see the module documentation for the two
/// widths). Needs at least two non-empty bins and a non-zero jump.
pub fn shear_band(profile: &VelocityProfile) -> Result<ShearBand, AnalysisError> {
    let (y, u) = (&profile.centre_m, &profile.velocity_m_per_s);
    if y.len() < 2 {
        return Err(AnalysisError::NotEnoughData(
            "a shear band needs at least two non-empty bins",
        ));
    }
    let jump = u[u.len() - 1] - u[0];
    if jump == 0.0 || !jump.is_finite() {
        return Err(AnalysisError::NotEnoughData(
            "the velocity does not change across the channel: no shear band",
        ));
    }
    let (mut peak, mut peak_at) = (0.0_f64, y[0]);
    for k in 0..y.len() - 1 {
        let rate = ((u[k + 1] - u[k]) / (y[k + 1] - y[k])).abs();
        if rate > peak {
            peak = rate;
            peak_at = 0.5 * (y[k] + y[k + 1]);
        }
    }
    // Fraction of the jump reached at each bin: 0 at the first, 1 at the last.
    let reached = |k: usize| (u[k] - u[0]) / jump;
    let crossing = |level: f64| -> f64 {
        for k in 0..y.len() - 1 {
            let (f0, f1) = (reached(k), reached(k + 1));
            if f0 < level && f1 >= level {
                return y[k] + (level - f0) / (f1 - f0) * (y[k + 1] - y[k]);
            }
        }
        y[y.len() - 1]
    };
    Ok(ShearBand {
        velocity_jump_m_per_s: jump,
        peak_shear_rate_per_s: peak,
        peak_at_m: peak_at,
        equivalent_width_m: jump.abs() / peak,
        width_10_90_m: crossing(0.9) - crossing(0.1),
    })
}
