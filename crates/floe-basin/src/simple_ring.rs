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
//! to a tolerance. The check is a sweep line ([`crate::ring_crossing`]):
//! `O(n log n)` for `n` vertices whatever the ring's shape.

use floe_dem::Vec2;

use crate::planar::{bounds, orient, signed_area};
use crate::ring_crossing::{meeting_edges, meeting_point};

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
    let mut points: Vec<Vec2> = ring.iter().map(|p| p.1).collect();
    if let Some((i, j)) = meeting_edges(&points) {
        let n = points.len();
        let at = meeting_point(
            points[i],
            points[(i + 1) % n],
            points[j],
            points[(j + 1) % n],
        );
        return Err(format!(
            "is not simple: its edge from vertex {} crosses or touches its edge from vertex {} near ({:.1}, {:.1}) m",
            ring[i].0, ring[j].0, at.x, at.y
        ));
    }
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
/// straight through them; a simple ring never folds back, so a vertex that
/// is not straight between its first neighbours stays a corner once the
/// straight ones around it are gone).
fn drop_straight_vertices(p: Vec<Vec2>) -> Vec<Vec2> {
    let n = p.len();
    let kept: Vec<Vec2> = (0..n)
        .filter(|&i| orient(p[(i + n - 1) % n], p[i], p[(i + 1) % n]) != 0.0)
        .map(|i| p[i])
        .collect();
    if kept.len() >= 3 {
        kept
    } else {
        p
    }
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
