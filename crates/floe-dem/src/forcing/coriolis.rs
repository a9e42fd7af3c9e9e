//! Coriolis force and the sea-surface tilt that balances it.
//!
//! ```text
//! F_cor  = −m f k × u                 (N),  k × (u_x, u_y) = (−u_y, u_x)
//! f      = 2 Ω sin(latitude),         Ω = 7.2921e-5 rad/s
//! F_tilt = −m g ∇η = m f k × U_w      (geostrophic tilt)
//! ```
//!
//! With `f > 0` (Northern Hemisphere) `F_cor` points to the right of the
//! velocity; it is perpendicular to `u` and does no work. The sea-surface
//! tilt is taken in geostrophic balance with the current `U_w`,
//! `f k × U_w = −g ∇η`, so that `F_tilt = m f k × U_w` exactly cancels the
//! Coriolis force on a floe moving with the current (`u = U_w`): without the
//! tilt, ice drifting with a geostrophic current would be pushed to its right.
//! The balance assumes the prescribed current is geostrophic (steady and
//! slowly varying); for idealised currents (a gyre, a shear channel) it is a
//! modelling choice. Subzero.jl applies the same pressure-gradient force,
//! `(−m/A f v_ocn, m/A f u_ocn)` per unit area.
//!
//! Rotation about the vertical does not feel Coriolis: for a floe spinning
//! rigidly, the force density `−ρh f k × (ω k × r) = ρh f ω r` is radial and
//! gives no torque about the centroid (and no net force).
//!
//! Default: [`Coriolis::Off`] (a non-rotating frame). Arctic runs:
//! [`Coriolis::LatitudeDeg`]`(75.0)` gives `f = 1.409e-4 /s`; Subzero.jl
//! defaults to `f = 1.4e-4 /s`.

use crate::{DemError, Vec2};

/// Earth's rotation rate Ω, rad/s (sidereal day).
pub const EARTH_ROTATION_RATE_RAD_PER_S: f64 = 7.2921e-5;

/// The Coriolis parameter of a run (a scenario's `[coriolis]` table,
/// docs/scenarios.md).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Coriolis {
    /// `f = 0`: no Coriolis force and no sea-surface tilt.
    #[default]
    Off,
    /// `f = 2 Ω sin(latitude)`, latitude in degrees, north positive, `|·| ≤ 90`.
    LatitudeDeg(f64),
    /// `f` given directly, 1/s (negative in the Southern Hemisphere).
    ParameterPerS(f64),
}

impl Coriolis {
    /// The Coriolis parameter `f`, 1/s.
    #[inline]
    pub fn parameter_per_s(&self) -> f64 {
        match *self {
            Coriolis::Off => 0.0,
            Coriolis::LatitudeDeg(lat) => {
                2.0 * EARTH_ROTATION_RATE_RAD_PER_S * lat.to_radians().sin()
            }
            Coriolis::ParameterPerS(f) => f,
        }
    }

    /// Checks `|latitude| ≤ 90°` or a finite `f`.
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] otherwise.
    pub fn validate(&self) -> Result<(), DemError> {
        match *self {
            Coriolis::Off => Ok(()),
            Coriolis::LatitudeDeg(lat) if lat.abs() <= 90.0 => Ok(()),
            Coriolis::LatitudeDeg(lat) => Err(DemError::InvalidParameter {
                name: "coriolis.latitude_deg",
                value: lat,
                reason: "must lie between -90 and 90 degrees",
            }),
            Coriolis::ParameterPerS(f) if f.is_finite() => Ok(()),
            Coriolis::ParameterPerS(f) => Err(DemError::InvalidParameter {
                name: "coriolis.f_per_s",
                value: f,
                reason: "must be finite",
            }),
        }
    }
}

/// Coriolis force, N: `−m f k × u` for mass `mass_kg` (kg), Coriolis
/// parameter `f_per_s` (1/s) and velocity `velocity_m_per_s` (m/s).
#[inline]
pub fn coriolis_force(mass_kg: f64, f_per_s: f64, velocity_m_per_s: Vec2) -> Vec2 {
    -(mass_kg * f_per_s) * velocity_m_per_s.perp()
}

/// Sea-surface tilt force, N: `−m g ∇η = m f k × U_w` for a surface tilted in
/// geostrophic balance with the current `current_m_per_s` (m/s).
#[inline]
pub fn sea_surface_tilt_force(mass_kg: f64, f_per_s: f64, current_m_per_s: Vec2) -> Vec2 {
    (mass_kg * f_per_s) * current_m_per_s.perp()
}
