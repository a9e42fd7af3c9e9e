//! The top wall's schedule as laboratory events (velocity steps, holds),
//! each run's friction series, and the events measured on each run and on
//! each law's mean over its seeds.

use std::path::Path;

use floe_analysis::step_response::{hold_healing, velocity_step, HoldHealing, VelocityStep};
use floe_analysis::AnalysisError;
use floe_dem::motion_schedule::MotionSegment;
use floe_io::RunFile;
use floe_run::Error;

use super::LawRuns;

/// Fraction of a segment's window read as its steady state (the new
/// steady friction after a step, the friction before the next event), and
/// of a reslide read for its peak.
pub const STEADY_FRACTION: f64 = 0.5;

/// The top wall's schedule: segments of constant speed along x (0: a
/// hold), back to back from t = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// `(start_s, duration_s, speed_m_per_s)` of each segment.
    segments: Vec<(f64, f64, f64)>,
}

/// What happens at an event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventKind {
    /// The speed changes from one sliding speed to another, m/s.
    Step {
        /// Speed before.
        from: f64,
        /// Speed after.
        to: f64,
    },
    /// Sliding at `speed` stops for `hold_s` seconds, then resumes at
    /// `speed` (the speed after the hold).
    Hold {
        /// The hold's length, s.
        hold_s: f64,
        /// The reslide speed, m/s.
        speed: f64,
    },
}

/// One event of the schedule: what happens, the window of steady sliding
/// before it and the window it is read over after it (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    /// Its kind.
    pub kind: EventKind,
    /// When the speed changes (the step, or the end of the hold), s.
    pub at_s: f64,
    /// Steady sliding before it: the last half of the segment before.
    pub before_s: (f64, f64),
    /// Read after it: the new segment (a step), or the first half of the
    /// reslide (a hold).
    pub after_s: (f64, f64),
}

impl Schedule {
    /// Reads a wall's `[[wall.segment]]` schedule along x and checks it:
    /// no ramps, speeds >= 0, a first segment that slides and at least one
    /// event.
    pub fn new(segments: &[MotionSegment]) -> Result<Self, String> {
        if segments.len() < 2 {
            return Err(
                "it needs [[wall.segment]] tables: at least a slide and a step or hold".into(),
            );
        }
        let mut t = 0.0;
        let mut out = Vec::new();
        for (k, seg) in segments.iter().enumerate() {
            let (d, v0, v1) = (seg.duration_s, seg.velocity_start.x, seg.velocity_end.x);
            if v0 != v1 {
                return Err(format!(
                    "segment {k} is a ramp ({v0} to {v1} m/s); steps and holds only"
                ));
            }
            if v0 < 0.0 {
                return Err(format!(
                    "segment {k} slides at {v0} m/s; speeds along +x (>= 0) only"
                ));
            }
            out.push((t, d, v0));
            t += d;
        }
        if out[0].2 == 0.0 {
            return Err("the first segment must slide (it sets the steady state)".into());
        }
        for k in 1..out.len() {
            if out[k].2 == 0.0 && out[k - 1].2 == 0.0 {
                return Err(format!(
                    "segments {} and {k} are both holds; one hold between slides",
                    k - 1
                ));
            }
            if out[k].2 == 0.0 && k + 1 < out.len() && out[k + 1].2 != out[k - 1].2 {
                return Err(format!(
                    "the hold of segment {k} is followed by {} m/s after {} m/s before it; a hold resumes at its speed (a step is its own event)",
                    out[k + 1].2,
                    out[k - 1].2
                ));
            }
        }
        let schedule = Self { segments: out };
        if schedule.events().is_empty() {
            return Err("no velocity step or hold between sliding segments".into());
        }
        Ok(schedule)
    }

    /// The schedule's length, s.
    pub fn duration_s(&self) -> f64 {
        let &(t, d, _) = self.segments.last().expect("checked non-empty");
        t + d
    }

    /// The first segment's speed, m/s.
    pub fn first_speed_m_per_s(&self) -> f64 {
        self.segments[0].2
    }

