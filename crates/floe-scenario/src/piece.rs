//! One floe to be created from a scenario: its polygon, thickness, motion
//! and where it came from (shared by the builders of floes, walls and land).

use std::ops::Range;

use floe_dem::motion_schedule::MotionSchedule;
use floe_dem::Vec2;

/// One floe to be created.
pub(crate) struct Piece {
    pub polygon: Vec<Vec2>,
    pub thickness_m: f64,
    pub velocity: Vec2,
    pub angular_velocity: f64,
    pub prescribed: bool,
    /// The motion schedule of a prescribed piece that has one.
    pub schedule: Option<MotionSchedule>,
    /// The load point (stiffness, N/m, and schedule) of a free piece.
    pub load_point: Option<(f64, MotionSchedule)>,
    /// What it is, for messages (`floe[3]`, `wall[0] (bottom)`...).
    pub label: Option<String>,
    /// Where it was written, for explicit floes.
    pub span: Option<Range<usize>>,
}

impl Piece {
    /// The mean of its vertices (a point inside it), m.
    pub(crate) fn vertex_mean(&self) -> Vec2 {
        self.polygon.iter().fold(Vec2::ZERO, |a, &b| a + b) / self.polygon.len() as f64
    }
}
