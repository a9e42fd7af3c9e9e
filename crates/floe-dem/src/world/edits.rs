//! Edits of the floe set and of a floe's motion: floes taken out and put
//! back with their contacts, the contact lists' handles renumbered around
//! them.

use super::World;
use crate::bonds::Bond;
use crate::contacts::{BrokenContact, ContactRecord};
use crate::error::DemError;
use crate::floes::{Floe, Floes, Motion};
use crate::forcing::ExternalForces;
use crate::pipeline::floe_stress::FloeStress;
use crate::pipeline::integrator::floe_stable_step;
use crate::Vec2;

/// A record of the state keyed by a pair of floe handles `(a, b)`, `a < b`.
trait HandlePair: Copy {
    fn pair(&self) -> (u32, u32);
    fn set_pair(&mut self, pair: (u32, u32));
}

impl HandlePair for ContactRecord {
    fn pair(&self) -> (u32, u32) {
        (self.a, self.b)
    }
    fn set_pair(&mut self, (a, b): (u32, u32)) {
        (self.a, self.b) = (a, b);
    }
}

impl HandlePair for BrokenContact {
    fn pair(&self) -> (u32, u32) {
        (self.a, self.b)
    }
    fn set_pair(&mut self, (a, b): (u32, u32)) {
        (self.a, self.b) = (a, b);
    }
}

impl HandlePair for Bond {
    fn pair(&self) -> (u32, u32) {
        (self.a, self.b)
    }
    fn set_pair(&mut self, (a, b): (u32, u32)) {
        (self.a, self.b) = (a, b);
    }
}

/// Takes the records of floe `h` out of `list`, with their floes' `ids`,
/// and moves the handles after `h` down one (the floe is leaving).
fn take_pairs_of<T: HandlePair>(list: &mut Vec<T>, h: usize, ids: &[u64]) -> Vec<([u64; 2], T)> {
    let touches = |(a, b): (u32, u32)| a as usize == h || b as usize == h;
    let taken = list
        .iter()
        .filter(|r| touches(r.pair()))
        .map(|r| ([ids[r.pair().0 as usize], ids[r.pair().1 as usize]], *r))
        .collect();
    let shift = |x: u32| if x as usize > h { x - 1 } else { x };
    list.retain(|r| !touches(r.pair()));
    for r in list.iter_mut() {
        let (a, b) = r.pair();
        r.set_pair((shift(a), shift(b)));
    }
    taken
}

/// Moves the handles from `h` up one (a floe arrived at `h`) and puts the
/// `records` of its pairs, named by ids, back in pair order. Every id is
/// in `floes` (checked by the caller).
fn put_pairs_back<T: HandlePair>(
    list: &mut Vec<T>,
    h: usize,
    floes: &Floes,
    records: Vec<([u64; 2], T)>,
) {
    let shift = |x: u32| if x as usize >= h { x + 1 } else { x };
    for r in list.iter_mut() {
        let (a, b) = r.pair();
        r.set_pair((shift(a), shift(b)));
    }
    let handle = |id: u64| floes.handle_of(id).expect("checked by the caller") as u32;
    for ([x, y], mut r) in records {
        r.set_pair((handle(x), handle(y)));
        let at = list.partition_point(|q| q.pair() < r.pair());
        list.insert(at, r);
    }
}

/// A floe taken out of a world with what it owns there: its forces from
/// the last evaluation, its contacts, its remembered broken contacts and its bonds.
/// [`World::insert_detached`] puts it back.
#[derive(Debug, Clone, PartialEq)]
pub struct DetachedFloe {
    /// The floe.
    pub floe: Floe,
    /// Total force from the last evaluation, N.
    pub force: Vec2,
    /// Total torque from the last evaluation, N m.
    pub torque: f64,
    /// External part of the force, N.
    pub external_force: Vec2,
    /// External part of the torque, N m.
    pub external_torque: f64,
    /// Its contacts, each with the ids of its two floes (the record's
    /// handles `a`, `b` are those it had and are reassigned on insertion).
    pub contacts: Vec<([u64; 2], ContactRecord)>,
    /// Its remembered broken contacts, each with the ids of its two floes.
    pub broken: Vec<([u64; 2], BrokenContact)>,
    /// Its bonds and quiet pairs on their way to one, each with the ids of
    /// its two floes.
    pub bonds: Vec<([u64; 2], Bond)>,
    /// Its time-averaged stress, if the world it left computed one (a
    /// world that computes stress gives a floe without one zero).
    pub stress: Option<FloeStress>,
}

