//! Irregular convex floes: Voronoi cells of random sites, clipped to the domain.

use super::{
    clip_convex, polygon_area, polygon_centroid, stream_rng, streams, unit, Rect, Tessellation,
    ThicknessDistribution, MAX_FLOES,
};
use crate::error::DemError;
use crate::Vec2;
use spade::{DelaunayTriangulation, Point2, Triangulation};

/// Irregular floes: the Voronoi cells of `count` random sites, restricted to
/// the domain.
///
/// Sites are uniform in the domain (ChaCha8 stream of `seed`). Spade's
/// Delaunay triangulation gives each site its neighbours; the cell of a site
/// is the domain rectangle clipped by the bisector half-plane of the site and
/// each Delaunay neighbour (Sutherland-Hodgman, one line at a time, in a
/// frame centred on the site). Such cells are convex, bounded by the domain,
/// contain their site and tile the domain. With `relax_iterations > 0`, the
/// sites are moved to their cells' centroids that many times (Lloyd), which
/// makes the floes more uniform in size and rounder; each iteration costs a
/// full rebuild.
///
/// Output order is site order; thickness is one draw per floe in that order.
#[derive(Debug, Clone, PartialEq)]
pub struct VoronoiFloes {
    /// Domain to fill (m).
    pub domain: Rect,
    /// Number of floes, 1..=[`MAX_FLOES`].
    pub count: usize,
    /// Seed of the site and thickness streams.
    pub seed: u64,
    /// Floe thickness distribution.
    pub thickness: ThicknessDistribution,
    /// Lloyd relaxation iterations (0 = plain random Voronoi).
    pub relax_iterations: usize,
}

