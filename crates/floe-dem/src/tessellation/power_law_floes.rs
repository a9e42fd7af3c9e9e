//! Floes whose sizes follow a power law: a Laguerre (power-diagram)
//! tessellation whose cell areas are drawn from [`PowerLawSizes`].
//!
//! 1. Sizes `d_k` are drawn from the truncated law by its inverse
//!    distribution function until their squares cover the region; each
//!    floe's target area is `d_k²`, scaled by the one factor (at most
//!    `max²/area` from 1) that makes the targets add up to the region.
//! 2. The floes are placed largest first as disks of area
//!    [`PACKING_FRACTION`] × target at random positions inside the region,
//!    each at the first of [`PLACEMENT_ATTEMPTS`] positions where it
//!    overlaps no disk placed before (random sequential addition), or at
//!    the attempt it overlaps least. Disks of every size thus spread over
//!    the region with room around them in proportion to their size.
//! 3. The power diagram of the disks (weights `r²`) gives convex cells
//!    that contain their disks' centres; the weights are then corrected by
//!    damped Newton steps until every cell's area is its target to
//!    [`AREA_TOLERANCE`], in at most [`MAX_WEIGHT_PASSES`] power diagrams
//!    (Kitagawa, Mérigot & Thibert 2019; `area_fit.rs`).
//!
//! A plain Voronoi diagram of the same disks would not do: its edges lie
//! halfway between centres, cutting a large floe's cell down where small
//! floes crowd it. Everything is seeded (the size and placement streams of
//! `seed`) and each cell is computed on its own in its site's frame, so the
//! floes are bitwise the same for a seed on any machine and thread count.

use std::ops::Not;

use super::area_fit::fit_areas;
use super::disk_grid::DiskGrid;
use super::power_law::{fit_power_law, PowerLawFit, PowerLawSizes};
use super::{
    derive_seed, polygon_area, polygon_centroid, stream_rng, streams, unit, Rect, Tessellation,
    ThicknessDistribution, MAX_FLOES,
};
use crate::error::DemError;
use crate::geometry::MAX_VERTICES;
use crate::Vec2;

/// The disks' share of the region when they are placed (below the 0.547
/// at which random sequential addition of equal disks jams, so that a
/// free place is found in a few attempts at every size).
pub const PACKING_FRACTION: f64 = 0.4;

/// Random positions tried per disk before the least overlapping is taken.
pub const PLACEMENT_ATTEMPTS: usize = 64;

/// Largest relative difference between a cell's area and its target at
/// which the weight passes stop.
pub const AREA_TOLERANCE: f64 = 1e-3;

/// Most power diagrams computed while fitting the weights.
pub const MAX_WEIGHT_PASSES: usize = 100;

/// Most floes a power-law tessellation may make: 10,000 take about 3 s,
/// 50,000 about 40 s (two cores shared with other work; a Newton fit from
/// the random packing, one Lloyd iteration and a second fit).
pub const MAX_POWER_LAW_FLOES: usize = 200_000;

/// Floes of a power-law size distribution filling a rectangle.
#[derive(Debug, Clone, PartialEq)]
pub struct PowerLawFloes {
    /// The region to fill, m.
    pub domain: Rect,
    /// The sizes (`sqrt(area)`).
    pub sizes: PowerLawSizes,
    /// Seed of the size, placement and thickness streams.
    pub seed: u64,
    /// Floe thickness distribution.
    pub thickness: ThicknessDistribution,
    /// Lloyd iterations: sites moved to their cells' centroids and the
    /// weights fitted again (rounder floes of the same areas).
    pub relax_iterations: usize,
}

/// What [`PowerLawFloes::build`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct PowerLawReport {
    /// Sizes drawn (floes made, empty cells included).
    pub drawn: usize,
    /// The factor applied to every drawn size so that the areas fill the
    /// region exactly.
    pub size_scale: f64,
    /// Disks placed overlapping another (no free place in
    /// [`PLACEMENT_ATTEMPTS`] attempts).
    pub forced_placements: usize,
    /// Power diagrams computed while fitting the weights.
    pub passes: usize,
    /// Largest `|area − target| / target` at the end.
    pub max_area_error: f64,
    /// Root mean square of the same.
    pub rms_area_error: f64,
    /// Cells left empty (dropped; only if the passes did not converge).
    pub empty_cells: usize,
    /// Cells of more than [`MAX_VERTICES`] vertices (a large floe among
    /// many small ones) cut down to that many.
    pub simplified: usize,
    /// The area those cuts removed (open water), m².
    pub simplified_area_m2: f64,
    /// The maximum-likelihood exponent of the floes made (`sqrt(area)`),
    /// between the law's bounds widened to the smallest and largest floe.
    pub fit: Option<PowerLawFit>,
}

