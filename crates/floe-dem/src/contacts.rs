//! The contact graph: one record per touching pair of floes, carrying the
//! friction law's state (tangential spring and `theta`) for as long as the
//! two floes touch.
//!
//! Records are kept sorted by the pair's floe handles `(a, b)`, `a < b`.
//! The floe set is sorted by id, so this is the order of the pairs' ids:
//! the order (and hence every sum over contacts) depends neither on the
//! thread count nor on which other floes are present.
//!
//! A new contact (a pair that did not touch at the end of the previous step)
//! starts with no tangential force and the state of steady sliding at the
//! reference slip rate of
//! [`ContactModel::new_contact_slip_rate_m_per_s`](crate::contact_model::ContactModel::new_contact_slip_rate_m_per_s).
//! A contact that breaks is remembered for
//! [`ContactModel::memory_s`](crate::contact_model::ContactModel::memory_s)
//! seconds: if the pair touches again within that time, the contact resumes
//! the `theta` it had when it broke (its spring starts unloaded: the floes
//! separated). After that, or with `memory_s = 0` (the default), it starts
//! afresh by the first rule.

use floe_friction::ContactState;

use crate::Vec2;

/// One touching pair and what the contact did over the last step.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactRecord {
    /// First floe (handle into the floe arrays; the smaller global id).
    pub a: u32,
    /// Second floe.
    pub b: u32,
    /// Offset added to `b`'s position to reach the image that touches `a`
    /// (non-zero across periodic boundaries), m.
    pub image_offset: Vec2,
    /// Friction state: tangential spring force and `theta`.
    pub friction: ContactState,
    /// Steps this contact has lasted.
    pub age_steps: u64,
    /// Overlap area, m^2.
    pub overlap_m2: f64,
    /// Contact point (overlap centroid), m.
    pub point: Vec2,
    /// Unit normal from `a` to `b`.
    pub normal: Vec2,
    /// Contact length, m.
    pub length_m: f64,
    /// Normal force on `b` (>= 0, elastic plus damping), N.
    pub normal_force_n: f64,

    /// Slip rate of `b` relative to `a` along `perp(normal)`, m/s.
    pub slip_rate_m_per_s: f64,
    /// Power dissipated by friction, W (`F_t` times slip rate).
    pub friction_power_w: f64,
    /// Power dissipated by the normal dashpot, W.
    pub damping_power_w: f64,
    /// Elastic part of the normal force, N.
    pub elastic_force_n: f64,
    /// Work done so far by the elastic normal force (energy stored in the
    /// overlap), integrated over the contact's life, J.
    pub normal_energy_j: f64,
    /// Energy stored in the tangential spring, `F_t^2 / 2 k_t`, J.
    pub tangential_energy_j: f64,
}

impl ContactRecord {
    /// Tangential force on `b` along `perp(normal)`, N: the friction spring's
    /// force, which resists the slip of `b` relative to `a`.
    #[inline]
    pub fn tangential_force_n(&self) -> f64 {
        -self.friction.tangential_force_n
    }

    /// Friction coefficient `|F_t| / F_n` (0 without normal force).
    pub fn mu(&self) -> f64 {
        if self.normal_force_n > 0.0 {
            self.friction.tangential_force_n.abs() / self.normal_force_n
        } else {
            0.0
        }
    }

    /// Elastic energy stored in the contact, J.
    pub fn elastic_energy_j(&self) -> f64 {
        self.normal_energy_j + self.tangential_energy_j
    }
}

/// The state of a contact that broke, kept for [`ContactModel::memory_s`](crate::contact_model::ContactModel::memory_s).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BrokenContact {
    /// First floe.
    pub a: u32,
    /// Second floe.
    pub b: u32,
    /// Friction state when the contact broke.
    pub friction: ContactState,
    /// When it broke, s.
    pub broke_at_s: f64,
}
