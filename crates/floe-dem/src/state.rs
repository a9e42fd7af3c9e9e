//! The world's state: everything a run needs to continue bitwise from the
//! end of a step, and nothing else. A checkpoint holds exactly this
//! ([`World::state`](crate::world::World::state) lends it);
//! [`World::resume`](crate::world::World::resume) continues from it.
//!
//! What is *not* in the state comes from the scenario: the contact model,
//! the forcing and the periodicity. Scratch is not in it either: the
//! broad-phase candidate list is rebuilt on the first step after a resume,
//! and the contacts found do not depend on when it was built (a candidate
//! list only has to contain every touching pair, and the contact list is
//! sorted by pair).

use crate::bonds::Bond;
use crate::contacts::{BrokenContact, ContactRecord};
use crate::energy_ledger::EnergyLedger;
use crate::error::DemError;
use crate::floes::Floes;
use crate::load_point::LoadPoint;
use crate::motion_schedule::ScheduledMotion;
use crate::pipeline::boundary_motion::{wall_stress, with_normal_speed};
use crate::pipeline::floe_stress::{FloeStress, StressFilter};
use crate::pipeline::integrator::half_kicked;
use crate::stress_control::StressControl;
use crate::Vec2;

/// Everything a run needs to continue bitwise from the end of a step.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldState {
    /// The floes, including prescribed ones (walls), sorted by id.
    pub floes: Floes,
    /// Contacts at the end of the step, sorted by `(a, b)`, with their
    /// friction state and integrated energies.
    pub contacts: Vec<ContactRecord>,
    /// Recently broken contacts remembered by the model, sorted by `(a, b)`.
    pub broken: Vec<BrokenContact>,
    /// Simulated time, s.
    pub time_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// The time step, s.
    pub dt_s: f64,
    /// Bonds and pairs quiet on their way to one, sorted by `(a, b)`
    /// (empty without cohesion).
    pub bonds: Vec<Bond>,
    /// Energy bookkeeping since the start.
    pub energy: EnergyLedger,
    /// Total force on each floe from the last evaluation, N. Saved rather
    /// than recomputed: it was evaluated at the half-step velocity.
    pub force: Vec<Vec2>,
    /// Total torque on each floe from the last evaluation, N m.
    pub torque: Vec<f64>,
    /// External (forcing) part of `force`, N; the next step's work integral
    /// starts from it.
    pub external_force: Vec<Vec2>,
    /// External part of `torque`, N m.
    pub external_torque: Vec<f64>,
    /// Prescribed floes that follow a motion schedule, sorted by floe id.
    pub schedules: Vec<ScheduledMotion>,
    /// Free floes driven through a spring from a moving point, sorted by
    /// floe id.
    pub load_points: Vec<LoadPoint>,
    /// Walls holding a normal stress (each piece in at most one).
    pub stress_controls: Vec<StressControl>,
    /// The floe stress's time average, when the world computes floe
    /// stress ([`World::set_stress_filter`](crate::world::World::set_stress_filter)).
    pub stress_filter: Option<StressFilter>,
    /// Each floe's time-averaged stress (`[xx, xy, yy]`, Pa, zero for
    /// prescribed floes) when `stress_filter` is set; empty otherwise.
    pub floe_stress: Vec<FloeStress>,
    /// No floe has had an id at or above this (0: none counted yet):
    /// fracture numbers its pieces from here, so no id is used twice.
    pub next_floe_id: u64,
    /// What ridging moved since the start ([`crate::ridging`]; zero
    /// without it).
    pub ridging: crate::ridging::RidgingLedger,
    /// What welding did since the start ([`crate::welding`]; zero
    /// without it).
    pub welding: crate::welding::WeldingLedger,
}

impl WorldState {
    /// A state with the given floes, no contacts, at time 0.
    pub(crate) fn start(floes: Floes, dt_s: f64) -> Self {
        let n = floes.len();
        WorldState {
            floes,
            contacts: Vec::new(),
            broken: Vec::new(),
            bonds: Vec::new(),
            time_s: 0.0,
            steps: 0,
            dt_s,
            energy: EnergyLedger::default(),
            force: vec![Vec2::ZERO; n],
            torque: vec![0.0; n],
            external_force: vec![Vec2::ZERO; n],
            external_torque: vec![0.0; n],
            schedules: Vec::new(),
            load_points: Vec::new(),
            stress_controls: Vec::new(),
            stress_filter: None,
            floe_stress: Vec::new(),
            next_floe_id: 0,
            ridging: Default::default(),
            welding: Default::default(),
        }
    }

