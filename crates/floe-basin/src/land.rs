//! Land as the engine sees it: the polygons of the coastline files cut
//! into convex pieces no larger than a floe ([`crate::convex_pieces`]), at
//! most [`MAX_LAND_PIECES`] of them, and queries against them (overlap
//! area with a floe through a grid of the pieces' bounding boxes; whether
//! a point is on land).

use std::collections::HashMap;

use floe_dem::Vec2;

use crate::coastline::LandPolygon;
use crate::convex_pieces::{convex_pieces, split_to_size};
use crate::planar::{bounds, contains, convex_intersection_area, signed_area};

/// Most land pieces: beyond it pieces grow (as a wall's segments do) so
/// that their number stays bounded whatever the ratio of land to floes.
pub const MAX_LAND_PIECES: usize = 1_000_000;

/// One convex piece of land.
#[derive(Debug, Clone, PartialEq)]
pub struct LandPiece {
    /// Index of the polygon (in [`Land::polygons`]) it belongs to.
    pub polygon: usize,
    /// Vertices, counter-clockwise, m.
    pub vertices: Vec<Vec2>,
}

/// Land polygons and their convex pieces.
#[derive(Debug, Clone)]
pub struct Land {
    /// The polygons, as read.
    pub polygons: Vec<LandPolygon>,
    /// Convex pieces tiling them exactly, each within the radius asked.
    pub pieces: Vec<LandPiece>,
    /// Number of convex pieces before the cut to size.
    pub convex_count: usize,
    /// Bounding radius the pieces were cut to, m.
    pub piece_radius_m: f64,
    polygon_bounds: Vec<(Vec2, Vec2)>,
    cell_m: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl Land {
    /// Cuts `polygons` into convex pieces of bounding radius (about their
    /// centroid) at most `max_radius_m`, or larger if that would make more
    /// than [`MAX_LAND_PIECES`].
    ///
    /// # Errors
    /// The reason, naming the polygon's feature, if a polygon cannot be
    /// decomposed (not simple), or `max_radius_m` is not positive.
    pub fn new(polygons: Vec<LandPolygon>, max_radius_m: f64) -> Result<Land, String> {
        Land::with_piece_limit(polygons, max_radius_m, MAX_LAND_PIECES)
    }

    /// As [`Land::new`], with at most `max_pieces` pieces instead of
    /// [`MAX_LAND_PIECES`] (unless the convex pieces alone are more): the
    /// radius grows until the pieces are few enough. Thin convex pieces
    /// (a long shore's triangles reaching far inland) are cut into about
    /// their length over the radius, not their area over its square, so
    /// the count is checked, not foretold.
    ///
    /// # Errors
    /// As [`Land::new`].
    pub fn with_piece_limit(
        polygons: Vec<LandPolygon>,
        max_radius_m: f64,
        max_pieces: usize,
    ) -> Result<Land, String> {
        if !(max_radius_m > 0.0 && max_radius_m.is_finite()) {
            return Err(format!("piece radius {max_radius_m} m must be positive"));
        }
        let mut convex = Vec::new();
        for (k, p) in polygons.iter().enumerate() {
            let pieces = convex_pieces(&p.ring).map_err(|why| {
                format!(
                    "feature {}: polygon cannot be cut into convex pieces: {why}",
                    p.feature
                )
            })?;
            convex.extend(pieces.into_iter().map(|v| (k, v)));
        }
        let convex_count = convex.len();
        let area: f64 = polygons.iter().map(|p| signed_area(&p.ring)).sum();
        let max_pieces = max_pieces.max(1);
        // About area / r^2 pieces of radius r.
        let mut radius = max_radius_m.max((area / max_pieces as f64).sqrt());
        let pieces = loop {
            let pieces: Vec<LandPiece> = convex
                .iter()
                .flat_map(|(k, v)| {
                    split_to_size(vec![v.clone()], radius)
                        .into_iter()
                        .map(|vertices| LandPiece {
                            polygon: *k,
                            vertices,
                        })
                })
                .collect();
            if pieces.len() <= max_pieces || pieces.len() == convex_count {
                break pieces;
            }
            radius *= (pieces.len() as f64 / max_pieces as f64).sqrt().max(1.1);
        };
        let cell_m = 2.0 * radius;
        let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (i, p) in pieces.iter().enumerate() {
            let (lo, hi) = bounds(&p.vertices);
            for key in cell_range(lo, hi, cell_m) {
                cells.entry(key).or_default().push(i);
            }
        }
        let polygon_bounds = polygons.iter().map(|p| bounds(&p.ring)).collect();
        Ok(Land {
            polygons,
            pieces,
            convex_count,
            piece_radius_m: radius,
            polygon_bounds,
            cell_m,
            cells,
        })
    }

    /// Total land area, m^2.
    pub fn area_m2(&self) -> f64 {
        self.polygons.iter().map(|p| signed_area(&p.ring)).sum()
    }

    /// Total number of vertices of the polygons.
    pub fn vertex_count(&self) -> usize {
        self.polygons.iter().map(|p| p.ring.len()).sum()
    }

    /// Area of the convex polygon `floe` (either orientation) that lies on
    /// land, m^2.
    pub fn overlap_area_m2(&self, floe: &[Vec2]) -> f64 {
        let (lo, hi) = bounds(floe);
        let mut seen: Vec<usize> = cell_range(lo, hi, self.cell_m)
            .filter_map(|key| self.cells.get(&key))
            .flatten()
            .copied()
            .collect();
        seen.sort_unstable();
        seen.dedup();
        seen.into_iter()
            .filter(|&i| {
                let (plo, phi) = bounds(&self.pieces[i].vertices);
                plo.x <= hi.x && plo.y <= hi.y && phi.x >= lo.x && phi.y >= lo.y
            })
            .map(|i| convex_intersection_area(&self.pieces[i].vertices, floe))
            .sum()
    }

    /// Whether the point `q` lies on land.
    pub fn contains(&self, q: Vec2) -> bool {
        self.polygons
            .iter()
            .zip(&self.polygon_bounds)
            .any(|(p, (lo, hi))| {
                q.x >= lo.x && q.y >= lo.y && q.x <= hi.x && q.y <= hi.y && contains(&p.ring, q)
            })
    }
}

/// The grid cells of width `cell` that the box `lo..hi` touches.
fn cell_range(lo: Vec2, hi: Vec2, cell: f64) -> impl Iterator<Item = (i64, i64)> {
    let c = |x: f64| (x / cell).floor() as i64;
    let (x0, x1, y0, y1) = (c(lo.x), c(hi.x), c(lo.y), c(hi.y));
    (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| (x, y)))
}
