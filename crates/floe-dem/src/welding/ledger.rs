//! What welding did since the start of a run: part of the world's state.

/// Welding's totals since the start of the run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WeldingLedger {
    /// Pairs welded.
    pub events: u64,
    /// Open water the hulls closed, m^2 (new ice of the welded floes).
    pub area_added_m2: f64,
    /// Kinetic energy lost in the merges, J: the pairs' relative motion,
    /// and the change of spin that keeps angular momentum as the centre of
    /// mass moves to the hull's centroid (either sign; negative: gained).
    pub kinetic_energy_lost_j: f64,
    /// Elastic energy of the contacts and bonds that ended in a weld (the
    /// pair's own, and one of two contacts or bonds a third floe had with
    /// both), J.
    pub contact_energy_released_j: f64,
}
