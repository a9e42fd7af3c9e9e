//! The regular grid of the model plane a [`GriddedField`](super::GriddedField)
//! is given on, and bilinear interpolation in its cells.

use crate::{DemError, Vec2};

/// A regular grid of the model plane: node `(i, j)` at
/// `origin + (i dx, j dy)`, `i < nx`, `j < ny`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneGrid {
    /// Node `(0, 0)`, m.
    pub origin_m: Vec2,
    /// `(dx, dy)`, m, both `> 0`.
    pub spacing_m: Vec2,
    /// Nodes along x, `≥ 2`.
    pub nx: usize,
    /// Nodes along y, `≥ 2`.
    pub ny: usize,
}

/// A point's cell: the index of its lower-left node and the fractions
/// `(fx, fy)` in `[0, 1]` across the cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellPosition {
    /// `j nx + i` of the lower-left node.
    pub node: usize,
    /// Fraction across the cell along x.
    pub fx: f64,
    /// Fraction across the cell along y.
    pub fy: f64,
}

impl CellPosition {
    /// The bilinear interpolant of the corner values `[v00, v10, v01, v11]`
    /// at this position.
    #[inline(always)]
    pub fn interpolate(&self, [v00, v10, v01, v11]: &[f64; 4]) -> f64 {
        let (fx, fy) = (self.fx, self.fy);
        (1.0 - fy) * ((1.0 - fx) * v00 + fx * v10) + fy * ((1.0 - fx) * v01 + fx * v11)
    }

    /// The corners' weights in [`CellPosition::interpolate`], in the same
    /// order.
    pub fn weights(&self) -> [f64; 4] {
        let (fx, fy) = (self.fx, self.fy);
        [
            (1.0 - fx) * (1.0 - fy),
            fx * (1.0 - fy),
            (1.0 - fx) * fy,
            fx * fy,
        ]
    }

    /// The interpolant's gradient `(∂/∂x, ∂/∂y)` on a grid of spacing
    /// `1 / inverse_spacing`.
    #[inline(always)]
    pub fn gradient(&self, [v00, v10, v01, v11]: &[f64; 4], inverse_spacing: Vec2) -> Vec2 {
        let (fx, fy) = (self.fx, self.fy);
        Vec2::new(
            ((1.0 - fy) * (v10 - v00) + fy * (v11 - v01)) * inverse_spacing.x,
            ((1.0 - fx) * (v01 - v00) + fx * (v11 - v10)) * inverse_spacing.y,
        )
    }
}

impl PlaneGrid {
    /// Checks the sizes and spacings.
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] for fewer than two nodes on an axis,
    /// or a spacing or origin that is not finite and positive.
    pub fn validate(&self) -> Result<(), DemError> {
        let bad = crate::error::invalid_parameter;
        if self.nx < 2 || self.ny < 2 {
            return bad(
                "grid nodes",
                self.nx.min(self.ny) as f64,
                "needs at least two nodes along each axis",
            );
        }
        for s in [self.spacing_m.x, self.spacing_m.y] {
            if !(s.is_finite() && s > 0.0) {
                return bad("grid spacing_m", s, "must be finite and > 0");
            }
        }
        if !(self.origin_m.x.is_finite() && self.origin_m.y.is_finite()) {
            return bad("grid origin_m", self.origin_m.x, "must be finite");
        }
        Ok(())
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.nx * self.ny
    }

    /// The far corner, node `(nx − 1, ny − 1)`, m.
    pub fn end_m(&self) -> Vec2 {
        self.origin_m
            + Vec2::new(
                (self.nx - 1) as f64 * self.spacing_m.x,
                (self.ny - 1) as f64 * self.spacing_m.y,
            )
    }

    /// The position of node `k` (`j nx + i`), m.
    pub fn node_position(&self, k: usize) -> Vec2 {
        let (i, j) = (k % self.nx, k / self.nx);
        self.origin_m + Vec2::new(i as f64 * self.spacing_m.x, j as f64 * self.spacing_m.y)
    }

    /// The cell of `p`, or `None` outside the grid (or not finite).
    #[inline]
    pub fn cell(&self, p: Vec2) -> Option<CellPosition> {
        let gx = (p.x - self.origin_m.x) / self.spacing_m.x;
        let gy = (p.y - self.origin_m.y) / self.spacing_m.y;
        let (mx, my) = ((self.nx - 1) as f64, (self.ny - 1) as f64);
        if !(gx >= 0.0 && gx <= mx && gy >= 0.0 && gy <= my) {
            return None;
        }
        let i = (gx as usize).min(self.nx - 2);
        let j = (gy as usize).min(self.ny - 2);
        Some(CellPosition {
            node: j * self.nx + i,
            fx: gx - i as f64,
            fy: gy - j as f64,
        })
    }
}
