//! Load-point protocols: what the apparatus's actuator does, as a list of
//! segments of constant or linearly ramped velocity.

use serde::{Deserialize, Serialize};

use crate::error::FrictionError;

/// One segment of a load-point history.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Load-point velocity at the start of the segment, m/s.
    pub start_velocity_m_per_s: f64,
    /// Load-point velocity at the end of the segment, m/s (equal to the start
    /// velocity for a constant-velocity segment; 0 for both is a hold).
    pub end_velocity_m_per_s: f64,
    /// Duration, s (> 0).
    pub duration_s: f64,
}

impl Segment {
    /// A constant-velocity segment (a hold if `velocity` is 0).
    pub fn constant(velocity_m_per_s: f64, duration_s: f64) -> Self {
        Self {
            start_velocity_m_per_s: velocity_m_per_s,
            end_velocity_m_per_s: velocity_m_per_s,
            duration_s,
        }
    }

    /// A hold: the load point stops.
    pub fn hold(duration_s: f64) -> Self {
        Self::constant(0.0, duration_s)
    }

    /// A linear velocity ramp from `from` to `to` (m/s) over `duration_s`.
    pub fn ramp(from_m_per_s: f64, to_m_per_s: f64, duration_s: f64) -> Self {
        Self {
            start_velocity_m_per_s: from_m_per_s,
            end_velocity_m_per_s: to_m_per_s,
            duration_s,
        }
    }

    /// Load-point displacement over the part `[t0, t1]` of the segment
    /// (times from the segment start, s): exact for the linear ramp.
    pub fn displacement_m(&self, t0: f64, t1: f64) -> f64 {
        let slope = (self.end_velocity_m_per_s - self.start_velocity_m_per_s) / self.duration_s;
        let v_mid = self.start_velocity_m_per_s + slope * 0.5 * (t0 + t1);
        v_mid * (t1 - t0)
    }
}

/// A validated load-point history.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Protocol {
    segments: Vec<Segment>,
}

impl Protocol {
    /// Checks the segments: at least one, durations finite and > 0, velocities finite.
    pub fn new(segments: Vec<Segment>) -> Result<Self, FrictionError> {
        if segments.is_empty() {
            return Err(FrictionError::InvalidProtocol {
                index: 0,
                reason: "no segments".into(),
            });
        }
        for (index, s) in segments.iter().enumerate() {
            if !(s.duration_s.is_finite() && s.duration_s > 0.0) {
                return Err(FrictionError::InvalidProtocol {
                    index,
                    reason: format!("duration_s = {} must be a finite number > 0", s.duration_s),
                });
            }
            if !(s.start_velocity_m_per_s.is_finite() && s.end_velocity_m_per_s.is_finite()) {
                return Err(FrictionError::InvalidProtocol {
                    index,
                    reason: "velocities must be finite".into(),
                });
            }
        }
        Ok(Self { segments })
    }

    /// The segments, in order.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Total duration, s.
    pub fn duration_s(&self) -> f64 {
        self.segments.iter().map(|s| s.duration_s).sum()
    }

    /// Load-point velocity at the very start, m/s.
    pub fn initial_velocity_m_per_s(&self) -> f64 {
        self.segments[0].start_velocity_m_per_s
    }

    /// Load-point velocity at time `t_s` from the start, m/s (at a segment
    /// boundary, the segment that starts there; past the end, the last value).
    pub fn velocity_at(&self, t_s: f64) -> f64 {
        let mut start = 0.0;
        for s in &self.segments {
            if t_s < start + s.duration_s {
                let f = ((t_s - start) / s.duration_s).clamp(0.0, 1.0);
                return s.start_velocity_m_per_s
                    + f * (s.end_velocity_m_per_s - s.start_velocity_m_per_s);
            }
            start += s.duration_s;
        }
        self.segments.last().map_or(0.0, |s| s.end_velocity_m_per_s)
    }
}
