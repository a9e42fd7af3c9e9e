//! Rhombus ("diamond") lattice of floes, clipped to the domain.

use super::lattice_periods::{fit_periods, IndexPeriods, PeriodFit};
use super::{
    clip_convex, polygon_area, streams, unit, NeumaierSum, Rect, Tessellation,
    ThicknessDistribution, MAX_FLOES,
};
use crate::error::DemError;
use crate::Vec2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A clipped cell whose area is below this fraction of the full cell area
/// (`side^2 sin(acute)`) is a sliver, dropped while the dropped area stays
/// within [`SLIVER_BUDGET_FRACTION`] of the domain area.
pub const SLIVER_AREA_FRACTION: f64 = 1e-9;

/// Largest total area, as a fraction of the domain area, that dropping
/// slivers may remove; slivers beyond the budget are kept. Well below the
/// 1e-9 relative area accuracy promised by [`DiamondLattice::build`].
pub const SLIVER_BUDGET_FRACTION: f64 = 1e-10;

/// Safety factor of the jitter bound, see [`max_jitter_fraction`].
const JITTER_SAFETY: f64 = 0.25;

/// Largest `jitter_fraction` accepted for a lattice with acute angle
/// `acute_angle_deg`: `0.25 * min(sin(a/2), cos(a/2))`.
///
/// Why: in a rhombus the distance from a vertex to the diagonal joining its
/// two neighbours is a half-diagonal, `s sin(a/2)` or `s cos(a/2)`. If every
/// node moves by at most `d <= 0.25 h` with `h` the smaller half-diagonal,
/// the signed area of each vertex triangle keeps at least `h^2/4 > 0`, so
/// every jittered cell stays strictly convex and counter-clockwise and the
/// cells still tile the plane. Examples: 0.125 at 60 deg, 0.152 at 75 deg,
/// 0.177 at 90 deg.
pub fn max_jitter_fraction(acute_angle_deg: f64) -> f64 {
    let half = 0.5 * acute_angle_deg.to_radians();
    JITTER_SAFETY * half.sin().min(half.cos())
}

/// A lattice of congruent rhombi filling `domain`.
///
/// The lattice is spanned by the edge vectors
/// `e1 = side (cos o, sin o)` and `e2 = side (cos(o + a), sin(o + a))`
/// (`o` = `orientation_deg`, `a` = `acute_angle_deg`), with nodes
/// `n_ij = domain.min + i e1 + j e2`; cell `(i, j)` is the rhombus
/// `(n_ij, n_i+1,j, n_i+1,j+1, n_i,j+1)` (counter-clockwise). Its long
/// diagonal points along `o + a/2` when `a < 90 deg`.
///
/// - Jitter: each node moves by a random vector, uniform in the disc of
///   radius `jitter_fraction * side`, the same for all four cells sharing it,
///   so the cells still tile the plane edge to edge. The displacement of node
///   `(i, j)` is a function of `(seed, i, j)` only (a ChaCha8 stream per
///   lattice row, positioned at the node), so it does not depend on the
///   domain size. `jitter_fraction` is bounded by [`max_jitter_fraction`].
/// - Clipping: cells crossing the domain boundary are clipped to it
///   (after jitter), cells outside are dropped; the outline of the result is
///   exactly the rectangle (boundary vertices carry the exact boundary
///   coordinate). Nodes within `1e-9 side` (plus a few ulps of the
///   coordinates) of a boundary line are snapped onto it, so a node that lies
///   on the boundary up to rounding creates no edge of rounding-error length;
///   snapping is a function of the node only, so neighbouring cells stay
///   edge-to-edge. (Genuinely short edges remain possible where a lattice
///   edge passes very close to a domain corner.)
/// - Slivers: clipped cells of zero area are dropped; clipped cells with
///   area below [`SLIVER_AREA_FRACTION`] of a full cell are dropped while the
///   total dropped area stays below [`SLIVER_BUDGET_FRACTION`] of the domain
///   area (see [`LatticeReport`]). Other small boundary pieces are kept:
///   check [`Tessellation::min_area_m2`] if the smallest floe mass matters.
/// - Thickness: one draw per floe, in output order, from `thickness` seeded
///   by a stream of `seed` independent of the jitter stream.
/// - Output order: by lattice row `j`, then `i`.
#[derive(Debug, Clone, PartialEq)]
pub struct DiamondLattice {
    /// Domain to fill (m).
    pub domain: Rect,
    /// Rhombus side length (m), > 0.
    pub side_m: f64,
    /// Angle between `e1` and `e2` (deg), in (0, 180). Values above 90 give
    /// the same rhombi as `180 - a`, with the long diagonal along `e2 - e1`.
    pub acute_angle_deg: f64,
    /// Direction of `e1`, counter-clockwise from +x (deg).
    pub orientation_deg: f64,
    /// Floe thickness distribution.
    pub thickness: ThicknessDistribution,
    /// Node jitter radius as a fraction of `side_m`, in
    /// `[0, max_jitter_fraction(acute_angle_deg)]`.
    pub jitter_fraction: f64,
    /// Seed of the jitter and thickness streams.
    pub seed: u64,
}