    /// The wall's speed at `t_s` (the segment that starts at or before it).
    pub fn speed_at(&self, t_s: f64) -> f64 {
        let k = self.segments.partition_point(|s| s.0 <= t_s);
        self.segments[k.saturating_sub(1)].2
    }

    /// Samples every `every_s` from 0 to the end.
    pub fn sample_times(&self, every_s: f64) -> Vec<f64> {
        let n = (self.duration_s() / every_s).floor() as usize;
        (0..=n).map(|k| k as f64 * every_s).collect()
    }

    /// The velocity steps (between two sliding segments of different
    /// speeds) and holds (a stop between two sliding segments).
    pub fn events(&self) -> Vec<Event> {
        let s = &self.segments;
        let last_half = |k: usize| (s[k].0 + (1.0 - STEADY_FRACTION) * s[k].1, s[k].0 + s[k].1);
        let mut out = Vec::new();
        for k in 0..s.len() - 1 {
            let (start, d, v) = s[k + 1];
            if s[k].2 > 0.0 && v > 0.0 && v != s[k].2 {
                out.push(Event {
                    kind: EventKind::Step {
                        from: s[k].2,
                        to: v,
                    },
                    at_s: start,
                    before_s: last_half(k),
                    after_s: (start, start + d),
                });
            }
            if s[k].2 > 0.0 && v == 0.0 && k + 2 < s.len() && s[k + 2].2 > 0.0 {
                let (reslide, rd, rv) = s[k + 2];
                out.push(Event {
                    kind: EventKind::Hold {
                        hold_s: d,
                        speed: rv,
                    },
                    at_s: reslide,
                    before_s: last_half(k),
                    after_s: (reslide, reslide + STEADY_FRACTION * rd),
                });
            }
        }
        out
    }
}

/// A run's pack friction on the common sample times: the free floes' mean
/// shear stress `tau = (s_xy + s_yx) / 2` and pressure `P = -s_yy` (the
/// `mean_stress` observable, N/m), linearly interpolated.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionSeries {
    /// Shear stress, N/m.
    pub tau: Vec<f64>,
    /// Pressure, N/m.
    pub p: Vec<f64>,
}

impl FrictionSeries {
    /// `tau / P` at each sample (NaN where the pack carries no pressure).
    pub fn mu(&self) -> Vec<f64> {
        ratio(&self.tau, &self.p)
    }
}

/// `tau / P`, NaN where `P <= 0` (no contact carries the layer).
fn ratio(tau: &[f64], p: &[f64]) -> Vec<f64> {
    tau.iter()
        .zip(p)
        .map(|(&t, &p)| if p > 0.0 { t / p } else { f64::NAN })
        .collect()
}

/// Reads `mean_stress` of the run file at `path` onto `times`.
pub fn read_series(path: &Path, times: &[f64]) -> Result<FrictionSeries, Error> {
    let run = RunFile::open(path)?;
    let stress = run.observable("mean_stress")?;
    if stress.sample_shape != [4] || stress.time_s.is_empty() {
        return Err(Error::Usage(format!(
            "{}: its mean_stress observable is not a series of 2 x 2 tensors",
            path.display()
        )));
    }
    // The last sample may fall up to a step before the schedule's end.
    let end = stress.time_s[stress.time_s.len() - 1];
    let spacing = times.get(1).map_or(0.0, |t| t - times[0]);
    if end + spacing < times[times.len() - 1] {
        return Err(Error::Usage(format!(
            "{}: the run ends at {end} s, before its schedule ({} s): run it to the end first",
            path.display(),
            times[times.len() - 1]
        )));
    }
    let tau: Vec<f64> = stress
        .value
        .chunks(4)
        .map(|s| 0.5 * (s[1] + s[2]))
        .collect();
    let p: Vec<f64> = stress.value.chunks(4).map(|s| -s[3]).collect();
    Ok(FrictionSeries {
        tau: interpolate(&stress.time_s, &tau, times),
        p: interpolate(&stress.time_s, &p, times),
    })
}

