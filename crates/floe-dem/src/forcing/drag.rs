//! Quadratic drag with a turning angle, the rotational drag torque, and the
//! polar moment `∫ r³ dA` of a polygon it needs.
//!
//! # Stress
//!
//! ```text
//! τ = ρ C_d |U_rel| R(φ) U_rel                     (Pa)
//! U_rel = U_fluid − u_ice   (relative_to_ice = true)
//! U_rel = U_fluid           (relative_to_ice = false)
//! R(φ) = [cos φ  −sin φ; sin φ  cos φ]            (counterclockwise by φ)
//! ```
//!
//! `φ > 0` rotates the stress counterclockwise (to the left) of `U_rel`. That
//! is the Northern-Hemisphere sense when `U_fluid` is a velocity outside the
//! boundary layer (geostrophic current below the ocean Ekman layer,
//! geostrophic wind above the atmospheric one): the Ekman spiral turns to the
//! right with distance from the ice in the north, so the stress on the ice is
//! to the left of the far-field relative velocity. Typical ocean values are
//! 20–25° (Hibler 1979 uses 25° for both media; McPhee's under-ice
//! boundary-layer measurements are in that range); Subzero.jl uses 15° for the
//! ocean, with the same counterclockwise sign (its `turnθ`). In the Southern
//! Hemisphere use `φ < 0`. With a surface-layer
//! velocity (10 m wind, current just under the ice) `φ = 0`, the default here.
//!
//! The force on a floe is `area × τ`, with the fluid velocity sampled at the
//! centroid and the ice velocity of the centroid.
//!
//! # Rotational drag torque
//!
//! A floe spinning at `ω` (rad/s, counterclockwise) relative to the fluid
//! sees a local relative velocity `−ω k × r` at `r` from its centroid. With
//! the same quadratic law, the stress there is `ρ C_d |ω| r R(φ)(−ω k × r)`,
//! whose moment about the centroid integrates to
//!
//! ```text
//! τ_z = −ρ C_d cos φ |ω_rel| ω_rel ∫_floe r³ dA    (N m),   ω_rel = ω − ζ/2
//! ```
//!
//! with `ζ` the fluid vorticity at the centroid (fluid in solid-body rotation
//! at `ζ/2` exerts no torque on a floe co-rotating with it). Approximations:
//! the translational relative velocity is ignored in `|·|` (no coupling
//! between translation and rotation; exact only for a floe drifting with the
//! fluid), so is the strain of the fluid velocity across the floe; the radial
//! part `sin φ` of the rotated stress, which gives no torque but a small net
//! force on asymmetric floes, is dropped. With `φ = 0` this is the usual
//! `τ_z = −ρ_w C_w |ω| ω ∫ r³ dA`. Only media whose drag is
//! `relative_to_ice` contribute (the wind, with ice motion neglected, exerts
//! no rotational drag). The moment `∫ r³ dA` is the shape's
//! ([`polygon_r3_moment`], in [`crate::geometry`]).

pub use crate::geometry::polygon_r3_moment;
use crate::{DemError, Vec2};

/// Air density, kg/m³: 1.2 (Subzero.jl `ρa`; dry air near 0 °C is 1.29, and
/// CICE-family codes often use 1.3).
pub const AIR_DENSITY_KG_PER_M3: f64 = 1.2;
/// Ice–air drag coefficient (10 m wind, neutral): 1.2e-3, DEMSI's value
/// (project notes); Subzero.jl uses 1e-3.
pub const AIR_DRAG_COEFFICIENT: f64 = 1.2e-3;
/// Sea-water density, kg/m³: 1027 (Subzero.jl `ρo`).
pub const SEAWATER_DENSITY_KG_PER_M3: f64 = 1027.0;
/// Ice–ocean drag coefficient: 5.5e-3, the upper DEMSI value (DEMSI
/// 0.0045–0.0055 per the project notes; Subzero.jl uses 3e-3). 5.5e-3 with
/// `C_a = 1.2e-3` is also the classic pair of Hibler (1979), there used with
/// geostrophic velocities and 25° turning angles (cited from memory).
pub const OCEAN_DRAG_COEFFICIENT: f64 = 5.5e-3;

/// Quadratic drag of one fluid (air or ocean) on the ice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DragParameters {
    /// Fluid density `ρ`, kg/m³; `≥ 0`.
    pub density_kg_per_m3: f64,
    /// Dimensionless drag coefficient `C_d`; `≥ 0`.
    pub drag_coefficient: f64,
    /// Turning angle `φ`, degrees, positive counterclockwise (Northern
    /// Hemisphere sense for a far-field velocity); `|φ| < 90`.
    pub turning_angle_deg: f64,
    /// `true`: `U_rel = U_fluid − u_ice` (and rotational drag applies);
    /// `false`: `U_rel = U_fluid` (ice motion neglected, as usual for wind).
    pub relative_to_ice: bool,
}

impl DragParameters {
    /// Air defaults: `ρ = 1.2 kg/m³`, `C_d = 1.2e-3`, `φ = 0`, ice motion
    /// neglected.
    pub const fn air() -> Self {
        DragParameters {
            density_kg_per_m3: AIR_DENSITY_KG_PER_M3,
            drag_coefficient: AIR_DRAG_COEFFICIENT,
            turning_angle_deg: 0.0,
            relative_to_ice: false,
        }
    }

