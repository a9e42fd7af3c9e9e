//! The steady free-drift velocity of a floe under uniform wind and current:
//! the `u` with zero net force, solved without any time integration.
//!
//! Per unit area, with `v = U_w − u` (water relative to ice), `c_w = ρ_w C_w`,
//! `θ` the ocean turning angle, `m' = m/A = ρ_ice h` and `f` the Coriolis
//! parameter, the balance
//!
//! ```text
//! τ_a + c_w |v| R(θ) v − m' f k × u + [tilt] m' f k × U_w = 0
//! ```
//!
//! becomes, using `−m' f k × u = −m' f k × U_w + m' f k × v`,
//!
//! ```text
//! c_w |v| R(θ) v + m' f k × v = s,      s = −τ_a + [no tilt] m' f k × U_w.
//! ```
//!
//! In complex notation (`R(θ) = e^{iθ}`, `k× = i`) this is `z(|v|) v = s`
//! with `z(w) = c_w w e^{iθ} + i m' f`, so `|v|` solves the scalar equation
//! `w |z(w)| = |s|` and then `v = s / z(|v|)`.
//!
//! * No Coriolis (`f = 0`): closed form `|v| = sqrt(|s|/c_w)`, i.e. with no
//!   current and `θ = φ = 0`, `u = sqrt(ρ_a C_a / (ρ_w C_w)) U_a`, the
//!   "2 % wind factor" (1.6 % with the defaults).
//! * With Coriolis: `w |z(w)|` is increasing in `w` whenever
//!   `|θ| < arcsin(sqrt(8/9)) ≈ 70.5°` (derivative
//!   `2w (2c²w² + 3 c m' f sin θ w + m'² f²) / (w|z|)`), so the root is unique;
//!   it is found by bisection to the last bit. In the Northern Hemisphere the
//!   drift is deflected to the right of the wind and is slower than without
//!   rotation (part of the wind stress balances Coriolis instead of drag).
//! * Air drag relative to the ice (`air.relative_to_ice`): `τ_a` depends on
//!   `u`; a fixed-point iteration on `τ_a(u)` is used, which contracts by
//!   about `sqrt(ρ_a C_a / (ρ_w C_w)) ≈ 0.016` per iteration.
//!
//! The wind stress uses `air.stress`, so any air turning angle is included.
//! The answer assumes `U_a`, `U_w` uniform and steady; for the engine's
//! fields, [`Forcing::free_drift_velocity_at`](super::Forcing::free_drift_velocity_at)
//! evaluates them at one point and time.

use super::drag::DragParameters;
use crate::{DemError, Vec2};

/// Solves `c_w |v| R(θ) v + a k × v = s` for `v` (see the module docs).
fn solve_relative(s: Vec2, cw: f64, theta_rad: f64, a: f64) -> Vec2 {
    let smag = s.length();
    if smag == 0.0 {
        return Vec2::ZERO;
    }
    let (st, ct) = theta_rad.sin_cos();
    let w = if a == 0.0 {
        (smag / cw).sqrt()
    } else {
        let m = |w: f64| w * (cw * w * ct).hypot(cw * w * st + a) - smag;
        let mut lo = 0.0_f64;
        let mut hi = (smag / cw).sqrt();
        while m(hi) < 0.0 {
            lo = hi;
            hi *= 2.0;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if m(mid) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    // v = s / z, z = c_w w e^{iθ} + i a.
    let zr = cw * w * ct;
    let zi = cw * w * st + a;
    let z2 = zr * zr + zi * zi;
    Vec2::new(s.x * zr + s.y * zi, s.y * zr - s.x * zi) / z2
}

/// The steady free-drift ice velocity, m/s, under a uniform, steady wind
/// `wind_m_per_s` and current `current_m_per_s` (m/s): the `u` at which wind drag +
/// ocean drag + Coriolis (+ sea-surface tilt) vanish. `coriolis_f_per_s` is
/// `f` (1/s; 0 for none), `mass_per_area_kg_per_m2` is `ρ_ice h` (kg/m²; only
/// used with `f ≠ 0`). The ocean turning angle and any air turning angle are
/// included. Method in the module docs; independent of any time stepping.
///
/// # Errors
/// [`DemError::InvalidParameter`] if the ocean drag is not relative to the
/// ice or `ρ_w C_w ≤ 0` (no steady state), if a parameter is invalid, or if
/// the mass per area is negative or not finite;
/// [`DemError::NoConvergence`] if the fixed-point iteration for air drag
/// relative to the ice does not converge (only when `ρ_a C_a` is not small
/// compared with `ρ_w C_w`).
pub fn free_drift_velocity(
    wind_m_per_s: Vec2,
    current_m_per_s: Vec2,
    air: &DragParameters,
    ocean: &DragParameters,
    coriolis_f_per_s: f64,
    mass_per_area_kg_per_m2: f64,
    sea_surface_tilt: bool,
) -> Result<Vec2, DemError> {
    air.validate()?;
    ocean.validate()?;
    if !ocean.relative_to_ice {
        return Err(DemError::InvalidParameter {
            name: "ocean.relative_to_ice",
            value: 0.0,
            reason: "must be true for a free-drift steady state to exist",
        });
    }
    let cw = ocean.rho_cd();
    if cw <= 0.0 {
        return Err(DemError::InvalidParameter {
            name: "ocean.drag_coefficient",
            value: ocean.drag_coefficient,
            reason: "ocean density times drag coefficient must be positive for a steady state",
        });
    }
    if !coriolis_f_per_s.is_finite() {
        return Err(DemError::InvalidParameter {
            name: "coriolis_f_per_s",
            value: coriolis_f_per_s,
            reason: "must be finite",
        });
    }
    if !(mass_per_area_kg_per_m2.is_finite() && mass_per_area_kg_per_m2 >= 0.0) {
        return Err(DemError::InvalidParameter {
            name: "mass_per_area_kg_per_m2",
            value: mass_per_area_kg_per_m2,
            reason: "must be finite and non-negative",
        });
    }
    let a = mass_per_area_kg_per_m2 * coriolis_f_per_s;
    let theta = ocean.turning_angle_deg.to_radians();
    let s_current = if sea_surface_tilt {
        Vec2::ZERO
    } else {
        a * current_m_per_s.perp()
    };
    let solve = |u_ice: Vec2| {
        let s = s_current - air.stress(wind_m_per_s, u_ice);
        current_m_per_s - solve_relative(s, cw, theta, a)
    };
    if !air.relative_to_ice {
        return Ok(solve(Vec2::ZERO));
    }
    const MAX_ITERATIONS: usize = 200;
    let mut u = current_m_per_s;
    for _ in 0..MAX_ITERATIONS {
        let next = solve(u);
        let step = (next - u).length();
        u = next;
        if step <= 64.0 * f64::EPSILON * (u.length() + current_m_per_s.length()) {
            return Ok(u);
        }
    }
    Err(DemError::NoConvergence {
        what: "free-drift fixed point with air drag relative to the ice",
        iterations: MAX_ITERATIONS,
    })
}
