//! Exact decomposition of a simple polygon into convex pieces, for land
//! made of convex prescribed floes.
//!
//! **Method.** Ear clipping triangulates the ring, then Hertel and
//! Mehlhorn's (1983) merge removes every diagonal whose removal leaves both
//! of its ends convex. This is exact: the pieces tile the polygon, with no
//! gap and no overlap, so a floe pressed against land overlaps the pieces
//! by exactly its overlap with the land, and the contact force (which is
//! proportional to overlap area) is the land's. Hertel-Mehlhorn gives at
//! most four times the fewest convex pieces possible. Chosen over the
//! alternatives: the `geo` crate triangulates (earcut) but does not merge
//! into convex pieces, and approximate convex decomposition (parry's
//! VHACD) covers water with land. All turn tests are exact orientation
//! predicates ([`crate::planar::orient`]), so the combinatorics do not
//! depend on round-off whatever the coordinates' magnitude.
//!
//! Ear clipping here visits candidate ears around the ring and tests each
//! against the vertices in its bounding box through a grid, so it costs
//! about `n` times the vertices per cell for coastlines (the worst case
//! remains `n^2`). Merged pieces are kept to at most [`MAX_PIECE_VERTICES`]
//! vertices, the engine's limit per floe.
//!
//! [`split_to_size`] then cuts pieces larger than a given radius across
//! their longest extent, again exactly tiling, so that no land piece is
//! much larger than a floe: the broad phase's cells are as wide as the
//! largest body.

use std::collections::HashMap;

use floe_dem::Vec2;

use crate::planar::{bounds, centroid, clip_left, orient};

/// Most vertices of a piece: the engine's limit per floe
/// ([`floe_dem::geometry::MAX_VERTICES`]).
pub const MAX_PIECE_VERTICES: usize = floe_dem::geometry::MAX_VERTICES;

/// Convex pieces (counter-clockwise) exactly tiling the simple,
/// counter-clockwise ring `ring` (as [`crate::simple_ring::simple_ring`]
/// returns it). Fails only if no ear is found, which for a simple ring
/// means it was not simple after all.
pub fn convex_pieces(ring: &[Vec2]) -> Result<Vec<Vec<Vec2>>, String> {
    let triangles = ear_clip(ring)?;
    let pieces = merge_hertel_mehlhorn(ring, &triangles);
    Ok(pieces
        .into_iter()
        .map(|p| drop_straight(p.iter().map(|&i| ring[i]).collect()))
        .collect())
}

/// Triangles (vertex indices, counter-clockwise) of the ring by ear
/// clipping.
pub fn ear_clip(ring: &[Vec2]) -> Result<Vec<[usize; 3]>, String> {
    let n = ring.len();
    if n < 3 {
        return Err("fewer than 3 vertices".into());
    }
    let mut next: Vec<usize> = (0..n).map(|i| (i + 1) % n).collect();
    let mut prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
    let mut alive = vec![true; n];
    let grid = VertexGrid::new(ring);
    let mut out = Vec::with_capacity(n - 2);
    let mut remaining = n;
    let mut i = 0;
    let mut misses = 0;
    while remaining > 3 {
        let (p, q) = (prev[i], next[i]);
        if is_ear(ring, &grid, &alive, p, i, q) {
            out.push([p, i, q]);
            alive[i] = false;
            next[p] = q;
            prev[q] = p;
            remaining -= 1;
            misses = 0;
            i = p;
        } else {
            misses += 1;
            if misses > remaining {
                return Err(format!(
                    "no ear found among {remaining} vertices left (the ring is not simple)"
                ));
            }
            i = q;
        }
    }
    let q = next[i];
    out.push([prev[i], i, q]);
    Ok(out)
}

/// Whether `p i q` is an ear: a strict left turn with no other live vertex
/// inside or on it.
fn is_ear(ring: &[Vec2], grid: &VertexGrid, alive: &[bool], p: usize, i: usize, q: usize) -> bool {
    let (a, b, c) = (ring[p], ring[i], ring[q]);
    if orient(a, b, c) <= 0.0 {
        return false;
    }
    let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
    !grid.any_in(lo, hi, |k| {
        if !alive[k] || k == p || k == i || k == q {
            return false;
        }
        let v = ring[k];
        orient(a, b, v) >= 0.0 && orient(b, c, v) >= 0.0 && orient(c, a, v) >= 0.0
    })
}

