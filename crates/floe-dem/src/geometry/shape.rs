//! A floe's shape: a convex polygon about its centroid, with area, polar
//! second moment and bounding radius.

use crate::error::DemError;
use crate::geometry::cross;
use crate::Vec2;

/// A convex polygon in the floe's own frame: vertices counter-clockwise,
/// relative to the centroid (m).
#[derive(Debug, Clone, PartialEq)]
pub struct FloeShape {
    /// Vertices, counter-clockwise, relative to the centroid, m.
    pub vertices: Vec<Vec2>,
    /// Area, m^2.
    pub area_m2: f64,
    /// Polar second moment of area about the centroid, `int r^2 dA`, m^4
    /// (moment of inertia = density x thickness x this).
    pub polar_moment_m4: f64,
    /// Largest distance from the centroid to a vertex, m.
    pub radius_m: f64,
}

impl FloeShape {
    /// The shape of a convex polygon given in world coordinates, and the
    /// world position of its centroid. Accepts either orientation (returns
    /// counter-clockwise); refuses fewer than 3 vertices, non-finite
    /// coordinates, zero area and non-convex polygons.
    pub fn from_world(index: usize, polygon: &[Vec2]) -> Result<(Self, Vec2), DemError> {
        let bad = |reason: &str| DemError::InvalidFloe {
            index,
            reason: reason.to_string(),
        };
        if polygon.len() < 3 {
            return Err(bad("a floe needs at least 3 vertices"));
        }
        if polygon.len() > crate::geometry::MAX_VERTICES {
            return Err(bad(&format!(
                "more than {} vertices",
                crate::geometry::MAX_VERTICES
            )));
        }
        if polygon.iter().any(|v| !v.x.is_finite() || !v.y.is_finite()) {
            return Err(bad("vertex coordinates must be finite"));
        }
        // Work relative to the first vertex: world coordinates reach 1e6 m.
        let origin = polygon[0];
        let local: Vec<Vec2> = polygon.iter().map(|&v| v - origin).collect();
        let (area, centroid) = area_and_centroid(&local);
        if area.abs() <= f64::EPSILON * bounding_extent(&local).powi(2) {
            return Err(bad("zero area"));
        }
        let mut vertices: Vec<Vec2> = local.iter().map(|&v| v - centroid).collect();
        if area < 0.0 {
            vertices.reverse();
        }
        if !is_convex_ccw(&vertices) {
            return Err(bad("not convex"));
        }
        let shape = Self {
            polar_moment_m4: polar_moment(&vertices),
            radius_m: vertices.iter().map(|v| v.length()).fold(0.0, f64::max),
            area_m2: area.abs(),
            vertices,
        };
        Ok((shape, origin + centroid))
    }
}

/// Signed area (positive counter-clockwise) and centroid of a polygon.
///
/// Computed relative to the first vertex: the shoelace sums cancel badly for
/// a small polygon far from the origin (a 1 cm overlap 1.5 km from its
/// frame's origin lost four digits of its centroid).
pub fn area_and_centroid(p: &[Vec2]) -> (f64, Vec2) {
    let n = p.len();
    if n == 0 {
        return (0.0, Vec2::ZERO);
    }
    let o = p[0];
    let (mut a2, mut c) = (0.0, Vec2::ZERO);
    // The first and last edges (from and to `p[0]`) are skipped, and with
    // them the wrap-around `% n` (this runs for every clipped pair): for
    // finite vertices one of their ends is `p[0] - o = +0`, so they would add
    // a signed zero, which leaves the sums' bits unchanged (they start at +0,
    // and a sum never becomes -0 unless both terms are -0).
    for edge in p[1..].windows(2) {
        let (u, v) = (edge[0] - o, edge[1] - o);
        let w = cross(u, v);
        a2 += w;
        c += (u + v) * w;
    }
    if a2 == 0.0 {
        return (0.0, o);
    }
    (0.5 * a2, o + c / (3.0 * a2))
}

/// `int (x^2 + y^2) dA` about the origin, for a counter-clockwise polygon.
pub fn polar_moment(p: &[Vec2]) -> f64 {
    let n = p.len();
    let mut sum = 0.0;
    for i in 0..n {
        let (u, v) = (p[i], p[(i + 1) % n]);
        sum += cross(u, v) * (u.dot(u) + u.dot(v) + v.dot(v));
    }
    sum / 12.0
}

fn bounding_extent(p: &[Vec2]) -> f64 {
    p.iter()
        .map(|v| v.x.abs().max(v.y.abs()))
        .fold(0.0, f64::max)
}

/// Every turn is a left turn (or straight, to round-off relative to the size).
fn is_convex_ccw(p: &[Vec2]) -> bool {
    let n = p.len();
    let scale = bounding_extent(p).powi(2);
    (0..n).all(|i| cross(p[(i + 1) % n] - p[i], p[(i + 2) % n] - p[(i + 1) % n]) >= -1e-12 * scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry2d_f64::mass_properties::MassProperties;

    #[test]
    fn rectangle_properties_are_analytic_at_any_offset() {
        for offset in [Vec2::ZERO, Vec2::new(1e6, -7e5)] {
            let (a, b) = (300.0, 120.0);
            let p = [
                Vec2::new(0.0, 0.0),
                Vec2::new(a, 0.0),
                Vec2::new(a, b),
                Vec2::new(0.0, b),
            ]
            .map(|v| v + offset);
            let (s, c) = FloeShape::from_world(0, &p).unwrap();
            assert!((s.area_m2 - a * b).abs() < 1e-9 * a * b);
            assert!((c - offset - Vec2::new(a / 2.0, b / 2.0)).length() < 1e-9);
            let j = a * b * (a * a + b * b) / 12.0;
            assert!((s.polar_moment_m4 - j).abs() < 1e-9 * j);
            assert!((s.radius_m - 0.5 * (a * a + b * b).sqrt()).abs() < 1e-9);
        }
    }

    #[test]
    fn mass_properties_agree_with_parry() {
        // A skewed pentagon, clockwise on input.
        let p = [
            Vec2::new(0.0, 0.0),
            Vec2::new(-20.0, 90.0),
            Vec2::new(60.0, 130.0),
            Vec2::new(140.0, 60.0),
            Vec2::new(100.0, -10.0),
        ];
        let (s, c) = FloeShape::from_world(0, &p).unwrap();
        let mut ccw = p.to_vec();
        ccw.reverse();
        let mp = MassProperties::from_convex_polygon(1.0, &ccw);
        assert!((mp.mass() - s.area_m2).abs() < 1e-9 * s.area_m2);
        assert!((mp.local_com - c).length() < 1e-9);
        assert!((mp.principal_inertia() - s.polar_moment_m4).abs() < 1e-9 * s.polar_moment_m4);
    }

    #[test]
    fn bad_polygons_are_errors() {
        let v = |x, y| Vec2::new(x, y);
        assert!(FloeShape::from_world(3, &[v(0.0, 0.0), v(1.0, 0.0)]).is_err());
        assert!(FloeShape::from_world(3, &[v(0.0, 0.0), v(1.0, 0.0), v(2.0, 0.0)]).is_err());
        assert!(FloeShape::from_world(
            3,
            &[
                v(0.0, 0.0),
                v(2.0, 0.0),
                v(1.0, 0.2),
                v(2.0, 2.0),
                v(0.0, 2.0)
            ]
        )
        .is_err());
        assert!(FloeShape::from_world(3, &[v(0.0, 0.0), v(f64::NAN, 0.0), v(1.0, 1.0)]).is_err());
    }
}