/// Bookkeeping of a lattice build.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LatticeReport {
    /// Lattice cells examined (those that may overlap the domain).
    pub candidate_cells: usize,
    /// Kept floes that were cut by the domain boundary.
    pub clipped_floes: usize,
    /// Candidates dropped because nothing of positive area was inside.
    pub dropped_empty: usize,
    /// Candidates dropped as slivers (positive area below
    /// [`SLIVER_AREA_FRACTION`] of a cell).
    pub dropped_slivers: usize,
    /// Total area of the dropped slivers (m^2).
    pub dropped_area_m2: f64,
}

impl DiamondLattice {
    /// A lattice given by its two diagonals instead of side and angle:
    /// `diagonal_along_m` points along `orientation_deg` (counter-clockwise
    /// from +x), `diagonal_across_m` is perpendicular to it. Side
    /// `= hypot(d_along, d_across) / 2`, angle between the edge vectors
    /// `= 2 atan(d_across / d_along)` (acute when `d_across < d_along`), and
    /// `e1` points along `orientation_deg - angle/2`.
    pub fn from_diagonals(
        domain: Rect,
        diagonal_along_m: f64,
        diagonal_across_m: f64,
        orientation_deg: f64,
        thickness: ThicknessDistribution,
        jitter_fraction: f64,
        seed: u64,
    ) -> Result<Self, DemError> {
        for (name, v) in [
            ("diagonal_along_m", diagonal_along_m),
            ("diagonal_across_m", diagonal_across_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(DemError::InvalidParameter {
                    name,
                    value: v,
                    reason: "must be finite and > 0",
                });
            }
        }
        if !orientation_deg.is_finite() {
            return Err(DemError::InvalidParameter {
                name: "orientation_deg",
                value: orientation_deg,
                reason: "must be finite",
            });
        }
        let angle = 2.0 * diagonal_across_m.atan2(diagonal_along_m).to_degrees();
        let lattice = Self {
            domain,
            side_m: 0.5 * diagonal_along_m.hypot(diagonal_across_m),
            acute_angle_deg: angle,
            orientation_deg: orientation_deg - 0.5 * angle,
            thickness,
            jitter_fraction,
            seed,
        };
        lattice.validate()?;
        Ok(lattice)
    }

    /// The two diagonals (m): along `e1 + e2` and along `e2 - e1`.
    pub fn diagonals_m(&self) -> (f64, f64) {
        let half = 0.5 * self.acute_angle_deg.to_radians();
        (
            2.0 * self.side_m * half.cos(),
            2.0 * self.side_m * half.sin(),
        )
    }

    /// Area of a full (unclipped, unjittered) cell, `side^2 sin(acute)` (m^2).
    pub fn cell_area_m2(&self) -> f64 {
        self.side_m * self.side_m * self.acute_angle_deg.to_radians().sin()
    }

