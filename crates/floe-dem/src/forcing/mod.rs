//! Wind and ocean forcing of a floe: quadratic drag with turning angles,
//! Coriolis, sea-surface tilt and rotational drag.
//!
//! For a floe of area `A` (m²), mass `m` (kg), centroid velocity `u` (m/s)
//! and angular velocity `ω` (rad/s, counterclockwise), with the wind `U_a` and
//! current `U_w` sampled at its centroid at time `t`:
//!
//! ```text
//! F = A τ_a + A τ_w − m f k × u + [tilt] m f k × U_w                  (N)
//! τ_a = ρ_a C_a |U_a| R(φ_a) U_a          (or U_a − u if air.relative_to_ice)
//! τ_w = ρ_w C_w |U_w − u| R(θ_w) (U_w − u)
//! T = −ρ_w C_w cos θ_w |ω − ζ_w/2| (ω − ζ_w/2) ∫ r³ dA                  (N m)
//! ```
//!
//! `R(φ)` rotates counterclockwise; `k × (x, y) = (−y, x)`; `f = 2 Ω sin(lat)`;
//! `ζ_w` is the current's vorticity at the centroid. Details, sign conventions
//! and approximations: [`drag`] (stress, turning angle, torque, `∫ r³ dA`),
//! [`coriolis`] (Coriolis, tilt), [`fields`] (velocity fields),
//! [`free_drift`] (steady drift without time stepping).
//!
//! # Defaults ([`Forcing::default`])
//!
//! | quantity | default | sources |
//! |---|---|---|
//! | wind, current | 0 m/s everywhere | — |
//! | air density `ρ_a` | 1.2 kg/m³ | Subzero.jl `ρa = 1.2`; 1.3 is common in CICE-family codes |
//! | air drag `C_a` | 1.2e-3 | DEMSI 0.0012 (project notes), Hibler (1979); Subzero.jl 1e-3 |
//! | ocean density `ρ_w` | 1027 kg/m³ | Subzero.jl `ρo = 1027` |
//! | ocean drag `C_w` | 5.5e-3 | DEMSI 0.0045–0.0055 (project notes), Hibler (1979); Subzero.jl 3e-3 |
//! | turning angles | 0° (air and ocean) | typical ocean 20–25° NH (Hibler 1979 25°; Subzero.jl 15°), counterclockwise positive |
//! | air drag relative to ice | no (ice speed ≪ wind) | usual practice |
//! | ocean drag relative to ice | yes | — |
//! | Coriolis | off | Subzero.jl default `f = 1.4e-4 /s` (≈ 74° N) |
//! | sea-surface tilt | on (acts only with Coriolis and a current) | Subzero.jl always applies it |
//! | rotational drag | on | — |
//!
//! With these defaults the free-drift wind factor (no current, no Coriolis)
//! is `sqrt(ρ_a C_a / (ρ_w C_w)) = 1.597 %`.
//!
//! The DEMSI values are those listed in the project notes
//! (`shared/notes/physics.md`), not re-checked against the DEMSI source;
//! Hibler (1979), *A dynamic thermodynamic sea ice model*, JPO 9, is cited
//! from memory.
//!
//! # Cost
//!
//! [`Forcing::force_and_torque`] runs for every floe every step. It does not
//! allocate: fields are evaluated in place (a time series by binary search).

pub mod coriolis;
pub mod drag;
pub mod external;
pub mod fields;
pub mod free_drift;
pub mod gridded;

pub use coriolis::{
    coriolis_force, sea_surface_tilt_force, Coriolis, EARTH_ROTATION_RATE_RAD_PER_S,
};
pub use drag::{
    polygon_r3_moment, rotate, DragParameters, AIR_DENSITY_KG_PER_M3, AIR_DRAG_COEFFICIENT,
    OCEAN_DRAG_COEFFICIENT, SEAWATER_DENSITY_KG_PER_M3,
};
pub use external::{ExternalForces, ForceRates, NoForcing};
pub use fields::{Envelope, VelocityField};
pub use free_drift::free_drift_velocity;
pub use gridded::{ForcingFailure, GriddedField, PlaneGrid, SliceSource};

