//! Exact decomposition of a simple polygon into convex pieces, for land
//! made of convex prescribed floes.
//!
//! **Method.** A constrained Delaunay triangulation of the ring
//! ([`crate::ring_triangulation`], spade), then Hertel and Mehlhorn's
//! (1983) merge removes every diagonal whose removal leaves both of its
//! ends convex. This is exact: the pieces tile the polygon, with no gap and
//! no overlap, so a floe pressed against land overlaps the pieces by
//! exactly its overlap with the land, and the contact force (which is
//! proportional to overlap area) is the land's. Hertel-Mehlhorn gives at
//! most four times the fewest convex pieces possible. Chosen over the
//! alternatives: the `geo` crate triangulates (earcut) but does not merge
//! into convex pieces, and approximate convex decomposition (parry's
//! VHACD) covers water with land. All turn tests are exact orientation
//! predicates ([`crate::planar::orient`]), so the combinatorics do not
//! depend on round-off whatever the coordinates' magnitude.
//!
//! **Cost.** `O(n log n)` time and `O(n)` memory for `n` vertices: the
//! triangulation's bulk loading, then one pass over its diagonals, each
//! merge touching two pieces of at most [`MAX_PIECE_VERTICES`] vertices
//! (the engine's limit per floe). Delaunay triangles are as round as the
//! vertices allow, so few pieces are long and thin.
//!
//! [`split_to_size`] then cuts pieces larger than a given radius across
//! their longest extent, the two halves sharing the cut's end points, so
//! that no land piece is much larger than a floe: the broad phase's cells
//! are as wide as the largest body. It costs the number of pieces made.

use floe_dem::Vec2;

use crate::planar::{centroid, clip_left, orient};
use crate::ring_triangulation::{triangulate, RingTriangles};

/// Most vertices of a piece: the engine's limit per floe
/// ([`floe_dem::geometry::MAX_VERTICES`]).
pub const MAX_PIECE_VERTICES: usize = floe_dem::geometry::MAX_VERTICES;

/// Convex pieces (counter-clockwise) exactly tiling the simple,
/// counter-clockwise ring `ring` (as [`crate::simple_ring::simple_ring`]
/// returns it). They depend on the polygon alone, not on the vertex the
/// ring starts from. Every vertex of a piece is a vertex of the ring.
///
/// # Errors
/// Why the ring cannot be triangulated ([`triangulate`]): it was not
/// simple after all, or is clockwise.
pub fn convex_pieces(ring: &[Vec2]) -> Result<Vec<Vec<Vec2>>, String> {
    let t = triangulate(ring)?;
    let pieces = merge_hertel_mehlhorn(&t);
    Ok(pieces
        .into_iter()
        .map(|p| drop_straight(p.iter().map(|&i| t.points[i as usize]).collect()))
        .collect())
}

/// Hertel-Mehlhorn: merges the triangles across their diagonals, in the
/// triangulation's order, wherever the merged piece stays convex at both
/// ends of the diagonal and has at most [`MAX_PIECE_VERTICES`] vertices.
/// Pieces as indices into `t.points`, counter-clockwise; a merged piece
/// takes the place of the triangle on the diagonal's first side.
pub fn merge_hertel_mehlhorn(t: &RingTriangles) -> Vec<Vec<u32>> {
    let mut pieces: Vec<Option<Vec<u32>>> =
        t.triangles.iter().map(|tri| Some(tri.to_vec())).collect();
    // Which piece holds each triangle now (union-find by direct relabel).
    let mut owner: Vec<u32> = (0..t.triangles.len() as u32).collect();
    let find = |owner: &mut Vec<u32>, mut k: u32| {
        while owner[k as usize] != k {
            owner[k as usize] = owner[owner[k as usize] as usize];
            k = owner[k as usize];
        }
        k as usize
    };
    for d in &t.diagonals {
        let [u, v] = d.ends;
        let (a, b) = (
            find(&mut owner, d.triangles[0]),
            find(&mut owner, d.triangles[1]),
        );
        if a == b {
            continue;
        }
        let (Some(pa), Some(pb)) = (&pieces[a], &pieces[b]) else {
            continue;
        };
        if pa.len() + pb.len() - 2 > MAX_PIECE_VERTICES {
            continue;
        }
        let Some(merged) = merge_across(pa, pb, u, v) else {
            continue;
        };
        if !convex_at(&t.points, &merged, u) || !convex_at(&t.points, &merged, v) {
            continue;
        }
        pieces[a] = Some(merged);
        pieces[b] = None;
        owner[b] = a as u32;
    }
    pieces.into_iter().flatten().collect()
}

/// The piece made of `a` and `b` joined along their common edge `u v`
/// (each holds it, in opposite directions), or `None` if they do not.
fn merge_across(a: &[u32], b: &[u32], u: u32, v: u32) -> Option<Vec<u32>> {
    // Rotate `p` so that it starts at `from` and its last vertex is `to`
    // (the shared edge `to -> from` closes it).
    let open = |p: &[u32], from: u32, to: u32| -> Option<Vec<u32>> {
        let k = p.iter().position(|&x| x == from)?;
        let r: Vec<u32> = p[k..].iter().chain(&p[..k]).copied().collect();
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
fn convex_at(points: &[Vec2], piece: &[u32], w: u32) -> bool {
    let n = piece.len();
    let Some(k) = piece.iter().position(|&x| x == w) else {
        return false;
    };
    let (p, q) = (piece[(k + n - 1) % n], piece[(k + 1) % n]);
    orient(points[p as usize], points[w as usize], points[q as usize]) >= 0.0
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
