//! Prescribed velocity fields (wind at 10 m, surface current) as functions
//! of position (m) and time (s), with their vertical vorticity.
//!
//! | variant | velocity `U(x, t)` (m/s) | vorticity `ζ = ∂U_y/∂x − ∂U_x/∂y` (1/s) |
//! |---|---|---|
//! | [`Uniform`](VelocityField::Uniform)`(U0)` | `U0` | 0 |
//! | [`TimeSeries`](VelocityField::TimeSeries) | piecewise linear in `t` between the samples, held constant before the first and after the last | 0 |
//! | [`LinearShear`](VelocityField::LinearShear) | `U_min + s (U_max − U_min)`, `s = clamp((y − y_min)/(y_max − y_min), 0, 1)` | `−(U_max,x − U_min,x)/(y_max − y_min)` inside the channel, 0 outside |
//! | [`Gyre`](VelocityField::Gyre) | Rankine vortex: `V r/R` inside the core `r ≤ R`, `V R/r` outside, along `k × r̂` | `2V/R` inside, 0 outside |
//! | [`Scaled`](VelocityField::Scaled) | `a(t) U_inner(x, t)`, `a(t)` a piecewise-linear [`Envelope`] | `a(t) ζ_inner` |
//! | [`Gridded`](VelocityField::Gridded) | bilinear in space on a grid, linear in time between slices ([`GriddedField`]) | of the bilinear interpolant |
//!
//! The Rankine vortex rotates as a solid body (angular velocity `V/R`) inside
//! its core and is irrotational outside, where the speed decays as `1/r`
//! (Rankine 1858; e.g. Acheson, *Elementary Fluid Dynamics*, 1990, §1.6).
//! `V > 0` is counterclockwise seen from above (cyclonic in the Northern
//! Hemisphere). The slow `1/r` decay means a gyre does not vanish at the edge
//! of a finite domain: put it in a [`Scaled`](VelocityField::Scaled) or pick
//! `R` against the domain size.
//!
//! Evaluation never allocates. The fields are meant to be checked once with
//! [`VelocityField::validate`] (a scenario reader should call it after
//! deserialising); an unvalidated field still evaluates without panicking
//! (an empty time series is zero, extra samples of the longer of `times_s`
//! and `values` are ignored), but the values are then not meaningful.

use crate::floes::FloeColumns;
use crate::forcing::gridded::{ForcingFailure, GriddedField};
use crate::{DemError, Vec2};

/// A prescribed 2-D velocity field, m/s, of position (m) and time (s).
#[derive(Debug, Clone, PartialEq)]
pub enum VelocityField {
    /// The same velocity everywhere and always, m/s.
    Uniform(Vec2),
    /// Spatially uniform, piecewise linear in time between samples, held at
    /// the first (last) sample before (after) the series.
    TimeSeries {
        /// Sample times, s, strictly increasing, at least one.
        times_s: Vec<f64>,
        /// Velocities at `times_s`, m/s, as `[x, y]` pairs; same length as `times_s`.
        values: Vec<Vec2>,
    },
    /// A channel shear profile: the velocity varies linearly in `y` from
    /// `velocity_at_y_min_m_per_s` at `y_min_m` to `velocity_at_y_max_m_per_s` at
    /// `y_max_m`, and is constant (clamped) outside `[y_min_m, y_max_m]`.
    /// Uniform in `x` and in time.
    LinearShear {
        /// Lower edge of the shear zone, m.
        y_min_m: f64,
        /// Upper edge of the shear zone, m; `> y_min_m`.
        y_max_m: f64,
        /// Velocity at and below `y_min_m`, m/s.
        velocity_at_y_min_m_per_s: Vec2,
        /// Velocity at and above `y_max_m`, m/s.
        velocity_at_y_max_m_per_s: Vec2,
    },
    /// A Rankine vortex: solid-body rotation inside `core_radius_m`, speed
    /// decaying as `1/r` outside. Steady.
    Gyre {
        /// Centre of the vortex, m.
        center_m: Vec2,
        /// Core radius `R`, m, where the speed peaks; `> 0`.
        core_radius_m: f64,
        /// Speed at `r = R`, m/s; positive counterclockwise (seen from above).
        max_speed_m_per_s: f64,
    },
    /// Another field multiplied by a time envelope (wind blows, stops,
    /// restarts).
    Scaled {
        /// The field being scaled.
        field: Box<VelocityField>,
        /// The dimensionless factor `a(t)`.
        envelope: Envelope,
    },
    /// Given on a grid at a sequence of times (a NetCDF file): see
    /// [`GriddedField`]. Needs [`VelocityField::prepare`] each step.
    Gridded(Box<GriddedField>),
}