impl<F: ExternalForces> World<F> {
    /// Sets floe `id`'s velocity (m/s) and angular velocity (rad/s).
    pub fn set_velocity(
        &mut self,
        id: u64,
        velocity: Vec2,
        angular_velocity: f64,
    ) -> Result<(), DemError> {
        let h = self.handle(id)?;
        if !(velocity.is_finite() && angular_velocity.is_finite()) {
            return Err(DemError::FloeEdit {
                id,
                reason: "velocities must be finite".into(),
            });
        }
        self.state.floes.set_velocity(h, velocity, angular_velocity);
        Ok(())
    }

    /// Moves floe `id` to `position` (m, wrapped into periodic axes) and
    /// `angle` (rad). Between the drift and the contact detection, the
    /// detection sees the new pose.
    pub fn set_pose(&mut self, id: u64, position: Vec2, angle: f64) -> Result<(), DemError> {
        let h = self.handle(id)?;
        if !(position.is_finite() && angle.is_finite()) {
            return Err(DemError::FloeEdit {
                id,
                reason: "position and angle must be finite".into(),
            });
        }
        let position = self.periodicity.wrap(position);
        self.state.floes.set_pose(h, position, angle);
        let p = &mut self.pipeline;
        if p.trig.len() == self.state.floes.len() {
            p.trig[h] = angle.sin_cos();
        }
        p.moved_far |= p
            .broad_phase
            .moved_beyond_allowance(h, position, angle, self.periodicity);
        Ok(())
    }

    /// Sets how floe `id` moves; a prescribed velocity is also its velocity.
    /// Refuses to free a floe the time step is too long for.
    pub fn set_motion(&mut self, id: u64, motion: Motion) -> Result<(), DemError> {
        let h = self.handle(id)?;
        match motion {
            Motion::Prescribed { velocity } if !velocity.is_finite() => {
                return Err(DemError::FloeEdit {
                    id,
                    reason: "a prescribed velocity must be finite".into(),
                })
            }
            Motion::Free => {
                let f = &self.state.floes;
                self.check_stable(
                    id,
                    floe_stable_step(
                        f.mass_kg[h],
                        f.inertia_kg_m2[h],
                        f.thickness_m[h],
                        f.area_m2[h],
                        f.radius_m[h],
                        &self.model,
                    ),
                )?;
            }
            Motion::Prescribed { .. } => {}
        }
        self.state.floes.set_motion(h, motion);
        // A floe set free, or given a constant velocity, leaves its
        // schedule; a prescribed one leaves its load point.
        self.state.schedules.retain(|s| s.floe_id != id);
        if matches!(motion, Motion::Prescribed { .. }) {
            self.state.load_points.retain(|l| l.floe_id != id);
        } else {
            self.leave_stress_control(id);
        }
        Ok(())
    }

    /// The stable time step of floe `f` under the world's contact model, s.
    pub(super) fn stable_step_of(&self, f: &Floe) -> f64 {
        floe_stable_step(
            f.mass_kg,
            f.inertia_kg_m2,
            f.thickness_m,
            f.area_m2,
            f.radius_m,
            &self.model,
        )
    }

    /// Refuses a free floe whose stable time step `limit_s` is below the
    /// world's.
    fn check_stable(&self, id: u64, limit_s: f64) -> Result<(), DemError> {
        if self.state.dt_s > limit_s {
            return Err(DemError::UnstableTimeStep {
                dt_s: self.state.dt_s,
                limit_s,
                reason: format!(
                    "floe {id} against a like neighbour, E = {} Pa",
                    self.model.youngs_modulus_pa
                ),
            });
        }
        Ok(())
    }

    /// Adds a floe between steps, with no contacts and no force yet (its
    /// first half kick is force-free; its contacts are found by the next
    /// detection, as new contacts).
    pub fn insert_floe(&mut self, floe: Floe) -> Result<(), DemError> {
        self.insert_detached(DetachedFloe {
            floe,
            force: Vec2::ZERO,
            torque: 0.0,
            external_force: Vec2::ZERO,
            external_torque: 0.0,
            contacts: Vec::new(),
            broken: Vec::new(),
            bonds: Vec::new(),
            stress: None,
        })
    }

