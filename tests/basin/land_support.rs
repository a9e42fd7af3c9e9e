//! A synthetic coastline ring of about `n` vertices, simple by
//! construction, deterministic from a seed: the boundary of an island (or
//! of mainland cut out of a map) on a grid of square cells (fractal value
//! noise: a ragged shore with bays, fjords a cell wide and peninsulas),
//! each grid edge of it cut into vertices that wander off the edge (a
//! random walk), so that the shore is rough at every scale; or a long
//! straight-ish shore closed far behind ([`Shape::Shore`]).
//!
//! Why it is simple: two grid edges of the boundary that are not
//! neighbours along it share no point (the island is one 4-connected piece
//! without holes, and no two of its cells touch at a corner alone), so
//! they are at least a cell apart; each edge's vertices stay within a thin
//! diamond on it ([`dress`]). Some stretches of shore are left straight
//! (exactly collinear runs), and some of their edges carry a needle
//! `1e-9` of a cell wide, out into the water or into the land.
//!
//! Used by tests/basin/land.rs and the `land_scaling` example of
//! floe-basin.
#![allow(dead_code)] // each user takes its part

use floe_dem::Vec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The land the ring bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// An island: shore all round.
    Island,
    /// Land below a shore across the grid, closed behind by three long
    /// straight edges (as a land polygon cut out of a map is).
    Mainland,
    /// A shore 200 km long without bays (a random walk in y over evenly
    /// spaced x), closed 100 km behind by two corners: every triangle
    /// inland reaches from the shore far along it or to a corner, long
    /// and thin. Not on the grid, and without straight runs or needles.
    Shore,
}

/// What the ring has besides its ragged shore.
#[derive(Debug, Clone, Copy)]
pub struct CoastStyle {
    /// Fraction of the shore left straight (exactly collinear runs).
    pub straight_fraction: f64,
    /// Chance that a straight grid edge carries a needle.
    pub needle_chance: f64,
}

impl CoastStyle {
    /// A natural-looking shore: rough everywhere, no needles.
    pub const NATURAL: CoastStyle = CoastStyle {
        straight_fraction: 0.0,
        needle_chance: 0.0,
    };
    /// A shore with a fifth left straight and needles on a tenth of that.
    pub const DEGENERATE: CoastStyle = CoastStyle {
        straight_fraction: 0.2,
        needle_chance: 0.1,
    };
}

/// Cell size of the grid, m.
pub const CELL_M: f64 = 100.0;

/// The ring (counter-clockwise, first vertex not repeated, m, about
/// (-2e6, 3e5) so that coordinates are large) of about `n` vertices.
pub fn coast_ring(n: usize, seed: u64, shape: Shape, style: CoastStyle) -> Vec<Vec2> {
    if shape == Shape::Shore {
        return shore_and_corners(n, seed);
    }
    // About 2 n^(2/3) grid edges of shore, each cut into the rest. The
    // shore's length grows about as the grid's side to the power 1.3: find
    // the side by a few trials.
    let edges = (2.0 * (n as f64).powf(2.0 / 3.0)).min(n as f64);
    let mut side = (edges.powf(1.0 / 1.3) as usize).max(24);
    let mut points = shore(side, seed, shape);
    for _ in 0..4 {
        let ratio = edges / points.len() as f64;
        if (ratio - 1.0).abs() < 0.05 {
            break;
        }
        side = ((side as f64 * ratio.clamp(0.25, 4.0).powf(1.0 / 1.3)) as usize).max(24);
        points = shore(side, seed, shape);
    }
    let margin = (0..points.len())
        .filter(|&k| on_margin(points[k], points[(k + 1) % points.len()], side))
        .count();
    let rough = (points.len() - margin).max(1);
    let per_edge = (n.saturating_sub(margin).div_ceil(rough)).max(1);
    dress(&points, side, per_edge, seed, style)
}

