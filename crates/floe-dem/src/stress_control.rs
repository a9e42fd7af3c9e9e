//! A stress-controlled wall: the prescribed floes of a wall whose normal
//! velocity follows the error in the normal stress the ice puts on it,
//! `v_n = G (sigma_target - sigma)` (inward positive), so that the wall
//! holds a set confining stress while the ice dilates or compacts (a
//! constant-pressure shear cell).
//!
//! `sigma` is the compressive stress on the wall, N/m (vertically
//! integrated): minus the contact forces on its pieces along the inward
//! normal, over the wall's length. The loop is a proportional controller on
//! the wall's velocity, so an integral one on its position: in a steady
//! state the wall's mean normal velocity is zero and the mean stress is
//! the target. Per step, a stress error `e` moves the wall `G e dt`, which
//! changes the stress by about `kappa G e dt` for a contact stiffness per
//! unit area `kappa` (the wall contact's `E h / sqrt(area)`): the loop is
//! stable for `G dt kappa < 2` and does not overshoot below 1; the pack's
//! own compliance only lowers the loop gain.

use crate::error::DemError;
use crate::Vec2;

/// A wall (its pieces) holding a normal stress.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StressControl {
    /// Global ids of the wall's pieces (prescribed floes), increasing.
    pub floe_ids: Vec<u64>,
    /// Unit normal from the wall into the ice.
    pub inward_normal: Vec2,
    /// Length of the wall that carries the stress, m.
    pub length_m: f64,
    /// Compressive normal stress to hold, N/m (>= 0).
    pub target_stress_n_per_m: f64,
    /// `G`: inward wall speed per unit stress deficit, (m/s) / (N/m).
    pub gain_m_per_s_per_n_per_m: f64,
}

impl StressControl {
    /// Checks the parts: pieces given in increasing id order, a unit
    /// normal, a length and a gain > 0, a target >= 0, all finite.
    pub fn new(
        floe_ids: Vec<u64>,
        inward_normal: Vec2,
        length_m: f64,
        target_stress_n_per_m: f64,
        gain_m_per_s_per_n_per_m: f64,
    ) -> Result<Self, DemError> {
        let bad = |name, value, reason| {
            Err(DemError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        if floe_ids.is_empty() || floe_ids.windows(2).any(|w| w[0] >= w[1]) {
            return bad(
                "floe_ids",
                floe_ids.len() as f64,
                "must be increasing, at least one",
            );
        }
        let unit = (inward_normal.length() - 1.0).abs() < 1e-9;
        if !unit {
            return bad(
                "inward_normal",
                inward_normal.length(),
                "must be a unit vector",
            );
        }
        if !(length_m.is_finite() && length_m > 0.0) {
            return bad("length_m", length_m, "must be a finite number > 0");
        }
        if !(target_stress_n_per_m.is_finite() && target_stress_n_per_m >= 0.0) {
            return bad(
                "target_stress_n_per_m",
                target_stress_n_per_m,
                "must be a finite number >= 0",
            );
        }
        if !(gain_m_per_s_per_n_per_m.is_finite() && gain_m_per_s_per_n_per_m > 0.0) {
            return bad(
                "gain_m_per_s_per_n_per_m",
                gain_m_per_s_per_n_per_m,
                "must be a finite number > 0",
            );
        }
        Ok(StressControl {
            floe_ids,
            inward_normal,
            length_m,
            target_stress_n_per_m,
            gain_m_per_s_per_n_per_m,
        })
    }

    /// The compressive stress on the wall, N/m, from the total forces on
    /// its pieces (`force_of(id)`, N).
    pub fn stress(&self, force_of: impl Fn(u64) -> Vec2) -> f64 {
        let total = self
            .floe_ids
            .iter()
            .fold(Vec2::ZERO, |sum, &id| sum + force_of(id));
        -total.dot(self.inward_normal) / self.length_m
    }

    /// The wall's inward normal speed for a measured stress, m/s.
    pub fn normal_speed(&self, stress_n_per_m: f64) -> f64 {
        self.gain_m_per_s_per_n_per_m * (self.target_stress_n_per_m - stress_n_per_m)
    }
}
