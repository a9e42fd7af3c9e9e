//! Ice area through a gate across a strait: the area of ice past a line
//! (floes clipped exactly to the half-plane beyond it), and the area flux
//! as its rate of change between snapshots.
//!
//! A gate is the line `y = y_gate` with "past" meaning `y < y_gate` (ice
//! flowing towards −y, down a strait laid along y). Only free floes count.
//! Between snapshots `k` and `k + 1` the flux is
//! `(A_{k+1} − A_k) / (t_{k+1} − t_k)` (m²/s), ice leaving the domain
//! beyond the gate counting as past it as long as it is in the snapshot.

use crate::error::AnalysisError;
use crate::polygon::{clip, polygon_area};

/// The area (m²) of the free floes' parts below `y_gate`.
///
/// `floes` holds each floe's vertices in world coordinates, `free` which
/// are free (walls and land are not ice).
pub fn area_past_gate(floes: &[Vec<[f64; 2]>], free: &[bool], y_gate: f64) -> f64 {
    floes
        .iter()
        .zip(free)
        .filter(|(_, &f)| f)
        .map(|(poly, _)| {
            let ys = poly.iter().map(|p| p[1]);
            let (lo, hi) = ys.fold((f64::MAX, f64::MIN), |(a, b), y| (a.min(y), b.max(y)));
            if hi <= y_gate {
                polygon_area(poly).abs()
            } else if lo >= y_gate {
                0.0
            } else {
                polygon_area(&clip(poly, |p| y_gate - p[1])).abs()
            }
        })
        .sum()
}

/// The area flux (m²/s) between consecutive samples of `area_m2` at
/// `times_s`, at the middle times.
///
/// # Errors
/// [`AnalysisError::LengthMismatch`] for series of different lengths,
/// [`AnalysisError::InvalidParameter`] for times not increasing.
pub fn flux(times_s: &[f64], area_m2: &[f64]) -> Result<Vec<(f64, f64)>, AnalysisError> {
    if times_s.len() != area_m2.len() {
        return Err(AnalysisError::LengthMismatch {
            what: "gate flux times and areas",
            left: times_s.len(),
            right: area_m2.len(),
        });
    }
    times_s
        .windows(2)
        .zip(area_m2.windows(2))
        .map(|(t, a)| {
            let dt = t[1] - t[0];
            if dt > 0.0 {
                Ok((0.5 * (t[0] + t[1]), (a[1] - a[0]) / dt))
            } else {
                Err(AnalysisError::InvalidParameter {
                    name: "gate flux times_s",
                    value: t[1],
                    reason: "must increase strictly",
                })
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, side: f64) -> Vec<[f64; 2]> {
        vec![[x, y], [x + side, y], [x + side, y + side], [x, y + side]]
    }

    #[test]
    fn a_square_crossing_the_gate_passes_its_width_times_its_speed() {
        // A 300 m square moving down at 0.2 m/s through y = 0: while it
        // straddles the gate, 300 m x 0.2 m/s = 60 m²/s passes.
        let times: Vec<f64> = (0..20).map(|k| 100.0 * k as f64).collect();
        let areas: Vec<f64> = times
            .iter()
            .map(|t| area_past_gate(&[square(50.0, 100.0 - 0.2 * t, 300.0)], &[true], 0.0))
            .collect();
        let f = flux(&times, &areas).unwrap();
        for &(t, q) in &f {
            let (top, bottom) = (400.0 - 0.2 * t, 100.0 - 0.2 * t);
            if bottom < -20.0 && top > 20.0 {
                assert!((q - 60.0).abs() < 1e-9, "{t} {q}");
            }
        }
        assert!((areas[0] - 0.0).abs() < 1e-9);
        // At t = 1900 s the square spans -280..20 m: 280 m of it is past.
        assert!((areas[19] - 84_000.0).abs() < 1e-6);
    }

    #[test]
    fn land_and_walls_are_not_ice() {
        let floes = [square(0.0, -10.0, 5.0), square(0.0, -10.0, 5.0)];
        assert_eq!(area_past_gate(&floes, &[true, false], 0.0), 25.0);
        assert!(flux(&[0.0, 0.0], &[1.0, 2.0]).is_err());
        assert!(flux(&[0.0], &[1.0, 2.0]).is_err());
    }
}
