//! Slip events: contacts whose slip rate jumps, from one snapshot to the
//! next, by a large factor. With rate-and-state friction a contact that has
//! healed while nearly stuck fails abruptly (stick-slip); with Amontons it
//! slides as soon as the load allows, without a jump from a healed state.
//!
//! Rule (documented in docs/studies and `floe compare`'s report):
//! * a contact *starts* an event at snapshot `k` when it was present at
//!   snapshot `k - 1` with slip rate `v_prev`, and now slips at
//!   `v >= jump_factor * v_prev` and `v >= min_rate`;
//! * the event *lasts* while the contact exists and slips at `>= min_rate`;
//! * its *size* is the slip during the event, `sum v_k (t_k - t_{k-1})`
//!   over its snapshots (a rectangle rule: snapshots are all there is);
//! * a contact that first appears already slipping is not an event: there
//!   is no earlier rate to jump from.
//!
//! Contacts are matched between snapshots by their floe pair; floe writes
//! contacts sorted by pair, which the detector checks.

use crate::AnalysisError;

/// Thresholds of the event rule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipEventRule {
    /// Factor by which the slip rate must jump between snapshots (> 1).
    pub jump_factor: f64,
    /// Slip rate an event must reach and stay above, m/s (> 0).
    pub min_rate_m_per_s: f64,
}

impl Default for SlipEventRule {
    /// A tenfold jump to at least 1 mm/s: well above the creep of a healed
    /// floe contact and the regularisation speed of the laws.
    fn default() -> Self {
        Self {
            jump_factor: 10.0,
            min_rate_m_per_s: 1e-3,
        }
    }
}

/// One finished (or, at the end of the data, still running) slip event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipEvent {
    /// The two floes.
    pub pair: [u32; 2],
    /// Time of the first snapshot of the event, s.
    pub start_s: f64,
    /// Time of its last snapshot, s.
    pub end_s: f64,
    /// Slip during the event, m.
    pub slip_m: f64,
    /// Largest slip rate during the event, m/s.
    pub peak_rate_m_per_s: f64,
}

#[derive(Debug, Clone, Copy)]
struct Tracked {
    pair: [u32; 2],
    rate: f64,
    event: Option<SlipEvent>,
}

/// Finds slip events in a sequence of contact snapshots, one snapshot at a
/// time (runs are too large to hold every snapshot's contacts at once).
#[derive(Debug, Clone)]
pub struct SlipEventDetector {
    rule: SlipEventRule,
    last_time_s: Option<f64>,
    tracked: Vec<Tracked>,
    scratch: Vec<Tracked>,
    events: Vec<SlipEvent>,
}

impl SlipEventDetector {
    /// A detector with `rule`.
    pub fn new(rule: SlipEventRule) -> Result<Self, AnalysisError> {
        if rule.jump_factor.is_nan() || rule.jump_factor <= 1.0 {
            return Err(AnalysisError::InvalidParameter {
                name: "jump_factor",
                value: rule.jump_factor,
                reason: "must be > 1",
            });
        }
        if rule.min_rate_m_per_s.is_nan() || rule.min_rate_m_per_s <= 0.0 {
            return Err(AnalysisError::InvalidParameter {
                name: "min_rate_m_per_s",
                value: rule.min_rate_m_per_s,
                reason: "must be > 0",
            });
        }
        Ok(Self {
            rule,
            last_time_s: None,
            tracked: Vec::new(),
            scratch: Vec::new(),
            events: Vec::new(),
        })
    }

