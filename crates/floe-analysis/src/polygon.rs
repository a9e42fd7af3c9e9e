//! Convex-polygon helpers shared by the metrics: clipping to a half-plane,
//! area and centroid.

/// Keeps the part of `poly` where `inside(p) >= 0` (a half-plane).
pub(crate) fn clip(poly: &[[f64; 2]], inside: impl Fn(&[f64; 2]) -> f64) -> Vec<[f64; 2]> {
    let mut out = Vec::with_capacity(poly.len() + 2);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let (dp, dq) = (inside(&p), inside(&q));
        if dp >= 0.0 {
            out.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let t = dp / (dp - dq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

/// Unsigned area of a simple polygon (shoelace), m².
pub(crate) fn polygon_area(poly: &[[f64; 2]]) -> f64 {
    let mut twice = 0.0;
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        twice += p[0] * q[1] - q[0] * p[1];
    }
    0.5 * twice.abs()
}

/// Centroid of a simple polygon of (unsigned) area `area` > 0.
pub(crate) fn polygon_centroid(poly: &[[f64; 2]], area: f64) -> [f64; 2] {
    let (mut cx, mut cy, mut twice) = (0.0, 0.0, 0.0);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let cross = p[0] * q[1] - q[0] * p[1];
        twice += cross;
        cx += (p[0] + q[0]) * cross;
        cy += (p[1] + q[1]) * cross;
    }
    // The signed area carries the winding; `area` is its magnitude.
    let signed = 0.5 * twice;
    debug_assert!((signed.abs() - area).abs() <= 1e-9 * area.max(1.0));
    [cx / (6.0 * signed), cy / (6.0 * signed)]
}