impl Default for VelocityField {
    /// No motion: `Uniform([0, 0])`.
    fn default() -> Self {
        VelocityField::Uniform(Vec2::ZERO)
    }
}

/// A dimensionless time factor `a(t)`: piecewise linear between the samples,
/// held at the first (last) factor before (after) the series. For example
/// `times_s = [0, 3600, 3700, 7200, 7300]`, `factors = [1, 1, 0, 0, 1]`: on
/// for an hour, ramped off in 100 s, off for an hour, ramped back on.
#[derive(Debug, Clone, PartialEq)]
pub struct Envelope {
    /// Sample times, s, strictly increasing, at least one.
    pub times_s: Vec<f64>,
    /// Factors at `times_s` (dimensionless; 1 = full field, 0 = off); same length.
    pub factors: Vec<f64>,
}

/// Where `t` falls in the strictly increasing `times`: `(i, w)` such that the
/// interpolated value is `(1 − w) v[i] + w v[i + 1]` (or `v[i]` with `w = 0`
/// at the clamped ends). `n ≥ 1` is the number of usable samples.
#[inline]
fn locate(times: &[f64], n: usize, t: f64) -> (usize, f64) {
    let times = &times[..n];
    if n == 1 || t.is_nan() || t <= times[0] {
        return (0, 0.0);
    }
    if t >= times[n - 1] {
        return (n - 1, 0.0);
    }
    let i = times
        .partition_point(|&x| x <= t)
        .saturating_sub(1)
        .min(n - 2);
    let w = (t - times[i]) / (times[i + 1] - times[i]);
    (i, w)
}

fn validate_times(times_s: &[f64], name: &'static str) -> Result<(), DemError> {
    if times_s.is_empty() {
        return Err(DemError::InvalidParameter {
            name,
            value: 0.0,
            reason: "needs at least one sample",
        });
    }
    for (k, &t) in times_s.iter().enumerate() {
        if !t.is_finite() {
            return Err(DemError::InvalidParameter {
                name,
                value: t,
                reason: "must be finite",
            });
        }
        if k > 0 && t <= times_s[k - 1] {
            return Err(DemError::InvalidParameter {
                name,
                value: t,
                reason: "must be strictly increasing",
            });
        }
    }
    Ok(())
}

fn finite_vec(v: Vec2, name: &'static str) -> Result<(), DemError> {
    for c in [v.x, v.y] {
        if !c.is_finite() {
            return Err(DemError::InvalidParameter {
                name,
                value: c,
                reason: "must be finite",
            });
        }
    }
    Ok(())
}

fn finite(x: f64, name: &'static str) -> Result<(), DemError> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(DemError::InvalidParameter {
            name,
            value: x,
            reason: "must be finite",
        })
    }
}

