//! A spatial index of disks of very different radii (floes of a power-law
//! size distribution span a factor of 10 to 1000): one uniform grid per
//! octave of radius, each disk in the one cell of its level that holds its
//! centre. Each cell keeps a bound (the largest radius in it, or another
//! number per disk such as a power-diagram weight, [`DiskGrid::rebound`]);
//! a query visits, per level, the cells within its reach of that level's
//! largest bound, and skips a cell that lies farther from the query point
//! than its reach of the cell's own bound. So its cost does not depend on
//! how many scales the disks span, nor on how the bound varies over the
//! region. Cells are linked lists (a head per cell, a next per disk), so
//! insertion is O(1) and memory is a few bytes per cell; the finest cells
//! are made no smaller than the mean spacing of the disks so that no level
//! has many more cells than disks.

use std::ops::Not;

use crate::Vec2;

const NONE: u32 = u32::MAX;

/// One grid level: cells of side `cell_m`.
#[derive(Debug, Clone)]
struct Level {
    cell_m: f64,
    nx: usize,
    ny: usize,
    head: Vec<u32>,
    /// Per cell, the largest bound of its disks.
    bound: Vec<f64>,
    /// The largest bound in this level.
    largest: f64,
    /// Disks in this level.
    count: usize,
}

/// Disks in a rectangle `[0, size]` (a frame local to the region).
#[derive(Debug, Clone)]
pub(crate) struct DiskGrid {
    levels: Vec<Level>,
    next: Vec<u32>,
    centre: Vec<Vec2>,
    level_of: Vec<u8>,
}

impl DiskGrid {
    /// An empty index for up to `capacity` disks of radii in
    /// `[r_min, r_max]` in `[0, size]`.
    pub(crate) fn new(size: Vec2, r_min: f64, r_max: f64, capacity: usize) -> Self {
        let spacing = (size.x * size.y / capacity.max(1) as f64).sqrt();
        let finest = (2.0 * r_min).max(spacing).max(1e-9 * size.x.max(size.y));
        let mut levels = Vec::new();
        let mut cell = finest;
        loop {
            let nx = ((size.x / cell).ceil() as usize).max(1);
            let ny = ((size.y / cell).ceil() as usize).max(1);
            levels.push(Level {
                cell_m: cell,
                nx,
                ny,
                head: vec![NONE; nx * ny],
                bound: vec![f64::NEG_INFINITY; nx * ny],
                largest: f64::NEG_INFINITY,
                count: 0,
            });
            if cell >= 2.0 * r_max || levels.len() == 60 {
                break;
            }
            cell *= 2.0;
        }
        DiskGrid {
            levels,
            next: Vec::with_capacity(capacity),
            centre: Vec::with_capacity(capacity),
            level_of: Vec::with_capacity(capacity),
        }
    }

    fn cell_index(level: &Level, p: Vec2) -> (usize, usize) {
        let i = ((p.x / level.cell_m).floor().max(0.0) as usize).min(level.nx - 1);
        let j = ((p.y / level.cell_m).floor().max(0.0) as usize).min(level.ny - 1);
        (i, j)
    }

    /// Adds disk number `self.len()` at `centre` with `radius`; returns
    /// its number.
    pub(crate) fn insert(&mut self, centre: Vec2, radius: f64) -> usize {
        let id = self.next.len();
        let l = self
            .levels
            .iter()
            .position(|l| l.cell_m >= 2.0 * radius)
            .unwrap_or(self.levels.len() - 1);
        let level = &mut self.levels[l];
        let (i, j) = Self::cell_index(level, centre);
        let cell = j * level.nx + i;
        self.next.push(level.head[cell]);
        level.head[cell] = id as u32;
        level.bound[cell] = level.bound[cell].max(radius);
        level.largest = level.largest.max(radius);
        level.count += 1;
        self.centre.push(centre);
        self.level_of.push(l as u8);
        id
    }

    /// Number of disks.
    pub(crate) fn len(&self) -> usize {
        self.next.len()
    }

    /// Sets each cell's bound to the largest of `bound(k)` over its disks
    /// (a weight instead of the radius, for power-diagram queries).
    pub(crate) fn rebound(&mut self, bound: impl Fn(usize) -> f64) {
        for l in &mut self.levels {
            l.largest = f64::NEG_INFINITY;
            l.bound.fill(f64::NEG_INFINITY);
        }
        for k in 0..self.len() {
            let l = &mut self.levels[self.level_of[k] as usize];
            let (i, j) = Self::cell_index(l, self.centre[k]);
            let b = bound(k);
            let cell = j * l.nx + i;
            l.bound[cell] = l.bound[cell].max(b);
            l.largest = l.largest.max(b);
        }
    }

    /// Calls `visit(k)` for every disk `k` whose centre may lie within
    /// `reach(bound)` of `p`, `reach` increasing in the bound (a superset:
    /// whole cells are visited, those within `reach` of their own bound),
    /// level by level from the finest, cells in row order, each cell's
    /// disks newest first: a deterministic order.
    pub(crate) fn visit_near(
        &self,
        p: Vec2,
        reach: impl Fn(f64) -> f64,
        mut visit: impl FnMut(usize),
    ) {
        for level in &self.levels {
            if level.count == 0 {
                continue;
            }
            let r = reach(level.largest);
            if (r >= 0.0).not() {
                continue;
            }
            let (i0, j0) = Self::cell_index(level, p - Vec2::splat(r));
            let (i1, j1) = Self::cell_index(level, p + Vec2::splat(r));
            let h = level.cell_m;
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let cell = j * level.nx + i;
                    if level.head[cell] == NONE {
                        continue;
                    }
                    // The distance from p to the cell's square.
                    let lo = Vec2::new(i as f64 * h, j as f64 * h);
                    let gap = (lo - p).max(p - (lo + Vec2::splat(h))).max(Vec2::ZERO);
                    if gap.length() >= reach(level.bound[cell]) {
                        continue;
                    }
                    let mut k = level.head[cell];
                    while k != NONE {
                        visit(k as usize);
                        k = self.next[k as usize];
                    }
                }
            }
        }
    }

    /// The centre of disk `k`.
    pub(crate) fn centre(&self, k: usize) -> Vec2 {
        self.centre[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_disk_within_reach_is_visited() {
        let size = Vec2::new(1000.0, 500.0);
        let mut g = DiskGrid::new(size, 1.0, 200.0, 100);
        let disks: Vec<(Vec2, f64)> = (0..100)
            .map(|k| {
                let t = k as f64;
                let p = Vec2::new((t * 137.0) % 1000.0, (t * 71.0) % 500.0);
                (p, 1.0 + (t * 13.0) % 199.0)
            })
            .collect();
        for &(p, r) in &disks {
            g.insert(p, r);
        }
        let q = Vec2::new(400.0, 250.0);
        let mut seen = Vec::new();
        g.visit_near(q, |largest| 30.0 + largest, |k| seen.push(k));
        for (k, &(p, r)) in disks.iter().enumerate() {
            if (p - q).length() < 30.0 + r {
                assert!(seen.contains(&k), "disk {k} missed");
            }
        }
        seen.sort_unstable();
        seen.dedup();
        assert!(seen.len() < 100);
    }
}
