//! Floe outlines for tests.

use floe_dem::Vec2;

/// The corners of a `w` x `h` rectangle centred on `center`,
/// counter-clockwise.
pub fn rect(center: Vec2, w: f64, h: f64) -> Vec<Vec2> {
    let (a, b) = (0.5 * w, 0.5 * h);
    vec![
        center + Vec2::new(-a, -b),
        center + Vec2::new(a, -b),
        center + Vec2::new(a, b),
        center + Vec2::new(-a, b),
    ]
}