impl Envelope {
    /// An envelope from samples, validated.
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] if the series is empty, the lengths
    /// differ, a time or factor is not finite, or the times do not increase.
    pub fn new(times_s: Vec<f64>, factors: Vec<f64>) -> Result<Self, DemError> {
        let e = Envelope { times_s, factors };
        e.validate()?;
        Ok(e)
    }

    /// The factor `a(t)` at time `t_s` (s), dimensionless. Never allocates.
    #[inline]
    pub fn factor(&self, t_s: f64) -> f64 {
        let n = self.times_s.len().min(self.factors.len());
        if n == 0 {
            return 0.0;
        }
        let (i, w) = locate(&self.times_s, n, t_s);
        if w == 0.0 {
            self.factors[i]
        } else {
            (1.0 - w) * self.factors[i] + w * self.factors[i + 1]
        }
    }

    /// Checks the samples (see [`Envelope::new`]).
    ///
    /// # Errors
    /// As [`Envelope::new`].
    pub fn validate(&self) -> Result<(), DemError> {
        validate_times(&self.times_s, "envelope.times_s")?;
        if self.factors.len() != self.times_s.len() {
            return Err(DemError::InvalidParameter {
                name: "envelope.factors",
                value: self.factors.len() as f64,
                reason: "needs exactly one factor per entry of times_s",
            });
        }
        for &a in &self.factors {
            finite(a, "envelope.factors")?;
        }
        Ok(())
    }
}

impl VelocityField {
    /// This field multiplied by `envelope`.
    pub fn scaled(self, envelope: Envelope) -> Self {
        VelocityField::Scaled {
            field: Box::new(self),
            envelope,
        }
    }

    /// The velocity at `position_m` (m) and time `t_s` (s), m/s. Never allocates.
    #[inline]
    pub fn velocity(&self, position_m: Vec2, t_s: f64) -> Vec2 {
        match self {
            VelocityField::Uniform(u) => *u,
            VelocityField::TimeSeries { times_s, values } => {
                let n = times_s.len().min(values.len());
                if n == 0 {
                    return Vec2::ZERO;
                }
                let (i, w) = locate(times_s, n, t_s);
                if w == 0.0 {
                    values[i]
                } else {
                    (1.0 - w) * values[i] + w * values[i + 1]
                }
            }
            VelocityField::LinearShear {
                y_min_m,
                y_max_m,
                velocity_at_y_min_m_per_s,
                velocity_at_y_max_m_per_s,
            } => {
                let s = ((position_m.y - y_min_m) / (y_max_m - y_min_m)).clamp(0.0, 1.0);
                if s.is_nan() {
                    return *velocity_at_y_min_m_per_s;
                }
                *velocity_at_y_min_m_per_s
                    + s * (*velocity_at_y_max_m_per_s - *velocity_at_y_min_m_per_s)
            }
            VelocityField::Gyre {
                center_m,
                core_radius_m,
                max_speed_m_per_s,
            } => {
                let r = position_m - *center_m;
                let d2 = r.length_squared();
                let rc = *core_radius_m;
                if d2 <= rc * rc {
                    // Solid body: angular velocity V/R.
                    (max_speed_m_per_s / rc) * r.perp()
                } else {
                    // Irrotational: speed V R / d along k × r̂ = (V R / d²) k × r.
                    (max_speed_m_per_s * rc / d2) * r.perp()
                }
            }
            VelocityField::Scaled { field, envelope } => {
                envelope.factor(t_s) * field.velocity(position_m, t_s)
            }
            VelocityField::Gridded(g) => g.vector(position_m, t_s),
        }
    }

    /// [`VelocityField::velocity`] and [`VelocityField::vorticity`]
    /// together (one grid lookup for a gridded field).
    #[inline]
    pub fn velocity_and_vorticity(&self, position_m: Vec2, t_s: f64) -> (Vec2, f64) {
        match self {
            VelocityField::Gridded(g) => g.vector_and_vorticity(position_m, t_s),
            VelocityField::Scaled { field, envelope } => {
                let a = envelope.factor(t_s);
                let (u, z) = field.velocity_and_vorticity(position_m, t_s);
                (a * u, a * z)
            }
            _ => (
                self.velocity(position_m, t_s),
                self.vorticity(position_m, t_s),
            ),
        }
    }

    /// Makes a gridded field ready for `t_s` and checks the free floes lie
    /// on its grid ([`GriddedField::prepare`]); nothing for the others.
    ///
    /// # Errors
    /// As [`GriddedField::prepare`].
    pub fn prepare(&mut self, t_s: f64, floes: &FloeColumns) -> Result<(), ForcingFailure> {
        match self {
            VelocityField::Gridded(g) => g.prepare(t_s, floes),
            VelocityField::Scaled { field, .. } => field.prepare(t_s, floes),
            _ => Ok(()),
        }
    }