    /// The lattice edge vectors `(e1, e2)` (m).
    pub fn edge_vectors_m(&self) -> (Vec2, Vec2) {
        let o = self.orientation_deg.to_radians();
        let (s1, c1) = o.sin_cos();
        let (s2, c2) = (o + self.acute_angle_deg.to_radians()).sin_cos();
        (
            Vec2::new(c1, s1) * self.side_m,
            Vec2::new(c2, s2) * self.side_m,
        )
    }

    /// Checks all parameters (see the field docs).
    pub fn validate(&self) -> Result<(), DemError> {
        self.domain.validate()?;
        if !(self.side_m.is_finite() && self.side_m > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "side_m",
                value: self.side_m,
                reason: "must be finite and > 0",
            });
        }
        let a = self.acute_angle_deg;
        if !(a.is_finite() && a > 0.0 && a < 180.0) {
            return Err(DemError::InvalidParameter {
                name: "acute_angle_deg",
                value: a,
                reason: "must be strictly between 0 and 180",
            });
        }
        let cell = self.cell_area_m2();
        if !(cell.is_finite() && cell > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "side_m",
                value: self.side_m,
                reason: "cell area side^2 sin(angle) must be finite and > 0",
            });
        }
        if !self.orientation_deg.is_finite() {
            return Err(DemError::InvalidParameter {
                name: "orientation_deg",
                value: self.orientation_deg,
                reason: "must be finite",
            });
        }
        let jf = self.jitter_fraction;
        if !(jf.is_finite() && jf >= 0.0 && jf <= max_jitter_fraction(a)) {
            return Err(DemError::InvalidParameter {
                name: "jitter_fraction",
                value: jf,
                reason: "must be in [0, 0.25 min(sin(a/2), cos(a/2))] so that cells stay convex",
            });
        }
        self.thickness.validate()
    }

    /// Builds the tessellation. The floe areas add up to the domain area to
    /// 1e-9 relative, the polygons are convex and counter-clockwise, and
    /// every edge either lies on the domain boundary or is shared, with the
    /// same two endpoints (bitwise), by exactly one other floe; the only
    /// exception are the edges that bordered a dropped sliver, which lie
    /// within about 1e-4 side of the boundary.
    pub fn build(&self) -> Result<Tessellation, DemError> {
        self.build_with_report().map(|(t, _)| t)
    }

    /// [`Self::build`], plus what was clipped and dropped.
    pub fn build_with_report(&self) -> Result<(Tessellation, LatticeReport), DemError> {
        self.validate()?;
        let (e1, e2) = self.edge_vectors_m();
        let jitter_r = self.jitter_fraction * self.side_m;
        self.build_cells((e1, e2), self.cell_area_m2(), jitter_r, None)
    }

    /// The tessellation of a domain periodic along x (`periodic[0]`) and/or
    /// y, for a world that wraps there: the lattice is fitted to the
    /// periods ([`fit_periods`]: unchanged when a lattice vector already
    /// spans the period, e.g. 25 sides of 800 m in 20 km), cells and node
    /// jitter are identified modulo the period vectors, and no cell is
    /// clipped along a periodic axis. Each cell appears once, whole, with
    /// the centre of its unjittered rhombus inside the domain; one that
    /// straddles the seam reaches beyond it, where its periodic image
    /// meets its neighbours edge to edge. The areas still add up to the
    /// domain's. Along open axes cells are clipped as by [`Self::build`].
    pub fn build_periodic(
        &self,
        periodic: [bool; 2],
    ) -> Result<(Tessellation, LatticeReport, PeriodFit), DemError> {
        self.validate()?;
        let dom = self.domain;
        let (e1, e2) = self.edge_vectors_m();
        let periods_m = [
            periodic[0].then(|| dom.width_m()),
            periodic[1].then(|| dom.height_m()),
        ];
        let fit = fit_periods(e1, e2, periods_m)?;
        let [[a, b], [c, d]] = fit.map;
        let cell_area = self.cell_area_m2() * (a * d - b * c).abs();
        // The jitter shrinks with the lattice's smallest stretch, so that
        // cells stay convex (see max_jitter_fraction).
        let jitter_r = self.jitter_fraction * self.side_m * fit.stretch_range().0;
        let periods = IndexPeriods::new(&fit);
        let (t, report) = self.build_cells(
            (fit.apply(e1), fit.apply(e2)),
            cell_area,
            jitter_r,
            Some(periods),
        )?;
        Ok((t, report, fit))
    }

    /// The cells of the lattice with edge vectors `(e1, e2)`, cells of area
    /// `cell_area` and node jitter `jitter_r`, clipped to the domain along
    /// the axes that `periods` leaves open (all without `periods`).
    fn build_cells(
        &self,
        (e1, e2): (Vec2, Vec2),
        cell_area: f64,
        jitter_r: f64,
        periods: Option<IndexPeriods>,
    ) -> Result<(Tessellation, LatticeReport), DemError> {
        let dom = self.domain;
        let det = e1.perp_dot(e2);
        let (w, h) = (dom.width_m(), dom.height_m());
        let open = [
            periods.is_none_or(|p| p.along(0).is_none()),
            periods.is_none_or(|p| p.along(1).is_none()),
        ];
        // Cells are enumerated over the domain grown by the jitter radius:
        // a jittered cell lies within jitter_r of its unjittered rhombus.
        let margin = jitter_r + 1e-6 * self.side_m;

        let estimate = (w + 2.0 * margin) * (h + 2.0 * margin) / det;
        if estimate.is_nan() || estimate > MAX_FLOES as f64 {
            return Err(too_many(estimate));
        }

        // Lattice coordinates (u, v) of the grown domain's corners, in the
        // frame local to domain.min.
        let to_uv = |p: Vec2| Vec2::new(p.perp_dot(e2) / det, e1.perp_dot(p) / det);
        let quad_uv = [
            to_uv(Vec2::new(-margin, -margin)),
            to_uv(Vec2::new(w + margin, -margin)),
            to_uv(Vec2::new(w + margin, h + margin)),
            to_uv(Vec2::new(-margin, h + margin)),
        ];
        let vmin = quad_uv.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        let vmax = quad_uv
            .iter()
            .map(|p| p.y)
            .fold(f64::NEG_INFINITY, f64::max);
        let rows = vmax.ceil() - vmin.floor();
        if rows.is_nan() || rows > MAX_FLOES as f64 {
            return Err(too_many(rows));
        }
        let (j0, j1) = (vmin.floor() as i64, vmax.ceil() as i64);

        let mut scratch = (Vec::with_capacity(8), Vec::with_capacity(8));
        let mut row_range = |j: i64| -> Option<(i64, i64)> {
            let (a, b) = (&mut scratch.0, &mut scratch.1);
            let lerp = |p: Vec2, dp: f64, q: Vec2, dq: f64| p + (q - p) * (dp / (dp - dq));
            let jf = j as f64;
            clip_convex(&quad_uv, a, |p| p.y - jf, lerp);
            clip_convex(a, b, |p| jf + 1.0 - p.y, lerp);
            if b.is_empty() {
                return None;
            }
            let umin = b.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
            let umax = b.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
            let i0 = umin.floor() as i64;
            let i1 = (umax.ceil() as i64).max(i0 + 1);
            Some((i0, i1))
        };

        // Pass 1: count candidates, refusing before any big allocation.
        let mut candidates: u64 = 0;
        for j in j0..j1 {
            if let Some((i0, i1)) = row_range(j) {
                candidates += (i1 - i0) as u64;
                if candidates > MAX_FLOES as u64 {
                    return Err(DemError::TooManyFloes {
                        requested: candidates.max(estimate as u64),
                        limit: MAX_FLOES as u64,
                    });
                }
            }
        }

        // Snap tolerance: 1e-9 side plus a few ulps of the world coordinates.
        let coord_scale = [dom.min.x, dom.min.y, dom.max.x, dom.max.y]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let eps = 1e-9 * self.side_m + 8.0 * f64::EPSILON * coord_scale;
        let sliver_area = SLIVER_AREA_FRACTION * cell_area;
        let sliver_budget = SLIVER_BUDGET_FRACTION * dom.area_m2();

        let mut nodes = NodeRows {
            origin: dom.min,
            e1,
            e2,
            jitter_r,
            rng: (jitter_r > 0.0)
                .then(|| ChaCha8Rng::seed_from_u64(super::derive_seed(self.seed, streams::JITTER))),
            periods,
        };
        let mut seen = std::collections::HashSet::new();
        let mut report = LatticeReport {
            candidate_cells: candidates as usize,
            ..Default::default()
        };
        let mut dropped = NeumaierSum::default();
        let mut polygons: Vec<Vec<Vec2>> = Vec::with_capacity(candidates as usize);
        let (mut lower, mut upper) = (Vec::new(), Vec::new());
        let (mut buf, mut out) = (Vec::with_capacity(8), Vec::with_capacity(8));
        for j in j0..j1 {
            let Some((i0, i1)) = row_range(j) else {
                continue;
            };
            if periods.is_none() {
                nodes.fill(&mut lower, i0, i1, j);
                nodes.fill(&mut upper, i0, i1, j + 1);
            }
            for k in 0..(i1 - i0) as usize {
                let quad = match periods {
                    None => [lower[k], lower[k + 1], upper[k + 1], upper[k]],
                    Some(p) => {
                        let i = i0 + k as i64;
                        if !seen.insert(p.canonical(i, j)) {
                            continue;
                        }
                        let (i, j) = member_in_domain(p, (e1, e2), dom, i, j);
                        nodes.cell(i, j)
                    }
                };
                let inside = quad.iter().all(|p| {
                    (!open[0] || (p.x - dom.min.x > eps && dom.max.x - p.x > eps))
                        && (!open[1] || (p.y - dom.min.y > eps && dom.max.y - p.y > eps))
                });
                if inside {
                    polygons.push(quad.to_vec());
                    continue;
                }
                buf.clear();
                buf.extend_from_slice(&quad);
                if open[0] {
                    clip_axis(&mut buf, &mut out, Axis::X, dom.min.x, true, eps);
                    clip_axis(&mut buf, &mut out, Axis::X, dom.max.x, false, eps);
                }
                if open[1] {
                    clip_axis(&mut buf, &mut out, Axis::Y, dom.min.y, true, eps);
                    clip_axis(&mut buf, &mut out, Axis::Y, dom.max.y, false, eps);
                }
                if buf.len() < 3 {
                    report.dropped_empty += 1;
                    continue;
                }
                let area = polygon_area(&buf);
                if area < -1e-9 * cell_area {
                    return Err(DemError::InvalidTessellation {
                        reason: format!(
                            "clipped lattice cell ({}, {j}) has negative area {area:e} m^2",
                            i0 + k as i64
                        ),
                    });
                }
                if area <= 0.0 {
                    report.dropped_empty += 1;
                    continue;
                }
                if area < sliver_area && dropped.value() + area <= sliver_budget {
                    dropped.add(area);
                    report.dropped_slivers += 1;
                    continue;
                }
                report.clipped_floes += 1;
                polygons.push(buf.clone());
            }
        }
        report.dropped_area_m2 = dropped.value();

        let thickness_m = self.thickness.sample(
            polygons.len(),
            super::derive_seed(self.seed, streams::THICKNESS),
        )?;
        Ok((
            Tessellation {
                polygons,
                thickness_m,
            },
            report,
        ))
    }
}