    /// Adds the contacts of the next snapshot, at `time_s`: `pair` sorted
    /// (equal pairs, periodic images of one pair, are merged taking the
    /// faster), `slip_rate_m_per_s` their slip rates.
    pub fn push(
        &mut self,
        time_s: f64,
        pair: &[[u32; 2]],
        slip_rate_m_per_s: &[f64],
    ) -> Result<(), AnalysisError> {
        if pair.len() != slip_rate_m_per_s.len() {
            return Err(AnalysisError::LengthMismatch {
                what: "contact pairs and slip rates",
                left: pair.len(),
                right: slip_rate_m_per_s.len(),
            });
        }
        if pair.windows(2).any(|w| w[0] > w[1]) {
            return Err(AnalysisError::NotEnoughData(
                "contacts must be sorted by floe pair",
            ));
        }
        let dt = match self.last_time_s {
            Some(t) if time_s > t => time_s - t,
            Some(_) => {
                return Err(AnalysisError::InvalidParameter {
                    name: "time_s",
                    value: time_s,
                    reason: "snapshots must come in increasing time",
                })
            }
            None => 0.0,
        };
        let first = self.last_time_s.is_none();
        self.last_time_s = Some(time_s);
        let rule = self.rule;
        let mut previous = self.tracked.iter().peekable();
        self.scratch.clear();
        let mut i = 0;
        while i < pair.len() {
            let p = pair[i];
            let mut v = slip_rate_m_per_s[i].abs();
            i += 1;
            while i < pair.len() && pair[i] == p {
                v = v.max(slip_rate_m_per_s[i].abs());
                i += 1;
            }
            // Contacts of the previous snapshot that are gone now end their events.
            while let Some(old) = previous.next_if(|old| old.pair < p) {
                if let Some(e) = old.event {
                    self.events.push(e);
                }
            }
            let before = previous.next_if(|old| old.pair == p);
            let event = match before {
                Some(old) => match old.event {
                    Some(mut e) if v >= rule.min_rate_m_per_s => {
                        e.end_s = time_s;
                        e.slip_m += v * dt;
                        e.peak_rate_m_per_s = e.peak_rate_m_per_s.max(v);
                        Some(e)
                    }
                    Some(e) => {
                        self.events.push(e);
                        None
                    }
                    None if !first
                        && v >= rule.min_rate_m_per_s
                        && v >= rule.jump_factor * old.rate =>
                    {
                        Some(SlipEvent {
                            pair: p,
                            start_s: time_s,
                            end_s: time_s,
                            slip_m: v * dt,
                            peak_rate_m_per_s: v,
                        })
                    }
                    None => None,
                },
                None => None,
            };
            self.scratch.push(Tracked {
                pair: p,
                rate: v,
                event,
            });
        }
        for old in previous {
            if let Some(e) = old.event {
                self.events.push(e);
            }
        }
        std::mem::swap(&mut self.tracked, &mut self.scratch);
        Ok(())
    }

    /// The events found, those still running at the last snapshot included,
    /// in the order they ended (running ones last, by pair).
    pub fn finish(mut self) -> Vec<SlipEvent> {
        self.events
            .extend(self.tracked.iter().filter_map(|t| t.event));
        self.events
    }
}

/// Counts of `sizes` in logarithmic bins, `bins_per_decade` per factor of
/// ten, from the decade of the smallest positive size to that of the
/// largest. Returns `(lower edge, upper edge, count)` per bin; non-positive
/// sizes are left out.
pub fn log_histogram(sizes: &[f64], bins_per_decade: usize) -> Vec<(f64, f64, usize)> {
    let positive: Vec<f64> = sizes
        .iter()
        .copied()
        .filter(|s| *s > 0.0 && s.is_finite())
        .collect();
    if positive.is_empty() || bins_per_decade == 0 {
        return Vec::new();
    }
    let lo = positive.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = positive.iter().copied().fold(0.0, f64::max);
    let per = bins_per_decade as f64;
    let first = (lo.log10() * per).floor() as i64;
    let last = (hi.log10() * per).floor() as i64;
    let mut counts = vec![0usize; (last - first + 1) as usize];
    for s in positive {
        let k = ((s.log10() * per).floor() as i64 - first).clamp(0, last - first) as usize;
        counts[k] += 1;
    }
    counts
        .into_iter()
        .enumerate()
        .map(|(k, c)| {
            let e = (first + k as i64) as f64 / per;
            (10f64.powf(e), 10f64.powf(e + 1.0 / per), c)
        })
        .collect()
}
