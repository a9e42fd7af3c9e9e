//! Broad phase: candidate contact pairs from a uniform cell grid, with a
//! skin so the list is rebuilt only when some floe has moved far enough.
//!
//! A cell grid rather than parry's BVH: floes of a tessellation have nearly
//! equal sizes, for which a grid of cells one floe diameter wide finds all
//! neighbours in the 3x3 block around a cell, is rebuilt in linear time and
//! needs no tree balancing (the cost is in docs/performance.md).
//! Pairs are produced sorted by (a, b) with a < b, whatever the thread count;
//! pairs of two prescribed floes (walls, land), which never interact, are
//! left out.
//!
//! Bounding circles alone keep pairs that cannot touch before the next
//! rebuild: in a 60-degree rhombus lattice a third of the circle pairs are
//! two cells apart, their floes 0.87 of a side away. Those are left out by
//! a lower bound on the floes' distance
//! ([`separation_lower_bound`]),
//! which needs a bound on rotation as well as on translation between
//! rebuilds ([`BroadPhase::max_rotation_rad`]).
use rayon::prelude::*;

use crate::error::DemError;
use crate::floes::FloeColumns;
use crate::geometry::{rotate, separation_lower_bound, MAX_VERTICES};
use crate::periodicity::{Period, Periodicity};
use crate::Vec2;

/// Default for [`BroadPhase::max_rotation_rad`]: about 6 degrees, which
/// moves a vertex a tenth of the floe's radius. A floe in a shear zone
/// turns at about half the shear rate, so this forces a rebuild far less
/// often than translation does.
pub const MAX_ROTATION_RAD: f64 = 0.1;

/// A pair of floes close enough to be tested for overlap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CandidatePair {
    /// First floe (the smaller index).
    pub a: u32,
    /// Second floe.
    pub b: u32,
}

/// The candidate list and what is needed to decide when to rebuild it.
#[derive(Debug, Clone)]
pub struct BroadPhase {
    /// Extra distance beyond touching bounding circles, m.
    pub skin_m: f64,
    /// See [`BroadPhase::max_rotation_rad`].
    max_rotation_rad: f64,
    /// Candidate pairs, sorted.
    pub pairs: Vec<CandidatePair>,
    positions_at_build: Vec<Vec2>,
    angles_at_build: Vec<f64>,
    /// Per floe, how far its centroid moved in its own material since the
    /// build (ridging cut it: the material the list was built for moved
    /// at most this much more than the centroid shows), m; empty if none.
    slack_m: Vec<f64>,
    /// Number of rebuilds so far (for diagnostics and tests).
    pub rebuilds: u64,
}

impl Default for BroadPhase {
    fn default() -> Self {
        Self::new(0.0)
    }
}

/// Relative allowance on the distance a pair must exceed to be left out,
/// for round-off: the lower bound is computed from vertices placed about
/// the first floe's centroid (a few ulps of the pair's extent). This
/// relative part is far above that.
const GAP_ROUND_OFF: f64 = 1e-9;

/// Absolute allowance on that distance, in ulps of the floes' coordinates:
/// the positions themselves are rounded at every drift, and the
/// displacement test compares positions as large as the basin (an ulp is
/// 1.2e-10 m at 1e6 m).
const GAP_ROUND_OFF_ULPS: f64 = 64.0;

impl BroadPhase {
    /// An empty broad phase with the given skin (m) and
    /// [`MAX_ROTATION_RAD`].
    pub fn new(skin_m: f64) -> Self {
        Self {
            skin_m,
            max_rotation_rad: MAX_ROTATION_RAD,
            pairs: Vec::new(),
            positions_at_build: Vec::new(),
            angles_at_build: Vec::new(),
            slack_m: Vec::new(),
            rebuilds: 0,
        }
    }

    /// Largest rotation of a floe between rebuilds, rad: a floe that has
    /// turned more since the list was built forces a rebuild, as one that
    /// has moved more than half the skin does. Until then each vertex of
    /// floe `i` has moved at most `skin_m / 2 + radius_i * max_rotation_rad`,
    /// so a pair whose floes are farther apart than the sum of that for
    /// both cannot touch and is left out. Infinite: every pair whose
    /// bounding circles come within the skin is kept, and rotation never
    /// forces a rebuild.
    pub fn max_rotation_rad(&self) -> f64 {
        self.max_rotation_rad
    }