/// The ring's vertices binned on a uniform grid.
struct VertexGrid {
    lo: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<usize>,
    members: Vec<usize>,
}

impl VertexGrid {
    fn new(ring: &[Vec2]) -> Self {
        let (lo, hi) = bounds(ring);
        let size = (hi - lo).max(Vec2::splat(f64::MIN_POSITIVE));
        let n = ring.len() as f64;
        let cell = (size.x * size.y / n)
            .sqrt()
            .max(size.max_element() / n)
            .max(f64::MIN_POSITIVE);
        let nx = ((size.x / cell).floor() as usize) + 1;
        let ny = ((size.y / cell).floor() as usize) + 1;
        let cell_of = |v: Vec2| {
            let cx = (((v.x - lo.x) / cell) as usize).min(nx - 1);
            let cy = (((v.y - lo.y) / cell) as usize).min(ny - 1);
            cy * nx + cx
        };
        let mut start = vec![0usize; nx * ny + 1];
        for &v in ring {
            start[cell_of(v) + 1] += 1;
        }
        for c in 0..nx * ny {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut members = vec![0; ring.len()];
        for (k, &v) in ring.iter().enumerate() {
            let c = cell_of(v);
            members[fill[c]] = k;
            fill[c] += 1;
        }
        VertexGrid {
            lo,
            cell,
            nx,
            ny,
            start,
            members,
        }
    }

    /// Whether `test` holds for a vertex in a cell the box `lo..hi` touches.
    fn any_in(&self, lo: Vec2, hi: Vec2, mut test: impl FnMut(usize) -> bool) -> bool {
        let index = |x: f64, n: usize| ((x / self.cell).max(0.0) as usize).min(n - 1);
        let (x0, x1) = (
            index(lo.x - self.lo.x, self.nx),
            index(hi.x - self.lo.x, self.nx),
        );
        let (y0, y1) = (
            index(lo.y - self.lo.y, self.ny),
            index(hi.y - self.lo.y, self.ny),
        );
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                let c = cy * self.nx + cx;
                if self.members[self.start[c]..self.start[c + 1]]
                    .iter()
                    .any(|&k| test(k))
                {
                    return true;
                }
            }
        }
        false
    }
}

/// Hertel-Mehlhorn: merges the triangles across their shared edges
/// (diagonals) wherever the merged piece stays convex at both ends of the
/// diagonal and has at most [`MAX_PIECE_VERTICES`] vertices. Pieces as
/// vertex indices, counter-clockwise.
pub fn merge_hertel_mehlhorn(ring: &[Vec2], triangles: &[[usize; 3]]) -> Vec<Vec<usize>> {
    let mut pieces: Vec<Option<Vec<usize>>> = triangles.iter().map(|t| Some(t.to_vec())).collect();
    // Which piece holds each triangle now (union-find by direct relabel).
    let mut owner: Vec<usize> = (0..triangles.len()).collect();
    let find = |owner: &mut Vec<usize>, mut t: usize| {
        while owner[t] != t {
            owner[t] = owner[owner[t]];
            t = owner[t];
        }
        t
    };
    // Diagonals: edges shared by two triangles, in the order clipped.
    let mut first_seen: HashMap<(usize, usize), usize> = HashMap::new();
    let mut diagonals: Vec<(usize, usize, usize, usize)> = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (u, v) = (tri[k], tri[(k + 1) % 3]);
            let key = (u.min(v), u.max(v));
            match first_seen.remove(&key) {
                Some(s) => diagonals.push((key.0, key.1, s, t)),
                None => {
                    first_seen.insert(key, t);
                }
            }
        }
    }
    for (u, v, s, t) in diagonals {
        let (a, b) = (find(&mut owner, s), find(&mut owner, t));
        if a == b {
            continue;
        }
        let (Some(pa), Some(pb)) = (&pieces[a], &pieces[b]) else {
            continue;
        };
        let Some(merged) = merge_across(pa, pb, u, v) else {
            continue;
        };
        if merged.len() > MAX_PIECE_VERTICES
            || !convex_at(ring, &merged, u)
            || !convex_at(ring, &merged, v)
        {
            continue;
        }
        pieces[a] = Some(merged);
        pieces[b] = None;
        owner[b] = a;
    }
    pieces.into_iter().flatten().collect()
}