use crate::floes::FloeColumns;
use crate::{DemError, Vec2};

/// Standard gravity, m/s², for the sea-surface tilt from a height field.
pub const GRAVITY_M_PER_S2: f64 = 9.80665;

/// Wind and ocean forcing of every floe. Scenario files describe it in
/// their `[wind]`, `[ocean]` and `[coriolis]` tables (floe-scenario reads
/// them; docs/scenarios.md); [`Default`] gives the values of the table
/// above. Call [`Forcing::validate`] on one built by hand.
#[derive(Debug, Clone, PartialEq)]
pub struct Forcing {
    /// Wind velocity (10 m), m/s.
    pub wind: VelocityField,
    /// Ocean surface current, m/s.
    pub current: VelocityField,
    /// Air drag parameters.
    pub air: DragParameters,
    /// Ocean drag parameters.
    pub ocean: DragParameters,
    /// Coriolis parameter.
    pub coriolis: Coriolis,
    /// Add the sea-surface tilt force `m f k × U_w` in geostrophic balance
    /// with the current (no effect without Coriolis or current).
    pub sea_surface_tilt: bool,
    /// Add the drag torque on floe rotation (media with drag relative to the ice).
    pub rotational_drag: bool,
    /// Sea-surface height `η` (m) on a grid: when given, the tilt force is
    /// `−m g ∇η` from it (with `sea_surface_tilt`), in place of the
    /// geostrophic `m f k × U_w`.
    pub sea_surface_height: Option<GriddedField>,
}

impl Default for Forcing {
    /// The defaults in the module table: no wind or current, air
    /// [`DragParameters::air`], ocean [`DragParameters::ocean`], Coriolis off,
    /// tilt and rotational drag on.
    fn default() -> Self {
        Forcing {
            wind: VelocityField::default(),
            current: VelocityField::default(),
            air: DragParameters::air(),
            ocean: DragParameters::ocean(),
            coriolis: Coriolis::Off,
            sea_surface_tilt: true,
            rotational_drag: true,
            sea_surface_height: None,
        }
    }
}

/// What the forcing needs to know about one floe, SI units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FloeDynamics {
    /// Centroid position, m.
    pub position: Vec2,
    /// Centroid velocity, m/s.
    pub velocity: Vec2,
    /// Angular velocity about the centroid, rad/s, counterclockwise positive.
    pub angular_velocity: f64,
    /// Plan-view area, m².
    pub area_m2: f64,
    /// Mass, kg (`ρ_ice h A`).
    pub mass_kg: f64,
    /// `∫ r³ dA` about the centroid, m⁵ ([`polygon_r3_moment`]).
    pub r3_moment_m5: f64,
}

impl Forcing {
    /// Net forcing on one floe at time `t_s` (s): the force on its centroid
    /// (N) and the torque about it (N m, counterclockwise positive). Formulas
    /// in the module docs. Does not allocate.
    #[inline]
    pub fn force_and_torque(&self, t_s: f64, floe: &FloeDynamics) -> (Vec2, f64) {
        let (force, torque, _) = self.force_torque_and_rates(t_s, floe);
        (force, torque)
    }

