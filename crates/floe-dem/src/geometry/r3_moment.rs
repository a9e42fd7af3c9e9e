//! `∫ r³ dA` of a polygon about its centroid: the moment the rotational
//! drag of [`crate::forcing::drag`] needs, a property of the floe's shape.
//!
//! [`polygon_r3_moment`] splits the polygon into triangles `(0, a, b)` from
//! the reference point (signed, so it works for any simple polygon and any
//! reference point). With the Duffy map `p = s (a + t (b − a))`,
//! `dA = s |a × b| ds dt`, the radial integral is exact,
//! `∫₀¹ s⁴ ds = 1/5`, and the remaining line integral along the edge has a
//! closed form: with `x` the coordinate along the edge line measured from the
//! foot of the perpendicular, `c` the distance of the line from the origin
//! and `L = |b − a|`,
//!
//! ```text
//! ∫_(0,a,b) r³ dA = (a × b)/(5 L) · [H(x_b) − H(x_a)],
//! H(x) = x (2x² + 5c²) √(x² + c²) / 8 + (3/8) c⁴ asinh(x / c),   H' = (x² + c²)^{3/2}.
//! ```
//!
//! So the "quadrature" is exact up to rounding (relative error ~1e-15 for
//! floes whose edges are not tiny compared with their distance from the
//! centroid). Disc of radius `R`: `2π R⁵/5`; square of half-side `a`:
//! `a⁵ (7√2 + 3 ln(1 + √2)) / 5 ≈ 2.50872 a⁵`.

use crate::Vec2;

/// `∫ (x² + c²)^{3/2} dx` (antiderivative; `c ≥ 0`).
#[inline]
fn h(x: f64, c: f64) -> f64 {
    let q = (x * x + c * c).sqrt();
    let algebraic = x * (2.0 * x * x + 5.0 * c * c) * q / 8.0;
    if c == 0.0 {
        algebraic
    } else {
        let c2 = c * c;
        algebraic + 0.375 * c2 * c2 * (x / c).asinh()
    }
}

/// `∫ r³ dA` over a simple polygon, m⁵, with `r` measured from the origin of
/// the vertex coordinates: pass the vertices relative to the centroid (m), in
/// either orientation, without repeating the first vertex. Exact up to
/// rounding (closed form per fan triangle, see the module docs). Fewer than
/// three vertices give 0. Never allocates.
pub fn polygon_r3_moment(vertices_rel_centroid_m: &[Vec2]) -> f64 {
    let n = vertices_rel_centroid_m.len();
    if n < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..n {
        let a = vertices_rel_centroid_m[i];
        let b = vertices_rel_centroid_m[(i + 1) % n];
        let e = b - a;
        let len = e.length();
        if len == 0.0 {
            continue;
        }
        let cross = a.perp_dot(b); // twice the signed triangle area
        let c = (cross / len).abs(); // distance of the edge line from the origin
        let xa = a.dot(e) / len;
        let xb = b.dot(e) / len;
        sum += cross / (5.0 * len) * (h(xb, c) - h(xa, c));
    }
    sum.abs()
}