/// A shore of `n - 2` vertices from west to east, 200 km long, its y a
/// random walk whose steps grow as the square root of the spacing (so that
/// its amplitude, about a kilometre, does not depend on `n`), and two
/// corners 100 km below its lowest point. Simple: x grows along the shore,
/// and the corners lie below it, at its ends' x.
fn shore_and_corners(n: usize, seed: u64) -> Vec<Vec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5407E);
    let m = n.max(5) - 2;
    let (x0, length) = (-2.0e6, 2.0e5);
    let dx = length / (m - 1) as f64;
    let step = 4.24 * dx.sqrt();
    let mut y = 3.0e5;
    let mut out: Vec<Vec2> = (0..m)
        .map(|k| {
            y += rng.gen_range(-step..step);
            Vec2::new(x0 + length * k as f64 / (m - 1) as f64, y)
        })
        .collect();
    let bottom = out.iter().map(|v| v.y).fold(f64::INFINITY, f64::min) - 1.0e5;
    // Clockwise so far (west to east with land below): close it through
    // the corners, then turn it.
    out.push(Vec2::new(x0 + length, bottom));
    out.push(Vec2::new(x0, bottom));
    out.reverse();
    out
}

/// The grid points along the land's boundary, counter-clockwise, on a
/// grid of `side` x `side` cells.
fn shore(side: usize, seed: u64, shape: Shape) -> Vec<(i64, i64)> {
    let land = land_cells(side, seed, shape);
    trace(&land, side)
}

/// Fractal value noise (about [-2.5, 2.5]): `octaves` octaves from a
/// period of `period` cells, each half the period and 0.6 the amplitude
/// of the one before.
fn noise(x: f64, y: f64, period: f64, octaves: u32, seed: u64) -> f64 {
    let mut sum = 0.0;
    let mut amplitude = 1.0;
    let mut f = 1.0 / period;
    for o in 0..octaves {
        sum += amplitude * value_noise(x * f, y * f, seed.wrapping_add(o as u64));
        amplitude *= 0.65;
        f *= 2.0;
    }
    sum
}

/// Smoothly interpolated random values at integer points.
fn value_noise(x: f64, y: f64, seed: u64) -> f64 {
    let (ix, iy) = (x.floor(), y.floor());
    let (fx, fy) = (x - ix, y - iy);
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (s(fx), s(fy));
    let at = |dx: i64, dy: i64| lattice(ix as i64 + dx, iy as i64 + dy, seed);
    let bottom = at(0, 0) + (at(1, 0) - at(0, 0)) * sx;
    let top = at(0, 1) + (at(1, 1) - at(0, 1)) * sx;
    bottom + (top - bottom) * sy
}