    /// Sets [`BroadPhase::max_rotation_rad`] (> 0, or `f64::INFINITY` for
    /// bounding circles alone) and forgets the list, which was built for the
    /// old value: the next [`BroadPhase::update`] rebuilds it. Not part of
    /// a checkpoint (results do not depend on it): a resumed world starts
    /// with [`MAX_ROTATION_RAD`].
    pub fn set_max_rotation_rad(&mut self, rad: f64) -> Result<(), DemError> {
        if rad.is_nan() || rad <= 0.0 {
            return Err(DemError::InvalidParameter {
                name: "max_rotation_rad",
                value: rad,
                reason: "must be > 0 (infinite: bounding circles alone)",
            });
        }
        self.max_rotation_rad = rad;
        self.positions_at_build.clear();
        self.angles_at_build.clear();
        Ok(())
    }

    /// Forgets the list (the floe set changed: its handles no longer name
    /// the floes it was built for); the next update rebuilds it.
    pub fn invalidate(&mut self) {
        self.positions_at_build.clear();
        self.angles_at_build.clear();
        self.slack_m.clear();
    }

    /// Floe `i`'s centroid moved `shift_m` within its material (a ridging
    /// cut; the material only shrank): the list stays valid while the
    /// centroid's displacement plus the shifts stays within half the skin.
    pub fn add_slack(&mut self, i: usize, shift_m: f64) {
        if self.slack_m.len() != self.positions_at_build.len() {
            self.slack_m = vec![0.0; self.positions_at_build.len()];
        }
        if let Some(s) = self.slack_m.get_mut(i) {
            *s += shift_m;
        }
    }

    /// Rebuilds the candidate list if any floe moved more than half the skin
    /// or turned more than [`BroadPhase::max_rotation_rad`] since the last
    /// build (then no pair left out can have come into contact). `trig`
    /// holds each floe's `(sin, cos)` of its angle. Returns whether it
    /// rebuilt.
    pub fn update(
        &mut self,
        floes: &FloeColumns,
        trig: &[(f64, f64)],
        periodic: Periodicity,
    ) -> bool {
        let stale = self.is_stale(floes, periodic);
        if stale {
            self.rebuild(floes, trig, periodic);
        }
        stale
    }

    /// `true` if the list must be rebuilt for `floes`: their number
    /// changed, or one moved beyond half the skin or turned beyond
    /// [`BroadPhase::max_rotation_rad`].
    pub fn is_stale(&self, floes: &FloeColumns, periodic: Periodicity) -> bool {
        self.built_for() != floes.len()
            || (floes.position.par_iter(), floes.angle.par_iter())
                .into_par_iter()
                .enumerate()
                .any(|(i, (&p, &angle))| self.moved_beyond_allowance(i, p, angle, periodic))
    }

    /// Number of floes the candidate list was built for.
    pub fn built_for(&self) -> usize {
        self.positions_at_build.len()
    }

    /// `true` if floe `i`, now at `position` and `angle`, has moved more
    /// than half the skin or turned more than
    /// [`BroadPhase::max_rotation_rad`] since the list was built (or was not
    /// there): the list must be rebuilt. Callers that visit every floe
    /// anyway (the world's drift) ask this per floe instead of calling
    /// [`BroadPhase::update`].
    #[inline]
    pub fn moved_beyond_allowance(
        &self,
        i: usize,
        position: Vec2,
        angle: f64,
        periodic: Periodicity,
    ) -> bool {
        let half_skin_sq = (0.5 * self.skin_m).powi(2);
        match (self.positions_at_build.get(i), self.angles_at_build.get(i)) {
            (Some(&q), Some(&turned_from)) => {
                let moved = position + periodic.nearest_image(q, position) - q;
                let beyond = match self.slack_m.get(i) {
                    Some(&slack) if slack > 0.0 => (moved.length() + slack).powi(2) > half_skin_sq,
                    _ => moved.length_squared() > half_skin_sq,
                };
                beyond || (angle - turned_from).abs() > self.max_rotation_rad
            }
            _ => true,
        }
    }

