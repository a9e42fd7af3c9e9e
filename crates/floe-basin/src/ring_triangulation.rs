//! The triangles of a simple polygon: spade's constrained Delaunay
//! triangulation of its vertices with its edges as constraints, the
//! triangles inside the ring kept, and the diagonals between them listed.
//!
//! Exact: spade decides with the same adaptive predicates as
//! [`crate::planar::orient`] (the `robust` crate), and a simple ring's
//! edges neither cross nor pass through a vertex, so no vertex is added
//! and the triangles tile the polygon with no gap and no overlap. Its bulk
//! loading (a circle sweep, then each constraint inserted as its second
//! vertex arrives) takes `O(n log n)` for a coastline; a constraint that
//! crosses many Delaunay edges of the vertices alone costs their number.
//!
//! The vertices are handed over sorted (x, then y) and the edges in a
//! fixed order, so the triangulation depends on the polygon alone, not on
//! which vertex the ring starts from.

use floe_dem::Vec2;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::planar::lexicographic as lex;

/// A polygon cut into triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct RingTriangles {
    /// The ring's vertices, sorted by x then y, m.
    pub points: Vec<Vec2>,
    /// Triangles, counter-clockwise, as indices into `points`.
    pub triangles: Vec<[u32; 3]>,
    /// Edges shared by two triangles: their ends (into `points`) and the
    /// two triangles (into `triangles`).
    pub diagonals: Vec<Diagonal>,
}

/// An edge shared by two triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Diagonal {
    /// Its ends, indices into [`RingTriangles::points`].
    pub ends: [u32; 2],
    /// The triangles on either side, indices into
    /// [`RingTriangles::triangles`].
    pub triangles: [u32; 2],
}

/// The triangles of the simple, counter-clockwise ring `ring` (as
/// [`crate::simple_ring::simple_ring`] returns it).
///
/// # Errors
/// Why not, if the ring turns out not to be simple (two constraints cross,
/// a vertex lies on an edge, a vertex repeats), is clockwise, or has a
/// coordinate spade refuses (nonzero below `1.8e-43` m in magnitude, or
/// above `3.2e60` m).
pub fn triangulate(ring: &[Vec2]) -> Result<RingTriangles, String> {
    let n = ring.len();
    if n < 3 {
        return Err("fewer than 3 vertices".into());
    }
    if n > u32::MAX as usize / 2 {
        return Err(format!("{n} vertices, more than a triangulation holds"));
    }
    let tiny = |c: f64| c != 0.0 && c.abs() < spade::MIN_ALLOWED_VALUE;
    if let Some(v) = ring.iter().find(|v| tiny(v.x) || tiny(v.y)) {
        return Err(format!(
            "its vertex at ({:e}, {:e}) m has a coordinate nearer 0 than {:e} m but not 0, \
             finer than the triangulation takes",
            v.x,
            v.y,
            spade::MIN_ALLOWED_VALUE
        ));
    }
    // rank[k]: where ring vertex k is among the sorted points.
    let mut by_position: Vec<u32> = (0..n as u32).collect();
    by_position.sort_unstable_by(|&a, &b| lex(ring[a as usize], ring[b as usize]));
    let mut rank = vec![0u32; n];
    for (r, &k) in by_position.iter().enumerate() {
        rank[k as usize] = r as u32;
    }
    let points: Vec<Vec2> = by_position.iter().map(|&k| ring[k as usize]).collect();
    let ring_edges: Vec<[u32; 2]> = (0..n).map(|k| [rank[k], rank[(k + 1) % n]]).collect();
    let mut constraints: Vec<[usize; 2]> = ring_edges
        .iter()
        .map(|&[a, b]| [a.min(b) as usize, a.max(b) as usize])
        .collect();
    constraints.sort_unstable();
    let vertices: Vec<Point2<f64>> = points.iter().map(|p| Point2::new(p.x, p.y)).collect();
    let mut conflicts = 0usize;
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(vertices, constraints, |_| {
            conflicts += 1
        })
        .map_err(|e| format!("a vertex cannot be triangulated: {e}"))?;
    if cdt.num_vertices() != n || conflicts > 0 || cdt.num_constraints() != n {
        return Err("its edges cross or touch (the ring is not simple)".into());
    }
    // The triangles left of the ring's edges, and those reached from them
    // without crossing an edge of the ring.
    let mut inside = vec![false; cdt.num_all_faces()];
    let mut todo = Vec::new();
    let fix = |r: u32| FixedVertexHandle::from_index(r as usize);
    for &[a, b] in &ring_edges {
        let edge = cdt
            .get_edge_from_neighbors(fix(a), fix(b))
            .ok_or("an edge of the ring is missing from the triangulation (not simple)")?;
        let face = edge.face().as_inner().ok_or("the ring is clockwise")?;
        if !inside[face.index()] {
            inside[face.index()] = true;
            todo.push(face.fix());
        }
    }
    while let Some(f) = todo.pop() {
        for edge in cdt.face(f).adjacent_edges() {
            if edge.as_undirected().is_constraint_edge() {
                continue;
            }
            let next = edge
                .rev()
                .face()
                .as_inner()
                .ok_or("the ring's edges do not enclose it (not simple)")?;
            if !inside[next.index()] {
                inside[next.index()] = true;
                todo.push(next.fix());
            }
        }
    }
    let mut triangle_of_face = vec![u32::MAX; cdt.num_all_faces()];
    let mut triangles = Vec::with_capacity(n - 2);
    for face in cdt.inner_faces() {
        if inside[face.index()] {
            triangle_of_face[face.index()] = triangles.len() as u32;
            triangles.push(face.vertices().map(|v| v.fix().index() as u32));
        }
    }
    if triangles.len() != n - 2 {
        return Err(format!(
            "{} triangles inside, not {} (the ring is not simple)",
            triangles.len(),
            n - 2
        ));
    }
    let diagonals = cdt
        .undirected_edges()
        .filter(|e| !e.is_constraint_edge())
        .filter_map(|e| {
            let d = e.as_directed();
            let s = triangle_of_face[d.face().index()];
            let t = triangle_of_face[d.rev().face().index()];
            (s != u32::MAX && t != u32::MAX).then(|| Diagonal {
                ends: [d.from().fix().index() as u32, d.to().fix().index() as u32],
                triangles: [s, t],
            })
        })
        .collect();
    Ok(RingTriangles {
        points,
        triangles,
        diagonals,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_is_two_triangles_and_a_tiny_coordinate_is_refused_by_name() {
        let p = |x: f64, y: f64| Vec2::new(x, y);
        let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
        let t = triangulate(&square).unwrap();
        assert_eq!((t.triangles.len(), t.diagonals.len()), (2, 1));
        let e = triangulate(&[p(0.0, 0.0), p(1.0, 1e-300), p(1.0, 1.0)]).unwrap_err();
        assert!(e.contains("1e-300"), "{e}");
        let e = triangulate(&[p(0.0, 0.0), p(0.0, 1.0), p(1.0, 0.0)]).unwrap_err();
        assert!(e.contains("clockwise"), "{e}");
    }
}