fn too_many(requested: f64) -> DemError {
    DemError::TooManyFloes {
        // Saturating float-to-int conversion: inf/NaN become u64::MAX / 0.
        requested: if requested.is_nan() {
            u64::MAX
        } else {
            requested as u64
        },
        limit: MAX_FLOES as u64,
    }
}

/// The member of `(i, j)`'s class modulo the periods whose unjittered
/// cell has its centre in `dom` along each periodic axis.
fn member_in_domain(
    periods: IndexPeriods,
    (e1, e2): (Vec2, Vec2),
    dom: Rect,
    mut i: i64,
    mut j: i64,
) -> (i64, i64) {
    let size = [dom.width_m(), dom.height_m()];
    for axis in 0..2 {
        if let Some([m, n]) = periods.along(axis) {
            let centre = e1 * (i as f64 + 0.5) + e2 * (j as f64 + 0.5);
            let along = [centre.x, centre.y][axis];
            let t = (along / size[axis]).floor() as i64;
            i -= t * m;
            j -= t * n;
        }
    }
    (i, j)
}

/// Generator of lattice node positions, row by row.
struct NodeRows {
    origin: Vec2,
    e1: Vec2,
    e2: Vec2,
    jitter_r: f64,
    rng: Option<ChaCha8Rng>,
    /// Nodes identified modulo these take the jitter of their canonical
    /// index.
    periods: Option<IndexPeriods>,
}

