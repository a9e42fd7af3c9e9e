//! Initial floe fields: sets of convex polygons that tile a rectangular
//! domain exactly, each with a thickness.
//!
//! Three generators:
//! - [`DiamondLattice`]: a rhombus (diamond) lattice, optionally with its
//!   nodes jittered, clipped to the domain (the geometry of ice-tank and
//!   laboratory "diamond floe" tests);
//! - [`VoronoiFloes`]: irregular convex floes, the Voronoi cells of random
//!   sites (optionally Lloyd-relaxed), clipped to the domain;
//! - [`PowerLawFloes`]: irregular convex floes whose sizes follow a
//!   power-law floe-size distribution ([`PowerLawSizes`]), the cells of a
//!   Laguerre (power) diagram fitted to drawn areas.
//!
//! [`select_by_concentration`] thins any of them to an ice concentration
//! field.
//!
//! All return a [`Tessellation`]: polygons in world coordinates (m),
//! counter-clockwise, without a repeated closing vertex, whose areas add up to
//! the domain's area. Geometry is computed in frames local to the domain,
//! the cell or the site so that domains placed at coordinates of order
//! 1e6 m keep their accuracy; only the final vertices are world coordinates.
//!
//! Randomness (node jitter, Voronoi sites, thickness) comes from
//! `rand_chacha::ChaCha8Rng` streams derived from the one `seed` of a
//! generator: the same parameters and seed give bitwise identical output on
//! every platform.

mod area_fit;
mod concentration;
mod diamond;
mod disk_grid;
mod laguerre;
mod lattice_periods;
mod power_law;
mod power_law_floes;
mod voronoi;

pub use concentration::{select_by_concentration, ConcentrationSelection};
pub use power_law::{fit_power_law, PowerLawFit, PowerLawSizes, MAX_POWER_LAW_EXPONENT};
pub use power_law_floes::{
    fit_sizes, PowerLawFloes, PowerLawReport, AREA_TOLERANCE, MAX_POWER_LAW_FLOES,
    MAX_WEIGHT_PASSES, PACKING_FRACTION, PLACEMENT_ATTEMPTS,
};

pub use diamond::{
    max_jitter_fraction, DiamondLattice, LatticeReport, SLIVER_AREA_FRACTION,
    SLIVER_BUDGET_FRACTION,
};
pub use lattice_periods::{fit_periods, PeriodFit, MAX_PERIOD_STRETCH};
pub use voronoi::VoronoiFloes;

use crate::error::DemError;
use crate::Vec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::Distribution;

/// Largest number of floes (for the lattice: of candidate cells overlapping
/// the domain) a generator accepts. Requests above it fail with
/// [`DemError::TooManyFloes`] before any large allocation; 1e7 floes take
/// about 1-2 GB as `Vec<Vec<Vec2>>`.
pub const MAX_FLOES: usize = 10_000_000;

/// A set of floes filling a domain: convex polygons in world coordinates
/// (m), counter-clockwise, no repeated closing vertex.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tessellation {
    /// Floe outlines, world coordinates (m), counter-clockwise, convex, no
    /// repeated closing vertex.
    pub polygons: Vec<Vec<Vec2>>,
    /// Floe thickness (m), one per polygon.
    pub thickness_m: Vec<f64>,
}

/// What [`Tessellation::drop_floes_smaller_than`] removed.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SmallFloeReport {
    /// Floes removed.
    pub dropped: usize,
    /// Their total area, m^2.
    pub dropped_area_m2: f64,
}

impl Tessellation {
    /// Number of floes.
    pub fn len(&self) -> usize {
        self.polygons.len()
    }

    /// `true` if there are no floes.
    pub fn is_empty(&self) -> bool {
        self.polygons.is_empty()
    }

    /// Plan-view area of floe `index` (m^2), computed relative to its first
    /// vertex (accurate far from the origin). Panics if `index` is out of
    /// range.
    pub fn area_m2(&self, index: usize) -> f64 {
        polygon_area(&self.polygons[index])
    }

    /// Sum of the floe areas (m^2), compensated summation.
    pub fn total_area_m2(&self) -> f64 {
        let mut sum = NeumaierSum::default();
        for p in &self.polygons {
            sum.add(polygon_area(p));
        }
        sum.value()
    }

    /// Smallest floe area (m^2); `None` if empty. Boundary clipping can make
    /// some floes much smaller than the nominal cell: this is the number that
    /// sets the smallest floe mass of a DEM run.
    pub fn min_area_m2(&self) -> Option<f64> {
        self.polygons
            .iter()
            .map(|p| polygon_area(p))
            .min_by(|a, b| a.total_cmp(b))
    }

