//! Floes coarse-grained onto a regular grid: ice concentration, mean
//! thickness, velocity, stress and the strain-rate invariants, the fields
//! continuum models and satellite deformation products (RGPS) give.
//!
//! Each floe (a convex polygon) is clipped exactly to every cell it
//! overlaps. Soft contacts let floes overlap; each field says how it
//! counts the overlap, and keeps an exact integral over the cells:
//!
//! * concentration: the area of the union of the floes in the cell (a
//!   place under two floes counted once) over the cell's area, by
//!   inclusion-exclusion over the floes' overlaps of every order
//!   (`polygon_overlaps`), so at most 1 to round-off. Sum over cells of
//!   `c A_cell` = the floes' area minus their overlaps' area.
//! * thickness: the floes' volume in the cell (each floe's own, so an
//!   overlap holds the volume of both: mass is conserved) over the ice
//!   area `c A_cell`. Sum of `c h A_cell` = the floes' volume.
//! * velocity: the floes' momentum in the cell over their mass (volume
//!   weights; one ice density), each floe's rigid-body velocity
//!   `v + w x (x - c)` over its part in the cell (a linear field, so the
//!   mean over a piece is its value at the piece's centroid). Sum of
//!   `c h u A_cell` = sum of `V v`, the floes' momentum over the density.
//! * stress: the floes' Love-Weber stress moments shared out by the
//!   fraction of each floe's area in the cell, over the cell's area
//!   (vertically integrated, N/m); each floe's moment is counted once.
//!   Sum of `sigma A_cell` = the sum of the moments.
//!
//! Strain rates come from the gridded velocity by centred differences
//! (one-sided at the grid's edges): divergence `u_x + v_y`, maximum shear
//! rate `sqrt((u_x - v_y)^2 + (u_y + v_x)^2)` and total deformation
//! `sqrt(div^2 + shear^2)`, all 1/s. Cells without ice have no velocity
//! (NaN), and neither have the strain rates that need them.

use crate::polygon::{bounds, clip, polygon_area, polygon_centroid};
use crate::polygon_overlaps::for_each_overlap;
pub use crate::polygon_overlaps::MAX_OVERLAP_ORDER;
use crate::AnalysisError;

/// A regular grid of `shape[0] x shape[1]` cells along x and y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Lower-left corner of the first cell, m.
    pub origin_m: [f64; 2],
    /// Cell size along x and y, m.
    pub cell_m: [f64; 2],
    /// Cells along x and y.
    pub shape: [usize; 2],
}

impl Grid {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.shape[0] * self.shape[1]
    }

    /// Whether the grid has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index of cell `(i, j)` in the field arrays (x fastest).
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.shape[0] + i
    }

    /// Centre of cell `(i, j)`, m.
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin_m[0] + (i as f64 + 0.5) * self.cell_m[0],
            self.origin_m[1] + (j as f64 + 0.5) * self.cell_m[1],
        ]
    }
}

/// The floes of one snapshot.
#[derive(Debug, Clone, Copy)]
pub struct FloeSnapshot<'a> {
    /// Each floe's vertices in world coordinates (convex, either winding), m.
    pub vertices: &'a [Vec<[f64; 2]>],
    /// Centroids, m.
    pub position: &'a [[f64; 2]],
    /// Centroid velocities, m/s.
    pub velocity: &'a [[f64; 2]],
    /// Angular velocities, rad/s (counter-clockwise positive).
    pub angular_velocity: &'a [f64],
    /// Thicknesses, m.
    pub thickness_m: &'a [f64],
    /// Each floe's Love-Weber stress moment `sum over its contacts of
    /// f (x) (x_c - x)` as `[xx, xy, yx, yy]`, N m; `None` for no stress field.
    pub stress_moment_n_m: Option<&'a [[f64; 4]]>,
}

/// Gridded fields, each an array over cells (x fastest, see [`Grid::index`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GridFields {
    /// Ice area (the union of the floes) over cell area.
    pub concentration: Vec<f64>,
    /// The floes' volume in the cell over its ice area, m (NaN without ice).
    pub thickness_m: Vec<f64>,
    /// The floes' momentum in the cell over their mass, m/s (NaN without ice).
    pub velocity: Vec<[f64; 2]>,
    /// Mean stress `[xx, xy, yx, yy]`, N/m (zero without a stress input).
    pub stress_n_per_m: Vec<[f64; 4]>,
    /// Divergence, 1/s.
    pub divergence_per_s: Vec<f64>,
    /// Maximum shear rate, 1/s.
    pub shear_per_s: Vec<f64>,
    /// Total deformation rate, 1/s.
    pub total_deformation_per_s: Vec<f64>,
    /// Entry `k - 2` counts the sets of `k` floes (`k >= 2`) whose common
    /// overlap reaches the grid: the terms of the concentration's
    /// inclusion-exclusion.
    pub overlap_sets: Vec<usize>,
}

