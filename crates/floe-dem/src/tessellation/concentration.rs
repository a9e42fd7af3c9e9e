//! Thinning a tessellation to an ice concentration: which floes to keep so
//! that the kept ice area matches concentration × area at every scale down
//! to the floes' own.
//!
//! Keeping each floe with probability `c` at its centroid gets the area
//! right on average only: over a grid cell of `N` equal floes of area `a`
//! the kept area scatters by `a sqrt(N c (1 − c))` (two floes, 12 % of the
//! cell, at `c = 0.6` with 16 floes a cell). Here the floes are visited in
//! a fixed order, and a running balance `E` of (concentration × area
//! wanted) − (area kept) decides: a floe of area `a` and concentration `c`
//! is kept when `E + c a ≥ u a`, `u` a seeded uniform draw in `[0, 1)`
//! (error diffusion with random thresholds). Then `|E| ≤ a_max` at every
//! step, so any run of consecutive floes holds its wanted area to within
//! two floes however many it has; the random threshold keeps the open
//! water from falling into a regular pattern.
//!
//! One balance for floes of every size would make the small floes pay for
//! the large ones' decisions, unevenly (after a large floe is dropped at
//! `c = 0.7`, each small floe kept repays only 0.3 of its area): the large
//! floes end up kept more often than `c` where `c > 1/2` and less where
//! `c < 1/2`, which steepens or flattens the floe-size distribution (by
//! 0.1 to 0.17 in the exponent of a power law). So each octave of floe
//! area keeps its own balance: every size class is thinned to `c` on its
//! own, and the total is held to `Σ a_max,class ≤ 2 a_max`.
//!
//! The order is cell by cell of the concentration's grid when the floes'
//! cells are given (each cell one run, the cells along a Hilbert curve so
//! that the balances carry over to a neighbour), and along a Hilbert curve
//! through the centroids within a cell (or over the whole region). Floes
//! where `c ≥ 1` are always kept and floes where `c ≤ 0` or `c` is unknown
//! never, without changing the balances.

use std::ops::Not;

use super::{stream_rng, streams, unit, Rect, Tessellation};
use crate::Vec2;

/// Size classes (octaves of area) with balances of their own.
const SIZE_CLASSES: usize = 64;

/// Side of the Hilbert curve's grid, `2^HILBERT_ORDER` cells.
const HILBERT_ORDER: u32 = 16;

/// What [`select_by_concentration`] kept.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ConcentrationSelection {
    /// Floes kept.
    pub kept: usize,
    /// Floes with a concentration in `(0, 1)` left as open water.
    pub thinned: usize,
    /// Floes where the concentration is `≤ 0` or not known (NaN).
    pub no_ice: usize,
    /// `Σ c a` over the floes with a concentration, m².
    pub wanted_area_m2: f64,
    /// `Σ a` over the floes kept, m².
    pub kept_area_m2: f64,
}

/// Which floes to keep (see the module docs): `areas[k]` and
/// `centroids[k]` of floe `k`, `concentration[k]` at its centroid (a
/// fraction; NaN where unknown; values above 1 count as 1), optionally
/// `cells[k]`, the column and row of the grid cell it counts in, the
/// region the centroids lie in, and the seed of the thresholds.
/// Deterministic.
///
/// # Panics
/// If the slices are not one entry per floe.
pub fn select_by_concentration(
    areas: &[f64],
    centroids: &[Vec2],
    concentration: &[f64],
    cells: Option<&[(u32, u32)]>,
    region: Rect,
    seed: u64,
) -> (Vec<bool>, ConcentrationSelection) {
    let n = areas.len();
    assert!(
        centroids.len() == n && concentration.len() == n,
        "one entry per floe"
    );
    assert!(cells.is_none_or(|c| c.len() == n), "one cell per floe");
    let mut keep = vec![false; n];
    let mut report = ConcentrationSelection::default();
    let order = visiting_order(centroids, cells, region);
    let mut rng = stream_rng(seed, streams::CONCENTRATION);
    // One balance per octave of floe area.
    let smallest = areas
        .iter()
        .copied()
        .filter(|a| *a > 0.0)
        .fold(f64::INFINITY, f64::min);
    let mut balances = [0.0f64; SIZE_CLASSES];
    for k in order {
        let (a, c) = (areas[k], concentration[k]);
        let class = ((a / smallest).log2().floor().max(0.0) as usize).min(SIZE_CLASSES - 1);
        let balance = &mut balances[class];
        if (c > 0.0).not() {
            report.no_ice += 1;
            continue;
        }
        let c = c.min(1.0);
        report.wanted_area_m2 += c * a;
        let u = unit(&mut rng);
        if c >= 1.0 {
            keep[k] = true;
        } else if *balance + c * a >= u * a {
            keep[k] = true;
            *balance += c * a - a;
        } else {
            *balance += c * a;
        }
        if keep[k] {
            report.kept += 1;
            report.kept_area_m2 += a;
        } else {
            report.thinned += 1;
        }
    }
    (keep, report)
}

impl Tessellation {
    /// Keeps the floes `k` with `keep[k]`, in order.
    ///
    /// # Panics
    /// If `keep` is not one flag per floe.
    pub fn retain(&mut self, keep: &[bool]) {
        assert_eq!(keep.len(), self.polygons.len(), "one flag per floe");
        let mut k = 0;
        self.polygons.retain(|_| {
            k += 1;
            keep[k - 1]
        });
        let mut k = 0;
        self.thickness_m.retain(|_| {
            k += 1;
            keep[k - 1]
        });
    }
}