/// The piece made of `a` and `b` joined along their common edge `u v`
/// (each holds it, in opposite directions), or `None` if they do not.
fn merge_across(a: &[usize], b: &[usize], u: usize, v: usize) -> Option<Vec<usize>> {
    // Rotate `p` so that it starts at `from` and its last vertex is `to`
    // (the shared edge `to -> from` closes it).
    let open = |p: &[usize], from: usize, to: usize| -> Option<Vec<usize>> {
        let k = p.iter().position(|&x| x == from)?;
        let r: Vec<usize> = p[k..].iter().chain(&p[..k]).copied().collect();
        (*r.last()? == to).then_some(r)
    };
    // In `a` the edge runs x -> y; in `b`, y -> x.
    let (x, y) = if open(a, u, v).is_some() {
        (v, u)
    } else {
        (u, v)
    };
    let ra = open(a, y, x)?;
    let rb = open(b, x, y)?;
    // ra: y ... x, rb: x ... y; join without repeating x and y.
    let mut m = ra;
    m.extend_from_slice(&rb[1..rb.len() - 1]);
    Some(m)
}

/// Whether the piece turns left or goes straight at vertex `w`.
fn convex_at(ring: &[Vec2], piece: &[usize], w: usize) -> bool {
    let n = piece.len();
    let Some(k) = piece.iter().position(|&x| x == w) else {
        return false;
    };
    let (p, q) = (piece[(k + n - 1) % n], piece[(k + 1) % n]);
    orient(ring[p], ring[w], ring[q]) >= 0.0
}

/// Removes vertices where a convex piece goes straight through.
fn drop_straight(mut p: Vec<Vec2>) -> Vec<Vec2> {
    let mut k = 0;
    while p.len() > 3 && k < p.len() {
        let n = p.len();
        if orient(p[(k + n - 1) % n], p[k], p[(k + 1) % n]) == 0.0 {
            p.remove(k);
        } else {
            k += 1;
        }
    }
    p
}

/// Cuts convex pieces whose bounding radius about their centroid is above
/// `max_radius_m`, or that have more than [`MAX_PIECE_VERTICES`] vertices,
/// in two across their longest extent (the line perpendicular to the
/// farthest pair of vertices, through its middle), until none is. The
/// halves tile the piece exactly.
pub fn split_to_size(pieces: Vec<Vec<Vec2>>, max_radius_m: f64) -> Vec<Vec<Vec2>> {
    let mut out = Vec::with_capacity(pieces.len());
    let mut todo = pieces;
    while let Some(p) = todo.pop() {
        let c = centroid(&p);
        let radius = p.iter().map(|&v| (v - c).length()).fold(0.0, f64::max);
        if (radius <= max_radius_m && p.len() <= MAX_PIECE_VERTICES) || p.len() < 3 {
            out.push(p);
            continue;
        }
        // The farthest pair of vertices.
        let (mut a, mut b, mut best) = (0, 0, -1.0);
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let d = (p[j] - p[i]).length_squared();
                if d > best {
                    (a, b, best) = (i, j, d);
                }
            }
        }
        let mid = 0.5 * (p[a] + p[b]);
        let along = p[b] - p[a];
        let across = Vec2::new(-along.y, along.x);
        let (one, other) = (
            clip_left(&p, mid, mid + across),
            clip_left(&p, mid + across, mid),
        );
        if one.len() < 3 || other.len() < 3 {
            out.push(p);
            continue;
        }
        todo.push(one);
        todo.push(other);
    }
    out
}
