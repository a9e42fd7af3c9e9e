//! Splitting a floe's polygon into convex pieces: the parent clipped by
//! the Voronoi half-planes of sites drawn inside it (as the anchors do,
//! Subzero.jl `split_floe`), with the sites from a counter-based random
//! generator keyed on (seed, floe id, step, attempt), so a split depends
//! on nothing but those four numbers: not on threads, processes, the
//! order floes are visited in, or a resume. A split whose pieces are too
//! small or have too many vertices is drawn again with the next attempt;
//! if every attempt fails the floe is left whole (no piece is dropped).
//!
//! Polygons here are relative to the parent's centroid, in world
//! orientation (the parent's vertices turned by its angle), counter-
//! clockwise.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::geometry::shape::area_and_centroid;
use crate::geometry::{cross, MAX_VERTICES};
use crate::Vec2;

/// What keys a split's random sites.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SplitKey {
    /// The scenario's seed.
    pub seed: u64,
    /// The parent floe's id.
    pub floe_id: u64,
    /// The step at which it breaks.
    pub step: u64,
}

/// How a floe is split.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplitRule {
    /// Sites drawn (pieces made), at least 2.
    pub pieces: usize,
    /// Smallest area a piece may have, m^2.
    pub min_piece_area_m2: f64,
    /// Attempts before the floe is left whole.
    pub attempts: u32,
}

impl Default for SplitRule {
    /// The anchors' three pieces (Subzero.jl's `npieces`), ten attempts,
    /// no smallest piece (the caller sets the smallest floe).
    fn default() -> Self {
        SplitRule {
            pieces: 3,
            min_piece_area_m2: 0.0,
            attempts: 10,
        }
    }
}

/// A 64-bit mix (SplitMix64's finaliser).
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The generator of attempt `attempt` of split `key`: its stream depends
/// on the four numbers only.
fn generator(key: SplitKey, attempt: u32) -> ChaCha8Rng {
    let mut h = mix(key.seed ^ 0x6a09_e667_f3bc_c909);
    for word in [key.floe_id, key.step, u64::from(attempt)] {
        h = mix(h ^ word);
    }
    ChaCha8Rng::seed_from_u64(h)
}

/// Up to `k` sites drawn uniformly inside `polygon` (rejection from its
/// bounding box, at most 1,000 draws a site: fewer only for a sliver), by
/// `rng`.
pub fn random_sites(polygon: &[Vec2], k: usize, rng: &mut impl Rng) -> Vec<Vec2> {
    let (lo, hi) = polygon.iter().fold(
        (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &v| (lo.min(v), hi.max(v)),
    );
    let inside = |p: Vec2| {
        let n = polygon.len();
        (0..n).all(|i| cross(polygon[(i + 1) % n] - polygon[i], p - polygon[i]) > 0.0)
    };
    let mut sites = Vec::with_capacity(k);
    for _ in 0..1000 * k {
        if sites.len() == k {
            break;
        }
        let p = Vec2::new(rng.gen_range(lo.x..hi.x), rng.gen_range(lo.y..hi.y));
        if inside(p) {
            sites.push(p);
        }
    }
    sites
}

/// `polygon` (convex, counter-clockwise) clipped to the half-plane
/// `normal . x <= offset`.
pub fn clip_half_plane(polygon: &[Vec2], normal: Vec2, offset: f64) -> Vec<Vec2> {
    let n = polygon.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..n {
        let (p, q) = (polygon[i], polygon[(i + 1) % n]);
        let (fp, fq) = (normal.dot(p) - offset, normal.dot(q) - offset);
        if fp <= 0.0 {
            out.push(p);
        }
        if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
            out.push(p + (q - p) * (fp / (fp - fq)));
        }
    }
    out
}

/// Drops repeated vertices and straight corners (to round-off relative to
/// the polygon's size).
fn tidy(polygon: Vec<Vec2>) -> Vec<Vec2> {
    let scale = polygon
        .iter()
        .map(|v| v.x.abs().max(v.y.abs()))
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut p = polygon;
    loop {
        let n = p.len();
        if n < 3 {
            return p;
        }
        let flat = (0..n).find(|&i| {
            let (a, b, c) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
            cross(b - a, c - b).abs() <= 1e-12 * scale * scale
        });
        match flat {
            Some(i) => {
                p.remove(i);
            }
            None => return p,
        }
    }
}

/// The Voronoi cells of `sites` inside `polygon`: cell `i` is the parent
/// clipped by the bisector half-plane of `sites[i]` with every other site.
/// A cell may be empty (fewer than 3 vertices) if its site lies outside.
pub fn voronoi_cells(polygon: &[Vec2], sites: &[Vec2]) -> Vec<Vec<Vec2>> {
    sites
        .iter()
        .enumerate()
        .map(|(i, &s)| {
            let mut cell = polygon.to_vec();
            for (j, &t) in sites.iter().enumerate() {
                if j != i && cell.len() >= 3 {
                    // Closer to s than to t: (t - s) . x <= (|t|^2 - |s|^2) / 2.
                    cell = clip_half_plane(&cell, t - s, 0.5 * (t.dot(t) - s.dot(s)));
                }
            }
            tidy(cell)
        })
        .collect()
}

/// The pieces `polygon` (convex, counter-clockwise, about its centroid)
/// splits into under `rule`, keyed by `key`: the first attempt whose every
/// piece has at least `rule.min_piece_area_m2` and at most
/// [`MAX_VERTICES`] vertices, with the attempt's number; `None` if no
/// attempt gives one (the floe stays whole).
pub fn split_polygon(
    polygon: &[Vec2],
    rule: &SplitRule,
    key: SplitKey,
) -> Option<(Vec<Vec<Vec2>>, u32)> {
    (0..rule.attempts).find_map(|attempt| {
        let sites = random_sites(polygon, rule.pieces, &mut generator(key, attempt));
        if sites.len() < rule.pieces {
            return None;
        }
        let cells = voronoi_cells(polygon, &sites);
        let fits = |c: &Vec<Vec2>| {
            let area = if c.len() >= 3 {
                area_and_centroid(c).0
            } else {
                0.0
            };
            c.len() <= MAX_VERTICES && area > 0.0 && area >= rule.min_piece_area_m2
        };
        cells.iter().all(fits).then_some((cells, attempt))
    })
}