    /// Removes the floes smaller than `min_area_m2` and reports what went.
    ///
    /// Clipping a lattice to its rectangle leaves pieces down to 1e-5 of a
    /// cell at the edges, and the smallest floe sets the stable time step of
    /// a DEM run (a 1 km diamond channel: 0.16 s with them, about 4 s
    /// without). Dropping them leaves open water where they were, a loss of
    /// area the report states; the remaining floes still tile without
    /// overlap.
    pub fn drop_floes_smaller_than(&mut self, min_area_m2: f64) -> SmallFloeReport {
        let mut report = SmallFloeReport::default();
        let mut keep = 0;
        for i in 0..self.polygons.len() {
            let area = polygon_area(&self.polygons[i]);
            if area < min_area_m2 {
                report.dropped += 1;
                report.dropped_area_m2 += area;
            } else {
                self.polygons.swap(keep, i);
                self.thickness_m.swap(keep, i);
                keep += 1;
            }
        }
        self.polygons.truncate(keep);
        self.thickness_m.truncate(keep);
        report
    }

    /// Shrinks every floe about its area centroid to `area_fraction` of its
    /// area (lengths by its square root): open water between floes that
    /// tiled the region, for a loose pack that a wall or the wind then
    /// compacts. A convex floe shrunk about an interior point stays inside
    /// its cell, so the floes still do not overlap. `area_fraction` in
    /// (0, 1]; at 1 the floes keep their bits.
    pub fn shrink_floes(&mut self, area_fraction: f64) {
        if area_fraction == 1.0 {
            return;
        }
        let s = area_fraction.sqrt();
        for p in &mut self.polygons {
            let c = polygon_centroid(p);
            for v in p.iter_mut() {
                *v = c + (*v - c) * s;
            }
        }
    }

    /// Area centroid of floe `index` (world coordinates, m). Panics if
    /// `index` is out of range.
    pub fn centroid_m(&self, index: usize) -> Vec2 {
        polygon_centroid(&self.polygons[index])
    }

    /// Floe volume `sum(area * thickness)` (m^3).
    pub fn total_volume_m3(&self) -> f64 {
        let mut sum = NeumaierSum::default();
        for (p, h) in self.polygons.iter().zip(&self.thickness_m) {
            sum.add(polygon_area(p) * h);
        }
        sum.value()
    }

    /// Checks what the engine relies on: one finite positive thickness per
    /// polygon; every polygon has at least 3 finite vertices, positive area,
    /// is counter-clockwise and convex (every turn is a left turn up to a
    /// tolerance of 1e-9 times the square of the polygon's bounding-box
    /// diagonal, and the turns add up to one full turn, which rules out
    /// self-intersecting outlines).
    pub fn validate(&self) -> Result<(), DemError> {
        if self.thickness_m.len() != self.polygons.len() {
            return Err(DemError::InvalidTessellation {
                reason: format!(
                    "{} polygons but {} thickness values",
                    self.polygons.len(),
                    self.thickness_m.len()
                ),
            });
        }
        for (index, (poly, &h)) in self.polygons.iter().zip(&self.thickness_m).enumerate() {
            let bad = |reason: String| DemError::InvalidFloe { index, reason };
            if !(h.is_finite() && h > 0.0) {
                return Err(bad(format!("thickness {h} m is not finite and > 0")));
            }
            if let Err(reason) = check_convex_ccw(poly) {
                return Err(bad(reason));
            }
        }
        Ok(())
    }
}

/// The rectangular domain to fill, world coordinates (m).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rect {
    /// Lower-left corner (m).
    pub min: Vec2,
    /// Upper-right corner (m).
    pub max: Vec2,
}

impl Rect {
    /// The rectangle with corners `min` (lower left) and `max` (upper right).
    pub fn new(min: Vec2, max: Vec2) -> Self {
        Self { min, max }
    }

    /// The rectangle with lower-left corner `min` and the given size (m).
    pub fn from_size(min: Vec2, width_m: f64, height_m: f64) -> Self {
        Self {
            min,
            max: min + Vec2::new(width_m, height_m),
        }
    }

    /// Width (m).
    pub fn width_m(&self) -> f64 {
        self.max.x - self.min.x
    }

    /// Height (m).
    pub fn height_m(&self) -> f64 {
        self.max.y - self.min.y
    }