    /// Takes floe `id` out between steps, with its forces, its contacts,
    /// its remembered broken contacts and its bonds (no energy is counted as
    /// released: the contacts leave with the floe).
    pub fn remove_floe(&mut self, id: u64) -> Result<DetachedFloe, DemError> {
        self.between_steps(id)?;
        let h = self.handle(id)?;
        // Its schedule, load point and place in a wall go with it (a
        // re-inserted floe has none).
        self.state.schedules.retain(|m| m.floe_id != id);
        self.state.load_points.retain(|l| l.floe_id != id);
        self.leave_stress_control(id);
        let s = &mut self.state;
        let contacts = take_pairs_of(&mut s.contacts, h, &s.floes.id);
        let broken = take_pairs_of(&mut s.broken, h, &s.floes.id);
        let bonds = take_pairs_of(&mut s.bonds, h, &s.floes.id);
        let detached = DetachedFloe {
            floe: s.floes.remove(h),
            force: s.force.remove(h),
            torque: s.torque.remove(h),
            external_force: s.external_force.remove(h),
            external_torque: s.external_torque.remove(h),
            contacts,
            broken,
            bonds,
            stress: s.stress_filter.map(|_| s.floe_stress.remove(h)),
        };
        self.pipeline.floes_changed();
        Ok(detached)
    }

    /// Puts back a floe taken out by [`World::remove_floe`] (or moved from
    /// another world), between steps, with its forces, contacts and contact
    /// memory. Refuses (changing nothing) an id already present, a contact
    /// whose other floe is absent or that does not name the floe.
    pub fn insert_detached(&mut self, d: DetachedFloe) -> Result<(), DemError> {
        let id = d.floe.id;
        self.between_steps(id)?;
        let floes = &self.state.floes;
        if floes.handle_of(id).is_some() {
            return Err(DemError::FloeEdit {
                id,
                reason: "a floe with this id is already present".into(),
            });
        }
        let pairs = d
            .contacts
            .iter()
            .map(|(ids, _)| *ids)
            .chain(d.broken.iter().map(|(ids, _)| *ids))
            .chain(d.bonds.iter().map(|(ids, _)| *ids));
        for [x, y] in pairs {
            let other = if x == id { y } else { x };
            if x >= y || (x != id && y != id) || floes.handle_of(other).is_none() {
                return Err(DemError::FloeEdit {
                    id,
                    reason: format!(
                        "a contact between floes {x} and {y} cannot be restored: \
                         it must name this floe and a floe present, smaller id first"
                    ),
                });
            }
        }
        let twice = |pairs: Vec<[u64; 2]>| {
            let mut sorted = pairs;
            sorted.sort_unstable();
            sorted.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
        };
        let repeated = twice(d.contacts.iter().map(|(ids, _)| *ids).collect())
            .or_else(|| twice(d.broken.iter().map(|(ids, _)| *ids).collect()))
            .or_else(|| twice(d.bonds.iter().map(|(ids, _)| *ids).collect()));
        if let Some([x, y]) = repeated {
            return Err(DemError::FloeEdit {
                id,
                reason: format!("the pair of floes {x} and {y} is listed twice"),
            });
        }
        if let Motion::Free = d.floe.motion {
            self.check_stable(id, self.stable_step_of(&d.floe))?;
        }
        let s = &mut self.state;
        let h = s.floes.insert(d.floe)?;
        put_pairs_back(&mut s.contacts, h, &s.floes, d.contacts);
        put_pairs_back(&mut s.broken, h, &s.floes, d.broken);
        put_pairs_back(&mut s.bonds, h, &s.floes, d.bonds);
        s.force.insert(h, d.force);
        s.torque.insert(h, d.torque);
        s.external_force.insert(h, d.external_force);
        s.external_torque.insert(h, d.external_torque);
        if s.stress_filter.is_some() {
            s.floe_stress.insert(h, d.stress.unwrap_or_default());
        }
        debug_assert!(self.state.validate().is_ok());
        self.pipeline.floes_changed();
        Ok(())
    }

    /// Edits the contact list between steps; the list must stay sorted
    /// pairs of existing floes (else it is left as it was and the edit
    /// refused). The force gathering's index is rebuilt.
    #[cfg(test)]
    pub(crate) fn edit_contacts(
        &mut self,
        edit: impl FnOnce(&mut Vec<ContactRecord>),
    ) -> Result<(), DemError> {
        let mut contacts = self.state.contacts.clone();
        edit(&mut contacts);
        if !crate::state::sorted_pairs(contacts.iter().map(|c| (c.a, c.b)), self.state.floes.len())
        {
            return Err(DemError::InvalidCheckpoint {
                reason: "edited contacts are not sorted pairs of existing floes".into(),
            });
        }
        self.state.contacts = contacts;
        self.pipeline.gathering.invalidate();
        Ok(())
    }
}