impl PowerLawFloes {
    /// Checks the region, the law, that the largest floe fits in the region
    /// (`max_m` at most its shorter side) and that the expected number of
    /// floes is at most [`MAX_POWER_LAW_FLOES`].
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] or [`DemError::TooManyFloes`].
    pub fn validate(&self) -> Result<(), DemError> {
        self.domain.validate()?;
        self.sizes.validate()?;
        self.thickness.validate()?;
        let side = self.domain.width_m().min(self.domain.height_m());
        if self.sizes.max_m > side {
            return Err(DemError::InvalidParameter {
                name: "max_m",
                value: self.sizes.max_m,
                reason: "must be at most the shorter side of the region",
            });
        }
        let n = self.sizes.expected_count(self.domain.area_m2());
        if (n <= MAX_POWER_LAW_FLOES as f64).not() {
            return Err(DemError::TooManyFloes {
                requested: n.min(u64::MAX as f64) as u64,
                limit: MAX_POWER_LAW_FLOES as u64,
            });
        }
        Ok(())
    }

    /// Builds the floes (see the module docs), largest first.
    ///
    /// # Errors
    /// As [`PowerLawFloes::validate`].
    pub fn build(&self) -> Result<(Tessellation, PowerLawReport), DemError> {
        self.validate()?;
        let dom = self.domain;
        let size = Vec2::new(dom.width_m(), dom.height_m());
        let area = dom.area_m2();

        // 1. Sizes until they cover the region, largest first.
        let mut rng = stream_rng(self.seed, streams::SIZES);
        let mut drawn: Vec<f64> = Vec::new();
        let mut covered = 0.0;
        while covered < area {
            if drawn.len() >= 2 * MAX_POWER_LAW_FLOES.min(MAX_FLOES) {
                return Err(DemError::TooManyFloes {
                    requested: drawn.len() as u64,
                    limit: MAX_POWER_LAW_FLOES as u64,
                });
            }
            let d = self.sizes.quantile(unit(&mut rng));
            covered += d * d;
            drawn.push(d);
        }
        drawn.sort_unstable_by(|a, b| b.total_cmp(a));
        let scale2 = area / covered;
        let targets: Vec<f64> = drawn.iter().map(|d| d * d * scale2).collect();
        let n = targets.len();

        // 2. Disks, largest first, by random sequential addition.
        let radius: Vec<f64> = targets
            .iter()
            .map(|t| (PACKING_FRACTION * t / std::f64::consts::PI).sqrt())
            .collect();
        let mut grid = DiskGrid::new(size, radius[n - 1], radius[0], n);
        let mut rng = stream_rng(self.seed, streams::PLACEMENT);
        let mut forced = 0;
        for &r in &radius {
            let (p, free) = place(&grid, &radius, size, r, &mut rng);
            forced += usize::from(!free);
            grid.insert(p, r);
        }
        let sites: Vec<Vec2> = (0..n).map(|k| grid.centre(k)).collect();

        // 3. Weights until the areas are the targets.
        let mut weights: Vec<f64> = radius.iter().map(|r| r * r).collect();
        let mut areas = fit_areas(
            &sites,
            &targets,
            &mut weights,
            size,
            (AREA_TOLERANCE, MAX_WEIGHT_PASSES),
        );
        let mut sites = sites;
        let mut passes = areas.passes;
        for _ in 0..self.relax_iterations {
            // Lloyd: each site to its cell's centroid, then the weights
            // fitted again (from the last ones; from equal weights if a
            // cell came out empty).
            for (s, c) in sites.iter_mut().zip(&areas.cells) {
                if c.polygon.len() >= 3 {
                    *s = (*s + polygon_centroid(&c.polygon)).clamp(Vec2::ZERO, size);
                }
            }
            let mut attempt = weights.clone();
            areas = fit_areas(
                &sites,
                &targets,
                &mut attempt,
                size,
                (AREA_TOLERANCE, MAX_WEIGHT_PASSES),
            );
            passes += areas.passes;
            if areas.empty() {
                attempt.fill(0.0);
                areas = fit_areas(
                    &sites,
                    &targets,
                    &mut attempt,
                    size,
                    (AREA_TOLERANCE, MAX_WEIGHT_PASSES),
                );
                passes += areas.passes;
            }
            weights = attempt;
        }
        let cells = areas.cells;

        let mut polygons = Vec::with_capacity(n);
        let mut empty = 0;
        let (mut simplified, mut simplified_area) = (0, 0.0);
        for (c, &s) in cells.iter().zip(&sites) {
            if c.polygon.len() < 3 || polygon_area(&c.polygon) <= 0.0 {
                empty += 1;
                continue;
            }
            let mut local = c.polygon.clone();
            if local.len() > MAX_VERTICES {
                simplified += 1;
                simplified_area += simplify(&mut local, MAX_VERTICES);
            }
            // Clamping only removes rounding of the boundary vertices.
            polygons.push(
                local
                    .iter()
                    .map(|&v| (dom.min + (s + v)).clamp(dom.min, dom.max))
                    .collect::<Vec<Vec2>>(),
            );
        }
        let thickness_m = self
            .thickness
            .sample(polygons.len(), derive_seed(self.seed, streams::THICKNESS))?;
        let t = Tessellation {
            polygons,
            thickness_m,
        };
        let fit = fit_sizes(&t, self.sizes);
        Ok((
            t,
            PowerLawReport {
                drawn: n,
                size_scale: scale2.sqrt(),
                forced_placements: forced,
                passes,
                max_area_error: areas.max_error,
                rms_area_error: areas.rms_error,
                empty_cells: empty,
                simplified,
                simplified_area_m2: simplified_area,
                fit,
            },
        ))
    }
}