    /// Area (m^2).
    pub fn area_m2(&self) -> f64 {
        self.width_m() * self.height_m()
    }

    /// `true` if `p` is inside or on the boundary.
    pub fn contains(&self, p: Vec2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// Checks that all coordinates are finite and the rectangle has positive
    /// width and height.
    pub fn validate(&self) -> Result<(), DemError> {
        for (name, v) in [
            ("domain.min.x_m", self.min.x),
            ("domain.min.y_m", self.min.y),
            ("domain.max.x_m", self.max.x),
            ("domain.max.y_m", self.max.y),
        ] {
            if !v.is_finite() {
                return Err(DemError::InvalidParameter {
                    name,
                    value: v,
                    reason: "must be finite",
                });
            }
        }
        let (w, h) = (self.width_m(), self.height_m());
        if !(w > 0.0 && w.is_finite()) {
            return Err(DemError::InvalidParameter {
                name: "domain width_m",
                value: w,
                reason: "domain must have max.x > min.x (non-empty, finite)",
            });
        }
        if !(h > 0.0 && h.is_finite()) {
            return Err(DemError::InvalidParameter {
                name: "domain height_m",
                value: h,
                reason: "domain must have max.y > min.y (non-empty, finite)",
            });
        }
        Ok(())
    }
}

/// Distribution of floe thickness (all values in m). Sampling is seeded and
/// deterministic; every sample is finite and > 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ThicknessDistribution {
    /// Every floe has the same thickness.
    Uniform {
        /// Thickness (m), > 0.
        thickness_m: f64,
    },
    /// Thickness uniformly distributed in `[min_m, max_m]`.
    UniformRange {
        /// Smallest thickness (m), > 0.
        min_m: f64,
        /// Largest thickness (m), >= `min_m`.
        max_m: f64,
    },
    /// Log-normal thickness with the given mean and standard deviation *of
    /// the thickness itself* (not of its logarithm): ln h ~ N(mu, s^2) with
    /// s^2 = ln(1 + (std/mean)^2), mu = ln(mean) - s^2/2. Samples are
    /// clamped below at [`LOGNORMAL_MIN_FRACTION`] x `mean_m` (reached only
    /// for extreme `std_m/mean_m`); `std_m = 0` gives exactly `mean_m`.
    LogNormal {
        /// Mean thickness (m), > 0.
        mean_m: f64,
        /// Standard deviation of the thickness (m), >= 0.
        std_m: f64,
    },
}

/// Lower clamp of [`ThicknessDistribution::LogNormal`] samples, as a fraction
/// of the mean.
pub const LOGNORMAL_MIN_FRACTION: f64 = 1e-6;

impl ThicknessDistribution {
    /// Checks the parameters (finite, positive, `min_m <= max_m`).
    pub fn validate(&self) -> Result<(), DemError> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(DemError::InvalidParameter {
                    name,
                    value: v,
                    reason: "must be finite and > 0",
                })
            }
        };
        match *self {
            Self::Uniform { thickness_m } => positive("thickness_m", thickness_m),
            Self::UniformRange { min_m, max_m } => {
                positive("min_m", min_m)?;
                positive("max_m", max_m)?;
                if max_m < min_m {
                    return Err(DemError::InvalidParameter {
                        name: "max_m",
                        value: max_m,
                        reason: "must be >= min_m",
                    });
                }
                Ok(())
            }
            Self::LogNormal { mean_m, std_m } => {
                positive("mean_m", mean_m)?;
                if !(std_m.is_finite() && std_m >= 0.0) {
                    return Err(DemError::InvalidParameter {
                        name: "std_m",
                        value: std_m,
                        reason: "must be finite and >= 0",
                    });
                }
                Ok(())
            }
        }
    }

    /// Mean thickness (m) of the distribution.
    pub fn mean_m(&self) -> f64 {
        match *self {
            Self::Uniform { thickness_m } => thickness_m,
            Self::UniformRange { min_m, max_m } => 0.5 * (min_m + max_m),
            Self::LogNormal { mean_m, .. } => mean_m,
        }
    }

    /// `n` seeded samples (m). The same `(self, n, seed)` gives the same
    /// values; the first `k` values do not depend on `n`.
    pub fn sample(&self, n: usize, seed: u64) -> Result<Vec<f64>, DemError> {
        self.validate()?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut out = Vec::with_capacity(n);
        match *self {
            Self::Uniform { thickness_m } => out.resize(n, thickness_m),
            Self::UniformRange { min_m, max_m } => {
                if min_m == max_m {
                    out.resize(n, min_m);
                } else {
                    let d = rand_distr::Uniform::new_inclusive(min_m, max_m);
                    out.extend((0..n).map(|_| d.sample(&mut rng).clamp(min_m, max_m)));
                }
            }
            Self::LogNormal { mean_m, std_m } => {
                if std_m == 0.0 {
                    out.resize(n, mean_m);
                } else {
                    let cv = std_m / mean_m;
                    let s2 = cv.mul_add(cv, 1.0).ln();
                    let mu = mean_m.ln() - 0.5 * s2;
                    let d = rand_distr::LogNormal::new(mu, s2.sqrt()).map_err(|e| {
                        DemError::InvalidTessellation {
                            reason: format!("log-normal thickness: {e}"),
                        }
                    })?;
                    let floor = LOGNORMAL_MIN_FRACTION * mean_m;
                    out.extend((0..n).map(|_| {
                        let h: f64 = d.sample(&mut rng);
                        // NaN cannot occur for valid parameters; `max` maps it to the floor anyway.
                        h.max(floor)
                    }));
                }
            }
        }
        Ok(out)
    }
}

