//! Small planar-geometry helpers shared by the land modules: signed area,
//! exact orientation, the lexicographic order of points, point in polygon,
//! and the intersection of two convex polygons. Areas are computed about
//! the polygon's first vertex, so that a polygon far from the origin
//! (projected coordinates reach 1e6 m) keeps its digits.

use std::cmp::Ordering;

use floe_dem::Vec2;

/// Sign of the turn `a -> b -> c`: positive counter-clockwise, zero when
/// collinear. Exact (Shewchuk's adaptive predicate, the `robust` crate).
pub fn orient(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    let p = |v: Vec2| robust::Coord { x: v.x, y: v.y };
    robust::orient2d(p(a), p(b), p(c))
}

/// Lexicographic order of points (x, then y; `-0.0` equals `0.0`); for
/// finite coordinates.
pub fn lexicographic(a: Vec2, b: Vec2) -> Ordering {
    a.x.partial_cmp(&b.x)
        .unwrap_or(Ordering::Equal)
        .then(a.y.partial_cmp(&b.y).unwrap_or(Ordering::Equal))
}

/// Signed area of a polygon (positive counter-clockwise), m^2.
pub fn signed_area(p: &[Vec2]) -> f64 {
    let Some(&o) = p.first() else {
        return 0.0;
    };
    let mut twice = 0.0;
    for w in p[1..].windows(2) {
        let (u, v) = (w[0] - o, w[1] - o);
        twice += u.x * v.y - u.y * v.x;
    }
    0.5 * twice
}

/// Centroid of a polygon of non-zero area.
pub fn centroid(p: &[Vec2]) -> Vec2 {
    let o = p[0];
    let (mut a2, mut c) = (0.0, Vec2::ZERO);
    for w in p[1..].windows(2) {
        let (u, v) = (w[0] - o, w[1] - o);
        let k = u.x * v.y - u.y * v.x;
        a2 += k;
        c += (u + v) * k;
    }
    if a2 == 0.0 {
        return o;
    }
    o + c / (3.0 * a2)
}

/// Whether `q` lies inside the polygon `ring` (even-odd rule; points on
/// the boundary may go either way).
pub fn contains(ring: &[Vec2], q: Vec2) -> bool {
    let n = ring.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (ring[i], ring[j]);
        if (a.y > q.y) != (b.y > q.y) {
            let x = a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if q.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// The part of the convex polygon `subject` on the left of the directed
/// line `a -> b` (Sutherland-Hodgman, one clip line).
pub fn clip_left(subject: &[Vec2], a: Vec2, b: Vec2) -> Vec<Vec2> {
    let d = b - a;
    let side = |p: Vec2| d.x * (p.y - a.y) - d.y * (p.x - a.x);
    let mut out = Vec::with_capacity(subject.len() + 1);
    let n = subject.len();
    for i in 0..n {
        let (p, q) = (subject[i], subject[(i + 1) % n]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            let t = sp / (sp - sq);
            out.push(p + (q - p) * t);
        }
    }
    out
}

/// Area of the intersection of two convex polygons (either orientation),
/// m^2. Both are placed about the first one's first vertex.
pub fn convex_intersection_area(a: &[Vec2], b: &[Vec2]) -> f64 {
    if a.len() < 3 || b.len() < 3 {
        return 0.0;
    }
    let o = a[0];
    let ccw = |p: &[Vec2]| {
        let mut v: Vec<Vec2> = p.iter().map(|&q| q - o).collect();
        if signed_area(&v) < 0.0 {
            v.reverse();
        }
        v
    };
    let (a, b) = (ccw(a), ccw(b));
    let mut out = a;
    for i in 0..b.len() {
        if out.len() < 3 {
            return 0.0;
        }
        out = clip_left(&out, b[i], b[(i + 1) % b.len()]);
    }
    if out.len() < 3 {
        return 0.0;
    }
    signed_area(&out).max(0.0)
}

/// Axis-aligned bounds `(min, max)` of points.
pub fn bounds(p: &[Vec2]) -> (Vec2, Vec2) {
    p.iter().fold(
        (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &q| (lo.min(q), hi.max(q)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_unit_squares_shifted_by_half_overlap_by_half() {
        let sq = |x: f64, y: f64| {
            vec![
                Vec2::new(x, y),
                Vec2::new(x + 1.0, y),
                Vec2::new(x + 1.0, y + 1.0),
                Vec2::new(x, y + 1.0),
            ]
        };
        let a = sq(1e6, 1e6);
        let mut b = sq(1e6 + 0.5, 1e6);
        b.reverse();
        assert!((convex_intersection_area(&a, &b) - 0.5).abs() < 1e-9);
        assert_eq!(convex_intersection_area(&a, &sq(1e6 + 1.0, 1e6)), 0.0);
        assert!(contains(&a, Vec2::new(1e6 + 0.5, 1e6 + 0.5)));
        assert!(!contains(&a, Vec2::new(1e6 + 1.5, 1e6 + 0.5)));
        assert!((centroid(&a) - Vec2::new(1e6 + 0.5, 1e6 + 0.5)).length() < 1e-9);
    }
}