/// A random value in [-1, 1] for a lattice point (splitmix64 of its
/// coordinates and the seed).
fn lattice(x: i64, y: i64, seed: u64) -> f64 {
    let mut z = (x as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add((y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        .wrapping_add(seed.wrapping_mul(0x1656_67B1_9E37_79F9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The land's cells (row-major, `side` x `side`): noise over a radial
/// fall-off (an island) or a slope down to the north (mainland), the
/// largest piece, holes filled, and no two cells touching at a corner
/// alone. The outer ring of cells is
/// water.
fn land_cells(side: usize, seed: u64, shape: Shape) -> Vec<bool> {
    let c = side as f64 / 2.0;
    let octaves = ((side as f64).log2() as u32).saturating_sub(1).max(3);
    let mut land: Vec<bool> = (0..side * side)
        .map(|k| {
            let (i, j) = (k % side, k / side);
            if i == 0 || j == 0 || i + 1 == side || j + 1 == side {
                return false;
            }
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            let height = match shape {
                Shape::Island => 1.0 - 1.8 * ((x - c).powi(2) + (y - c).powi(2)) / (c * c),
                Shape::Mainland | Shape::Shore => 1.0 - 2.0 * y / side as f64,
            };
            height + 1.6 * noise(x, y, side as f64 / 5.0, octaves, seed) > 0.0
        })
        .collect();
    keep_largest_piece(&mut land, side);
    loop {
        fill_holes(&mut land, side);
        if !fill_corner_touches(&mut land, side) {
            return land;
        }
    }
}

/// Keeps only the largest 4-connected piece of land.
fn keep_largest_piece(land: &mut [bool], side: usize) {
    let mut piece = vec![u32::MAX; land.len()];
    let mut sizes = Vec::new();
    for start in 0..land.len() {
        if !land[start] || piece[start] != u32::MAX {
            continue;
        }
        let label = sizes.len() as u32;
        let mut size = 0usize;
        let mut stack = vec![start];
        piece[start] = label;
        while let Some(k) = stack.pop() {
            size += 1;
            for m in neighbours(k, side) {
                if land[m] && piece[m] == u32::MAX {
                    piece[m] = label;
                    stack.push(m);
                }
            }
        }
        sizes.push(size);
    }
    let largest = (0..sizes.len()).max_by_key(|&l| (sizes[l], usize::MAX - l));
    for (l, p) in land.iter_mut().zip(&piece) {
        *l = Some(*p as usize) == largest;
    }
}

/// Makes land of water that the open water (from the grid's edge) cannot
/// reach.
fn fill_holes(land: &mut [bool], side: usize) {
    let mut open = vec![false; land.len()];
    let mut stack = vec![0];
    open[0] = true;
    while let Some(k) = stack.pop() {
        for m in neighbours(k, side) {
            if !land[m] && !open[m] {
                open[m] = true;
                stack.push(m);
            }
        }
    }
    for (l, o) in land.iter_mut().zip(&open) {
        *l = !*o;
    }
}

/// Fills the water of every 2 x 2 block whose land cells touch at a corner
/// alone; whether any was.
fn fill_corner_touches(land: &mut [bool], side: usize) -> bool {
    let mut changed = false;
    for j in 0..side - 1 {
        for i in 0..side - 1 {
            let k = j * side + i;
            let (a, b, c, d) = (land[k], land[k + 1], land[k + side], land[k + side + 1]);
            if (a && d && !b && !c) || (b && c && !a && !d) {
                for m in [k, k + 1, k + side, k + side + 1] {
                    land[m] = true;
                }
                changed = true;
            }
        }
    }
    changed
}

/// The 4-neighbours of cell `k` on the grid.
fn neighbours(k: usize, side: usize) -> impl Iterator<Item = usize> {
    let (i, j) = (k % side, k / side);
    [
        (i > 0).then(|| k - 1),
        (i + 1 < side).then(|| k + 1),
        (j > 0).then(|| k - side),
        (j + 1 < side).then(|| k + side),
    ]
    .into_iter()
    .flatten()
}

/// The grid points along the boundary of `land`, counter-clockwise (land
/// on the left), from the lowest row's first land cell.
fn trace(land: &[bool], side: usize) -> Vec<(i64, i64)> {
    let is_land = |i: i64, j: i64| {
        i >= 0 && j >= 0 && (i as usize) < side && (j as usize) < side && {
            land[j as usize * side + i as usize]
        }
    };
    let first = land.iter().position(|&l| l).expect("an island");
    let start = ((first % side) as i64, (first / side) as i64);
    let (mut p, mut d) = (start, (1i64, 0i64));
    let mut out = Vec::new();
    loop {
        out.push(p);
        p = (p.0 + d.0, p.1 + d.1);
        // The cells ahead of p, on the left and on the right of d.
        let cell_ahead = |left: bool| {
            let (dx, dy) = d;
            // Cell whose lower-left corner is p, shifted by the direction.
            let (li, lj) = match (dx, dy, left) {
                (1, 0, true) => (p.0, p.1),
                (1, 0, false) => (p.0, p.1 - 1),
                (-1, 0, true) => (p.0 - 1, p.1 - 1),
                (-1, 0, false) => (p.0 - 1, p.1),
                (0, 1, true) => (p.0 - 1, p.1),
                (0, 1, false) => (p.0, p.1),
                (0, -1, true) => (p.0, p.1 - 1),
                (0, -1, false) => (p.0 - 1, p.1 - 1),
                _ => unreachable!(),
            };
            is_land(li, lj)
        };
        d = if !cell_ahead(true) {
            (-d.1, d.0)
        } else if cell_ahead(false) {
            (d.1, -d.0)
        } else {
            d
        };
        if p == start && d == (1, 0) {
            return out;
        }
    }
}

/// Whether the grid edge `p q` runs along the grid's margin.
fn on_margin(p: (i64, i64), q: (i64, i64), side: usize) -> bool {
    let line = |a: i64, b: i64| a == b && (a == 1 || a == side as i64 - 1);
    line(p.0, q.0) || line(p.1, q.1)
}

/// The ring in metres: each grid edge of the shore (from `p` to `q`)
/// replaced by `per_edge` vertices at `p + t (q - p)`, `t = j / per_edge`,
/// moved across the edge by `h(t)` with `|h| <= 0.45 min(t, 1 - t)` (a
/// random walk squashed by `tanh`), so that each edge's vertices stay in a
/// thin diamond on it: diamonds of edges that are not neighbours are half
/// a cell apart, and neighbours' meet only at their common grid point.
/// Edges of straight stretches stay straight; some carry a needle at their
/// middle (tip 0.24 of a cell across, base `1e-9` of a cell wide). Edges
/// along the grid's margin (land reaching the grid's side) stay single
/// straight edges.
fn dress(
    points: &[(i64, i64)],
    side: usize,
    per_edge: usize,
    seed: u64,
    style: CoastStyle,
) -> Vec<Vec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5EED);
    let n = points.len();
    let origin = Vec2::new(-2.0e6, 3.0e5);
    let at = |p: (i64, i64)| origin + Vec2::new(p.0 as f64, p.1 as f64) * CELL_M;
    let step = 1.5 / (per_edge as f64).sqrt();
    let mut out = Vec::with_capacity(n * per_edge + n / 10);
    let mut calm_left = 0usize;
    let mut calm = false;
    for k in 0..n {
        if calm_left == 0 {
            calm_left = rng.gen_range(20..60);
            calm = rng.gen_bool(style.straight_fraction);
        }
        calm_left -= 1;
        let (gp, gq) = (points[k], points[(k + 1) % n]);
        let (p, q) = (at(gp), at(gq));
        let along = q - p;
        let across = Vec2::new(-along.y, along.x);
        out.push(p);
        if on_margin(gp, gq, side) {
            continue;
        }
        if calm {
            if rng.gen_bool(style.needle_chance) {
                let side = if rng.gen_bool(0.5) { 0.24 } else { -0.24 };
                let tiny = 1e-9;
                for j in 1..per_edge {
                    let t = j as f64 / per_edge as f64;
                    if t < 0.5 - 1e-6 {
                        out.push(p + along * t);
                    }
                }
                out.push(p + along * (0.5 - tiny));
                out.push(p + along * 0.5 + across * side);
                out.push(p + along * (0.5 + tiny));
                for j in 1..per_edge {
                    let t = j as f64 / per_edge as f64;
                    if t > 0.5 + 1e-6 {
                        out.push(p + along * t);
                    }
                }
            } else {
                out.extend((1..per_edge).map(|j| p + along * (j as f64 / per_edge as f64)));
            }
            continue;
        }
        let mut walk = 0.0;
        for j in 1..per_edge {
            let t = j as f64 / per_edge as f64;
            walk += rng.gen_range(-step..step);
            let h = 0.45 * t.min(1.0 - t) * walk.tanh();
            out.push(p + along * t + across * h);
        }
    }
    out
}