    /// Builds the candidate list from scratch: the pairs whose bounding
    /// circles come within the skin, less those whose floes are too far
    /// apart to touch before the next rebuild (see
    /// [`BroadPhase::max_rotation_rad`]). `trig` holds each floe's
    /// `(sin, cos)` of its angle.
    pub fn rebuild(&mut self, floes: &FloeColumns, trig: &[(f64, f64)], periodic: Periodicity) {
        let (position, radius) = (&floes.position[..], &floes.radius_m[..]);
        assert_eq!(trig.len(), position.len(), "one (sin, cos) per floe");
        debug_assert!(
            trig.iter()
                .zip(&floes.angle)
                .all(|(&t, a)| t == a.sin_cos()),
            "trig must be the floes' (sin, cos) of their angles"
        );
        self.rebuilds += 1;
        self.positions_at_build.clear();
        self.positions_at_build.extend_from_slice(position);
        self.angles_at_build.clear();
        self.angles_at_build.extend_from_slice(&floes.angle);
        self.slack_m.clear();
        self.pairs.clear();
        let n = position.len();
        if n < 2 {
            return;
        }
        let r_max = radius.iter().copied().fold(0.0, f64::max);
        let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
        for p in position {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        // Cells one reach wide, but at most about four per floe however far
        // apart the floes are (a grid growing with their distance exhausts
        // memory): cells are only ever widened, so every pair within reach
        // still lies in neighbouring cells, and the pairs found are the same.
        let extent =
            |lo: f64, hi: f64, period: Option<Period>| period.map_or(hi - lo, |p| p.length_m);
        let (ex, ey) = (
            extent(lo.x, hi.x, periodic.x),
            extent(lo.y, hi.y, periodic.y),
        );
        let most = (4 * n + 64) as f64;
        let cells_for = |c: f64| ((ex / c).floor() + 1.0) * ((ey / c).floor() + 1.0);
        let mut cell = (2.0 * r_max + self.skin_m).max(f64::MIN_POSITIVE);
        // NaN extents (non-finite positions) widen the cells to infinity.
        let too_many = |c: f64| {
            use std::cmp::Ordering::Greater;
            matches!(cells_for(c).partial_cmp(&most), Some(Greater) | None)
        };
        while too_many(cell) && cell.is_finite() {
            cell = (2.0 * cell).max((ex * ey / most).sqrt());
        }
        // Along a periodic axis the grid covers exactly one period, so that
        // cells at its two ends are neighbours; elsewhere it covers the floes.
        let axis = |lo: f64, hi: f64, period: Option<Period>| match period {
            Some(p) => (
                p.min_m,
                ((p.length_m / cell).floor() as usize).max(1),
                p.length_m,
            ),
            None => {
                let count = ((hi - lo) / cell).floor() as usize + 1;
                (lo, count, count as f64 * cell)
            }
        };
        let (x0, nx, wx) = axis(lo.x, hi.x, periodic.x);
        let (y0, ny, wy) = axis(lo.y, hi.y, periodic.y);
        let (cell_x, cell_y) = (wx / nx as f64, wy / ny as f64);
        let cell_of = |p: Vec2| {
            let cx = (((p.x - x0) / cell_x).max(0.0) as usize).min(nx - 1);
            let cy = (((p.y - y0) / cell_y).max(0.0) as usize).min(ny - 1);
            cy * nx + cx
        };
        // Counting sort of floes into cells (deterministic order within a cell).
        let mut start = vec![0u32; nx * ny + 1];
        let cells: Vec<usize> = position.iter().map(|&p| cell_of(p)).collect();
        for &c in &cells {
            start[c + 1] += 1;
        }
        for c in 0..nx * ny {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut members = vec![0u32; n];
        for (i, &c) in cells.iter().enumerate() {
            members[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        // The free floes of each cell too: two prescribed floes never touch
        // (the narrow phase skips them), and a coastline of 1e5 fixed
        // pieces would otherwise pair each piece with every piece near it.
        let mut free_start = vec![0u32; nx * ny + 1];
        for (i, &c) in cells.iter().enumerate() {
            if floes.is_free(i) {
                free_start[c + 1] += 1;
            }
        }
        for c in 0..nx * ny {
            free_start[c + 1] += free_start[c];
        }
        let mut fill = free_start.clone();
        let mut free_members = vec![0u32; free_start[nx * ny] as usize];
        for (i, &c) in cells.iter().enumerate() {
            if floes.is_free(i) {
                free_members[fill[c] as usize] = i as u32;
                fill[c] += 1;
            }
        }
        let wrap_x = periodic.x.is_some();
        let wrap_y = periodic.y.is_some();
        let neighbours = |c: usize| {
            let (cx, cy) = ((c % nx) as isize, (c / nx) as isize);
            let mut out = [usize::MAX; 9];
            let mut k = 0;
            for dy in -1..=1isize {
                for dx in -1..=1isize {
                    let (mut x, mut y) = (cx + dx, cy + dy);
                    if wrap_x {
                        x = x.rem_euclid(nx as isize);
                    }
                    if wrap_y {
                        y = y.rem_euclid(ny as isize);
                    }
                    if x < 0 || y < 0 || x >= nx as isize || y >= ny as isize {
                        continue;
                    }
                    let id = y as usize * nx + x as usize;
                    if !out[..k].contains(&id) {
                        out[k] = id;
                        k += 1;
                    }
                }
            }
            (out, k)
        };
        let skin = self.skin_m;
        let max_rotation = self.max_rotation_rad;
        // Floe `i`'s vertices, turned, relative to `shift`.
        let place = |i: usize, shift: Vec2, out: &mut [Vec2; MAX_VERTICES]| {
            let (sin, cos) = trig[i];
            let local = floes.local_vertices(i);
            for (slot, &v) in out.iter_mut().zip(local) {
                *slot = shift + rotate(v, cos, sin);
            }
            local.len()
        };
        // Periodic axes narrower than three cells: test every pair along them.
        let brute_force = (wrap_x && nx < 3) || (wrap_y && ny < 3);
        let mut pairs: Vec<CandidatePair> = (0..n)
            .into_par_iter()
            .flat_map_iter(|i| {
                let p = position[i];
                let mut near = [Vec2::ZERO; MAX_VERTICES];
                let mut other = [Vec2::ZERO; MAX_VERTICES];
                let n_near = if max_rotation.is_finite() {
                    place(i, Vec2::ZERO, &mut near)
                } else {
                    0
                };
                let reach = |j: usize, other: &mut [Vec2; MAX_VERTICES]| {
                    let d = position[j] + periodic.nearest_image(p, position[j]) - p;
                    let circles = radius[i] + radius[j];
                    let distance = d.length();
                    if distance > circles + skin {
                        return false;
                    }
                    if !max_rotation.is_finite() {
                        return true;
                    }
                    // Near half a period apart, another image of `j` may
                    // become the nearest before the next rebuild (each floe
                    // moves at most half the skin), and the bound below
                    // measures only this one: keep the pair.
                    let near_half_period = |delta: f64, period: Option<Period>| {
                        period.is_some_and(|q| {
                            delta.abs() >= 0.5 * q.length_m - skin * (1.0 + GAP_ROUND_OFF)
                        })
                    };
                    if near_half_period(d.x, periodic.x) || near_half_period(d.y, periodic.y) {
                        return true;
                    }
                    // Each floe's vertices move at most half the skin plus
                    // its radius times the rotation allowed before a rebuild.
                    let coordinates = p.abs().max_element().max(position[j].abs().max_element());
                    let reachable = (skin + max_rotation * circles) * (1.0 + GAP_ROUND_OFF)
                        + GAP_ROUND_OFF * (distance + circles)
                        + GAP_ROUND_OFF_ULPS * f64::EPSILON * coordinates;
                    let n_other = place(j, d, other);
                    separation_lower_bound(&near[..n_near], &other[..n_other]) <= reachable
                };
                let mut found: Vec<CandidatePair> = Vec::new();
                let i_free = floes.is_free(i);
                if brute_force {
                    found.extend(
                        ((i + 1)..n)
                            .filter(|&j| (i_free || floes.is_free(j)) && reach(j, &mut other))
                            .map(|j| CandidatePair {
                                a: i as u32,
                                b: j as u32,
                            }),
                    );
                } else {
                    let (cells_near, k) = neighbours(cells[i]);
                    // A prescribed floe pairs with free floes only.
                    let (list, first) = if i_free {
                        (&members, &start)
                    } else {
                        (&free_members, &free_start)
                    };
                    for &c in &cells_near[..k] {
                        for &j in &list[first[c] as usize..first[c + 1] as usize] {
                            let j = j as usize;
                            if j > i && reach(j, &mut other) {
                                found.push(CandidatePair {
                                    a: i as u32,
                                    b: j as u32,
                                });
                            }
                        }
                    }
                }
                found.sort_unstable_by_key(|p| p.b);
                found
            })
            .collect();
        // flat_map_iter keeps the order of i, and each i's list is sorted by b.
        pairs.dedup();
        self.pairs = pairs;
    }
}
