//! `tessellation.fill_fraction` (voronoi, with or without a size
//! distribution): each floe shrunk about its centroid to a fraction of its
//! cell's area, for a loose start.

use floe_dem::tessellation::Tessellation;

use super::Keys;
use crate::error::ScenarioError;
use crate::numbers::sig;
use crate::resolve::limits::within;

/// Smallest `fill_fraction`: below it the floes are far apart, not a pack.
const MIN_FILL_FRACTION: f64 = 0.1;

/// `tessellation.fill_fraction`: the fraction of its cell's area each floe
/// keeps, shrunk about its centroid (default 1: the cells fill the region).
pub(super) fn fill_fraction(k: &Keys<'_>) -> Result<f64, ScenarioError> {
    match &k.t.fill_fraction {
        Some(v) => within(
            k.f,
            v,
            "tessellation.fill_fraction",
            MIN_FILL_FRACTION,
            1.0,
            false,
        ),
        None => Ok(1.0),
    }
}

/// Shrinks the floes of `t` to `fill` of their cells' areas (nothing at
/// 1), with a report line.
pub(super) fn fill(t: &mut Tessellation, fill: f64, report: &mut Vec<String>) {
    if fill < 1.0 {
        t.shrink_floes(fill);
        report.push(format!(
            "  each floe shrunk about its centroid to {} of its cell's area (open water between the floes)",
            sig(fill)
        ));
    }
}
