//! Bonds: pairs of floes frozen together ([`crate::cohesion`]), kept
//! sorted by their floes' handles `(a, b)`, `a < b`, as the contacts are.
//!
//! A pair enters the list when its contact turns quiet (a candidate,
//! `formed == false`, counting the time from `quiet_since_s`), and leaves
//! it when the contact stops being quiet or ends before the bond forms.
//! A formed bond no longer needs the contact: it holds the two floes by
//! anchor points fixed in each (where the contact point was when it
//! formed) until it breaks. Its mechanics are in
//! [`crate::bond_kernel`].

use crate::Vec2;

/// A bond, or a pair on its way to one.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bond {
    /// First floe (handle; the smaller id).
    pub a: u32,
    /// Second floe.
    pub b: u32,
    /// Since when the pair's contact has been quiet, s.
    pub quiet_since_s: f64,
    /// Whether the bond has formed (else the pair is a candidate and the
    /// fields below are zero).
    pub formed: bool,
    /// When the bond formed, s.
    pub formed_at_s: f64,
    /// Its anchor on `a`, in `a`'s body frame (from its centroid), m.
    pub anchor_a: Vec2,
    /// Its anchor on `b`, in `b`'s body frame, m.
    pub anchor_b: Vec2,
    /// The contact normal (from `a` to `b`) when it formed, in `a`'s body frame.
    pub normal_a: Vec2,
    /// `b`'s angle minus `a`'s when it formed, rad.
    pub rest_angle_rad: f64,
    /// The contact's length when it formed, m: the bond's length.
    pub length_m: f64,
    /// Its normal stiffness, N/m: the contact's when it formed (kept
    /// through fracture, so a split does not change the joint).
    pub stiffness_n_per_m: f64,

    /// `a`'s anchor in the world at the last evaluation, m.
    pub point_a: Vec2,
    /// `b`'s anchor (at the image of `b` that touches `a`), m.
    pub point_b: Vec2,
    /// Force on `b`, N (`a` gets the opposite).
    pub force_on_b: Vec2,
    /// Torque on `a` about its centroid, N m.
    pub torque_on_a: f64,
    /// Torque on `b` about its centroid, N m.
    pub torque_on_b: f64,
    /// Elastic energy stored in the bond, J.
    pub energy_j: f64,
    /// Power dissipated by the bond's dashpots, W.
    pub damping_power_w: f64,
    /// Tensile load per unit length (normal pull and bending), N/m.
    pub tension_n_per_m: f64,
    /// Shear load per unit length, N/m.
    pub shear_n_per_m: f64,
}

impl Bond {
    /// A candidate: the pair `(a, b)`'s contact quiet since `since_s`.
    pub fn candidate(a: u32, b: u32, since_s: f64) -> Self {
        Bond {
            a,
            b,
            quiet_since_s: since_s,
            formed: false,
            formed_at_s: 0.0,
            anchor_a: Vec2::ZERO,
            anchor_b: Vec2::ZERO,
            normal_a: Vec2::ZERO,
            rest_angle_rad: 0.0,
            length_m: 0.0,
            stiffness_n_per_m: 0.0,
            point_a: Vec2::ZERO,
            point_b: Vec2::ZERO,
            force_on_b: Vec2::ZERO,
            torque_on_a: 0.0,
            torque_on_b: 0.0,
            energy_j: 0.0,
            damping_power_w: 0.0,
            tension_n_per_m: 0.0,
            shear_n_per_m: 0.0,
        }
    }

    /// The bond's age at `time_s`, s (0 for a candidate).
    pub fn age_s(&self, time_s: f64) -> f64 {
        if self.formed {
            time_s - self.formed_at_s
        } else {
            0.0
        }
    }
}