/// Coarse-grains `floes` onto `grid`. Floe parts outside the grid are left
/// out (give periodic images as extra floes to wrap them).
pub fn grid_fields(grid: &Grid, floes: &FloeSnapshot) -> Result<GridFields, AnalysisError> {
    let n = floes.vertices.len();
    for (what, len) in [
        ("polygons and positions", floes.position.len()),
        ("polygons and velocities", floes.velocity.len()),
        (
            "polygons and angular velocities",
            floes.angular_velocity.len(),
        ),
        ("polygons and thicknesses", floes.thickness_m.len()),
        (
            "polygons and stress moments",
            floes.stress_moment_n_m.map_or(n, <[_]>::len),
        ),
    ] {
        if len != n {
            return Err(AnalysisError::LengthMismatch {
                what,
                left: n,
                right: len,
            });
        }
    }
    for (name, v) in [("cell_m[0]", grid.cell_m[0]), ("cell_m[1]", grid.cell_m[1])] {
        if !(v.is_finite() && v > 0.0) {
            return Err(AnalysisError::InvalidParameter {
                name,
                value: v,
                reason: "grid cells need a positive finite size",
            });
        }
    }
    if grid.is_empty() {
        return Err(AnalysisError::NotEnoughData("a grid needs cells"));
    }
    if let Some(&h) = floes
        .thickness_m
        .iter()
        .find(|h| !(h.is_finite() && **h > 0.0))
    {
        return Err(AnalysisError::InvalidParameter {
            name: "thickness_m",
            value: h,
            reason: "floe thicknesses are finite and > 0",
        });
    }
    let cells = grid.len();
    let cell_area = grid.cell_m[0] * grid.cell_m[1];
    // Per cell: the floes' area (each floe's own), the largest floe piece,
    // the union's area, volume, volume x velocity and stress.
    let mut area = vec![0.0; cells];
    let mut largest = vec![0.0_f64; cells];
    let mut union = vec![0.0; cells];
    let mut volume = vec![0.0; cells];
    let mut momentum = vec![[0.0; 2]; cells];
    let mut stress = vec![[0.0; 4]; cells];
    for p in 0..n {
        let poly = &floes.vertices[p];
        let floe_area = polygon_area(poly);
        if floe_area <= 0.0 {
            continue;
        }
        let (v, w, x, h) = (
            floes.velocity[p],
            floes.angular_velocity[p],
            floes.position[p],
            floes.thickness_m[p],
        );
        for_each_piece(grid, poly, |k, piece, a| {
            let c = polygon_centroid(piece, a);
            // Rigid-body velocity at the piece's centroid.
            let u = [v[0] - w * (c[1] - x[1]), v[1] + w * (c[0] - x[0])];
            area[k] += a;
            largest[k] = largest[k].max(a);
            union[k] += a;
            volume[k] += a * h;
            momentum[k][0] += a * h * u[0];
            momentum[k][1] += a * h * u[1];
            if let Some(moments) = floes.stress_moment_n_m {
                let share = a / floe_area / cell_area;
                for (s, m) in stress[k].iter_mut().zip(moments[p]) {
                    *s += share * m;
                }
            }
        });
    }
    // The union: minus the pairs' overlaps, plus the triples', ...
    let (grid_lo, grid_hi) = (
        grid.origin_m,
        [0, 1].map(|a| grid.origin_m[a] + grid.shape[a] as f64 * grid.cell_m[a]),
    );
    let in_grid =
        |lo: [f64; 2], hi: [f64; 2]| (0..2).all(|a| hi[a] >= grid_lo[a] && lo[a] <= grid_hi[a]);
    let mut overlap_sets = Vec::new();
    for_each_overlap(floes.vertices, in_grid, |order, overlap| {
        if overlap_sets.len() < order - 1 {
            overlap_sets.resize(order - 1, 0);
        }
        overlap_sets[order - 2] += 1;
        let sign = if order % 2 == 0 { -1.0 } else { 1.0 };
        for_each_piece(grid, overlap, |k, _, a| union[k] += sign * a);
    })?;
    // Within the union's exact bounds (the largest piece, the sum of the
    // pieces) against round-off.
    let ice: Vec<f64> = (0..cells)
        .map(|k| union[k].clamp(largest[k], area[k]))
        .collect();
    let concentration: Vec<f64> = ice.iter().map(|a| a / cell_area).collect();
    let per = |sum: f64, by: f64| if by > 0.0 { sum / by } else { f64::NAN };
    let thickness_m = (0..cells).map(|k| per(volume[k], ice[k])).collect();
    let velocity: Vec<[f64; 2]> = (0..cells)
        .map(|k| {
            [
                per(momentum[k][0], volume[k]),
                per(momentum[k][1], volume[k]),
            ]
        })
        .collect();
    let (divergence_per_s, shear_per_s, total_deformation_per_s) = strain_rates(grid, &velocity);
    Ok(GridFields {
        concentration,
        thickness_m,
        velocity,
        stress_n_per_m: stress,
        divergence_per_s,
        shear_per_s,
        total_deformation_per_s,
        overlap_sets,
    })
}