impl VoronoiFloes {
    /// Floes of mean area `mean_area_m2` (m^2): `count = round(domain area /
    /// mean area)`, at least 1.
    pub fn from_mean_area(
        domain: Rect,
        mean_area_m2: f64,
        seed: u64,
        thickness: ThicknessDistribution,
        relax_iterations: usize,
    ) -> Result<Self, DemError> {
        domain.validate()?;
        if !(mean_area_m2.is_finite() && mean_area_m2 > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "mean_area_m2",
                value: mean_area_m2,
                reason: "must be finite and > 0",
            });
        }
        let n = (domain.area_m2() / mean_area_m2).round().max(1.0);
        if n > MAX_FLOES as f64 {
            return Err(DemError::TooManyFloes {
                requested: n as u64,
                limit: MAX_FLOES as u64,
            });
        }
        let v = Self {
            domain,
            count: n as usize,
            seed,
            thickness,
            relax_iterations,
        };
        v.validate()?;
        Ok(v)
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), DemError> {
        self.domain.validate()?;
        if self.count == 0 {
            return Err(DemError::InvalidParameter {
                name: "count",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        if self.count > MAX_FLOES {
            return Err(DemError::TooManyFloes {
                requested: self.count as u64,
                limit: MAX_FLOES as u64,
            });
        }
        self.thickness.validate()
    }

    /// Builds the tessellation (see the type docs).
    pub fn build(&self) -> Result<Tessellation, DemError> {
        self.build_with_sites().map(|(t, _)| t)
    }

    /// [`Self::build`], plus the final sites (world coordinates, m): floe
    /// `k` is the Voronoi cell of site `k`.
    pub fn build_with_sites(&self) -> Result<(Tessellation, Vec<Vec2>), DemError> {
        self.validate()?;
        let dom = self.domain;
        let size = Vec2::new(dom.width_m(), dom.height_m());
        let mut rng = stream_rng(self.seed, streams::SITES);
        // Sites in the frame local to domain.min.
        let mut sites: Vec<Vec2> = (0..self.count)
            .map(|_| Vec2::new(unit(&mut rng) * size.x, unit(&mut rng) * size.y))
            .collect();
        // Identical sites would leave a cell undefined: redraw them
        // (never happens in practice, but must not break determinism).
        loop {
            let dups = duplicate_indices(&sites);
            if dups.is_empty() {
                break;
            }
            for k in dups {
                sites[k] = Vec2::new(unit(&mut rng) * size.x, unit(&mut rng) * size.y);
            }
        }

        let mut cells = voronoi_cells(&sites, size)?;
        for _ in 0..self.relax_iterations {
            for (site, cell) in sites.iter_mut().zip(&cells) {
                // Centroid in the site frame, then back; it is inside the
                // (convex) cell, hence inside the domain.
                *site += polygon_centroid(cell);
            }
            if !duplicate_indices(&sites).is_empty() {
                return Err(DemError::InvalidTessellation {
                    reason: "Lloyd relaxation produced coincident sites".into(),
                });
            }
            cells = voronoi_cells(&sites, size)?;
        }

        let polygons: Vec<Vec<Vec2>> = cells
            .iter()
            .zip(&sites)
            .map(|(cell, &s)| {
                // Clamping only removes rounding of the boundary vertices.
                cell.iter()
                    .map(|&v| (dom.min + (s + v)).clamp(dom.min, dom.max))
                    .collect()
            })
            .collect();
        let world_sites = sites.iter().map(|&s| dom.min + s).collect();
        let thickness_m = self.thickness.sample(
            polygons.len(),
            super::derive_seed(self.seed, streams::THICKNESS),
        )?;
        Ok((
            Tessellation {
                polygons,
                thickness_m,
            },
            world_sites,
        ))
    }
}

/// Indices of sites equal to an earlier site (all but the first of each group).
fn duplicate_indices(sites: &[Vec2]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..sites.len()).collect();
    let key = |k: usize| (sites[k].x.to_bits(), sites[k].y.to_bits());
    order.sort_unstable_by_key(|&k| (key(k), k));
    order
        .windows(2)
        .filter(|w| key(w[0]) == key(w[1]))
        .map(|w| w[1])
        .collect()
}

/// Voronoi cells of `sites` (domain-local frame, all distinct, inside
/// `[0, size]`) restricted to the domain; cell `k` in the frame centred on
/// site `k`.
fn voronoi_cells(sites: &[Vec2], size: Vec2) -> Result<Vec<Vec<Vec2>>, DemError> {
    let points: Vec<Point2<f64>> = sites.iter().map(|s| Point2::new(s.x, s.y)).collect();
    let tri = DelaunayTriangulation::<Point2<f64>>::bulk_load_stable(points).map_err(|e| {
        DemError::InvalidTessellation {
            reason: format!("Delaunay triangulation failed: {e:?}"),
        }
    })?;
    if tri.num_vertices() != sites.len() {
        return Err(DemError::InvalidTessellation {
            reason: "Delaunay triangulation merged coincident sites".into(),
        });
    }
    let mut cells = Vec::with_capacity(sites.len());
    let (mut a, mut b) = (Vec::with_capacity(16), Vec::with_capacity(16));
    for (k, v) in tri.vertices().enumerate() {
        debug_assert_eq!(v.fix().index(), k);
        let p = sites[k];
        a.clear();
        a.extend_from_slice(&[
            Vec2::new(-p.x, -p.y),
            Vec2::new(size.x - p.x, -p.y),
            Vec2::new(size.x - p.x, size.y - p.y),
            Vec2::new(-p.x, size.y - p.y),
        ]);
        for e in v.out_edges() {
            let n = sites[e.to().fix().index()] - p;
            let c = 0.5 * n.length_squared();
            // Keep n.x <= |n|^2 / 2: the side of the bisector nearer the site.
            clip_convex(
                &a,
                &mut b,
                |x| c - n.dot(x),
                |p_in, d_in, p_out, d_out| p_in + (p_out - p_in) * (d_in / (d_in - d_out)),
            );
            std::mem::swap(&mut a, &mut b);
        }
        if a.len() < 3 || polygon_area(&a).is_nan() || polygon_area(&a) <= 0.0 {
            return Err(DemError::InvalidTessellation {
                reason: format!("Voronoi cell {k} is degenerate ({} vertices)", a.len()),
            });
        }
        cells.push(a.clone());
    }
    Ok(cells)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_and_two_and_collinear_sites() {
        let size = Vec2::new(2.0, 1.0);
        let c = voronoi_cells(&[Vec2::new(0.5, 0.5)], size).unwrap();
        assert_eq!(polygon_area(&c[0]), 2.0);
        let c = voronoi_cells(&[Vec2::new(0.5, 0.5), Vec2::new(1.5, 0.5)], size).unwrap();
        assert!((polygon_area(&c[0]) - 1.0).abs() < 1e-15);
        assert!((polygon_area(&c[1]) - 1.0).abs() < 1e-15);
        let line: Vec<Vec2> = (0..4)
            .map(|k| Vec2::new(0.25 + 0.5 * k as f64, 0.5))
            .collect();
        let c = voronoi_cells(&line, size).unwrap();
        for cell in &c {
            assert!((polygon_area(cell) - 0.5).abs() < 1e-15);
        }
    }

    #[test]
    fn duplicates_found() {
        let s = [Vec2::ONE, Vec2::ZERO, Vec2::ONE, Vec2::ONE];
        assert_eq!(duplicate_indices(&s), vec![2, 3]);
    }
}
