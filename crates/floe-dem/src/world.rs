//! The simulation: the world's state, the pipeline that steps it, and what
//! comes from the scenario (contact model, forcing, periodicity).
//!
//! # A step
//! [`World::step`] is [`World::drift`], [`World::detect_contacts`],
//! [`World::gather_forces`] and [`World::kick`], in that order (velocity
//! Verlet; the stages are described in [`crate::pipeline`]). The four may
//! be called one by one, so that other work can run between them.
//!
//! # Editing
//! The state is read through [`World::state`] and its parts; it changes
//! only through the world's methods, which mark what changed for the
//! pipeline: floes are added and removed between steps
//! ([`World::insert_floe`], [`World::remove_floe`],
//! [`World::insert_detached`]), their velocity, pose and motion set at any
//! stage. A removed floe takes its contacts and contact memory with it, and
//! putting it back restores them: the run continues as if it had never been
//! taken out.
//!
//! # Parallelism and determinism
//! Work is spread with rayon on the pool the caller installs (`pool.install(|| world.step())`);
//! the world never creates threads. Every loop either writes one element per
//! index (floes, candidate pairs) or sums in a fixed order: contact forces
//! are gathered per floe through a contact list sorted by pair, never
//! scattered with atomics, and the energy sums are exact
//! ([`crate::exact_sum`]). The result is bitwise identical for any number
//! of threads, and for any split of the floes between processes (a ghost,
//! [`World::set_ghosts`], is another process's floe).
//!
//! # Example
//! Two squares pushed into each other, stepped for a second:
//! ```
//! use floe_dem::{contact_model::ContactModel, floes::Floes, forcing::NoForcing};
//! use floe_dem::{periodicity::Periodicity, world::World, Vec2};
//!
//! let square = |x0: f64| {
//!     [(0.0, 0.0), (100.0, 0.0), (100.0, 100.0), (0.0, 100.0)]
//!         .map(|(x, y)| Vec2::new(x0 + x, y))
//!         .to_vec()
//! };
//! // 1 m thick ice, 917 kg/m^3; the squares overlap by 1 m.
//! let floes = Floes::from_polygons(&[square(0.0), square(99.0)], &[1.0, 1.0], 917.0)?;
//! let dt = 0.5 * floe_dem::world::stable_time_step(&floes, &ContactModel::default()).0;
//! let mut world = World::new(floes, ContactModel::default(), NoForcing, Periodicity::default(), dt)?;
//! assert_eq!(world.contacts().len(), 1);
//! while world.time_s() < 1.0 {
//!     world.step();
//! }
//! // The overlap pushed them apart, equally and oppositely.
//! let v = &world.floes().velocity;
//! assert!(v[0].x < 0.0 && v[1].x > 0.0);
//! assert!((v[0].x + v[1].x).abs() < 1e-12 * v[1].x);
//! # Ok::<(), floe_dem::DemError>(())
//! ```

use crate::contact_model::ContactModel;
use crate::contacts::{BrokenContact, ContactRecord};
use crate::energy_ledger::EnergyLedger;
use crate::error::DemError;
use crate::floes::{Floe, Floes, Motion};
use crate::forcing::{ExternalForces, ForceRates, ForcingFailure};
use crate::load_point::LoadPoint;
use crate::motion_schedule::{MotionSchedule, ScheduledMotion};
use crate::periodicity::Periodicity;
use crate::pipeline::boundary_motion;
use crate::pipeline::broad_phase::BroadPhase;
use crate::pipeline::energy_accounting::{book_step, StepSums};
use crate::pipeline::force_gathering::ForceBuffers;
use crate::pipeline::integrator::{self, floe_stable_step, KickForces};
use crate::pipeline::narrow_phase::{ContactSet, DetectionInput};
use crate::pipeline::{Pipeline, Stage};
use crate::state::WorldState;
use crate::stress_control::StressControl;
use crate::Vec2;
use floe_friction::{FrictionLaw, LAW_STATE_SLOTS};

