//! Floe stress: each free floe's stress tensor from its contacts, averaged
//! in time. What the fracture criteria judge.
//!
//! A floe's instantaneous stress is the Love-Weber sum over its contacts of
//! the force on it times its arm from its centroid to the contact point,
//! symmetrised and divided by its volume (area times thickness):
//! `sigma_ij = sym(sum f_i r_j) / (A h)`, Pa, tension positive. Wall and
//! land contacts count (they load the floe); body forces (drag, Coriolis)
//! do not, as in the anchors (Subzero.jl `calc_stress!`).
//!
//! The stress kept is an exponential average over a time scale `T`:
//! `sigma <- sigma + w (sigma_now - sigma)` with `w = 1 - exp(-dt / T)`, so a
//! constant load is followed as `1 - exp(-t / T)` whatever the time step
//! (the anchors' `lambda` per step is `T = -dt / ln(1 - lambda)`: 45 s at
//! their `lambda` 0.2 and dt 10 s).

use rayon::prelude::*;

use crate::contact_kernel::contact_force_on_b;
use crate::contacts::ContactRecord;
use crate::error::DemError;
use crate::floes::FloeColumns;

use super::force_gathering::ForceGathering;

/// A floe's stress, Pa, vertically averaged, tension positive, as
/// `[xx, xy, yy]` (the tensor is symmetric).
pub type FloeStress = [f64; 3];

/// The time average of the floe stress.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressFilter {
    /// The exponential average's time scale, s.
    pub time_scale_s: f64,
}

/// The anchors' averaging: Subzero.jl's `lambda` 0.2 per step at its
/// 10 s step, `-10 / ln 0.8` s.
pub const DEFAULT_STRESS_TIME_SCALE_S: f64 = 44.814_201_177_245_34;

impl StressFilter {
    /// A filter of time scale `time_scale_s` (finite, > 0).
    pub fn new(time_scale_s: f64) -> Result<Self, DemError> {
        if !(time_scale_s.is_finite() && time_scale_s > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "time_scale_s",
                value: time_scale_s,
                reason: "must be finite and > 0",
            });
        }
        Ok(StressFilter { time_scale_s })
    }

    /// The weight of the newest stress after a step of `dt_s`.
    pub fn weight(&self, dt_s: f64) -> f64 {
        -(-dt_s / self.time_scale_s).exp_m1()
    }
}

impl Default for StressFilter {
    fn default() -> Self {
        StressFilter {
            time_scale_s: DEFAULT_STRESS_TIME_SCALE_S,
        }
    }
}

/// The principal stresses `(sigma_1, sigma_2)`, `sigma_1 >= sigma_2`, Pa.
pub fn principal(s: FloeStress) -> (f64, f64) {
    crate::fracture::criteria::principal_stresses([s[0], s[1], s[1], s[2]])
}

/// Moves every free floe's averaged stress `stress` towards its
/// instantaneous stress by `weight`; prescribed floes keep zero. Each
/// floe's contacts are summed in contact order (the force gathering's
/// index), so the result is the same for any thread count; then its
/// entry of `bond_moments` (the bonds' moments, summed as
/// [`from_contacts`] sums; empty without bonds) is added.
pub(crate) fn update(
    f: &FloeColumns,
    contacts: &[ContactRecord],
    index: &ForceGathering,
    bond_moments: &[[f64; 3]],
    weight: f64,
    stress: &mut [FloeStress],
) {
    stress.par_iter_mut().enumerate().for_each(|(i, s)| {
        if !f.is_free(i) {
            return;
        }
        let (as_b, as_a) = index.contacts_of(i, contacts);
        let now = from_contacts(f, i, as_b.chain(as_a), bond_moments.get(i));
        for (s, now) in s.iter_mut().zip(now) {
            *s += weight * (now - *s);
        }
    });
}

/// Floe `i`'s stress from `contacts`, each of which touches it, and its
/// bonds' moments `bonds` (if any), Pa.
pub(crate) fn from_contacts<'c>(
    f: &FloeColumns,
    i: usize,
    contacts: impl Iterator<Item = &'c ContactRecord>,
    bonds: Option<&[f64; 3]>,
) -> FloeStress {
    let mut m = [0.0; 3];
    for c in contacts {
        let on_b = contact_force_on_b(c);
        let (force, arm) = if c.b as usize == i {
            (on_b, c.point - (f.position[i] + c.image_offset))
        } else {
            (-on_b, c.point - f.position[i])
        };
        m[0] += force.x * arm.x;
        m[1] += force.x * arm.y + force.y * arm.x;
        m[2] += force.y * arm.y;
    }
    if let Some(b) = bonds {
        for (m, b) in m.iter_mut().zip(b) {
            *m += b;
        }
    }
    let volume = f.area_m2[i] * f.thickness_m[i];
    [m[0] / volume, 0.5 * m[1] / volume, m[2] / volume]
}