    /// Ocean defaults: `ρ = 1027 kg/m³`, `C_d = 5.5e-3`, `φ = 0`, relative
    /// to the ice.
    pub const fn ocean() -> Self {
        DragParameters {
            density_kg_per_m3: SEAWATER_DENSITY_KG_PER_M3,
            drag_coefficient: OCEAN_DRAG_COEFFICIENT,
            turning_angle_deg: 0.0,
            relative_to_ice: true,
        }
    }

    /// `ρ C_d`, kg/m³.
    #[inline]
    pub fn rho_cd(&self) -> f64 {
        self.density_kg_per_m3 * self.drag_coefficient
    }

    /// The relative velocity `U_rel` (m/s) for a fluid velocity and an ice
    /// velocity (m/s).
    #[inline]
    pub fn relative_velocity(&self, fluid_m_per_s: Vec2, ice_m_per_s: Vec2) -> Vec2 {
        if self.relative_to_ice {
            fluid_m_per_s - ice_m_per_s
        } else {
            fluid_m_per_s
        }
    }

    /// Stress on the ice, Pa: `ρ C_d |U_rel| R(φ) U_rel`. Never allocates.
    #[inline]
    pub fn stress(&self, fluid_m_per_s: Vec2, ice_m_per_s: Vec2) -> Vec2 {
        let u = self.relative_velocity(fluid_m_per_s, ice_m_per_s);
        let k = self.rho_cd() * u.length();
        if self.turning_angle_deg == 0.0 {
            k * u
        } else {
            k * rotate(u, self.turning_angle_deg.to_radians())
        }
    }

    /// `∂τ/∂u_ice`, Pa s/m, row by row: `−ρ C_d R(φ) (|U_rel| I + U_rel
    /// U_rel^T / |U_rel|)`; zero when the drag ignores the ice's motion (or
    /// at `U_rel = 0`, where `|U_rel| U_rel` has a zero derivative).
    #[inline]
    pub fn stress_rate(&self, fluid_m_per_s: Vec2, ice_m_per_s: Vec2) -> [[f64; 2]; 2] {
        let u = self.relative_velocity(fluid_m_per_s, ice_m_per_s);
        let speed = u.length();
        if !self.relative_to_ice || speed == 0.0 {
            return [[0.0; 2]; 2];
        }
        let k = self.rho_cd();
        // d(|u| u)/du, and du/du_ice = -I.
        let s = [
            [speed + u.x * u.x / speed, u.x * u.y / speed],
            [u.y * u.x / speed, speed + u.y * u.y / speed],
        ];
        let (sin, cos) = if self.turning_angle_deg == 0.0 {
            (0.0, 1.0)
        } else {
            self.turning_angle_deg.to_radians().sin_cos()
        };
        let r = [[cos, -sin], [sin, cos]];
        let mut out = [[0.0; 2]; 2];
        for (i, row) in out.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = -k * (r[i][0] * s[0][j] + r[i][1] * s[1][j]);
            }
        }
        out
    }

    /// `∂T/∂ω` of [`DragParameters::rotational_torque`], N m s:
    /// `−2 ρ C_d cos φ |ω| ∫ r³ dA`.
    #[inline]
    pub fn rotational_torque_rate(
        &self,
        relative_angular_velocity_rad_per_s: f64,
        r3_moment_m5: f64,
    ) -> f64 {
        let cos_phi = if self.turning_angle_deg == 0.0 {
            1.0
        } else {
            self.turning_angle_deg.to_radians().cos()
        };
        -2.0 * self.rho_cd() * cos_phi * relative_angular_velocity_rad_per_s.abs() * r3_moment_m5
    }

    /// Rotational drag torque, N m, on a floe spinning at
    /// `relative_angular_velocity_rad_per_s` (`ω − ζ/2`, counterclockwise
    /// positive) with `∫ r³ dA = r3_moment_m5` (m⁵):
    /// `−ρ C_d cos φ |ω| ω ∫ r³ dA`. Never allocates.
    #[inline]
    pub fn rotational_torque(
        &self,
        relative_angular_velocity_rad_per_s: f64,
        r3_moment_m5: f64,
    ) -> f64 {
        let w = relative_angular_velocity_rad_per_s;
        let cos_phi = if self.turning_angle_deg == 0.0 {
            1.0
        } else {
            self.turning_angle_deg.to_radians().cos()
        };
        -self.rho_cd() * cos_phi * w.abs() * w * r3_moment_m5
    }

    /// Checks `ρ ≥ 0`, `C_d ≥ 0` (finite) and `|φ| < 90°`.
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] naming the first offending field.
    pub fn validate(&self) -> Result<(), DemError> {
        let checks: [(&'static str, f64, bool, &'static str); 3] = [
            (
                "density_kg_per_m3",
                self.density_kg_per_m3,
                self.density_kg_per_m3.is_finite() && self.density_kg_per_m3 >= 0.0,
                "must be finite and non-negative",
            ),
            (
                "drag_coefficient",
                self.drag_coefficient,
                self.drag_coefficient.is_finite() && self.drag_coefficient >= 0.0,
                "must be finite and non-negative",
            ),
            (
                "turning_angle_deg",
                self.turning_angle_deg,
                self.turning_angle_deg.abs() < 90.0,
                "must lie strictly between -90 and 90 degrees",
            ),
        ];
        for (name, value, ok, reason) in checks {
            if !ok {
                return Err(DemError::InvalidParameter {
                    name,
                    value,
                    reason,
                });
            }
        }
        Ok(())
    }
}

/// `v` rotated counterclockwise by `angle_rad`.
#[inline]
pub fn rotate(v: Vec2, angle_rad: f64) -> Vec2 {
    let (s, c) = angle_rad.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}