/// Removes vertices of the convex polygon `poly`, each time the one whose
/// triangle with its neighbours is smallest, until it has `max`; returns
/// the area removed. The polygon stays convex and inside the original.
fn simplify(poly: &mut Vec<Vec2>, max: usize) -> f64 {
    let mut removed = 0.0;
    while poly.len() > max {
        let n = poly.len();
        let triangle = |k: usize| {
            let (a, b, c) = (poly[(k + n - 1) % n], poly[k], poly[(k + 1) % n]);
            0.5 * (b - a).perp_dot(c - a)
        };
        let (k, area) = (0..n)
            .map(|k| (k, triangle(k)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .expect("more than max >= 3 vertices");
        removed += area.max(0.0);
        poly.remove(k);
    }
    removed
}

/// The fitted exponent of a tessellation's floe sizes `sqrt(area)` under
/// `law`'s bounds, widened to the smallest and largest floe.
pub fn fit_sizes(t: &Tessellation, law: PowerLawSizes) -> Option<PowerLawFit> {
    let sizes: Vec<f64> = (0..t.len()).map(|k| t.area_m2(k).sqrt()).collect();
    let smallest = sizes.iter().copied().fold(f64::INFINITY, f64::min);
    let largest = sizes.iter().copied().fold(0.0, f64::max);
    fit_power_law(&sizes, law.min_m.min(smallest), law.max_m.max(largest))
}

/// A place for a disk of radius `r` inside `[0, size]`: the first of
/// [`PLACEMENT_ATTEMPTS`] random positions free of the disks in `grid`, or
/// (`false`) the one overlapping least among those whose centre lies
/// outside every disk placed (all larger than this one, so the power cell
/// of every centre is then not empty), or the least overlapping at all.
fn place(
    grid: &DiskGrid,
    radius: &[f64],
    size: Vec2,
    r: f64,
    rng: &mut rand_chacha::ChaCha8Rng,
) -> (Vec2, bool) {
    let span = |len: f64| {
        if len > 2.0 * r {
            (r, len - 2.0 * r)
        } else {
            (0.5 * len, 0.0)
        }
    };
    let ((x0, wx), (y0, wy)) = (span(size.x), span(size.y));
    // (centre inside a disk, deepest overlap relative to r, position)
    let mut best = (true, f64::INFINITY, Vec2::ZERO);
    for _ in 0..PLACEMENT_ATTEMPTS {
        let p = Vec2::new(x0 + unit(rng) * wx, y0 + unit(rng) * wy);
        let mut depth = 0.0f64;
        let mut inside = false;
        grid.visit_near(
            p,
            |largest| r + largest,
            |j| {
                let d = (grid.centre(j) - p).length();
                depth = depth.max((r + radius[j] - d) / r);
                inside |= d < radius[j];
            },
        );
        if depth <= 0.0 {
            return (p, true);
        }
        if (inside, depth) < (best.0, best.1) {
            best = (inside, depth, p);
        }
    }
    (best.2, false)
}
