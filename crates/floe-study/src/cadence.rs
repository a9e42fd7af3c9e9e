//! Which of a run's snapshots an output derived from them takes: all of
//! them, every K-th, or the ones nearest to the multiples of an interval
//! (`floe grid --every K`, `--interval-s T`), so that such an output has a
//! cadence of its own.

use floe_run::Error;

/// A cadence over a run's snapshots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cadence {
    /// Every snapshot.
    All,
    /// Snapshots 0, K, 2K, ... (by index: with `[[output.window]]` they
    /// are not evenly spaced in time).
    Every(usize),
    /// For each multiple of this many seconds (0, T, 2T, ...) that has a
    /// snapshot within T/2 of it, the snapshot nearest to it (the earlier
    /// of two as near); each snapshot once.
    IntervalS(f64),
}

impl Cadence {
    /// The indices, ascending, of the snapshots taken among snapshots at
    /// `times_s` (ascending, as a run writes them).
    pub fn select(self, times_s: &[f64]) -> Result<Vec<usize>, Error> {
        self.check()?;
        Ok(match self {
            Cadence::All => (0..times_s.len()).collect(),
            Cadence::Every(k) => (0..times_s.len()).step_by(k).collect(),
            Cadence::IntervalS(t) => nearest_to_multiples(times_s, t),
        })
    }

    /// Refuses `Every(0)` and an interval that is not a finite number > 0
    /// (bad input, named by its flag).
    pub fn check(self) -> Result<(), Error> {
        match self {
            Cadence::Every(0) => Err(Error::Usage("--every must be at least 1".into())),
            Cadence::IntervalS(t) if !(t.is_finite() && t > 0.0) => Err(Error::Usage(format!(
                "--interval-s {t}: an interval in s, > 0"
            ))),
            _ => Ok(()),
        }
    }
}

/// For each multiple `m T` within `T/2` of some time, the index of the
/// time nearest to it (ties to the earlier); ascending, each index once.
/// Only the one or two multiples within `T/2` of each time are looked at,
/// so a tiny `T` costs no more than a large one.
fn nearest_to_multiples(times_s: &[f64], interval_s: f64) -> Vec<usize> {
    let mut multiples: Vec<f64> = times_s
        .iter()
        .flat_map(|&t| {
            let q = t / interval_s;
            [q.floor(), q.ceil()]
        })
        .filter(|&m| m.is_finite())
        .collect();
    multiples.sort_by(f64::total_cmp);
    multiples.dedup();
    let mut taken: Vec<usize> = Vec::new();
    for m in multiples {
        let target = m * interval_s;
        let after = times_s.partition_point(|&t| t < target);
        let nearest = match (after.checked_sub(1), times_s.get(after)) {
            (Some(before), Some(&later)) if target - times_s[before] <= later - target => before,
            (Some(before), None) => before,
            (_, Some(_)) => after,
            (None, None) => continue,
        };
        if (times_s[nearest] - target).abs() <= 0.5 * interval_s && taken.last() != Some(&nearest) {
            taken.push(nearest);
        }
    }
    taken
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kth_and_all() {
        let times = [0.0, 1.0, 2.0, 3.0, 4.0];
        assert_eq!(Cadence::All.select(&times).unwrap(), vec![0, 1, 2, 3, 4]);
        assert_eq!(Cadence::Every(2).select(&times).unwrap(), vec![0, 2, 4]);
        assert!(Cadence::Every(0).select(&times).is_err());
        assert!(Cadence::IntervalS(0.0).select(&times).is_err());
        assert!(Cadence::IntervalS(f64::NAN).select(&times).is_err());
    }

    #[test]
    fn the_snapshot_nearest_each_multiple() {
        // Multiples 0, 3, 6 and 21 have a time within 1.5 s; 6 is nearest
        // to 7, 21 to 20; 9 to 18 have none.
        let times = [0.0, 1.0, 2.4, 7.0, 7.2, 20.0];
        assert_eq!(
            Cadence::IntervalS(3.0).select(&times).unwrap(),
            vec![0, 2, 3, 5]
        );
        // A run ending just short of a multiple still gives its last snapshot.
        let times: Vec<f64> = (0..=15).map(|k| 119.9 * k as f64).collect();
        assert_eq!(
            Cadence::IntervalS(600.0).select(&times).unwrap(),
            vec![0, 5, 10, 15]
        );
        // Ties go to the earlier snapshot; an interval shorter than the
        // spacing takes every snapshot once.
        assert_eq!(
            Cadence::IntervalS(2.0).select(&[0.0, 2.0, 4.0]).unwrap(),
            vec![0, 1, 2]
        );
        assert_eq!(
            Cadence::IntervalS(2.0).select(&[1.0, 3.0]).unwrap(),
            vec![0, 1]
        );
        assert_eq!(
            Cadence::IntervalS(4.0).select(&[3.0, 5.0]).unwrap(),
            vec![0]
        );
        assert_eq!(
            Cadence::IntervalS(1e-9).select(&[0.0, 5.0, 6.0]).unwrap(),
            vec![0, 1, 2]
        );
        assert!(Cadence::IntervalS(1.0).select(&[]).unwrap().is_empty());
    }
}
