//! What bounds a prescribed motion (a wall, a prescribed floe, a schedule):
//! the run's duration and its domain.

use crate::domain::Domain;

/// How far, in domain sizes, a prescribed floe or wall may travel across a
/// non-periodic axis: walls are built as long as their travel, so this
/// bounds their segments (along a periodic axis they wrap and nothing grows).
pub(crate) const MAX_TRAVEL_DOMAINS: f64 = 100.0;

/// What bounds a prescribed motion: the run's duration and its domain.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Extent {
    pub(crate) duration_s: f64,
    pub(crate) domain: Domain,
}

/// Fastest spin a file may give a floe or a schedule, rad/s (a turn in
/// 0.06 s; sea ice turns at most a few degrees an hour).
pub(crate) const MAX_ANGULAR_VELOCITY_RAD_PER_S: f64 = 100.0;