impl NodeRows {
    /// World positions of nodes `(i, j)` for `i` in `i0..=i1`, into `buf`.
    ///
    /// The jitter of node `(i, j)` is read from ChaCha8 stream `j` at word
    /// `4 (i + 2^62)` (two f64 draws = four 32-bit words per node), so it is
    /// the same whichever row range asks for it.
    fn fill(&mut self, buf: &mut Vec<Vec2>, i0: i64, i1: i64, j: i64) {
        buf.clear();
        let row = self.e2 * j as f64;
        if let Some(rng) = self.rng.as_mut() {
            rng.set_stream(j as u64);
            rng.set_word_pos((i0 as i128 + (1i128 << 62)) as u128 * 4);
        }
        for i in i0..=i1 {
            let mut local = self.e1 * i as f64 + row;
            if let Some(rng) = self.rng.as_mut() {
                local += jitter(rng, self.jitter_r);
            }
            buf.push(self.origin + local);
        }
    }

    /// The nodes of cell `(i, j)` (counter-clockwise), each jittered as its
    /// canonical index modulo the periods is.
    fn cell(&mut self, i: i64, j: i64) -> [Vec2; 4] {
        [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)].map(|(i, j)| {
            let mut local = self.e1 * i as f64 + self.e2 * j as f64;
            if let Some(rng) = self.rng.as_mut() {
                let (ci, cj) = self.periods.map_or((i, j), |p| p.canonical(i, j));
                rng.set_stream(cj as u64);
                rng.set_word_pos((ci as i128 + (1i128 << 62)) as u128 * 4);
                local += jitter(rng, self.jitter_r);
            }
            self.origin + local
        })
    }
}

