//! The energy ledger: work done on the floes and energy dissipated since
//! the start of a run, part of the world's state.

/// Energy bookkeeping since the start of the run, J.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EnergyLedger {
    /// Work done on the floes by external forcing.
    pub forcing_work_j: f64,
    /// Energy dissipated by contact friction.
    pub friction_dissipation_j: f64,
    /// Energy dissipated by the normal dashpots.
    pub damping_dissipation_j: f64,
    /// Work done on the floes by floes with prescribed motion (walls).
    pub boundary_work_j: f64,
    /// Energy held by contacts at the moment they broke: the elastic work
    /// the overlap force did over the contact's life, plus the tangential
    /// spring's energy. An overlap-area force is not the gradient of a
    /// potential (sliding changes the overlap without normal motion), so this
    /// is not zero: it is the model's own non-conservation, reported rather
    /// than hidden. Bonds that break ([`crate::cohesion`]) add the
    /// elastic energy they held. Positive: energy lost from the floes.
    pub released_at_break_j: f64,
}
