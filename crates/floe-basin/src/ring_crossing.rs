//! Two edges of a closed ring that meet where they should not: a sweep
//! line (Shamos and Hoey, 1976), in `O(n log n)` time and `O(n)` memory
//! whatever the ring's shape.
//!
//! The vertices are visited in lexicographic order (x, then y); the edges
//! the sweep line crosses are kept in a balanced tree ordered from bottom
//! to top, and two edges are tested when they become neighbours in it
//! (when one is inserted, or when the one between them is removed). If
//! some two edges meet, the pair meeting at the lexicographically first
//! such point becomes neighbours before the sweep passes it, so one pair
//! is found (not necessarily that one). Duplicate vertices are found
//! from the sorted order and edges folding back on their neighbour (a
//! spike) by one pass around the ring. Every test is an exact orientation
//! predicate ([`crate::planar::orient`]): "meet" includes touching, and
//! the answer does not depend on round-off.
//!
//! Hand-written: no library the workspace uses answers "do any two of
//! these segments meet, and which" exactly (spade's constrained
//! triangulation merges duplicate vertices and routes a constraint through
//! a vertex lying on it without a word, and names only one of two
//! crossing edges).

use std::cmp::Ordering;
use std::collections::BTreeSet;

use floe_dem::Vec2;

use crate::planar::{lexicographic as lex, orient};

/// Two edges of `ring` (closed: the last vertex joins the first; no two
/// consecutive vertices equal) that share a point other than the vertex
/// joining neighbours, by the index of their first vertex, smaller first;
/// `None` if the ring is simple.
pub fn meeting_edges(ring: &[Vec2]) -> Option<(usize, usize)> {
    let n = ring.len();
    if n < 3 {
        return None;
    }
    if let Some(i) = (0..n).find(|&i| folds_back(ring[i], ring[(i + 1) % n], ring[(i + 2) % n])) {
        return Some(ordered(i, (i + 1) % n));
    }
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_unstable_by(|&a, &b| lex(ring[a as usize], ring[b as usize]));
    if let Some(w) = order
        .windows(2)
        .find(|w| ring[w[0] as usize] == ring[w[1] as usize])
    {
        return Some(ordered(w[0] as usize, w[1] as usize));
    }
    let edge = |k: usize| {
        let (a, b) = (ring[k], ring[(k + 1) % n]);
        if lex(a, b) == Ordering::Less {
            Edge {
                left: a,
                right: b,
                index: k,
            }
        } else {
            Edge {
                left: b,
                right: a,
                index: k,
            }
        }
    };
    let adjacent = |i: usize, j: usize| (i + 1) % n == j || (j + 1) % n == i;
    let meets = |a: &Edge, b: &Edge| {
        !adjacent(a.index, b.index) && segments_meet(a.left, a.right, b.left, b.right)
    };
    let mut status: BTreeSet<Edge> = BTreeSet::new();
    for &v in &order {
        let v = v as usize;
        let here = ring[v];
        let incident = [edge((v + n - 1) % n), edge(v)];
        // Edges ending here leave first, then those starting here enter.
        for e in incident.iter().filter(|e| e.right == here) {
            let below = status.range(..*e).next_back().copied();
            let above = status.range(*e..).nth(1).copied();
            status.remove(e);
            if let (Some(b), Some(a)) = (below, above) {
                if meets(&b, &a) {
                    return Some(ordered(a.index, b.index));
                }
            }
        }
        for e in incident.iter().filter(|e| e.left == here) {
            status.insert(*e);
            let below = status.range(..*e).next_back();
            let above = status.range(*e..).nth(1);
            for other in below.into_iter().chain(above) {
                if meets(e, other) {
                    return Some(ordered(e.index, other.index));
                }
            }
        }
    }
    None
}

/// A point where the closed segments `p1 p2` and `q1 q2`, which meet, do:
/// where they cross, or an end of one lying on the other.
pub fn meeting_point(p1: Vec2, p2: Vec2, q1: Vec2, q2: Vec2) -> Vec2 {
    let on = |a: Vec2, b: Vec2, c: Vec2| orient(a, b, c) == 0.0 && within(a, b, c);
    for (c, a, b) in [(q1, p1, p2), (q2, p1, p2), (p1, q1, q2), (p2, q1, q2)] {
        if on(a, b, c) {
            return c;
        }
    }
    let (d, e) = (p2 - p1, q2 - q1);
    let t = (q1 - p1).perp_dot(e) / d.perp_dot(e);
    p1 + d * t
}

/// Whether the closed segments `p1 p2` and `q1 q2` share a point.
pub fn segments_meet(p1: Vec2, p2: Vec2, q1: Vec2, q2: Vec2) -> bool {
    let (o1, o2) = (orient(p1, p2, q1), orient(p1, p2, q2));
    let (o3, o4) = (orient(q1, q2, p1), orient(q1, q2, p2));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && within(p1, p2, q1))
        || (o2 == 0.0 && within(p1, p2, q2))
        || (o3 == 0.0 && within(q1, q2, p1))
        || (o4 == 0.0 && within(q1, q2, p2))
}

