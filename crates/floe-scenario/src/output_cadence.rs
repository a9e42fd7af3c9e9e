//! How often a run writes its outputs.

use floe_dem::run::Cadence;

/// How often a run writes its outputs, in simulated seconds.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputCadence {
    /// Floe snapshots (default: duration / 100).
    pub snapshot_every_s: f64,
    /// Observables: energies, stress, contact statistics (default: duration / 1000).
    pub observables_every_s: f64,
    /// Checkpoints to resume from (default: duration / 10).
    pub checkpoint_every_s: f64,
    /// `[[output.window]]`: stretches of the run with denser output.
    pub windows: Vec<OutputWindow>,
    /// Write the ridging event log `/ridging`, a row per floe cut (default
    /// false: a pack that ridges at every step logs tens of events a step,
    /// 70 times the rest of the file in the compression box).
    pub ridging_log: bool,
}

/// A stretch of the run whose snapshots or observables (or both) are also
/// written at a cadence of their own, besides the base cadence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputWindow {
    /// Start of the window, s (0 <= from_s < to_s).
    pub from_s: f64,
    /// End of the window, s (at most the run's duration).
    pub to_s: f64,
    /// Snapshots in the window, if it sets them, s.
    pub snapshot_every_s: Option<f64>,
    /// Observables in the window, if it sets them, s.
    pub observables_every_s: Option<f64>,
}

impl OutputCadence {
    /// The cadence in steps of `dt_s` (every cadence and window end
    /// rounded to whole steps, cadences at least one step).
    pub fn in_steps(&self, dt_s: f64) -> Cadence {
        self.windows.iter().fold(
            Cadence::from_seconds(
                self.snapshot_every_s,
                self.observables_every_s,
                self.checkpoint_every_s,
                dt_s,
            ),
            |c, w| {
                c.with_window_seconds(
                    (w.from_s, w.to_s),
                    w.snapshot_every_s,
                    w.observables_every_s,
                    dt_s,
                )
            },
        )
    }
}
