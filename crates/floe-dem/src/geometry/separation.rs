//! A lower bound on the distance between two convex floes, for the broad
//! phase: a candidate pair whose floes are farther apart than both can move
//! before the next rebuild is left out of the list.
//!
//! Hand-rolled, not parry's `distance` (GJK): the broad phase needs a bound
//! that is never above the true distance, which the separating-axis form
//! below is by construction, while GJK returns the distance to within a
//! tolerance, from either side. Its cost (a few cross products per pair,
//! once per rebuild) does not matter.

use crate::geometry::cross;
use crate::Vec2;

/// The largest gap between `a` and `b` along the outward normal of an edge
/// of either: for an edge of `a` (counter-clockwise, so the interior is on
/// its left), how far every vertex of `b` lies beyond the edge's line, the
/// nearest vertex deciding, less how far any vertex of `a` itself lies
/// beyond it; then the same with the roles swapped. Both polygons
/// counter-clockwise, in one frame; m.
///
/// It is at most the Euclidean distance between the polygons: `a` lies
/// within its farthest vertex of each of its edge lines (on the inner side
/// for a convex polygon, its vertices then adding nothing), so any point of
/// `b` is at least its distance beyond that line, less that, away from
/// `a`; and over `b` that distance is least at a vertex. Allowing for `a`'s
/// own vertices keeps the bound for floes that are convex only to the
/// tolerance that `FloeShape` accepts, where a vertex beside a very short
/// edge may lie beyond that edge's line. It equals the distance where the
/// nearest features are an edge and a vertex, and is negative when the
/// floes overlap.
pub fn separation_lower_bound(a: &[Vec2], b: &[Vec2]) -> f64 {
    beyond_edges(a, b).max(beyond_edges(b, a))
}

