//! Power (Laguerre) cells: the weighted Voronoi diagram in which site `i`
//! with weight `w_i` owns the points `x` with
//! `|x − p_i|² − w_i ≤ |x − p_j|² − w_j` for every other site `j`. The
//! boundary between two cells is a straight line (the radical axis), so
//! cells are convex polygons; with `w = r²` the cells of non-overlapping
//! disks contain their disks. Raising `w_i` moves every edge of cell `i`
//! outwards by `δw / (2 |p_j − p_i|)`: the weights set the cells' areas
//! (Aurenhammer, Hoffmann & Aronov 1998: any areas summing to the domain's
//! are reached by one set of weights).
//!
//! A cell is the domain rectangle clipped by the half-plane of each site
//! that can reach it, found through a [`DiskGrid`]: if the cell lies within
//! `ρ` of its site, site `j` can cut it only if
//! `|p_j − p_i| < ρ + sqrt(ρ² − w_i + w_j)`. A pass assumes a `ρ`, clips
//! by the sites that pass the test (nearest first, skipping those that can
//! no longer reach the shrinking cell), and is exact if the cell it makes
//! lies within `ρ`; otherwise `ρ` doubles. Each cell is computed on its
//! own, in a frame centred on its site, so the result does not depend on
//! the order or the thread count.

use super::disk_grid::DiskGrid;
use super::polygon_area;
use crate::Vec2;

/// An edge tag: the neighbouring site across it, or none (the domain's
/// boundary).
pub(crate) const BOUNDARY: u32 = u32::MAX;

/// One power cell in the frame centred on its site: vertices
/// counter-clockwise, and per vertex the tag of the edge that starts at it.
#[derive(Debug, Clone, Default)]
pub(crate) struct PowerCell {
    pub polygon: Vec<Vec2>,
    pub tags: Vec<u32>,
}

impl PowerCell {
    /// Its area, m² (0 for an empty cell).
    pub(crate) fn area(&self) -> f64 {
        if self.polygon.len() < 3 {
            0.0
        } else {
            polygon_area(&self.polygon).max(0.0)
        }
    }

    /// The farthest vertex from the site, m.
    pub(crate) fn reach(&self) -> f64 {
        self.polygon.iter().map(|v| v.length()).fold(0.0, f64::max)
    }
}

/// The sites, their weights and the index over them.
pub(crate) struct PowerDiagram<'a> {
    /// Sites in the domain's frame (`[0, size]`).
    pub sites: &'a [Vec2],
    /// Weights, m².
    pub weights: &'a [f64],
    /// The index of the sites, bounded by the weights
    /// ([`DiskGrid::rebound`]).
    pub grid: &'a DiskGrid,
    /// The domain's size (its lower-left corner is the origin).
    pub size: Vec2,
}

impl PowerDiagram<'_> {
    /// The cell of site `i`, assuming first that it lies within `rho` of
    /// the site. `candidates` is scratch.
    pub(crate) fn cell(&self, i: usize, rho: f64, candidates: &mut Vec<(f64, u32)>) -> PowerCell {
        let p = self.sites[i];
        let wi = self.weights[i];
        let mut rho = rho.max(f64::MIN_POSITIVE);
        let mut cell = PowerCell::default();
        let mut scratch = PowerCell::default();
        for _ in 0..64 {
            candidates.clear();
            let reach = |wj: f64| rho + (rho * rho - wi + wj).max(0.0).sqrt();
            self.grid.visit_near(p, reach, |j| {
                if j != i {
                    let d = (self.sites[j] - p).length();
                    if d < reach(self.weights[j]) {
                        candidates.push((d, j as u32));
                    }
                }
            });
            // Nearest first: the cell shrinks early; ties by index.
            candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            cell.polygon.clear();
            cell.polygon.extend_from_slice(&[
                Vec2::new(-p.x, -p.y),
                Vec2::new(self.size.x - p.x, -p.y),
                Vec2::new(self.size.x - p.x, self.size.y - p.y),
                Vec2::new(-p.x, self.size.y - p.y),
            ]);
            cell.tags.clear();
            cell.tags.extend_from_slice(&[BOUNDARY; 4]);
            // The cell only shrinks: a candidate that cannot reach the
            // current cell is skipped.
            let mut reach_now = cell.reach();
            for &(d, j) in candidates.iter() {
                let wj = self.weights[j as usize];
                if d >= reach_now + (reach_now * reach_now - wi + wj).max(0.0).sqrt() {
                    continue;
                }
                let n = self.sites[j as usize] - p;
                let c = 0.5 * (n.length_squared() + wi - wj);
                clip_tagged(&cell, &mut scratch, n, c, j);
                std::mem::swap(&mut cell, &mut scratch);
                if cell.polygon.len() < 3 {
                    cell.polygon.clear();
                    cell.tags.clear();
                    return cell;
                }
                reach_now = cell.reach();
            }
            if reach_now <= rho {
                return cell;
            }
            // Sites beyond `rho` may still cut the cell: look twice as far
            // (not at once as far as the cell reaches, which for a cell
            // still open to the domain's edge is the whole domain).
            rho *= 2.0;
        }
        cell
    }
}

