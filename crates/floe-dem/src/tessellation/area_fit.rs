//! Weights of a power diagram that give its cells prescribed areas: the
//! damped Newton method of Kitagawa, Mérigot & Thibert (2019, J. Eur.
//! Math. Soc. 21, 2603) for semi-discrete optimal transport.
//!
//! The areas' derivatives form a graph Laplacian: raising `w_i` by `δ`
//! moves the edge between cells `i` and `j` by `δ / (2 d_ij)`, so
//! `∂A_i/∂w_j = −ℓ_ij / (2 d_ij)` (`ℓ_ij` the edge's length) and
//! `∂A_i/∂w_i` is minus the sum of those. A Newton step solves
//! `L δ = target − area` by conjugate gradients (Jacobi-preconditioned;
//! the residual sums to zero as the areas always fill the domain, and the
//! solution is fixed up to a constant, which moves no edge). The step is
//! halved until every cell keeps at least half the smaller of the
//! smallest starting area and the smallest target, and the residual has
//! fallen by at least a quarter of the step's fraction (`‖r'‖ ≤ (1 − τ/4)
//! ‖r‖`): from any weights with no empty cell this converges, quadratically
//! near the solution.

use std::ops::Not;

use std::f64::consts::PI;

use rayon::prelude::*;

use super::disk_grid::DiskGrid;
use super::laguerre::{PowerCell, PowerDiagram, BOUNDARY};
use crate::Vec2;

/// The outcome of [`fit_areas`].
pub(crate) struct AreaFit {
    /// The cells at the final weights.
    pub cells: Vec<PowerCell>,
    /// Power diagrams computed (Newton steps and halvings).
    pub passes: usize,
    /// Largest `|area − target| / target`.
    pub max_error: f64,
    /// Root mean square of the same.
    pub rms_error: f64,
}

impl AreaFit {
    /// Whether a cell is empty (the fit could not start).
    pub(crate) fn empty(&self) -> bool {
        self.cells.iter().any(|c| c.area() <= 0.0)
    }
}

/// Most halvings of one Newton step.
const MAX_HALVINGS: usize = 30;

/// Most conjugate-gradient iterations of one Newton step.
const MAX_CG_ITERATIONS: usize = 2000;

/// Fits `weights` (in place) so that the power cells of `sites` in
/// `[0, size]` have areas `targets` to a relative `tolerance`, in at most
/// `max_passes` power diagrams.
pub(crate) fn fit_areas(
    sites: &[Vec2],
    targets: &[f64],
    weights: &mut [f64],
    size: Vec2,
    (tolerance, max_passes): (f64, usize),
) -> AreaFit {
    let n = sites.len();
    let mut rho: Vec<f64> = targets.iter().map(|t| t.sqrt()).collect();
    let mut passes = 1;
    // Indexed by the radius of a disk of half the target area: levels by
    // the floes' own sizes, bounds by their weights.
    let radius: Vec<f64> = targets.iter().map(|t| (0.5 * t / PI).sqrt()).collect();
    let smallest = radius.iter().copied().fold(f64::INFINITY, f64::min);
    let largest = radius.iter().copied().fold(0.0, f64::max);
    let mut grid = DiskGrid::new(size, smallest, largest, sites.len());
    for (&s, &r) in sites.iter().zip(&radius) {
        grid.insert(s, r);
    }
    let mut cells = power_cells(sites, weights, &rho, &mut grid, size);
    let floor = 0.5
        * cells
            .iter()
            .map(|c| c.area())
            .chain(targets.iter().copied())
            .fold(f64::INFINITY, f64::min);
    let residual = |cells: &[PowerCell]| -> Vec<f64> {
        cells
            .iter()
            .zip(targets)
            .map(|(c, t)| t - c.area())
            .collect()
    };
    let norm = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut r = residual(&cells);
    loop {
        let (max_error, rms_error) = errors(&r, targets);
        if max_error <= tolerance || passes >= max_passes || (floor > 0.0).not() {
            return AreaFit {
                cells,
                passes,
                max_error,
                rms_error,
            };
        }
        for (k, c) in cells.iter().enumerate() {
            rho[k] = 1.25 * c.reach();
        }
        let laplacian = Laplacian::of(&cells, sites);
        let step = laplacian.solve(&r);
        let before = norm(&r);
        let mut tau = 1.0;
        let mut trial = weights.to_vec();
        let mut accepted = false;
        for _ in 0..=MAX_HALVINGS {
            for k in 0..n {
                trial[k] = weights[k] + tau * step[k];
            }
            let next = power_cells(sites, &trial, &rho, &mut grid, size);
            passes += 1;
            let smallest = next.iter().map(|c| c.area()).fold(f64::INFINITY, f64::min);
            let r_next = residual(&next);
            if smallest >= floor && norm(&r_next) <= (1.0 - 0.25 * tau) * before {
                weights.copy_from_slice(&trial);
                cells = next;
                r = r_next;
                accepted = true;
                break;
            }
            if passes >= max_passes {
                break;
            }
            tau *= 0.5;
        }
        if !accepted {
            // No progress along the Newton direction (rounding at the
            // scale of the areas): the current weights are the answer.
            let (max_error, rms_error) = errors(&r, targets);
            return AreaFit {
                cells,
                passes,
                max_error,
                rms_error,
            };
        }
    }
}