    /// Checks that the arrays agree in length, that the contacts refer to
    /// floes that exist and are sorted, and that the clock is valid, so a
    /// damaged checkpoint is refused, not stepped.
    pub fn validate(&self) -> Result<(), DemError> {
        let n = self.floes.len();
        let bad = |reason: String| Err(DemError::InvalidCheckpoint { reason });
        for (name, len) in [
            ("force", self.force.len()),
            ("torque", self.torque.len()),
            ("external_force", self.external_force.len()),
            ("external_torque", self.external_torque.len()),
        ] {
            if len != n {
                return bad(format!("{name} has {len} entries for {n} floes"));
            }
        }
        let stresses = if self.stress_filter.is_some() { n } else { 0 };
        if self.floe_stress.len() != stresses {
            return bad(format!(
                "floe_stress has {} entries for {n} floes (one per floe with a stress filter, none without)",
                self.floe_stress.len()
            ));
        }
        if let Some(filter) = self.stress_filter {
            if StressFilter::new(filter.time_scale_s).is_err() {
                return bad(format!(
                    "the stress filter's time scale {} s is not > 0",
                    filter.time_scale_s
                ));
            }
        }
        if !sorted_pairs(self.contacts.iter().map(|c| (c.a, c.b)), n) {
            return bad("contacts are not sorted pairs (a, b) of existing floes with a < b".into());
        }
        if !sorted_pairs(self.broken.iter().map(|c| (c.a, c.b)), n) {
            return bad(
                "broken contacts are not sorted pairs (a, b) of existing floes with a < b".into(),
            );
        }
        if !sorted_pairs(self.bonds.iter().map(|c| (c.a, c.b)), n) {
            return bad("bonds are not sorted pairs (a, b) of existing floes with a < b".into());
        }
        if !self.time_s.is_finite() {
            return bad(format!("time {} is not finite", self.time_s));
        }
        if !(self.dt_s.is_finite() && self.dt_s > 0.0) {
            return bad(format!("time step {} s is not > 0", self.dt_s));
        }
        self.check_driven(
            self.schedules.iter().map(|s| s.floe_id),
            "a schedule",
            false,
        )?;
        self.check_driven(
            self.load_points.iter().map(|l| l.floe_id),
            "a load point",
            true,
        )?;
        let mut pieces: Vec<u64> = self
            .stress_controls
            .iter()
            .flat_map(|c| c.floe_ids.iter().copied())
            .collect();
        pieces.sort_unstable();
        self.check_driven(pieces.into_iter(), "a stress control", false)?;
        Ok(())
    }

    /// Each floe's velocity and angular velocity in the next drift, as the
    /// step will set them: a scheduled floe's mean over the step, a
    /// stress-controlled wall's normal speed from the forces now, a free
    /// floe's half-kicked ones (`v + F dt / 2m`). Times `dt_s`, how far a
    /// floe will move and turn before the next contact detection.
    pub fn next_drift_velocities(&self) -> Vec<(Vec2, f64)> {
        let f = self.floes.columns();
        let dt = self.dt_s;
        let mut next: Vec<(Vec2, f64)> = (0..f.len())
            .map(|i| {
                let motion = (f.velocity[i], f.angular_velocity[i]);
                if f.is_free(i) {
                    half_kicked(
                        motion,
                        (self.force[i], self.torque[i]),
                        (f.mass_kg[i], f.inertia_kg_m2[i]),
                        dt,
                    )
                } else {
                    motion
                }
            })
            .collect();
        for s in &self.schedules {
            if let Some(h) = self.floes.handle_of(s.floe_id) {
                next[h] = s.schedule.mean_velocity(self.time_s, dt);
            }
        }
        for c in &self.stress_controls {
            let v_n = c.next_speed(wall_stress(&self.floes, &self.force, c), dt);
            for &id in &c.floe_ids {
                if let Some(h) = self.floes.handle_of(id) {
                    next[h].0 = with_normal_speed(next[h].0, c.inward_normal, v_n);
                }
            }
        }
        next
    }

    /// Refuses `ids` (of floes with `what`) unless they are increasing and
    /// name floes that exist and are free (`free`) or prescribed.
    fn check_driven(
        &self,
        ids: impl Iterator<Item = u64>,
        what: &str,
        free: bool,
    ) -> Result<(), DemError> {
        let bad = |reason: String| Err(DemError::InvalidCheckpoint { reason });
        let mut last = None;
        for id in ids {
            if last >= Some(id) {
                return bad(format!("{what} per floe, sorted by floe id, expected"));
            }
            last = Some(id);
            match self.floes.handle_of(id) {
                Some(h) if self.floes.is_free(h) == free => {}
                Some(_) => {
                    let kind = if free { "free" } else { "prescribed" };
                    return bad(format!("floe {id} has {what} but is not {kind}"));
                }
                None => return bad(format!("{what} names floe {id}, which is not there")),
            }
        }
        Ok(())
    }
}

/// Whether `pairs` are strictly increasing pairs `(a, b)` of handles below
/// `n` with `a < b` (the force gathering relies on `a < b`: a floe's
/// contacts as `a` come after its contacts as `b`).
pub(crate) fn sorted_pairs(pairs: impl Iterator<Item = (u32, u32)>, n: usize) -> bool {
    let mut last = None;
    for (a, b) in pairs {
        if a as usize >= n || b as usize >= n || a >= b || last >= Some((a, b)) {
            return false;
        }
        last = Some((a, b));
    }
    true
}