/// Calls `f(cell, piece, area)` for each cell of `grid` where the convex
/// `poly` has a part of positive area, with that part (world coordinates).
fn for_each_piece(grid: &Grid, poly: &[[f64; 2]], mut f: impl FnMut(usize, &[[f64; 2]], f64)) {
    let (lo, hi) = bounds(poly);
    let range = |axis: usize| {
        let first = ((lo[axis] - grid.origin_m[axis]) / grid.cell_m[axis]).floor();
        let last = ((hi[axis] - grid.origin_m[axis]) / grid.cell_m[axis]).floor();
        let top = grid.shape[axis] as f64 - 1.0;
        (first.max(0.0), last.min(top))
    };
    let ((i0, i1), (j0, j1)) = (range(0), range(1));
    if i0 > i1 || j0 > j1 {
        return;
    }
    for j in j0 as usize..=j1 as usize {
        for i in i0 as usize..=i1 as usize {
            let x0 = grid.origin_m[0] + i as f64 * grid.cell_m[0];
            let y0 = grid.origin_m[1] + j as f64 * grid.cell_m[1];
            let piece = clip_to_box(poly, [x0, y0], [x0 + grid.cell_m[0], y0 + grid.cell_m[1]]);
            let a = polygon_area(&piece);
            if a > 0.0 {
                f(grid.index(i, j), &piece, a);
            }
        }
    }
}

/// Divergence, shear and total deformation of a gridded velocity field.
fn strain_rates(grid: &Grid, velocity: &[[f64; 2]]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let [nx, ny] = grid.shape;
    // d(component)/d(axis) at (i, j): centred inside, one-sided at the edges.
    let derivative = |i: usize, j: usize, component: usize, axis: usize| -> f64 {
        let (count, h) = ([nx, ny][axis], grid.cell_m[axis]);
        let at = |k: usize| {
            let (ii, jj) = if axis == 0 { (k, j) } else { (i, k) };
            velocity[grid.index(ii, jj)][component]
        };
        let here = if axis == 0 { i } else { j };
        if count < 2 {
            return 0.0;
        }
        let (a, b) = match here {
            0 => (0, 1),
            k if k == count - 1 => (k - 1, k),
            k => (k - 1, k + 1),
        };
        (at(b) - at(a)) / ((b - a) as f64 * h)
    };
    let cells = grid.len();
    let (mut div, mut shear, mut total) = (vec![0.0; cells], vec![0.0; cells], vec![0.0; cells]);
    for j in 0..ny {
        for i in 0..nx {
            let (ux, uy) = (derivative(i, j, 0, 0), derivative(i, j, 0, 1));
            let (vx, vy) = (derivative(i, j, 1, 0), derivative(i, j, 1, 1));
            let k = grid.index(i, j);
            div[k] = ux + vy;
            shear[k] = ((ux - vy).powi(2) + (uy + vx).powi(2)).sqrt();
            total[k] = (div[k].powi(2) + shear[k].powi(2)).sqrt();
        }
    }
    (div, shear, total)
}

/// The part of a convex polygon inside the box `[lo, hi]`.
fn clip_to_box(poly: &[[f64; 2]], lo: [f64; 2], hi: [f64; 2]) -> Vec<[f64; 2]> {
    let mut out = poly.to_vec();
    for (axis, bound, sign) in [
        (0, lo[0], 1.0),
        (0, hi[0], -1.0),
        (1, lo[1], 1.0),
        (1, hi[1], -1.0),
    ] {
        out = clip(&out, |p| sign * (p[axis] - bound));
        if out.is_empty() {
            break;
        }
    }
    out
}