/// Random streams derived from a generator's seed.
pub(crate) mod streams {
    /// Lattice node jitter.
    pub const JITTER: u64 = 0x6a69_7474_6572; // "jitter"
    /// Floe thickness.
    pub const THICKNESS: u64 = 0x0074_6869_636b; // "thick"
    /// Voronoi sites.
    pub const SITES: u64 = 0x0073_6974_6573; // "sites"
    /// Floe sizes of a size distribution.
    pub const SIZES: u64 = 0x0073_697a_6573; // "sizes"
    /// Placement of the floes of a size distribution.
    pub const PLACEMENT: u64 = 0x0070_6c61_6365; // "place"
    /// Thresholds of the selection by concentration.
    pub const CONCENTRATION: u64 = 0x0000_636f_6e63; // "conc"
}

/// A 64-bit seed for stream `stream` of generator seed `seed` (SplitMix64
/// finaliser of the combination), so that streams of one seed are unrelated.
pub(crate) fn derive_seed(seed: u64, stream: u64) -> u64 {
    let mut z = seed ^ stream.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A ChaCha8 generator for stream `stream` of `seed`.
pub(crate) fn stream_rng(seed: u64, stream: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(derive_seed(seed, stream))
}

/// A uniform draw in `[0, 1)` (53 random bits).
pub(crate) fn unit(rng: &mut ChaCha8Rng) -> f64 {
    rng.gen::<f64>()
}

/// Neumaier-compensated sum.
#[derive(Default)]
pub(crate) struct NeumaierSum {
    sum: f64,
    comp: f64,
}

impl NeumaierSum {
    pub(crate) fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.comp += (self.sum - t) + x;
        } else {
            self.comp += (x - t) + self.sum;
        }
        self.sum = t;
    }

    pub(crate) fn value(&self) -> f64 {
        self.sum + self.comp
    }
}

/// Signed area (m^2, positive counter-clockwise), computed relative to the
/// first vertex.
pub(crate) fn polygon_area(poly: &[Vec2]) -> f64 {
    if poly.len() < 3 {
        return 0.0;
    }
    let o = poly[0];
    let mut a = 0.0;
    let mut prev = poly[1] - o;
    for &p in &poly[2..] {
        let cur = p - o;
        a += prev.perp_dot(cur);
        prev = cur;
    }
    0.5 * a
}

/// Area centroid, computed relative to the first vertex; the vertex mean for
/// degenerate (zero-area) input.
pub(crate) fn polygon_centroid(poly: &[Vec2]) -> Vec2 {
    if poly.is_empty() {
        return Vec2::new(f64::NAN, f64::NAN);
    }
    let o = poly[0];
    let mut a2 = 0.0;
    let mut c = Vec2::ZERO;
    for k in 1..poly.len().saturating_sub(1) {
        let p = poly[k] - o;
        let q = poly[k + 1] - o;
        let w = p.perp_dot(q);
        a2 += w;
        c += (p + q) * w;
    }
    if a2 != 0.0 && a2.is_finite() {
        o + c / (3.0 * a2)
    } else {
        let mut m = Vec2::ZERO;
        for &p in poly {
            m += p - o;
        }
        o + m / poly.len() as f64
    }
}