pub use crate::pipeline::integrator::{stable_time_step, STABILITY_SAFETY};

/// A floe's motion and the forces on it at the end of a step: what a
/// ghost copies from its owner ([`World::set_kinematics`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Centroid position, m.
    pub position: Vec2,
    /// Orientation, rad.
    pub angle: f64,
    /// Centroid velocity, m/s.
    pub velocity: Vec2,
    /// Angular velocity, rad/s.
    pub angular_velocity: f64,
    /// Total force, N.
    pub force: Vec2,
    /// Total torque, N m.
    pub torque: f64,
}

/// The simulation state and what steps it.
pub struct World<F: ExternalForces> {
    state: WorldState,
    pipeline: Pipeline,
    model: ContactModel,
    /// `model.damping_ratio()`, a root search: found once.
    damping_ratio: f64,
    forcing: F,
    periodicity: Periodicity,
    /// The first failure of the forcing's per-step preparation.
    forcing_failure: Option<ForcingFailure>,
}

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
/// the last evaluation, its contacts and its remembered broken contacts.
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
}

impl<F: ExternalForces> World<F> {
    /// A world at time 0: detects the contacts of `floes` (their friction
    /// state is the new contacts' one) and evaluates the forces. Refuses a
    /// time step above the stable limit.
    pub fn new(
        floes: Floes,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
        dt_s: f64,
    ) -> Result<Self, DemError> {
        let mut world =
            Self::assemble(WorldState::start(floes, dt_s), model, forcing, periodicity)?;
        let f = &world.state.floes;
        world.pipeline.trig.clear();
        world
            .pipeline
            .trig
            .extend(f.angle.iter().map(|a| a.sin_cos()));
        world.pipeline.moved_far = true;
        world.detect(0.0);
        world.pipeline.next = Stage::GatherForces;
        world.gather_forces();
        world.pipeline.next = Stage::Drift;
        match world.forcing_failure.take() {
            Some(failure) => Err(failure.into()),
            None => Ok(world),
        }
    }

    /// A world continuing from a saved [`WorldState`]: the next step is
    /// bitwise the step the saved world would have taken. Nothing is
    /// recomputed: re-detecting contacts would advance their friction state,
    /// and the saved forces were evaluated at the half-step velocity (drag,
    /// dashpots), which the end-of-step state no longer holds.
    pub fn resume(
        state: WorldState,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
    ) -> Result<Self, DemError> {
        state.validate()?;
        Self::assemble(state, model, forcing, periodicity)
    }

