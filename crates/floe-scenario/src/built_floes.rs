//! What building a scenario's floes made: the floe set, where each floe
//! came from in the file (for located errors), and report lines.

use std::ops::Range;

use floe_dem::floes::Floes;
use floe_dem::motion_schedule::MotionSchedule;

/// The floes and what was done to make them.
pub(crate) struct BuiltFloes {
    pub floes: Floes,
    /// The motion schedules of prescribed floes, by floe id.
    pub schedules: Vec<(u64, MotionSchedule)>,
    /// The load points of free floes (stiffness, N/m, and schedule), by
    /// floe id; anchored where the floe starts.
    pub load_points: Vec<(u64, (f64, MotionSchedule))>,
    /// Walls that hold a normal stress.
    pub stress_walls: Vec<StressWall>,
    pub pieces_span: Vec<Option<Range<usize>>>,
    pub labels: Vec<Option<String>>,
    pub report: Vec<String>,
    /// Number of free floes.
    pub free: usize,
    /// Ids of the land pieces (fixed prescribed floes), increasing.
    pub land_ids: Vec<u64>,
}

/// A wall that holds a normal stress, as built: its pieces and geometry.
pub(crate) struct StressWall {
    /// `wall[index]` in the file.
    pub index: usize,
    /// Ids of its pieces, increasing.
    pub floe_ids: Vec<u64>,
    /// Unit normal into the ice.
    pub inward_normal: floe_dem::Vec2,
    /// The ice region's extent along the wall, m.
    pub length_m: f64,
    /// Compressive stress to hold, N/m.
    pub target_n_per_m: f64,
    /// The control's keys as the file gives them.
    pub control: crate::stress_wall::ControlKeys,
    /// The `[[wall]]` table in the file.
    pub span: std::ops::Range<usize>,
}