    /// [`Forcing::force_and_torque`] and its derivatives with the floe's
    /// velocity and angular velocity (drag and Coriolis depend on them).
    #[inline]
    pub fn force_torque_and_rates(&self, t_s: f64, floe: &FloeDynamics) -> (Vec2, f64, ForceRates) {
        // Vorticity only where the rotational drag will use it.
        let spin = |relative: bool| self.rotational_drag && relative;
        let field = |f: &VelocityField, with_vorticity: bool| {
            if with_vorticity {
                f.velocity_and_vorticity(floe.position, t_s)
            } else {
                (f.velocity(floe.position, t_s), 0.0)
            }
        };
        let (wind, wind_zeta) = field(&self.wind, spin(self.air.relative_to_ice));
        let (current, current_zeta) = field(&self.current, spin(self.ocean.relative_to_ice));
        let stress =
            self.air.stress(wind, floe.velocity) + self.ocean.stress(current, floe.velocity);
        let mut force = floe.area_m2 * stress;
        let mut rates = ForceRates::ZERO;
        let (air, ocean) = (
            self.air.stress_rate(wind, floe.velocity),
            self.ocean.stress_rate(current, floe.velocity),
        );
        for (i, row) in rates.force_per_velocity.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = floe.area_m2 * (air[i][j] + ocean[i][j]);
            }
        }
        let f = self.coriolis.parameter_per_s();
        if f != 0.0 {
            force += coriolis_force(floe.mass_kg, f, floe.velocity);
            // -m f k x u = m f (u_y, -u_x).
            let mf = floe.mass_kg * f;
            rates.force_per_velocity[0][1] += mf;
            rates.force_per_velocity[1][0] -= mf;
            if self.sea_surface_tilt && self.sea_surface_height.is_none() {
                force += sea_surface_tilt_force(floe.mass_kg, f, current);
            }
        }
        if let (true, Some(eta)) = (self.sea_surface_tilt, &self.sea_surface_height) {
            let (_, slope) = eta.value_and_gradient(0, floe.position, t_s);
            force -= floe.mass_kg * GRAVITY_M_PER_S2 * slope;
        }
        let mut torque = 0.0;
        if self.rotational_drag {
            for (drag, zeta) in [(&self.ocean, current_zeta), (&self.air, wind_zeta)] {
                if drag.relative_to_ice {
                    let w_rel = floe.angular_velocity - 0.5 * zeta;
                    torque += drag.rotational_torque(w_rel, floe.r3_moment_m5);
                    rates.torque_per_angular_velocity +=
                        drag.rotational_torque_rate(w_rel, floe.r3_moment_m5);
                }
            }
        }
        (force, torque, rates)
    }

    /// The steady free-drift velocity (m/s) of ice of mass per area
    /// `mass_per_area_kg_per_m2` (`ρ_ice h`, kg/m²) under the wind and current
    /// found at `position_m` (m) and `t_s` (s), taken as uniform and steady.
    /// See [`free_drift_velocity`].
    ///
    /// # Errors
    /// As [`free_drift_velocity`].
    pub fn free_drift_velocity_at(
        &self,
        t_s: f64,
        position_m: Vec2,
        mass_per_area_kg_per_m2: f64,
    ) -> Result<Vec2, DemError> {
        free_drift_velocity(
            self.wind.velocity(position_m, t_s),
            self.current.velocity(position_m, t_s),
            &self.air,
            &self.ocean,
            self.coriolis.parameter_per_s(),
            mass_per_area_kg_per_m2,
            self.sea_surface_tilt,
        )
    }

    /// Makes the gridded fields (wind, current, sea-surface height) ready
    /// for `t_s` ([`GriddedField::prepare`]).
    ///
    /// # Errors
    /// As [`GriddedField::prepare`].
    pub fn prepare(&mut self, t_s: f64, floes: &FloeColumns) -> Result<(), ForcingFailure> {
        self.wind.prepare(t_s, floes)?;
        self.current.prepare(t_s, floes)?;
        match &mut self.sea_surface_height {
            Some(eta) => eta.prepare(t_s, floes),
            None => Ok(()),
        }
    }

    /// Checks every part: fields, drag parameters, Coriolis.
    ///
    /// # Errors
    /// [`DemError::InvalidParameter`] for the first invalid value found (wind,
    /// current, air, ocean, Coriolis, in that order).
    pub fn validate(&self) -> Result<(), DemError> {
        self.wind.validate()?;
        self.current.validate()?;
        self.air.validate()?;
        self.ocean.validate()?;
        self.coriolis.validate()
    }
}