    /// Checks the time step and puts the parts together.
    fn assemble(
        state: WorldState,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
    ) -> Result<Self, DemError> {
        let slots = model.law.state_slots();
        if slots > LAW_STATE_SLOTS {
            return Err(DemError::InvalidModel {
                reason: format!(
                    "law `{}` declares {slots} state slots per contact; a contact holds {LAW_STATE_SLOTS}",
                    model.law.name()
                ),
            });
        }
        let dt_s = state.dt_s;
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "dt_s",
                value: dt_s,
                reason: "must be > 0",
            });
        }
        let floes = &state.floes;
        let (limit, culprit) = stable_time_step(floes, &model);
        if dt_s > limit {
            return Err(DemError::UnstableTimeStep {
                dt_s,
                limit_s: limit,
                reason: format!(
                    "floe {} against a like neighbour, E = {} Pa",
                    floes.id[culprit], model.youngs_modulus_pa
                ),
            });
        }
        let mean_radius = floes.radius_m.iter().sum::<f64>() / floes.len().max(1) as f64;
        Ok(Self {
            pipeline: Pipeline::new(mean_radius),
            state,
            damping_ratio: model.damping_ratio(),
            model,
            forcing,
            periodicity,
            forcing_failure: None,
        })
    }

    /// The state a checkpoint must hold to continue this run bitwise.
    pub fn state(&self) -> &WorldState {
        &self.state
    }

    /// The floes.
    pub fn floes(&self) -> &Floes {
        &self.state.floes
    }

    /// Contacts at the end of the last step, sorted by floe handles `(a, b)`.
    pub fn contacts(&self) -> &[ContactRecord] {
        &self.state.contacts
    }

    /// Contacts that broke within the last
    /// [`ContactModel::memory_s`], sorted by `(a, b)`.
    pub fn broken_contacts(&self) -> &[BrokenContact] {
        &self.state.broken
    }

    /// Simulated time, s.
    pub fn time_s(&self) -> f64 {
        self.state.time_s
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.state.steps
    }

    /// The time step, s.
    pub fn dt_s(&self) -> f64 {
        self.state.dt_s
    }

    /// Energy bookkeeping since the start.
    pub fn energy(&self) -> &EnergyLedger {
        &self.state.energy
    }

    /// Contact parameters and friction law.
    pub fn model(&self) -> &ContactModel {
        &self.model
    }

    /// The external forcing.
    pub fn forcing(&self) -> &F {
        &self.forcing
    }

    /// Why the forcing could not be prepared for a step (a gridded field's
    /// time or grid), if it failed since the world was made: the steps
    /// since then used the slices it held and should be discarded.
    pub fn forcing_failure(&self) -> Option<&ForcingFailure> {
        self.forcing_failure.as_ref()
    }

    /// The external forcing, to change between stages (it holds no state
    /// of the run; the next force gathering reads it).
    pub fn forcing_mut(&mut self) -> &mut F {
        &mut self.forcing
    }

    /// Periodic axes of the domain.
    pub fn periodicity(&self) -> Periodicity {
        self.periodicity
    }

    /// The pipeline's scratch, for diagnostics.
    pub fn pipeline(&self) -> &Pipeline {
        &self.pipeline
    }

    /// The broad phase (for diagnostics: rebuild count, skin).
    pub fn broad_phase(&self) -> &BroadPhase {
        &self.pipeline.broad_phase
    }

    /// The rotation a floe may make before the candidate list is rebuilt
    /// ([`BroadPhase::set_max_rotation_rad`]; default
    /// [`MAX_ROTATION_RAD`](crate::pipeline::broad_phase::MAX_ROTATION_RAD)).
    /// Results do not depend on it, only how many candidate pairs are
    /// tested and how often the list is rebuilt; `f64::INFINITY` keeps every
    /// pair whose bounding circles come within the skin.
    pub fn set_max_rotation_rad(&mut self, rad: f64) -> Result<(), DemError> {
        self.pipeline.broad_phase.set_max_rotation_rad(rad)
    }

    /// Advances one time step: [`World::drift`], [`World::detect_contacts`],
    /// [`World::gather_forces`], [`World::kick`].
    pub fn step(&mut self) {
        self.drift();
        self.detect_contacts();
        self.gather_forces();
        self.kick();
    }

    /// First stage of a step: the scheduled floes' velocities for the step
    /// (boundary motion), the first half kick and the drift, and the
    /// clock's advance. Panics unless the last step is complete.
    pub fn drift(&mut self) {
        self.pipeline.enter(Stage::Drift);
        let s = &mut self.state;
        let p = &mut self.pipeline;
        let dt = s.dt_s;
        boundary_motion::apply(&mut s.floes, &s.schedules, s.time_s, dt);
        boundary_motion::apply_stress_controls(&mut s.floes, &s.force, &mut s.stress_controls, dt);
        p.moved_far = integrator::drift(
            s.floes.columns_mut(),
            (&s.force, &s.torque),
            &mut p.trig,
            &p.broad_phase,
            self.periodicity,
            dt,
        );
        s.time_s += dt;
        s.steps += 1;
        p.accounting
            .begin_step(&mut s.external_force, &mut s.external_torque);
    }

    /// Second stage: the contacts at the drifted positions (broad phase,
    /// narrow phase, friction), and the contact memory.
    pub fn detect_contacts(&mut self) {
        self.pipeline.enter(Stage::DetectContacts);
        self.detect(self.state.dt_s);
    }

    /// The contact update over `dt` (0 at the start: no friction step).
    fn detect(&mut self, dt: f64) {
        let s = &mut self.state;
        let p = &mut self.pipeline;
        if p.trig.len() != s.floes.len() {
            p.trig.clear();
            p.trig.extend(s.floes.angle.iter().map(|a| a.sin_cos()));
        }
        let input = DetectionInput {
            floes: &s.floes,
            trig: &p.trig,
            model: &self.model,
            damping_ratio: self.damping_ratio,
            periodicity: self.periodicity,
            dt,
            time_s: s.time_s,
            ghost: &p.ghost,
        };
        let set = ContactSet {
            contacts: &mut s.contacts,
            broken: &mut s.broken,
            released_at_break_j: &mut p.accounting.released_j,
        };
        let changed = p
            .narrow_phase
            .update_contacts(&mut p.broad_phase, p.moved_far, &input, set);
        p.moved_far = false;
        if changed {
            p.gathering.invalidate();
        }
    }

    /// Third stage: external and contact forces on every floe, and beside
    /// them the contacts' powers for the energy accounting.
    pub fn gather_forces(&mut self) {
        self.pipeline.enter(Stage::GatherForces);
        let s = &mut self.state;
        let p = &mut self.pipeline;
        let (floes, contacts) = (&s.floes, &s.contacts);
        let accounting = &mut p.accounting;
        if let Err(failure) = self.forcing.prepare(s.time_s, floes) {
            // The step goes on with the slices held; the run loop stops on it.
            self.forcing_failure.get_or_insert(failure);
        }
        p.rates.resize(floes.len(), ForceRates::ZERO);
        let out = ForceBuffers {
            force: &mut s.force,
            torque: &mut s.torque,
            external_force: &mut s.external_force,
            external_torque: &mut s.external_torque,
            rates: &mut p.rates,
        };
        let ghost = &p.ghost;
        p.gathering
            .gather(floes, contacts, &self.forcing, s.time_s, out, || {
                accounting.sum_contact_power(contacts, floes, ghost)
            });
        boundary_motion::add_load_point_forces(
            &s.floes,
            &s.load_points,
            self.periodicity,
            s.time_s,
            (&mut s.force, &mut s.external_force),
        );
    }

    /// Last stage: the second half kick, and the step's work and
    /// dissipation into the energy ledger.
    pub fn kick(&mut self) {
        self.kick_with(|_| {});
    }

    /// [`World::kick`], handing the step's energy sums of this process's
    /// floes and contacts to `combine` before they are booked: a
    /// distributed run adds every process's sums there, so that each
    /// books the whole.
    pub fn kick_with(&mut self, combine: impl FnOnce(&mut StepSums)) {
        self.pipeline.enter(Stage::Kick);
        let s = &mut self.state;
        let p = &mut self.pipeline;
        let a = &mut p.accounting;
        integrator::kick(
            s.floes.columns_mut(),
            KickForces {
                force: &mut s.force,
                torque: &mut s.torque,
                external_force: &mut s.external_force,
                external_torque: &mut s.external_torque,
                rates: &p.rates,
            },
            (&a.previous_external_force, &a.previous_external_torque),
            (&mut a.forcing_partials, &p.ghost),
            s.dt_s,
        );
        let mut sums = a.take_step_sums();
        combine(&mut sums);
        book_step(&sums, &mut s.energy, s.dt_s);
    }

    /// Marks which floes are ghosts: copies of floes another process owns,
    /// stepped here for the contacts of this process's floes but left out
    /// of the energy sums (`ghost`, one per floe; empty: none). Adding or
    /// removing a floe clears the marks.
    pub fn set_ghosts(&mut self, ghost: Vec<bool>) -> Result<(), DemError> {
        if !ghost.is_empty() && ghost.len() != self.state.floes.len() {
            return Err(DemError::InvalidParameter {
                name: "ghost",
                value: ghost.len() as f64,
                reason: "one mark per floe expected",
            });
        }
        self.pipeline.ghost = ghost;
        Ok(())
    }

    /// Per floe, whether it is a ghost ([`World::set_ghosts`]; empty: none is).
    pub fn ghosts(&self) -> &[bool] {
        &self.pipeline.ghost
    }

    /// Floe `h`'s motion and the forces the next drift reads.
    pub fn kinematics(&self, h: usize) -> Kinematics {
        let s = &self.state;
        let f = s.floes.columns();
        Kinematics {
            position: f.position[h],
            angle: f.angle[h],
            velocity: f.velocity[h],
            angular_velocity: f.angular_velocity[h],
            force: s.force[h],
            torque: s.torque[h],
        }
    }

    /// Overwrites floe `h`'s motion and forces between steps with its
    /// owner's ([`World::kinematics`] there): a ghost then drifts as the
    /// owner's floe does. Refused inside a step.
    pub fn set_kinematics(&mut self, h: usize, k: &Kinematics) -> Result<(), DemError> {
        self.between_steps(self.state.floes.columns().id[h])?;
        let s = &mut self.state;
        let f = s.floes.columns_mut();
        f.position[h] = k.position;
        f.angle[h] = k.angle;
        f.velocity[h] = k.velocity;
        f.angular_velocity[h] = k.angular_velocity;
        s.force[h] = k.force;
        s.torque[h] = k.torque;
        let p = &mut self.pipeline;
        if p.trig.len() == s.floes.len() {
            p.trig[h] = k.angle.sin_cos();
        }
        p.moved_far |=
            p.broad_phase
                .moved_beyond_allowance(h, k.position, k.angle, self.periodicity);
        Ok(())
    }

    /// The world taken apart: its state and what came from the scenario,
    /// to be put together again (`World::resume`) with other floes.
    pub fn into_parts(self) -> (WorldState, ContactModel, F, Periodicity) {
        (self.state, self.model, self.forcing, self.periodicity)
    }

    /// The handle of floe `id`, or an error naming it.
    fn handle(&self, id: u64) -> Result<usize, DemError> {
        self.state.floes.handle_of(id).ok_or(DemError::FloeEdit {
            id,
            reason: "no such floe".into(),
        })
    }

    /// Refuses an edit of the floe set inside a step.
    fn between_steps(&self, id: u64) -> Result<(), DemError> {
        if self.pipeline.next == Stage::Drift {
            Ok(())
        } else {
            Err(DemError::FloeEdit {
                id,
                reason: "floes are added and removed between steps, not inside one".into(),
            })
        }
    }

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
            for c in &mut self.state.stress_controls {
                c.floe_ids.retain(|&f| f != id);
            }
            self.state
                .stress_controls
                .retain(|c| !c.floe_ids.is_empty());
        }
        Ok(())
    }

    /// Makes prescribed floe `id` follow `schedule` from the next step on
    /// (replacing any schedule it had). The schedule's time is the world's
    /// clock: `t = 0` at the start of the run.
    pub fn set_schedule(&mut self, id: u64, schedule: MotionSchedule) -> Result<(), DemError> {
        let h = self.handle(id)?;
        if self.state.floes.is_free(h) {
            return Err(DemError::FloeEdit {
                id,
                reason: "only a prescribed floe follows a motion schedule".into(),
            });
        }
        let schedules = &mut self.state.schedules;
        let entry = ScheduledMotion {
            floe_id: id,
            schedule,
        };
        match schedules.binary_search_by_key(&id, |s| s.floe_id) {
            Ok(k) => schedules[k] = entry,
            Err(k) => schedules.insert(k, entry),
        }
        Ok(())
    }

    /// The prescribed floes that follow a schedule, sorted by floe id.
    pub fn schedules(&self) -> &[ScheduledMotion] {
        &self.state.schedules
    }

    /// Drives free floe `load_point.floe_id` through `load_point`'s spring
    /// (replacing any load point it had). The spring's force at the
    /// current time joins the floe's force at once, so the next half kick
    /// feels it.
    pub fn set_load_point(&mut self, load_point: LoadPoint) -> Result<(), DemError> {
        let id = load_point.floe_id;
        let h = self.handle(id)?;
        if !self.state.floes.is_free(h) {
            return Err(DemError::FloeEdit {
                id,
                reason: "a load point drives a free floe".into(),
            });
        }
        let s = &mut self.state;
        let new = load_point.force(s.time_s, s.floes.position[h], self.periodicity);
        let list = &mut s.load_points;
        let old = match list.binary_search_by_key(&id, |l| l.floe_id) {
            Ok(k) => {
                let old = list[k].force(s.time_s, s.floes.position[h], self.periodicity);
                list[k] = load_point;
                old
            }
            Err(k) => {
                list.insert(k, load_point);
                Vec2::ZERO
            }
        };
        s.force[h] += new - old;
        s.external_force[h] += new - old;
        Ok(())
    }

    /// The load points, sorted by floe id.
    pub fn load_points(&self) -> &[LoadPoint] {
        &self.state.load_points
    }

    /// Makes the prescribed floes of `control` (a wall) hold its normal
    /// stress from the next step on; a floe already in a control is
    /// refused.
    pub fn add_stress_control(&mut self, control: StressControl) -> Result<(), DemError> {
        for &id in &control.floe_ids {
            let h = self.handle(id)?;
            if self.state.floes.is_free(h) {
                return Err(DemError::FloeEdit {
                    id,
                    reason: "a stress-controlled wall is made of prescribed floes".into(),
                });
            }
            if self.stress_control_of(id).is_some() {
                return Err(DemError::FloeEdit {
                    id,
                    reason: "already in a stress-controlled wall".into(),
                });
            }
        }
        self.state.stress_controls.push(control);
        Ok(())
    }

    /// The stress-controlled walls.
    pub fn stress_controls(&self) -> &[StressControl] {
        &self.state.stress_controls
    }

    /// The stress control floe `id` belongs to, if any.
    fn stress_control_of(&self, id: u64) -> Option<usize> {
        self.state
            .stress_controls
            .iter()
            .position(|c| c.floe_ids.binary_search(&id).is_ok())
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
        })
    }

    /// Takes floe `id` out between steps, with its forces, its contacts
    /// and its remembered broken contacts (no energy is counted as
    /// released: the contacts leave with the floe).
    pub fn remove_floe(&mut self, id: u64) -> Result<DetachedFloe, DemError> {
        self.between_steps(id)?;
        let h = self.handle(id)?;
        let s = &mut self.state;
        let contacts = take_pairs_of(&mut s.contacts, h, &s.floes.id);
        let broken = take_pairs_of(&mut s.broken, h, &s.floes.id);
        // Its schedule and load point go with it (a re-inserted floe has
        // none).
        s.schedules.retain(|m| m.floe_id != id);
        s.load_points.retain(|l| l.floe_id != id);
        for c in &mut s.stress_controls {
            c.floe_ids.retain(|&f| f != id);
        }
        s.stress_controls.retain(|c| !c.floe_ids.is_empty());
        let detached = DetachedFloe {
            floe: s.floes.remove(h),
            force: s.force.remove(h),
            torque: s.torque.remove(h),
            external_force: s.external_force.remove(h),
            external_torque: s.external_torque.remove(h),
            contacts,
            broken,
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
            .chain(d.broken.iter().map(|(ids, _)| *ids));
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
            .or_else(|| twice(d.broken.iter().map(|(ids, _)| *ids).collect()));
        if let Some([x, y]) = repeated {
            return Err(DemError::FloeEdit {
                id,
                reason: format!("the pair of floes {x} and {y} is listed twice"),
            });
        }
        if let Motion::Free = d.floe.motion {
            let f = &d.floe;
            self.check_stable(
                id,
                floe_stable_step(
                    f.mass_kg,
                    f.inertia_kg_m2,
                    f.thickness_m,
                    f.area_m2,
                    f.radius_m,
                    &self.model,
                ),
            )?;
        }
        let s = &mut self.state;
        let h = s.floes.insert(d.floe)?;
        put_pairs_back(&mut s.contacts, h, &s.floes, d.contacts);
        put_pairs_back(&mut s.broken, h, &s.floes, d.broken);
        s.force.insert(h, d.force);
        s.torque.insert(h, d.torque);
        s.external_force.insert(h, d.external_force);
        s.external_torque.insert(h, d.external_torque);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forcing::NoForcing;

    /// A 12 x 12 grid of squares pressed 2 % into each other and let go:
    /// the pack springs apart and most of its contacts break within a few
    /// steps of each other, spread over every task of the narrow phase.
    fn released_pack() -> World<NoForcing> {
        let square = |c: Vec2| {
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| c + 50.0 * Vec2::new(x, y))
                .to_vec()
        };
        let polys: Vec<Vec<Vec2>> = (0..144)
            .map(|k| {
                square(Vec2::new(
                    (k % 12) as f64 * 98.0,
                    (k / 12) as f64 * 98.0 + 0.7 * (k % 12) as f64,
                ))
            })
            .collect();
        let thickness: Vec<f64> = (0..144).map(|k| 1.0 + 0.01 * k as f64).collect();
        let floes = Floes::from_polygons(&polys, &thickness, 917.0).unwrap();
        // Restitution 0.5503: the damping ratio (0.2155) these tests were
        // written with, when restitution 0.5 was mapped by the textbook
        // formula (contact_model::damping_ratio_for_restitution).
        let model = ContactModel {
            restitution: 0.5503,
            ..ContactModel::default()
        };
        let dt = 0.5 * stable_time_step(&floes, &model).0;
        World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap()
    }

    #[test]
    fn results_do_not_depend_on_how_the_candidate_pairs_are_cut_into_tasks() {
        let mut runs: Vec<World<NoForcing>> = [None, Some(7), Some(64)]
            .into_iter()
            .map(|cut| {
                let mut w = released_pack();
                w.pipeline.narrow_phase.fixed_pair_chunk = cut;
                w
            })
            .collect();
        let initial = runs[0].contacts().len();
        let mut most_broken_in_a_step = 0;
        for _ in 0..400 {
            let before = runs[0].contacts().len();
            for w in &mut runs {
                w.step();
            }
            most_broken_in_a_step =
                most_broken_in_a_step.max(before.saturating_sub(runs[0].contacts().len()));
        }
        // The scenario does what it is for: contacts break, many at once.
        assert!(initial > 200, "{initial} initial contacts");
        assert!(
            runs[0].contacts().len() < initial / 2,
            "{} contacts left",
            runs[0].contacts().len()
        );
        assert!(most_broken_in_a_step >= 10, "{most_broken_in_a_step}");
        assert!(runs[0].energy().released_at_break_j != 0.0);
        for w in &runs[1..] {
            assert_eq!(w.energy(), runs[0].energy());
            assert_eq!(w.floes().position, runs[0].floes().position);
            assert_eq!(w.floes().velocity, runs[0].floes().velocity);
            assert_eq!(w.contacts(), runs[0].contacts());
        }
    }

    /// The force gathering's contact index, kept across steps where the
    /// contact list did not change, gives bitwise the results of building
    /// it at every step, in a pack where contacts break and form.
    #[test]
    fn keeping_the_contact_index_gives_the_results_of_rebuilding_it() {
        let (mut kept, mut rebuilt) = (released_pack(), released_pack());
        let builds = kept.pipeline.gathering.index_builds;
        for _ in 0..400 {
            kept.step();
            rebuilt.pipeline.gathering.invalidate();
            rebuilt.step();
        }
        let built = kept.pipeline.gathering.index_builds - builds;
        assert!(built < 200, "the index was built in {built} of 400 steps");
        assert_eq!(kept.energy(), rebuilt.energy());
        assert_eq!(kept.floes().position, rebuilt.floes().position);
        assert_eq!(kept.floes().velocity, rebuilt.floes().velocity);
        assert_eq!(kept.contacts(), rebuilt.contacts());
    }

    /// Two copies of the released pack stepped in lockstep (the steps are
    /// deterministic), each with the index its own last step built, until
    /// `edit`, shown the contact list now and the one the next step would
    /// make, returns an edited list. Both copies then take it and step: the
    /// first keeping its index if it can, the second made to rebuild it.
    /// Asks that the edited step formed no contact, built the first copy's
    /// index once, and gave both copies the same floes and contacts; returns
    /// the first copy for the caller's own checks.
    fn step_after_an_edit(
        edit: impl Fn(&[ContactRecord], &[ContactRecord]) -> Option<Vec<ContactRecord>>,
    ) -> World<NoForcing> {
        let (mut checked, mut rebuilt) = (released_pack(), released_pack());
        let (model, periodicity) = (checked.model.clone(), checked.periodicity);
        for _ in 0..400 {
            let mut ahead = World::resume(
                checked.state().clone(),
                model.clone(),
                NoForcing,
                periodicity,
            )
            .unwrap();
            ahead.step();
            let Some(edited) = edit(checked.contacts(), ahead.contacts()) else {
                checked.step();
                rebuilt.step();
                continue;
            };
            checked.edit_contacts(|c| c.clone_from(&edited)).unwrap();
            rebuilt.edit_contacts(|c| *c = edited).unwrap();
            let builds = checked.pipeline.gathering.index_builds;
            checked.step();
            rebuilt.pipeline.gathering.invalidate();
            rebuilt.step();
            assert!(checked.pipeline.narrow_phase.born.iter().all(Vec::is_empty));
            assert_eq!(checked.pipeline.gathering.index_builds, builds + 1);
            assert_eq!(checked.floes().velocity, rebuilt.floes().velocity);
            assert_eq!(checked.contacts(), rebuilt.contacts());
            return checked;
        }
        panic!("no step allowed the edit");
    }

    fn key(c: &ContactRecord) -> (u32, u32) {
        (c.a, c.b)
    }

    /// A contact list edited between steps so that the step neither ends
    /// nor forms a contact, yet the list is not the one the index was built
    /// for: the edit marks the index stale and it is rebuilt. The edit
    /// swaps the contacts that end in the next step for those that form in
    /// it; without the mark, the step would gather forces through a stale
    /// index.
    #[test]
    fn an_index_of_a_list_edited_between_steps_is_rebuilt() {
        let checked = step_after_an_edit(|now, next| {
            let ending = now
                .iter()
                .filter(|c| next.binary_search_by_key(&key(c), key).is_err())
                .count();
            let forming = next
                .iter()
                .filter(|c| now.binary_search_by_key(&key(c), key).is_err());
            if ending == 0 || ending != forming.clone().count() {
                return None;
            }
            let mut edited: Vec<ContactRecord> = now
                .iter()
                .filter(|c| next.binary_search_by_key(&key(c), key).is_ok())
                .chain(forming)
                .copied()
                .collect();
            edited.sort_by_key(key);
            Some(edited)
        });
        assert!(checked
            .pipeline
            .narrow_phase
            .chunk_ended
            .iter()
            .all(|&e| !e));
    }

    /// A contact list shortened between steps by the contacts at its end
    /// that the next step would end anyway: the step ends and forms
    /// nothing, but the list is shorter than the index: rebuilt.
    #[test]
    fn an_index_of_a_list_shortened_between_steps_is_rebuilt() {
        let checked = step_after_an_edit(|now, next| {
            let ends = |c: &&ContactRecord| next.binary_search_by_key(&key(c), key).is_err();
            let forming = next
                .iter()
                .filter(|c| now.binary_search_by_key(&key(c), key).is_err())
                .count();
            // The contacts after the last one that continues, all ending.
            let tail = now.iter().rev().take_while(ends).count();
            let ending = now.iter().filter(ends).count();
            (tail > 0 && ending == tail && forming == 0 && tail < now.len())
                .then(|| now[..now.len() - tail].to_vec())
        });
        assert!(checked
            .pipeline
            .narrow_phase
            .chunk_ended
            .iter()
            .all(|&e| !e));
    }
}
