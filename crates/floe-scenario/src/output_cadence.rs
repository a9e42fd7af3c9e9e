//! How often a run writes its outputs.

/// How often a run writes its outputs, in simulated seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputCadence {
    /// Floe snapshots (default: duration / 100).
    pub snapshot_every_s: f64,
    /// Observables: energies, stress, contact statistics (default: duration / 1000).
    pub observables_every_s: f64,
    /// Checkpoints to resume from (default: duration / 10).
    pub checkpoint_every_s: f64,
}