/// The largest, over the edges of `p`, of the least distance of a vertex of
/// `q` beyond that edge's line, less the greatest of a vertex of `p`.
fn beyond_edges(p: &[Vec2], q: &[Vec2]) -> f64 {
    let outward = |dir: Vec2, s: Vec2, v: Vec2| -cross(dir, v - s);
    let mut best = f64::NEG_INFINITY;
    for (k, &s) in p.iter().enumerate() {
        let e = p[(k + 1) % p.len()];
        let dir = e - s;
        let nearest = q
            .iter()
            .map(|&v| outward(dir, s, v))
            .fold(f64::INFINITY, f64::min);
        let length = dir.length();
        // `own` (>= 0) can only lower this edge's gap: skip it where the
        // gap could not win anyway (most edges of a pair that touches).
        if nearest / length <= best {
            continue;
        }
        let own = p.iter().map(|&v| outward(dir, s, v)).fold(0.0, f64::max);
        best = best.max((nearest - own) / length);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry2d_f64::math::Pose;
    use parry2d_f64::shape::ConvexPolygon;

    /// A convex polygon: points at sorted angles on an ellipse, rotated and
    /// shifted.
    fn convex(angles: &[f64], (sx, sy): (f64, f64), turn: f64, at: Vec2) -> Vec<Vec2> {
        let mut angles = angles.to_vec();
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|x, y| (*x - *y).abs() < 0.05);
        let (s, c) = turn.sin_cos();
        angles
            .iter()
            .map(|t| {
                let v = Vec2::new(sx * t.cos(), sy * t.sin());
                at + crate::geometry::rotate(v, c, s)
            })
            .collect()
    }

    /// The distance between two convex polygons by parry's GJK.
    fn parry_distance(a: &[Vec2], b: &[Vec2]) -> f64 {
        let shape = |v: &[Vec2]| ConvexPolygon::from_convex_polyline(v.to_vec()).expect("convex");
        parry2d_f64::query::distance(&Pose::IDENTITY, &shape(a), &Pose::IDENTITY, &shape(b))
            .expect("distance")
            .distance
    }

    #[test]
    fn two_squares_side_by_side_are_as_far_apart_as_their_gap() {
        let square = |x: f64| {
            vec![
                Vec2::new(x, 0.0),
                Vec2::new(x + 1.0, 0.0),
                Vec2::new(x + 1.0, 1.0),
                Vec2::new(x, 1.0),
            ]
        };
        assert_eq!(separation_lower_bound(&square(0.0), &square(3.0)), 2.0);
        assert_eq!(separation_lower_bound(&square(3.0), &square(0.0)), 2.0);
        // Edge to edge: zero; overlapping by a quarter: minus the depth.
        assert_eq!(separation_lower_bound(&square(0.0), &square(1.0)), 0.0);
        assert_eq!(separation_lower_bound(&square(0.0), &square(0.75)), -0.25);
    }

    #[test]
    fn diamonds_two_lattice_cells_apart_are_a_side_times_sin_60_apart() {
        // The far candidate pairs of a 60-degree rhombus lattice: cells at
        // 2 a1 - a2 do not touch, and lie sqrt(3)/2 of a side away.
        let (a1, a2) = (Vec2::new(1.0, 0.0), Vec2::new(0.5, 0.75f64.sqrt()));
        let cell = |o: Vec2| vec![o, o + a1, o + a1 + a2, o + a2];
        let far = separation_lower_bound(&cell(Vec2::ZERO), &cell(2.0 * a1 - a2));
        assert!((far - 0.75f64.sqrt()).abs() < 1e-15, "{far}");
        // Vertex neighbours touch at a point.
        let vertex = separation_lower_bound(&cell(Vec2::ZERO), &cell(a1 + a2));
        assert!(vertex.abs() < 1e-15, "{vertex}");
    }

    #[test]
    fn a_vertex_beyond_a_tiny_edge_of_a_nearly_convex_floe_is_allowed_for() {
        // A 2 m x 1 m floe whose top right corner doubles back by 4e-13 m:
        // a reflex turn of -8e-13 m^2, which FloeShape accepts (it allows
        // -1e-12 extent^2, extent 1 m here). The tiny edge points straight down, so its line
        // is x = 2 with the floe itself beyond it. Measured from that line
        // alone, the neighbour 0.01 m above the floe would seem 0.5 m away.
        let floe = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(2.0, 1.0),
            Vec2::new(2.0, 1.0 - 4e-13),
            Vec2::new(0.0, 1.0),
        ];
        assert!(crate::geometry::FloeShape::from_world(0, &floe).is_ok());
        let neighbour = [
            Vec2::new(0.5, 1.01),
            Vec2::new(1.5, 1.01),
            Vec2::new(1.5, 2.0),
            Vec2::new(0.5, 2.0),
        ];
        for bound in [
            separation_lower_bound(&floe, &neighbour),
            separation_lower_bound(&neighbour, &floe),
        ] {
            assert!(bound <= 0.01 + 1e-12, "bound {bound}");
        }
    }

    proptest::proptest! {
        /// Never above the distance that parry's GJK computes, and positive
        /// whenever the floes are apart: two disjoint convex polygons are
        /// separated along the normal of one of their edges.
        #[test]
        fn the_bound_is_never_above_the_distance(
            angles_a in proptest::collection::vec(0.0..std::f64::consts::TAU, 3..10),
            angles_b in proptest::collection::vec(0.0..std::f64::consts::TAU, 3..10),
            scale_a in (0.3..3.0f64, 0.3..3.0f64),
            scale_b in (0.3..3.0f64, 0.3..3.0f64),
            turn in 0.0..std::f64::consts::TAU,
            at in (-8.0..8.0f64, -8.0..8.0f64),
        ) {
            let a = convex(&angles_a, scale_a, 0.0, Vec2::ZERO);
            let b = convex(&angles_b, scale_b, turn, Vec2::new(at.0, at.1));
            proptest::prop_assume!(a.len() >= 3 && b.len() >= 3);
            let bound = separation_lower_bound(&a, &b);
            let distance = parry_distance(&a, &b);
            // parry reports 0 for overlapping shapes; the bound is then <= 0.
            proptest::prop_assert!(bound <= distance + 1e-9, "bound {} distance {}", bound, distance);
            if distance > 1e-6 {
                proptest::prop_assert!(bound > 0.0, "bound {} distance {}", bound, distance);
            }
        }
    }
}