    /// The vertical vorticity `ζ = ∂U_y/∂x − ∂U_x/∂y` at `position_m` (m)
    /// and `t_s` (s), 1/s (positive counterclockwise). On the edges of the
    /// shear channel and of the vortex core, where the field has a kink, the
    /// inside value is returned. Never allocates.
    #[inline]
    pub fn vorticity(&self, position_m: Vec2, t_s: f64) -> f64 {
        match self {
            VelocityField::Uniform(_) | VelocityField::TimeSeries { .. } => 0.0,
            VelocityField::LinearShear {
                y_min_m,
                y_max_m,
                velocity_at_y_min_m_per_s,
                velocity_at_y_max_m_per_s,
            } => {
                let y = position_m.y;
                if y >= *y_min_m && y <= *y_max_m && y_max_m > y_min_m {
                    -(velocity_at_y_max_m_per_s.x - velocity_at_y_min_m_per_s.x)
                        / (y_max_m - y_min_m)
                } else {
                    0.0
                }
            }
            VelocityField::Gyre {
                center_m,
                core_radius_m,
                max_speed_m_per_s,
            } => {
                let d2 = (position_m - *center_m).length_squared();
                if d2 <= core_radius_m * core_radius_m {
                    2.0 * max_speed_m_per_s / core_radius_m
                } else {
                    0.0
                }
            }
            VelocityField::Scaled { field, envelope } => {
                envelope.factor(t_s) * field.vorticity(position_m, t_s)
            }
            VelocityField::Gridded(g) => g.vorticity(position_m, t_s),
        }
    }

    /// Checks the parameters: finite values, strictly increasing sample
    /// times, one value per time, `y_max_m > y_min_m`, `core_radius_m > 0`.
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] naming the first offending field.
    pub fn validate(&self) -> Result<(), DemError> {
        match self {
            VelocityField::Uniform(u) => finite_vec(*u, "uniform"),
            VelocityField::TimeSeries { times_s, values } => {
                validate_times(times_s, "time-series.times_s")?;
                if values.len() != times_s.len() {
                    return Err(DemError::InvalidParameter {
                        name: "time-series.values",
                        value: values.len() as f64,
                        reason: "needs exactly one value per entry of times_s",
                    });
                }
                for v in values {
                    finite_vec(*v, "time-series.values")?;
                }
                Ok(())
            }
            VelocityField::LinearShear {
                y_min_m,
                y_max_m,
                velocity_at_y_min_m_per_s,
                velocity_at_y_max_m_per_s,
            } => {
                finite(*y_min_m, "linear-shear.y_min_m")?;
                finite(*y_max_m, "linear-shear.y_max_m")?;
                if y_max_m <= y_min_m {
                    return Err(DemError::InvalidParameter {
                        name: "linear-shear.y_max_m",
                        value: *y_max_m,
                        reason: "must be greater than y_min_m",
                    });
                }
                finite_vec(
                    *velocity_at_y_min_m_per_s,
                    "linear-shear.velocity_at_y_min_m_per_s",
                )?;
                finite_vec(
                    *velocity_at_y_max_m_per_s,
                    "linear-shear.velocity_at_y_max_m_per_s",
                )
            }
            VelocityField::Gyre {
                center_m,
                core_radius_m,
                max_speed_m_per_s,
            } => {
                finite_vec(*center_m, "gyre.center_m")?;
                finite(*max_speed_m_per_s, "gyre.max_speed_m_per_s")?;
                if !(core_radius_m.is_finite() && *core_radius_m > 0.0) {
                    return Err(DemError::InvalidParameter {
                        name: "gyre.core_radius_m",
                        value: *core_radius_m,
                        reason: "must be positive and finite",
                    });
                }
                Ok(())
            }
            VelocityField::Scaled { field, envelope } => {
                envelope.validate()?;
                field.validate()
            }
            // Checked when built (GriddedField::new).
            VelocityField::Gridded(_) => Ok(()),
        }
    }
}