/// Clips `cell` to the half-plane `n·x ≤ c` into `out`; the new edge along
/// the line is tagged `tag`. A vertex on the line is kept once; a crossing
/// is computed from the inside endpoint.
fn clip_tagged(cell: &PowerCell, out: &mut PowerCell, n: Vec2, c: f64, tag: u32) {
    out.polygon.clear();
    out.tags.clear();
    let poly = &cell.polygon;
    let m = poly.len();
    if m == 0 {
        return;
    }
    let isect = |p_in: Vec2, d_in: f64, p_out: Vec2, d_out: f64| {
        p_in + (p_out - p_in) * (d_in / (d_in - d_out))
    };
    let dist = |x: Vec2| c - n.dot(x);
    let mut retag_last = false;
    let mut dp = dist(poly[m - 1]);
    for k in 0..m {
        let prev = (k + m - 1) % m;
        let dc = dist(poly[k]);
        if dc >= 0.0 {
            if dp < 0.0 && dc > 0.0 {
                // Entering: the rest of the edge prev → k.
                out.polygon.push(isect(poly[k], dc, poly[prev], dp));
                out.tags.push(cell.tags[prev]);
            }
            out.polygon.push(poly[k]);
            out.tags.push(cell.tags[k]);
        } else if dp > 0.0 {
            // Leaving: the edge from here runs along the line.
            out.polygon.push(isect(poly[prev], dp, poly[k], dc));
            out.tags.push(tag);
        } else if dp == 0.0 {
            // `prev` lies on the line (kept): its edge now runs along it.
            if k == 0 {
                retag_last = true;
            } else if let Some(t) = out.tags.last_mut() {
                *t = tag;
            }
        }
        dp = dc;
    }
    if retag_last {
        if let Some(t) = out.tags.last_mut() {
            *t = tag;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diagram_cells(sites: &[Vec2], weights: &[f64], size: Vec2) -> Vec<PowerCell> {
        let mut grid = DiskGrid::new(size, 1.0, 10.0, sites.len());
        for &s in sites {
            grid.insert(s, 1.0);
        }
        grid.rebound(|k| weights[k]);
        let d = PowerDiagram {
            sites,
            weights,
            grid: &grid,
            size,
        };
        let mut scratch = Vec::new();
        (0..sites.len())
            .map(|i| d.cell(i, 1.0, &mut scratch))
            .collect()
    }

    #[test]
    fn two_sites_split_at_the_radical_axis() {
        let size = Vec2::new(10.0, 4.0);
        let sites = [Vec2::new(3.0, 2.0), Vec2::new(7.0, 2.0)];
        // Equal weights: the bisector x = 5.
        let c = diagram_cells(&sites, &[0.0, 0.0], size);
        assert!((c[0].area() - 20.0).abs() < 1e-12);
        // w0 − w1 = 8: the line moves by 8 / (2 * 4) = 1 towards site 1.
        let c = diagram_cells(&sites, &[9.0, 1.0], size);
        assert!((c[0].area() - 24.0).abs() < 1e-12, "{}", c[0].area());
        assert!((c[1].area() - 16.0).abs() < 1e-12);
        let shared = c[0].tags.iter().filter(|&&t| t == 1).count();
        assert_eq!(shared, 1);
    }

    #[test]
    fn cells_tile_the_domain_whatever_the_weights() {
        let size = Vec2::new(50.0, 30.0);
        let sites: Vec<Vec2> = (0..40)
            .map(|k| {
                let t = k as f64;
                Vec2::new((t * 17.3) % 50.0, (t * 7.9 + 0.5) % 30.0)
            })
            .collect();
        let weights: Vec<f64> = (0..40).map(|k| ((k * 7) % 5) as f64 * 3.0).collect();
        let cells = diagram_cells(&sites, &weights, size);
        let total: f64 = cells.iter().map(|c| c.area()).sum();
        assert!((total - 1500.0).abs() < 1e-9, "{total}");
        // Every tagged edge has the neighbour's cell on its other side.
        for (i, c) in cells.iter().enumerate() {
            for (k, &t) in c.tags.iter().enumerate() {
                if t == BOUNDARY {
                    continue;
                }
                let n = c.polygon.len();
                let mid = 0.5 * (c.polygon[k] + c.polygon[(k + 1) % n]) + sites[i];
                let j = t as usize;
                let power = |s: usize| (mid - sites[s]).length_squared() - weights[s];
                assert!((power(i) - power(j)).abs() < 1e-9, "{i} {j}");
            }
        }
    }
}