/// The floes' indices cell by cell along a Hilbert curve through the
/// cells (when given), then along the Hilbert curve through the region
/// (ties by index).
fn visiting_order(centroids: &[Vec2], cells: Option<&[(u32, u32)]>, region: Rect) -> Vec<usize> {
    let side = (1u64 << HILBERT_ORDER) as f64;
    let span = Vec2::new(region.width_m(), region.height_m()).max(Vec2::splat(f64::MIN_POSITIVE));
    let cell = |v: f64, lo: f64, len: f64| -> u32 {
        let t = ((v - lo) / len * side).floor();
        if t.is_nan() {
            0
        } else {
            t.clamp(0.0, side - 1.0) as u32
        }
    };
    let mut keyed: Vec<(u64, u64, usize)> = centroids
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let x = cell(p.x, region.min.x, span.x);
            let y = cell(p.y, region.min.y, span.y);
            let grid_cell = cells.map_or(0, |c| hilbert_index(c[k].0, c[k].1, 32));
            (grid_cell, hilbert_index(x, y, HILBERT_ORDER), k)
        })
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, _, k)| k).collect()
}

/// The distance along the Hilbert curve of order `order` (a grid of
/// `2^order` cells a side, `order ≤ 32`) of cell `(x, y)` (the classic
/// rotate-and-flip formulation).
fn hilbert_index(x: u32, y: u32, order: u32) -> u64 {
    let n: u64 = 1 << order;
    let (mut x, mut y) = (x as u64, y as u64);
    let mut d: u64 = 0;
    let mut s = n / 2;
    while s > 0 {
        let rx = u64::from(x & s > 0);
        let ry = u64::from(y & s > 0);
        d = d.wrapping_add(s.wrapping_mul(s).wrapping_mul((3 * rx) ^ ry));
        if ry == 0 {
            if rx == 1 {
                x = n - 1 - x;
                y = n - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s /= 2;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hilbert_curve_visits_neighbours_in_turn() {
        // Consecutive indices are adjacent cells: check on a 2^16 grid's
        // first 4096 cells by inverting through a brute-force map of a
        // 64 x 64 corner.
        let mut at = vec![None; 64 * 64];
        for y in 0..64u32 {
            for x in 0..64u32 {
                let d = hilbert_index(x, y, HILBERT_ORDER);
                // A corner of a curve of even order more is the same curve.
                assert_eq!(d, hilbert_index(x, y, 32), "{x} {y}");
                if d < 4096 {
                    at[d as usize] = Some((x, y));
                }
            }
        }
        let cells: Vec<(u32, u32)> = at.into_iter().map(|c| c.unwrap()).collect();
        for w in cells.windows(2) {
            let (a, b) = (w[0], w[1]);
            assert_eq!(a.0.abs_diff(b.0) + a.1.abs_diff(b.1), 1, "{a:?} {b:?}");
        }
    }

    #[test]
    fn the_balance_stays_within_a_floe_and_extremes_are_exact() {
        // 1000 floes in a row with areas 1..3 and concentrations 0..1.
        let n = 1000;
        let region = Rect::new(Vec2::ZERO, Vec2::new(1000.0, 1.0));
        let centroids: Vec<Vec2> = (0..n).map(|k| Vec2::new(k as f64 + 0.5, 0.5)).collect();
        let areas: Vec<f64> = (0..n).map(|k| 1.0 + (k % 3) as f64).collect();
        let conc: Vec<f64> = (0..n)
            .map(|k| match k % 10 {
                0 => 0.0,
                1 => 1.0,
                2 => f64::NAN,
                m => m as f64 / 10.0,
            })
            .collect();
        let (keep, r) = select_by_concentration(&areas, &centroids, &conc, None, region, 7);
        for (k, &kept) in keep.iter().enumerate() {
            match k % 10 {
                0 | 2 => assert!(!kept),
                1 => assert!(kept),
                _ => {}
            }
        }
        assert_eq!(r.no_ice, 200);
        assert_eq!(r.kept + r.thinned, 800);
        // Areas 1 (octave 0) and 2, 3 (octave 1): within 1 + 3.
        assert!((r.kept_area_m2 - r.wanted_area_m2).abs() <= 4.0, "{r:?}");
        // Same seed, same choice; another seed, another.
        let (again, _) = select_by_concentration(&areas, &centroids, &conc, None, region, 7);
        assert_eq!(keep, again);
        let (other, _) = select_by_concentration(&areas, &centroids, &conc, None, region, 8);
        assert_ne!(keep, other);
        // Cells of 50 floes: each holds its wanted area to 2 (1 + 3).
        let cells: Vec<(u32, u32)> = (0..n).map(|k| ((k / 50) as u32, 0)).collect();
        let (keep, _) = select_by_concentration(&areas, &centroids, &conc, Some(&cells), region, 7);
        for cell in 0..n / 50 {
            let (mut wanted, mut kept) = (0.0, 0.0);
            for k in cell * 50..(cell + 1) * 50 {
                if conc[k] > 0.0 {
                    wanted += conc[k] * areas[k];
                }
                if keep[k] {
                    kept += areas[k];
                }
            }
            assert!((kept - wanted).abs() <= 8.0, "cell {cell}: {kept} {wanted}");
        }
    }
}
