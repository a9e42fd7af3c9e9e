//! The simulation: the world's state, the pipeline that steps it, and what
//! comes from the scenario (contact model, forcing, periodicity).
//!
//! This file holds the world's state and the stages of a step; its
//! methods by job: `edits.rs` (floes added, removed and moved, handles
//! renumbered), `drivers.rs` (motion schedules, load points, stress
//! controls), `cohesion.rs` (bonds between floes frozen together),
//! `ghosts.rs` (what a distributed run copies between processes),
//! `life_cycle.rs` (floe stress), `split.rs` (a floe broken into pieces),
//! `fracture.rs` (the floes a criterion breaks, split), `ridging.rs` and
//! `ridging_apply.rs` (floes cut under pressure), `welding.rs` and
//! `welding_apply.rs` (bonded pairs joined into one floe).
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
//! stage. A removed floe takes its contacts, contact memory and bonds with it, and
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
use crate::floes::Floes;
use crate::forcing::{ExternalForces, ForceRates, ForcingFailure};
use crate::periodicity::Periodicity;
use crate::pipeline::boundary_motion;
use crate::pipeline::broad_phase::BroadPhase;
use crate::pipeline::energy_accounting::{book_step, StepSums};
use crate::pipeline::force_gathering::ForceBuffers;
use crate::pipeline::integrator::{self, KickForces};
use crate::pipeline::narrow_phase::{ContactSet, DetectionInput};
use crate::pipeline::{Pipeline, Stage};
use crate::state::WorldState;
use floe_friction::{FrictionLaw, LAW_STATE_SLOTS};

mod cohesion;
mod drivers;
mod edits;
mod fracture;
mod ghosts;
mod life_cycle;
mod ridging;
mod ridging_apply;
mod split;
#[cfg(test)]
mod tests;
mod welding;
mod welding_apply;

pub use crate::pipeline::integrator::{stable_time_step, STABILITY_SAFETY};
pub use edits::DetachedFloe;
pub use fracture::{FractureEvent, PackSums, PlannedSplit};
pub use ghosts::Kinematics;
pub use ridging::{PlannedRidge, RidgedIce, RidgingTally, CRUSHED_OVERLAP_FRACTION};
pub use ridging_apply::{final_gainers, IceTarget};
pub use welding::{candidate_ids, choose_welds, Weld, WeldRecords};

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
    /// Fracture after every step (through `Stepper::step`), if on.
    fracturing: Option<crate::fracture::rule::Fracturing>,
    /// Bonds form and break, if on.
    cohesion: Option<crate::cohesion::Cohesion>,
    /// Floes ridge after every step (through `Stepper::step`), if on.
    ridging: Option<crate::ridging::Ridging>,
    /// Bonded floes weld after every step (through `Stepper::step`), if on.
    welding: Option<crate::welding::Welding>,
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
            fracturing: None,
            cohesion: None,
            ridging: None,
            welding: None,
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
    /// narrow phase, friction), the contact memory, and the contacts'
    /// powers for the energy accounting.
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
            power: &mut p.accounting.contact_partials,
        };
        let changed = p
            .narrow_phase
            .update_contacts(&mut p.broad_phase, p.moved_far, &input, set);
        p.moved_far = false;
        if changed {
            p.gathering.invalidate();
        }
        if dt > 0.0 {
            self.update_bonds();
        }
    }

    /// Third stage: external and contact forces on every floe, and (when
    /// on) the floe stress.
    pub fn gather_forces(&mut self) {
        self.pipeline.enter(Stage::GatherForces);
        let s = &mut self.state;
        let p = &mut self.pipeline;
        let (floes, contacts) = (&s.floes, &s.contacts);
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
        p.gathering
            .gather(floes, contacts, &self.forcing, s.time_s, out);
        if self.cohesion.is_some() {
            crate::pipeline::cohesion::add_bond_forces(&s.bonds, &mut s.force, &mut s.torque);
        }
        boundary_motion::add_load_point_forces(
            &s.floes,
            &s.load_points,
            self.periodicity,
            s.time_s,
            (&mut s.force, &mut s.external_force),
        );
        self.update_floe_stress();
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
}
