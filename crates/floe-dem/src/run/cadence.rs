//! When a run writes, in steps: base cadences for the whole run, and
//! windows of steps with denser ones (around a hold, a restart).
//!
//! Everything is counted in absolute steps: an output is due at step `n`
//! when `n` is a multiple of the base cadence, or when a window holds `n`
//! and `n` is a multiple of the window's cadence. Whether an output is due
//! depends only on `n`, so a resumed run writes exactly where the
//! uninterrupted run would have.

/// A stretch of steps with its own snapshot and observable cadences, on
/// top of the base ones.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CadenceWindow {
    /// First step of the window.
    pub from_step: u64,
    /// Last step of the window (inclusive).
    pub to_step: u64,
    /// Steps between snapshots in the window (>= 1), if it sets them.
    pub snapshot: Option<u64>,
    /// Steps between observable samples in the window (>= 1), if it sets them.
    pub observables: Option<u64>,
}

/// When to write, in steps.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cadence {
    /// Steps between snapshots (>= 1).
    pub snapshot: u64,
    /// Steps between observable samples (>= 1).
    pub observables: u64,
    /// Steps between checkpoints (>= 1).
    pub checkpoint: u64,
    /// Windows of denser snapshots or observables (may overlap).
    pub windows: Vec<CadenceWindow>,
}

/// What is due at one step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Due {
    /// One sample of the observables.
    pub observables: bool,
    /// A snapshot.
    pub snapshot: bool,
    /// A checkpoint.
    pub checkpoint: bool,
}

impl Due {
    /// Everything (the first and the last step of a run).
    pub const ALL: Due = Due {
        observables: true,
        snapshot: true,
        checkpoint: true,
    };
}

/// The three outputs, to pick a cadence.
#[derive(Debug, Clone, Copy)]
enum Output {
    Observables,
    Snapshot,
    Checkpoint,
}

/// Seconds as whole steps of `dt_s`, at least one: how every interval
/// given in seconds (output cadences, fracture and welding checks) becomes
/// a count of steps.
pub fn whole_steps(s: f64, dt_s: f64) -> u64 {
    ((s / dt_s).round() as u64).max(1)
}

/// The first multiple of `every` at or after `step`, if it fits in a u64
/// (none of 0, which only step 0 is a multiple of).
fn multiple_from(step: u64, every: u64) -> Option<u64> {
    if every == 0 {
        return (step == 0).then_some(0);
    }
    step.div_ceil(every).checked_mul(every)
}

impl Cadence {
    /// Cadences given in seconds, rounded to whole steps of `dt_s`, at
    /// least one step; no windows.
    pub fn from_seconds(snapshot_s: f64, observables_s: f64, checkpoint_s: f64, dt_s: f64) -> Self {
        Self {
            snapshot: whole_steps(snapshot_s, dt_s),
            observables: whole_steps(observables_s, dt_s),
            checkpoint: whole_steps(checkpoint_s, dt_s),
            windows: Vec::new(),
        }
    }

    /// Adds a window from `from_s` to `to_s` (ends rounded to the nearest
    /// step) with cadences in seconds, rounded as the base ones.
    pub fn with_window_seconds(
        mut self,
        (from_s, to_s): (f64, f64),
        snapshot_s: Option<f64>,
        observables_s: Option<f64>,
        dt_s: f64,
    ) -> Self {
        self.windows.push(CadenceWindow {
            from_step: (from_s / dt_s).round() as u64,
            to_step: (to_s / dt_s).round() as u64,
            snapshot: snapshot_s.map(|s| whole_steps(s, dt_s)),
            observables: observables_s.map(|s| whole_steps(s, dt_s)),
        });
        self
    }

    fn base(&self, output: Output) -> u64 {
        match output {
            Output::Observables => self.observables,
            Output::Snapshot => self.snapshot,
            Output::Checkpoint => self.checkpoint,
        }
    }

    /// The windows that set a cadence for `output`, with that cadence.
    fn windows_of(&self, output: Output) -> impl Iterator<Item = (&CadenceWindow, u64)> {
        self.windows.iter().filter_map(move |w| {
            let every = match output {
                Output::Observables => w.observables,
                Output::Snapshot => w.snapshot,
                Output::Checkpoint => None,
            };
            every.map(|e| (w, e))
        })
    }

    fn is_due(&self, output: Output, step: u64) -> bool {
        step.is_multiple_of(self.base(output))
            || self.windows_of(output).any(|(w, every)| {
                (w.from_step..=w.to_step).contains(&step) && step.is_multiple_of(every)
            })
    }

    /// What is due at `step`.
    pub fn due_at(&self, step: u64) -> Due {
        Due {
            observables: self.is_due(Output::Observables, step),
            snapshot: self.is_due(Output::Snapshot, step),
            checkpoint: self.is_due(Output::Checkpoint, step),
        }
    }

    /// The first step after `step` at which `output` is due (`u64::MAX`
    /// when none fits in a u64).
    fn next_after(&self, output: Output, step: u64) -> u64 {
        let Some(start) = step.checked_add(1) else {
            return u64::MAX;
        };
        let base = multiple_from(start, self.base(output));
        self.windows_of(output)
            .filter_map(|(w, every)| {
                multiple_from(start.max(w.from_step), every).filter(|&n| n <= w.to_step)
            })
            .chain(base)
            .min()
            .unwrap_or(u64::MAX)
    }
}

