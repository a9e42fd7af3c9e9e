//! A polygon ring checked to be simple: what the convex decomposition
//! ([`crate::convex_pieces`]) needs and what a coastline file may give.
//!
//! The closing vertex (GeoJSON repeats the first) and repeated vertices are
//! dropped, straight-through vertices (exactly collinear with their
//! neighbours) are removed, and the ring is turned counter-clockwise. It is
//! refused, with the reason, when it has fewer than three distinct
//! vertices, a non-finite coordinate, no area, or when two of its edges
//! cross or touch (a figure eight, a spike folding back on itself, a
//! vertex on another edge). The tests use exact orientation predicates
//! ([`crate::planar::orient`]), so a ring that passes is simple exactly, not
//! to a tolerance. Edges are binned on a grid first, so the check costs
//! about the number of edges, not its square.

use floe_dem::Vec2;

use crate::planar::{bounds, orient, signed_area};

/// The ring `raw` cleaned, checked simple and counter-clockwise; or why it
/// is not simple (with vertex indices of `raw`, 0-based, and where).
pub fn simple_ring(raw: &[Vec2]) -> Result<Vec<Vec2>, String> {
    if let Some(k) = raw
        .iter()
        .position(|v| !(v.x.is_finite() && v.y.is_finite()))
    {
        return Err(format!("vertex {k} is not a finite point"));
    }
    // Original indices kept for messages.
    let mut ring: Vec<(usize, Vec2)> = Vec::with_capacity(raw.len());
    for (k, &v) in raw.iter().enumerate() {
        if ring.last().is_none_or(|&(_, w)| w != v) {
            ring.push((k, v));
        }
    }
    while ring.len() > 1 && ring.first().map(|p| p.1) == ring.last().map(|p| p.1) {
        ring.pop();
    }
    if ring.len() < 3 {
        return Err(format!(
            "has {} distinct vertices; a polygon needs at least 3",
            ring.len()
        ));
    }
    if let Some((i, j, at)) = first_crossing(&ring) {
        return Err(format!(
            "is not simple: its edge from vertex {} crosses or touches its edge from vertex {} near ({:.1}, {:.1}) m",
            ring[i].0, ring[j].0, at.x, at.y
        ));
    }
    let mut points: Vec<Vec2> = ring.iter().map(|p| p.1).collect();
    let area = signed_area(&points);
    let (lo, hi) = bounds(&points);
    let extent = (hi - lo).max_element();
    // (Finite: every vertex is.)
    if area.abs() <= 1e-12 * extent * extent {
        return Err("has no area".to_string());
    }
    if area < 0.0 {
        points.reverse();
    }
    Ok(drop_straight_vertices(points))
}

/// Removes vertices exactly collinear with their neighbours (the ring goes
/// straight through them; a simple ring never folds back).
fn drop_straight_vertices(mut p: Vec<Vec2>) -> Vec<Vec2> {
    loop {
        let n = p.len();
        if n <= 3 {
            return p;
        }
        let keep: Vec<bool> = (0..n)
            .map(|i| orient(p[(i + n - 1) % n], p[i], p[(i + 1) % n]) != 0.0)
            .collect();
        if keep.iter().all(|&k| k) {
            return p;
        }
        // One at a time from each run, so that no run vanishes whole.
        let drop = keep.iter().position(|&k| !k).expect("one to drop");
        p.remove(drop);
    }
}

/// Whether the closed segments `p1 p2` and `q1 q2` share a point.
fn segments_meet(p1: Vec2, p2: Vec2, q1: Vec2, q2: Vec2) -> bool {
    let (o1, o2) = (orient(p1, p2, q1), orient(p1, p2, q2));
    let (o3, o4) = (orient(q1, q2, p1), orient(q1, q2, p2));
    let on = |a: Vec2, b: Vec2, c: Vec2| {
        c.x >= a.x.min(b.x) && c.x <= a.x.max(b.x) && c.y >= a.y.min(b.y) && c.y <= a.y.max(b.y)
    };
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && on(p1, p2, q1))
        || (o2 == 0.0 && on(p1, p2, q2))
        || (o3 == 0.0 && on(q1, q2, p1))
        || (o4 == 0.0 && on(q1, q2, p2))
}

