//! Convex-polygon helpers shared by the metrics: clipping to a half-plane
//! or to another convex polygon, area, centroid and bounding box.

/// Keeps the part of `poly` where `inside(p) >= 0` (a half-plane).
pub(crate) fn clip(poly: &[[f64; 2]], inside: impl Fn(&[f64; 2]) -> f64) -> Vec<[f64; 2]> {
    let mut out = Vec::with_capacity(poly.len() + 2);
    clip_into(poly, inside, &mut out);
    out
}

/// [`clip`] into `out` (cleared first).
fn clip_into(poly: &[[f64; 2]], inside: impl Fn(&[f64; 2]) -> f64, out: &mut Vec<[f64; 2]>) {
    out.clear();
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
}

/// Unsigned area of a simple polygon (shoelace), m². About the first
/// vertex, so that the round-off scales with the polygon's size rather than
/// its distance from the origin (floes kilometres out, cells of 100 m).
pub(crate) fn polygon_area(poly: &[[f64; 2]]) -> f64 {
    let Some(&o) = poly.first() else { return 0.0 };
    let mut twice = 0.0;
    for k in 1..poly.len().saturating_sub(1) {
        let (p, q) = (poly[k], poly[k + 1]);
        twice += (p[0] - o[0]) * (q[1] - o[1]) - (q[0] - o[0]) * (p[1] - o[1]);
    }
    0.5 * twice.abs()
}

/// Centroid of a simple polygon of (unsigned) area `area` > 0, found about
/// its first vertex as [`polygon_area`].
pub(crate) fn polygon_centroid(poly: &[[f64; 2]], area: f64) -> [f64; 2] {
    let o = poly[0];
    let (mut cx, mut cy, mut twice) = (0.0, 0.0, 0.0);
    for k in 1..poly.len().saturating_sub(1) {
        let (p, q) = (
            [poly[k][0] - o[0], poly[k][1] - o[1]],
            [poly[k + 1][0] - o[0], poly[k + 1][1] - o[1]],
        );
        let cross = p[0] * q[1] - q[0] * p[1];
        twice += cross;
        cx += (p[0] + q[0]) * cross;
        cy += (p[1] + q[1]) * cross;
    }
    // The signed area carries the winding; `area` is its magnitude.
    let signed = 0.5 * twice;
    debug_assert!((signed.abs() - area).abs() <= 1e-9 * area.max(1.0));
    [o[0] + cx / (6.0 * signed), o[1] + cy / (6.0 * signed)]
}

/// The intersection of two convex polygons (either winding): `a` clipped
/// by every edge of `b`; empty or degenerate (zero area) where they do not
/// overlap.
pub(crate) fn intersect_convex(a: &[[f64; 2]], b: &[[f64; 2]]) -> Vec<[f64; 2]> {
    // The side of b's edges its interior lies on: +1 counter-clockwise.
    let twice: f64 = (0..b.len())
        .map(|k| {
            let (p, q) = (b[k], b[(k + 1) % b.len()]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum();
    let side = if twice < 0.0 { -1.0 } else { 1.0 };
    // Two buffers in turn: each clip adds at most one vertex.
    let mut out = Vec::with_capacity(a.len() + b.len());
    out.extend_from_slice(a);
    let mut next = Vec::with_capacity(a.len() + b.len());
    for k in 0..b.len() {
        if out.is_empty() {
            break;
        }
        let (p, q) = (b[k], b[(k + 1) % b.len()]);
        let e = [q[0] - p[0], q[1] - p[1]];
        clip_into(
            &out,
            |x| side * (e[0] * (x[1] - p[1]) - e[1] * (x[0] - p[0])),
            &mut next,
        );
        std::mem::swap(&mut out, &mut next);
    }
    out
}

/// Lower-left and upper-right corners of the bounding box of `poly`.
pub(crate) fn bounds(poly: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    poly.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    )
}
