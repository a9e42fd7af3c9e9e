//! What ridging moved since the start of a run: part of the world's state.

use crate::Vec2;

/// Ridging's totals since the start of the run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RidgingLedger {
    /// Ridging events (a floe cut against a thicker floe or a wall).
    pub events: u64,
    /// Ice volume moved from the losers to thicker floes, m^3.
    pub volume_to_floes_m3: f64,
    /// Ice volume lost against walls and land (to the coast), m^3.
    pub volume_to_coast_m3: f64,
    /// Momentum that went with it, N s.
    pub momentum_to_coast_n_s: Vec2,
    /// Angular momentum about the origin that went with it, kg m^2/s.
    pub angular_momentum_to_coast: f64,
    /// Kinetic energy lost: the inelastic merge of the ridged ice with its
    /// gainer, and the kinetic energy of the ice lost to the coast, J.
    pub kinetic_energy_lost_j: f64,
    /// Elastic energy the ridging contacts held beyond the cap and
    /// released when cut, J.
    pub contact_energy_released_j: f64,
}