/// Two edges of the ring that cross or touch (by their first vertex's
/// position in `ring`), and a point near where; adjacent edges may share
/// their common vertex but not fold back over each other.
fn first_crossing(ring: &[(usize, Vec2)]) -> Option<(usize, usize, Vec2)> {
    let n = ring.len();
    let v = |i: usize| ring[i % n].1;
    // Adjacent edges: only a fold back (a spike) overlaps them.
    for i in 0..n {
        let (a, b, c) = (v(i), v(i + 1), v(i + 2));
        if orient(a, b, c) == 0.0 && (b - a).dot(c - b) < 0.0 {
            return Some((i, (i + 1) % n, b));
        }
    }
    let (lo, hi) = bounds(&ring.iter().map(|p| p.1).collect::<Vec<_>>());
    let size = (hi - lo).max(Vec2::splat(f64::MIN_POSITIVE));
    // Cells so that there are about as many as edges, widened while the
    // edges would cover far more cells than there are edges.
    let mut cell = (size.x * size.y / n as f64)
        .sqrt()
        .max(size.max_element() / n as f64);
    let cells_of = |i: usize, cell: f64| {
        let (a, b) = (v(i), v(i + 1));
        let c0 = ((a.min(b) - lo) / cell).floor();
        let c1 = ((a.max(b) - lo) / cell).floor();
        (c0, c1)
    };
    loop {
        let covered: f64 = (0..n)
            .map(|i| {
                let (c0, c1) = cells_of(i, cell);
                (c1.x - c0.x + 1.0) * (c1.y - c0.y + 1.0)
            })
            .sum();
        if covered <= 16.0 * n as f64 + 64.0 {
            break;
        }
        cell *= 2.0;
    }
    let nx = ((size.x / cell).floor() as usize) + 1;
    let mut bins: std::collections::HashMap<usize, Vec<usize>> = std::collections::HashMap::new();
    for i in 0..n {
        let (c0, c1) = cells_of(i, cell);
        for cy in c0.y as usize..=c1.y as usize {
            for cx in c0.x as usize..=c1.x as usize {
                bins.entry(cy * nx + cx).or_default().push(i);
            }
        }
    }
    let mut keys: Vec<usize> = bins.keys().copied().collect();
    keys.sort_unstable();
    let mut found: Option<(usize, usize, Vec2)> = None;
    for key in keys {
        let edges = &bins[&key];
        for (s, &i) in edges.iter().enumerate() {
            for &j in &edges[s + 1..] {
                let (i, j) = (i.min(j), i.max(j));
                let adjacent = j == i + 1 || (i == 0 && j == n - 1);
                if adjacent || found.is_some_and(|f| (f.0, f.1) <= (i, j)) {
                    continue;
                }
                if segments_meet(v(i), v(i + 1), v(j), v(j + 1)) {
                    found = Some((i, j, 0.5 * (v(i) + v(i + 1))));
                }
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(p: &[(f64, f64)]) -> Vec<Vec2> {
        p.iter().map(|&(x, y)| Vec2::new(x, y)).collect()
    }

    #[test]
    fn a_closed_clockwise_square_with_a_straight_vertex_is_cleaned() {
        let r = simple_ring(&pts(&[
            (0.0, 0.0),
            (0.0, 1.0),
            (1.0, 1.0),
            (1.0, 0.5),
            (1.0, 0.0),
            (0.0, 0.0),
        ]))
        .unwrap();
        assert_eq!(r.len(), 4);
        assert!(signed_area(&r) > 0.0);
    }

    #[test]
    fn figure_eights_spikes_and_touching_vertices_are_refused() {
        let eight = pts(&[(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]);
        assert!(simple_ring(&eight).unwrap_err().contains("not simple"));
        let spike = pts(&[(0.0, 0.0), (2.0, 0.0), (3.0, 0.0), (2.0, 0.0), (2.0, 1.0)]);
        assert!(simple_ring(&spike).is_err());
        // Vertex 4 touches edge 0-1 from inside.
        let touch = pts(&[
            (0.0, 0.0),
            (4.0, 0.0),
            (4.0, 4.0),
            (2.0, 4.0),
            (2.0, 0.0),
            (0.0, 4.0),
        ]);
        assert!(simple_ring(&touch).unwrap_err().contains("not simple"));
        assert!(simple_ring(&pts(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)])).is_err());
        assert!(simple_ring(&pts(&[(0.0, 0.0), (1.0, 0.0)])).is_err());
        assert!(simple_ring(&pts(&[(0.0, 0.0), (f64::NAN, 0.0), (1.0, 1.0)])).is_err());
    }
}
