//! Detecting a numerical blow-up: a state an explicit integrator reaches
//! when the time step is too long for the stiffest contact, or when a
//! scenario drives floes into each other faster than contacts can push back.

use std::fmt;

use crate::forcing::ExternalForces;
use crate::world::World;

/// Overlap, as a fraction of the smaller floe's area, beyond which a contact
/// is taken as a blow-up. Elastic overlaps in a sea-ice pack are a tiny
/// fraction of a floe (the contact stiffness is set for that); a quarter of
/// a floe means the contact force cannot stop the approach. Against a
/// prescribed body (a wall segment, a piece of land) the fraction is of the
/// free floe: a land piece may be far smaller than a floe (a 100 m spit),
/// and a floe pressing on it normally covers much of it.
pub const MAX_OVERLAP_FRACTION: f64 = 0.25;

/// What went wrong, where and when.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BlowUp {
    /// The step at which it was detected.
    pub step: u64,
    /// Simulated time, s.
    pub time_s: f64,
    /// The time step in use, s.
    pub dt_s: f64,
    /// Which floes, and what is wrong with them.
    pub what: Fault,
}

/// The kind of fault.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Fault {
    /// A floe's position, angle or velocity is not finite.
    NonFinite {
        /// Global id of the floe.
        floe_id: u64,
    },
    /// A free floe travels farther in one step than its bounding radius
    /// (or turns by more than a radian): contacts would be stepped over.
    TooFast {
        /// Global id of the floe.
        floe_id: u64,
        /// How far its rim moves in one step, m.
        step_travel_m: f64,
        /// Its bounding radius, m.
        radius_m: f64,
    },
    /// Two floes overlap beyond [`MAX_OVERLAP_FRACTION`].
    Overlap {
        /// Global ids of the two floes.
        floe_ids: (u64, u64),
        /// Overlap area over the smaller floe's area (the free floe's
        /// against a prescribed body).
        fraction: f64,
    },
}

impl BlowUp {
    /// A time step to try: half the one that failed.
    pub fn suggested_dt_s(&self) -> f64 {
        0.5 * self.dt_s
    }
}

impl fmt::Display for BlowUp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "numerical blow-up at step {} (t = {}): ",
            self.step,
            super::sim_time::format_sim_time(self.time_s)
        )?;
        match &self.what {
            Fault::NonFinite { floe_id } => {
                write!(f, "floe {floe_id} has a non-finite position or velocity")?
            }
            Fault::TooFast {
                floe_id,
                step_travel_m,
                radius_m,
            } => write!(
                f,
                "floe {floe_id} moves {step_travel_m:.3e} m in one step, more than its radius \
                 {radius_m:.3e} m"
            )?,
            Fault::Overlap { floe_ids, fraction } => write!(
                f,
                "floes {} and {} overlap by {:.0} % of the smaller one (of the free one against a wall or land; limit {:.0} %)",
                floe_ids.0,
                floe_ids.1,
                100.0 * fraction,
                100.0 * MAX_OVERLAP_FRACTION
            )?,
        }
        write!(
            f,
            "; try dt_s = {} (half of {} s) or weaker forcing",
            seconds(self.suggested_dt_s()),
            seconds(self.dt_s)
        )
    }
}

/// The first fault in `world`, if any: floes in handle order, then contacts
/// in pair order (so the report is the same for any thread count).
pub fn check_health<F: ExternalForces>(world: &World<F>) -> Option<BlowUp> {
    let f = &world.floes();
    let dt = world.dt_s();
    let fault = (0..f.len())
        .find(|&i| {
            !(f.position[i].is_finite()
                && f.velocity[i].is_finite()
                && f.angle[i].is_finite()
                && f.angular_velocity[i].is_finite())
        })
        .map(|i| Fault::NonFinite { floe_id: f.id[i] })
        .or_else(|| {
            (0..f.len()).find_map(|i| {
                let r = f.radius_m[i];
                let travel = (f.velocity[i].length() + f.angular_velocity[i].abs() * r) * dt;
                (f.is_free(i) && travel > r).then_some(Fault::TooFast {
                    floe_id: f.id[i],
                    step_travel_m: travel,
                    radius_m: r,
                })
            })
        })
        .or_else(|| {
            world.contacts().iter().find_map(|c| {
                let (a, b) = (c.a as usize, c.b as usize);
                let area = match (f.is_free(a), f.is_free(b)) {
                    (true, false) => f.area_m2[a],
                    (false, true) => f.area_m2[b],
                    _ => f.area_m2[a].min(f.area_m2[b]),
                };
                let fraction = c.overlap_m2 / area;
                (fraction > MAX_OVERLAP_FRACTION).then_some(Fault::Overlap {
                    floe_ids: (f.id[a], f.id[b]),
                    fraction,
                })
            })
        })?;
    Some(BlowUp {
        step: world.steps(),
        time_s: world.time_s(),
        dt_s: world.dt_s(),
        what: fault,
    })
}

/// A time step for a message: four significant digits, plain or scientific.
fn seconds(x: f64) -> String {
    if (1e-2..1e4).contains(&x.abs()) {
        format!("{x:.4}")
    } else {
        format!("{x:.3e}")
    }
}