/// Whether `c` lies in the bounding box of `a b`.
fn within(a: Vec2, b: Vec2, c: Vec2) -> bool {
    c.x >= a.x.min(b.x) && c.x <= a.x.max(b.x) && c.y >= a.y.min(b.y) && c.y <= a.y.max(b.y)
}

/// Whether the path `a b c` turns back on itself at `b` (a spike).
fn folds_back(a: Vec2, b: Vec2, c: Vec2) -> bool {
    orient(a, b, c) == 0.0 && (b - a).dot(c - b) < 0.0
}

fn ordered(i: usize, j: usize) -> (usize, usize) {
    (i.min(j), i.max(j))
}

/// An edge on the sweep line: its lexicographically first and last ends.
#[derive(Debug, Clone, Copy)]
struct Edge {
    left: Vec2,
    right: Vec2,
    index: usize,
}

impl PartialEq for Edge {
    fn eq(&self, other: &Self) -> bool {
        self.index == other.index
    }
}

impl Eq for Edge {}

impl PartialOrd for Edge {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Edge {
    /// Bottom to top along the sweep line, for two edges it crosses that
    /// do not meet before it (the only ones the tree compares until a
    /// meeting is found): the side of one edge on which the later-starting
    /// one starts, or, for two edges from one vertex, the side on which
    /// the other ends. Edges that meet (collinear, touching) are ordered
    /// by index, so that the tree stays usable until the meeting is found.
    fn cmp(&self, other: &Self) -> Ordering {
        if self.index == other.index {
            return Ordering::Equal;
        }
        let side = |e: &Edge, p: Vec2| orient(e.left, e.right, p);
        let mut s = if lex(self.left, other.left) != Ordering::Less {
            side(other, self.left)
        } else {
            -side(self, other.left)
        };
        if s == 0.0 {
            s = if lex(self.right, other.right) != Ordering::Greater {
                side(other, self.right)
            } else {
                -side(self, other.right)
            };
        }
        if s > 0.0 {
            Ordering::Greater
        } else if s < 0.0 {
            Ordering::Less
        } else {
            self.index.cmp(&other.index)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every pair tested: the reference the sweep must agree with.
    fn brute_force(ring: &[Vec2]) -> bool {
        let n = ring.len();
        let v = |i: usize| ring[i % n];
        (0..n).any(|i| folds_back(v(i), v(i + 1), v(i + 2)))
            || (0..n).any(|i| {
                (i + 1..n).any(|j| {
                    let adjacent = j == i + 1 || (i == 0 && j == n - 1);
                    !adjacent && segments_meet(v(i), v(i + 1), v(j), v(j + 1))
                })
            })
    }

    #[test]
    fn the_sweep_agrees_with_testing_every_pair_on_degenerate_rings() {
        // Vertices on a 5 x 5 grid of integers far from the origin: many
        // collinear edges, touching vertices, shared points.
        let mut rng = ChaCha8Rng::seed_from_u64(29);
        let (mut simple, mut not) = (0, 0);
        for _ in 0..40_000 {
            let n = rng.gen_range(3..9);
            let mut ring: Vec<Vec2> = Vec::with_capacity(n);
            while ring.len() < n {
                let p = Vec2::new(
                    1e6 + rng.gen_range(0..5) as f64,
                    -3e5 + rng.gen_range(0..5) as f64,
                );
                if ring.last() != Some(&p) {
                    ring.push(p);
                }
            }
            if ring[0] == ring[n - 1] {
                continue;
            }
            let want = brute_force(&ring);
            let got = meeting_edges(&ring);
            assert_eq!(got.is_some(), want, "{ring:?}: sweep {got:?}");
            if let Some((i, j)) = got {
                let v = |k: usize| ring[k % n];
                assert!(
                    (i + 1) % n == j
                        || (j + 1) % n == i
                        || segments_meet(v(i), v(i + 1), v(j), v(j + 1)),
                    "{ring:?}: {i} {j} do not meet"
                );
                not += 1;
            } else {
                simple += 1;
            }
        }
        // Both answers are common, so each side of the agreement is tested.
        assert!(simple > 1000 && not > 1000, "{simple} simple, {not} not");
    }

    #[test]
    fn a_crossing_point_and_a_touching_vertex_are_located() {
        let p = |x: f64, y: f64| Vec2::new(x, y);
        let at = meeting_point(p(0.0, 0.0), p(2.0, 2.0), p(0.0, 2.0), p(2.0, 0.0));
        assert_eq!(at, p(1.0, 1.0));
        let at = meeting_point(p(0.0, 0.0), p(4.0, 0.0), p(2.0, 3.0), p(2.0, 0.0));
        assert_eq!(at, p(2.0, 0.0));
    }
}