fn interpolate(t: &[f64], y: &[f64], at: &[f64]) -> Vec<f64> {
    at.iter()
        .map(|&x| {
            let k = t.partition_point(|&ti| ti <= x);
            if k == 0 {
                y[0]
            } else if k == t.len() {
                y[t.len() - 1]
            } else {
                let w = (x - t[k - 1]) / (t[k] - t[k - 1]);
                y[k - 1] + w * (y[k] - y[k - 1])
            }
        })
        .collect()
}

/// What one event measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Measured {
    /// A velocity step.
    Step(VelocityStep),
    /// A hold.
    Hold(HoldHealing),
}

/// One law's events: on the mean over its seeds (`sum tau / sum P` at each
/// time) and on each seed's run (`None` where a window had no valid
/// friction, e.g. the layer lost the walls).
#[derive(Debug, Clone)]
pub struct LawEvents {
    /// The law's name.
    pub law: String,
    /// The friction of the mean over seeds at each sample.
    pub mean_mu: Vec<f64>,
    /// The mean over seeds' pressure at each sample, N/m.
    pub mean_p: Vec<f64>,
    /// Each event on the mean over seeds.
    pub on_mean: Vec<Option<Measured>>,
    /// Each seed's events: `(seed, one per event)`.
    pub per_seed: Vec<(u64, Vec<Option<Measured>>)>,
}

/// Measures every event of `schedule` on each law's seeds and their mean.
pub fn measure(
    schedule: &Schedule,
    times: &[f64],
    laws: &[LawRuns],
) -> Result<Vec<LawEvents>, AnalysisError> {
    let events = schedule.events();
    let mut out = Vec::new();
    for law in laws {
        if law.runs.is_empty() {
            return Err(AnalysisError::NotEnoughData("a law without runs"));
        }
        let sum = |f: fn(&FrictionSeries) -> &Vec<f64>| -> Vec<f64> {
            (0..times.len())
                .map(|i| law.runs.iter().map(|(_, s)| f(s)[i]).sum::<f64>())
                .collect()
        };
        let tau = sum(|s| &s.tau);
        let p = sum(|s| &s.p);
        let mean_mu = ratio(&tau, &p);
        let n = law.runs.len() as f64;
        let read = |mu: &[f64]| {
            events
                .iter()
                .map(|e| measure_event(e, times, mu).ok())
                .collect()
        };
        out.push(LawEvents {
            law: law.law.clone(),
            on_mean: read(&mean_mu),
            per_seed: law
                .runs
                .iter()
                .map(|(seed, s)| (*seed, read(&s.mu())))
                .collect(),
            mean_p: p.iter().map(|v| v / n).collect(),
            mean_mu,
        });
    }
    Ok(out)
}

/// One event read from `mu` at `times` (`times[i] = i x spacing`).
pub fn measure_event(event: &Event, times: &[f64], mu: &[f64]) -> Result<Measured, AnalysisError> {
    let every = times.get(1).map_or(1.0, |t| t - times[0]);
    // Samples by index, so that a sample on a window's edge is in or out
    // whatever the rounding of its time.
    let window = |(a, b): (f64, f64), open_start: bool| -> Vec<usize> {
        let (a, b) = (a / every, b / every);
        let first = if open_start {
            (a + 1e-6).floor() as usize + 1
        } else {
            (a - 1e-6).ceil() as usize
        };
        let last = ((b + 1e-6).floor() as usize).min(times.len() - 1);
        (first..=last).collect()
    };
    // velocity_step and hold_healing refuse a window with a friction that
    // is not finite (no contact carried the layer).
    let before: Vec<f64> = window(event.before_s, false)
        .iter()
        .map(|&i| mu[i])
        .collect();
    let after = window(event.after_s, true);
    match event.kind {
        EventKind::Step { from, to } => {
            let slip: Vec<f64> = after
                .iter()
                .map(|&i| to * (times[i] - event.at_s))
                .collect();
            let mu_after: Vec<f64> = after.iter().map(|&i| mu[i]).collect();
            velocity_step(&before, &slip, &mu_after, STEADY_FRACTION, (to / from).ln())
                .map(Measured::Step)
        }
        EventKind::Hold { .. } => {
            let reslide: Vec<f64> = after.iter().map(|&i| mu[i]).collect();
            hold_healing(&before, &reslide).map(Measured::Hold)
        }
    }
}