/// The next step each output is due at, so that the loop compares three
/// numbers a step however many windows there are; [`Cadence::due_at`]
/// gives the same answers.
#[derive(Debug, Clone)]
pub(crate) struct NextDue {
    observables: u64,
    snapshot: u64,
    checkpoint: u64,
}

impl NextDue {
    /// The outputs due after `step` (the step the world is at).
    pub(crate) fn after(cadence: &Cadence, step: u64) -> Self {
        Self {
            observables: cadence.next_after(Output::Observables, step),
            snapshot: cadence.next_after(Output::Snapshot, step),
            checkpoint: cadence.next_after(Output::Checkpoint, step),
        }
    }

    /// What is due at `step`, which must be one past the step of the last
    /// call (or of [`NextDue::after`]).
    pub(crate) fn take(&mut self, cadence: &Cadence, step: u64) -> Due {
        let take = |next: &mut u64, output: Output| {
            let due = *next == step;
            if due {
                *next = cadence.next_after(output, step);
            }
            due
        };
        Due {
            observables: take(&mut self.observables, Output::Observables),
            snapshot: take(&mut self.snapshot, Output::Snapshot),
            checkpoint: take(&mut self.checkpoint, Output::Checkpoint),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cadence(windows: Vec<CadenceWindow>) -> Cadence {
        Cadence {
            snapshot: 50,
            observables: 7,
            checkpoint: 60,
            windows,
        }
    }

    fn window(from_step: u64, to_step: u64, s: Option<u64>, o: Option<u64>) -> CadenceWindow {
        CadenceWindow {
            from_step,
            to_step,
            snapshot: s,
            observables: o,
        }
    }

    #[test]
    fn a_window_adds_its_multiples_inside_it_and_nothing_outside() {
        let c = cadence(vec![window(122, 262, Some(5), Some(2))]);
        let snapshots: Vec<u64> = (0..=400).filter(|&n| c.due_at(n).snapshot).collect();
        let mut expected: Vec<u64> = (0..=400).step_by(50).collect();
        expected.extend((125..=260).step_by(5));
        expected.sort();
        expected.dedup();
        assert_eq!(snapshots, expected);
        let observables = (0..=400).filter(|&n| c.due_at(n).observables).count();
        // Multiples of 7 outside [122, 262], every even step inside it, and
        // the odd multiples of 7 inside it (133, 147, ..., 259).
        let outside = (0..=400).filter(|n| n % 7 == 0 && !(122..=262).contains(n));
        let odd_sevens = (122..=262).filter(|n| n % 7 == 0 && n % 2 == 1).count();
        assert_eq!(observables, outside.count() + 71 + odd_sevens);
        // Checkpoints ignore windows.
        assert!((0..=400).all(|n| c.due_at(n).checkpoint == (n % 60 == 0)));
    }

    #[test]
    fn the_tracker_agrees_with_due_at_from_any_starting_step() {
        let cases = [
            cadence(vec![]),
            cadence(vec![window(0, 0, Some(1), Some(1))]),
            cadence(vec![
                window(10, 90, Some(3), None),
                window(40, 200, None, Some(4)),
                window(45, 60, Some(1), Some(1)),
                window(300, 310, Some(1000), Some(7)),
            ]),
            Cadence {
                snapshot: u64::MAX,
                observables: u64::MAX / 2,
                checkpoint: 1,
                windows: vec![window(5, u64::MAX, Some(u64::MAX - 1), Some(3))],
            },
            // Out of range (the fields ask for >= 1): never due, no panic.
            Cadence {
                snapshot: 0,
                observables: 0,
                checkpoint: 0,
                windows: vec![window(50, 20, Some(1), Some(0))],
            },
        ];
        for c in &cases {
            for start in [0, 1, 44, 57, 299] {
                let mut next = NextDue::after(c, start);
                for n in start + 1..400 {
                    assert_eq!(next.take(c, n), c.due_at(n), "step {n} from {start}: {c:?}");
                }
            }
        }
        // Near the end of the u64 range nothing overflows.
        let c = &cases[3];
        let mut next = NextDue::after(c, u64::MAX - 3);
        for n in u64::MAX - 2..=u64::MAX - 1 {
            assert_eq!(next.take(c, n), c.due_at(n));
        }
    }

    #[test]
    fn seconds_round_to_whole_steps_and_window_ends_to_the_nearest_step() {
        let c = Cadence::from_seconds(25.0, 3.5, 30.0, 0.5).with_window_seconds(
            (61.0, 131.2),
            Some(2.5),
            None,
            0.5,
        );
        assert_eq!((c.snapshot, c.observables, c.checkpoint), (50, 7, 60));
        assert_eq!(c.windows, vec![window(122, 262, Some(5), None)]);
        let tiny = Cadence::from_seconds(1e-9, 1e-9, 1e-9, 0.5).with_window_seconds(
            (0.0, 1.0),
            Some(1e-9),
            Some(0.1),
            0.5,
        );
        assert_eq!(tiny.windows[0].snapshot, Some(1));
        assert_eq!(tiny.windows[0].observables, Some(1));
    }
}