/// Every power cell at weights `w` (`rho`: where to look first), the
/// sites indexed in `grid`.
pub(crate) fn power_cells(
    sites: &[Vec2],
    w: &[f64],
    rho: &[f64],
    grid: &mut DiskGrid,
    size: Vec2,
) -> Vec<PowerCell> {
    grid.rebound(|k| w[k]);
    let d = PowerDiagram {
        sites,
        weights: w,
        grid,
        size,
    };
    (0..sites.len())
        .into_par_iter()
        .map_init(Vec::new, |scratch, k| d.cell(k, rho[k], scratch))
        .collect()
}

fn errors(r: &[f64], targets: &[f64]) -> (f64, f64) {
    let mut max = 0.0f64;
    let mut sum = 0.0;
    for (x, t) in r.iter().zip(targets) {
        let e = x.abs() / t;
        max = max.max(e);
        sum += e * e;
    }
    (max, (sum / r.len().max(1) as f64).sqrt())
}

/// The areas' Laplacian, row by row: `(L x)_i = Σ_j c_ij (x_i − x_j)`.
struct Laplacian {
    rows: Vec<Vec<(u32, f64)>>,
    diagonal: Vec<f64>,
}

impl Laplacian {
    fn of(cells: &[PowerCell], sites: &[Vec2]) -> Self {
        let rows: Vec<Vec<(u32, f64)>> = cells
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let m = c.polygon.len();
                let mut row: Vec<(u32, f64)> = Vec::with_capacity(m);
                for k in 0..m {
                    let j = c.tags[k];
                    if j == BOUNDARY {
                        continue;
                    }
                    let edge = (c.polygon[(k + 1) % m] - c.polygon[k]).length();
                    let d = (sites[j as usize] - sites[i]).length();
                    if edge > 0.0 && d > 0.0 {
                        row.push((j, edge / (2.0 * d)));
                    }
                }
                row
            })
            .collect();
        let diagonal = rows
            .iter()
            .map(|row| row.iter().map(|&(_, c)| c).sum())
            .collect();
        Laplacian { rows, diagonal }
    }

    fn apply(&self, x: &[f64], out: &mut [f64]) {
        out.par_iter_mut().enumerate().for_each(|(i, o)| {
            *o = self.rows[i]
                .iter()
                .map(|&(j, c)| c * (x[i] - x[j as usize]))
                .sum();
        });
    }

    /// `x` with `L x = b` (b made to sum to zero), by Jacobi-preconditioned
    /// conjugate gradients to a relative residual of 1e-10.
    fn solve(&self, b: &[f64]) -> Vec<f64> {
        let n = b.len();
        let mean = b.iter().sum::<f64>() / n as f64;
        let mut r: Vec<f64> = b.iter().map(|v| v - mean).collect();
        let inv: Vec<f64> = self
            .diagonal
            .iter()
            .map(|&d| if d > 0.0 { 1.0 / d } else { 0.0 })
            .collect();
        let mut x = vec![0.0; n];
        let mut z: Vec<f64> = r.iter().zip(&inv).map(|(a, b)| a * b).collect();
        let mut p = z.clone();
        let mut q = vec![0.0; n];
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut rz = dot(&r, &z);
        let stop = 1e-20 * dot(&r, &r);
        for _ in 0..MAX_CG_ITERATIONS {
            if (dot(&r, &r) > stop).not() {
                break;
            }
            self.apply(&p, &mut q);
            let pq = dot(&p, &q);
            if (pq > 0.0).not() {
                break;
            }
            let a = rz / pq;
            for i in 0..n {
                x[i] += a * p[i];
                r[i] -= a * q[i];
            }
            for i in 0..n {
                z[i] = r[i] * inv[i];
            }
            let rz_next = dot(&r, &z);
            let beta = rz_next / rz;
            rz = rz_next;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
        }
        x
    }
}
