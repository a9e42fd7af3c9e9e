//! Which processes hold a floe: its owner, and every process with an owned
//! floe it could touch before the next migration (a ghost there).
//!
//! A free floe `j` is a ghost on process `k` when its centre is within
//! `r_j + R + skin` of `k`'s box (`R` the largest free floe's bounding
//! radius): any floe `k` owns lies in the box at the migration, so until
//! the next one (every floe moves less than `skin / 2`) every floe that
//! can touch it is there. Prescribed floes (walls, land) are everywhere;
//! so that the owner of one computes the force on it whole, every free
//! floe within `r_j + skin` of its outline is a ghost on its owner.
//! Distances are periodic images' on periodic axes.

use std::collections::HashMap;

use floe_dem::periodicity::Periodicity;
use floe_dem::tessellation::Rect;
use floe_dem::Vec2;

/// The images of `p` that can be nearest to something in the domain: `p`
/// and its shifts by one period along each periodic axis.
pub(crate) fn images(p: Vec2, periodicity: Periodicity) -> Vec<Vec2> {
    let shifts = |period: Option<floe_dem::periodicity::Period>| match period {
        Some(q) => vec![0.0, -q.length_m, q.length_m],
        None => vec![0.0],
    };
    let (xs, ys) = (shifts(periodicity.x), shifts(periodicity.y));
    xs.iter()
        .flat_map(|&dx| ys.iter().map(move |&dy| p + Vec2::new(dx, dy)))
        .collect()
}

/// A prescribed floe's outline in the plane, and its owner.
pub(crate) struct Outline {
    pub(crate) owner: usize,
    pub(crate) vertices: Vec<Vec2>,
}

/// Distance from `p` to the polygon `v` (0 inside).
fn distance_to_polygon(p: Vec2, v: &[Vec2]) -> f64 {
    let mut inside = false;
    let mut best = f64::INFINITY;
    for k in 0..v.len() {
        let (a, b) = (v[k], v[(k + 1) % v.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        best = best.min((a + t * ab - p).length());
    }
    if inside {
        0.0
    } else {
        best
    }
}

/// The prescribed floes' outlines on a uniform grid, to find those near a point.
pub(crate) struct OutlineGrid {
    cell_m: f64,
    cells: HashMap<(i64, i64), Vec<u32>>,
    outlines: Vec<Outline>,
}

impl OutlineGrid {
    /// The grid of `outlines`, each entered in the cells its box grown by
    /// `margin_m` covers; cells about `margin_m` wide.
    pub(crate) fn new(outlines: Vec<Outline>, margin_m: f64) -> Self {
        let cell_m = (2.0 * margin_m).max(f64::MIN_POSITIVE);
        let mut cells: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
        for (k, o) in outlines.iter().enumerate() {
            let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
            for v in &o.vertices {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
            let (c0, c1) = (
                cell_of(lo - Vec2::splat(margin_m), cell_m),
                cell_of(hi + Vec2::splat(margin_m), cell_m),
            );
            for cx in c0.0..=c1.0 {
                for cy in c0.1..=c1.1 {
                    cells.entry((cx, cy)).or_default().push(k as u32);
                }
            }
        }
        OutlineGrid {
            cell_m,
            cells,
            outlines,
        }
    }

    /// Adds to `ranks` the owners of the outlines within `reach_m` of any
    /// of `points`.
    pub(crate) fn owners_near(&self, points: &[Vec2], reach_m: f64, ranks: &mut Vec<usize>) {
        for &p in points {
            let Some(list) = self.cells.get(&cell_of(p, self.cell_m)) else {
                continue;
            };
            for &k in list {
                let o = &self.outlines[k as usize];
                if !ranks.contains(&o.owner) && distance_to_polygon(p, &o.vertices) < reach_m {
                    ranks.push(o.owner);
                }
            }
        }
    }
}

fn cell_of(p: Vec2, cell_m: f64) -> (i64, i64) {
    ((p.x / cell_m).floor() as i64, (p.y / cell_m).floor() as i64)
}

/// Distance from box `b` to the nearest of `points` (a floe's periodic images).
pub(crate) fn box_distance(b: Rect, points: &[Vec2]) -> f64 {
    points
        .iter()
        .map(|p| {
            let dx = (b.min.x - p.x).max(0.0).max(p.x - b.max.x);
            let dy = (b.min.y - p.y).max(0.0).max(p.y - b.max.y);
            (dx * dx + dy * dy).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_a_square() {
        let sq = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)].map(|(x, y)| Vec2::new(x, y));
        assert_eq!(distance_to_polygon(Vec2::new(1.0, 1.0), &sq), 0.0);
        assert_eq!(distance_to_polygon(Vec2::new(5.0, 1.0), &sq), 3.0);
        assert_eq!(distance_to_polygon(Vec2::new(5.0, 6.0), &sq), 5.0);
    }

    #[test]
    fn the_grid_finds_the_owner_of_a_near_wall_only() {
        let wall = |x0: f64, owner| Outline {
            owner,
            vertices: [(0.0, 0.0), (1.0, 0.0), (1.0, 100.0), (0.0, 100.0)]
                .map(|(x, y)| Vec2::new(x0 + x, y))
                .to_vec(),
        };
        let grid = OutlineGrid::new(vec![wall(0.0, 3), wall(50.0, 5)], 2.0);
        let mut ranks = Vec::new();
        grid.owners_near(&[Vec2::new(2.5, 70.0)], 2.0, &mut ranks);
        assert_eq!(ranks, vec![3]);
        ranks.clear();
        grid.owners_near(&[Vec2::new(25.0, 70.0)], 2.0, &mut ranks);
        assert!(ranks.is_empty());
        // A periodic image reaches the far wall.
        grid.owners_near(
            &[Vec2::new(25.0, 70.0), Vec2::new(49.5, 70.0)],
            2.0,
            &mut ranks,
        );
        assert_eq!(ranks, vec![5]);
    }
}