/// A node's jitter: uniform in the disc of radius `r` (two draws).
fn jitter(rng: &mut ChaCha8Rng, r: f64) -> Vec2 {
    let r = r * unit(rng).sqrt();
    let (s, c) = (std::f64::consts::TAU * unit(rng)).sin_cos();
    Vec2::new(c, s) * r
}

#[derive(Clone, Copy)]
enum Axis {
    X,
    Y,
}

impl Axis {
    fn get(self, p: Vec2) -> f64 {
        match self {
            Axis::X => p.x,
            Axis::Y => p.y,
        }
    }

    fn set(self, p: &mut Vec2, v: f64) {
        match self {
            Axis::X => p.x = v,
            Axis::Y => p.y = v,
        }
    }
}

/// Clips `buf` (convex) to `coord >= c` (`keep_greater`) or `coord <= c`,
/// in place (`out` is scratch). Vertices within `eps` of the line are first
/// snapped onto it; crossing points get the coordinate `c` exactly and the
/// other coordinate interpolated from the inside endpoint (see
/// [`clip_convex`]), so shared edges are cut identically in both floes.
fn clip_axis(
    buf: &mut Vec<Vec2>,
    out: &mut Vec<Vec2>,
    axis: Axis,
    c: f64,
    keep_greater: bool,
    eps: f64,
) {
    for p in buf.iter_mut() {
        if (axis.get(*p) - c).abs() <= eps {
            axis.set(p, c);
        }
    }
    let sign = if keep_greater { 1.0 } else { -1.0 };
    clip_convex(
        buf,
        out,
        |p| sign * (axis.get(p) - c),
        |p_in, d_in, p_out, d_out| {
            let t = d_in / (d_in - d_out);
            let mut q = p_in + (p_out - p_in) * t;
            axis.set(&mut q, c);
            q
        },
    );
    std::mem::swap(buf, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice(side: f64) -> DiamondLattice {
        DiamondLattice {
            domain: Rect::from_size(Vec2::new(0.0, 0.0), 100.0, 50.0),
            side_m: side,
            acute_angle_deg: 60.0,
            orientation_deg: 17.0,
            thickness: ThicknessDistribution::Uniform { thickness_m: 1.0 },
            jitter_fraction: 0.1,
            seed: 7,
        }
    }

    #[test]
    fn jitter_bound_values() {
        assert!((max_jitter_fraction(60.0) - 0.125).abs() < 1e-12);
        assert!((max_jitter_fraction(90.0) - 0.25 * 0.5f64.sqrt()).abs() < 1e-12);
        assert!((max_jitter_fraction(120.0) - 0.125).abs() < 1e-12);
    }

    #[test]
    fn diagonals_round_trip() {
        let l = DiamondLattice::from_diagonals(
            Rect::from_size(Vec2::ZERO, 10.0, 10.0),
            3.0,
            2.0,
            30.0,
            ThicknessDistribution::Uniform { thickness_m: 1.0 },
            0.0,
            1,
        )
        .unwrap();
        let (d1, d2) = l.diagonals_m();
        assert!((d1 - 3.0).abs() < 1e-12 && (d2 - 2.0).abs() < 1e-12);
        let (e1, e2) = l.edge_vectors_m();
        let long = e1 + e2;
        assert!((long.y.atan2(long.x).to_degrees() - 30.0).abs() < 1e-9);
        assert!((l.cell_area_m2() - 0.5 * 3.0 * 2.0).abs() < 1e-12);
    }

    #[test]
    fn node_jitter_depends_on_node_only() {
        let l = lattice(2.0);
        let (e1, e2) = l.edge_vectors_m();
        let mut nodes = NodeRows {
            origin: Vec2::ZERO,
            e1,
            e2,
            jitter_r: 0.2,
            rng: Some(ChaCha8Rng::seed_from_u64(3)),
            periods: None,
        };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        nodes.fill(&mut a, -5, 5, 3);
        nodes.fill(&mut b, 0, 9, 3);
        assert_eq!(&a[5..], &b[..6]);
        for (k, p) in a.iter().enumerate() {
            let ideal = e1 * (k as f64 - 5.0) + e2 * 3.0;
            assert!((*p - ideal).length() <= 0.2);
        }
    }

    #[test]
    fn lattice_of_1e5_floes_builds() {
        let mut l = lattice(1.0);
        l.domain = Rect::from_size(Vec2::new(5e5, -2e5), 400.0, 217.0);
        let (t, rep) = l.build_with_report().unwrap();
        let expect = l.domain.area_m2() / l.cell_area_m2();
        assert!(t.len() as f64 > expect && t.len() as f64 <= rep.candidate_cells as f64);
        assert!(t.len() > 100_000);
        let rel = (t.total_area_m2() - l.domain.area_m2()).abs() / l.domain.area_m2();
        assert!(rel < 1e-9, "{rel}");
        t.validate().unwrap();
    }

    #[test]
    fn cap_is_checked_before_allocating() {
        let mut l = lattice(1e-4);
        l.domain = Rect::from_size(Vec2::ZERO, 1e3, 1e3);
        assert!(matches!(l.build(), Err(DemError::TooManyFloes { .. })));
        // Thin domain: few cells by area, many rows.
        let mut l = lattice(1e-3);
        l.jitter_fraction = 0.0;
        l.domain = Rect::from_size(Vec2::ZERO, 1e-3, 1e5);
        assert!(matches!(l.build(), Err(DemError::TooManyFloes { .. })));
    }
}