/// Convexity / orientation check behind [`Tessellation::validate`].
pub(crate) fn check_convex_ccw(poly: &[Vec2]) -> Result<(), String> {
    let n = poly.len();
    if n < 3 {
        return Err(format!("{n} vertices, need at least 3"));
    }
    if poly.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return Err("non-finite vertex".into());
    }
    let area = polygon_area(poly);
    if area.is_nan() || area <= 0.0 {
        return Err(format!(
            "signed area {area} m^2 is not positive (clockwise or degenerate)"
        ));
    }
    let o = poly[0];
    let (mut lo, mut hi) = (Vec2::ZERO, Vec2::ZERO);
    for &p in poly {
        let q = p - o;
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let tol = 1e-9 * (hi - lo).length_squared();
    let mut turning = 0.0;
    for k in 0..n {
        let a = poly[k];
        let b = poly[(k + 1) % n];
        let c = poly[(k + 2) % n];
        let (e1, e2) = (b - a, c - b);
        let cross = e1.perp_dot(e2);
        if cross < -tol {
            return Err(format!(
                "reflex turn at vertex {} (cross {cross:e} m^2)",
                (k + 1) % n
            ));
        }
        turning += cross.atan2(e1.dot(e2));
    }
    if (turning - std::f64::consts::TAU).abs() > 1e-6 {
        return Err(format!("outline turns {turning} rad, not one full turn"));
    }
    Ok(())
}

/// One Sutherland-Hodgman step: clips the convex polygon `poly` to the
/// closed half-plane `dist(p) >= 0`, writing the result to `out`.
///
/// An intersection vertex is created only where an edge strictly crosses the
/// line, so vertices lying on the line are kept once and never duplicated.
/// `isect(p_in, d_in, p_out, d_out)` computes the crossing from the inside
/// endpoint: it therefore does not depend on the direction in which the edge
/// is traversed, and an edge shared by two neighbouring polygons is cut at
/// bitwise the same point in both.
pub(crate) fn clip_convex<D, I>(poly: &[Vec2], out: &mut Vec<Vec2>, dist: D, isect: I)
where
    D: Fn(Vec2) -> f64,
    I: Fn(Vec2, f64, Vec2, f64) -> Vec2,
{
    out.clear();
    let Some(&last) = poly.last() else {
        return;
    };
    let mut prev = last;
    let mut dp = dist(prev);
    for &cur in poly {
        let dc = dist(cur);
        if dc >= 0.0 {
            if dp < 0.0 && dc > 0.0 {
                out.push(isect(cur, dc, prev, dp));
            }
            out.push(cur);
        } else if dp > 0.0 {
            out.push(isect(prev, dp, cur, dc));
        }
        prev = cur;
        dp = dc;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<Vec2> {
        vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ]
    }

    #[test]
    fn area_and_centroid_far_from_origin() {
        let off = Vec2::new(1e6, -1e6);
        let sq: Vec<Vec2> = square().into_iter().map(|p| p + off).collect();
        assert_eq!(polygon_area(&sq), 1.0);
        let c = polygon_centroid(&sq) - off;
        assert!((c - Vec2::new(0.5, 0.5)).length() < 1e-12);
    }

    #[test]
    fn clip_keeps_on_line_vertices_once() {
        let mut out = Vec::new();
        // Keep x >= 1: the right edge lies on the line, nothing remains but a segment.
        clip_convex(
            &square(),
            &mut out,
            |p| p.x - 1.0,
            |a, da, b, db| a + (b - a) * (da / (da - db)),
        );
        assert_eq!(out, vec![Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0)]);
        // Keep x >= 0.5.
        clip_convex(
            &square(),
            &mut out,
            |p| p.x - 0.5,
            |a, da, b, db| a + (b - a) * (da / (da - db)),
        );
        assert_eq!(out.len(), 4);
        assert!((polygon_area(&out) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn convexity_check_rejects_bad_polygons() {
        assert!(check_convex_ccw(&square()).is_ok());
        let mut cw = square();
        cw.reverse();
        assert!(check_convex_ccw(&cw).is_err());
        let dent = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.5, 0.2),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        assert!(check_convex_ccw(&dent).is_err());
        assert!(check_convex_ccw(&square()[..2]).is_err());
    }

    #[test]
    fn thickness_validation() {
        assert!(ThicknessDistribution::Uniform { thickness_m: 0.0 }
            .validate()
            .is_err());
        assert!(ThicknessDistribution::UniformRange {
            min_m: 2.0,
            max_m: 1.0
        }
        .validate()
        .is_err());
        assert!(ThicknessDistribution::LogNormal {
            mean_m: 1.0,
            std_m: f64::NAN
        }
        .validate()
        .is_err());
    }
}
