//! The step as a pipeline of stages over the world's state.
//!
//! | stage | module | reads | writes |
//! |---|---|---|---|
//! | boundary motion | `boundary_motion` | motion schedules, clock | velocities of scheduled prescribed floes |
//! | drift | [`integrator`] | forces, velocities | positions, angles, half-step velocities; per-floe rotation; whether the candidate list is stale |
//! | broad phase | [`broad_phase`] | positions, angles, radii | candidate pairs (rebuilt when stale) |
//! | narrow phase | [`narrow_phase`] | candidate pairs, floes | contact list: overlaps, normal forces; contacts formed, continued, ended; contact memory; the contacts' power sums |
//! | friction | [`friction`] | each contact's load | its tangential spring and friction state (the one call of the law) |
//! | cohesion (when on) | [`cohesion`] | contacts, floes | bonds formed, their forces, broken bonds |
//! | force gathering | [`force_gathering`] | contacts, forcing | per-floe force and torque |
//! | floe stress (when on) | [`floe_stress`] | contacts, per-floe contact index | each free floe's time-averaged stress |
//! | kick | [`integrator`] | forces and their rates with velocity | velocities; external forces at the new velocities |
//! | energy accounting | [`energy_accounting`] | the contacts' power sums, forces, velocities | the energy ledger |
//!
//! [`World::step`](crate::world::World::step) runs them in that order;
//! the world also offers the stages as four calls,
//! [`drift`](crate::world::World::drift),
//! [`detect_contacts`](crate::world::World::detect_contacts) (broad and
//! narrow phase with friction), [`gather_forces`](crate::world::World::gather_forces)
//! and [`kick`](crate::world::World::kick) (with the energy accounting),
//! so that other work (a halo exchange, a boundary update) can run between
//! them. The [`Pipeline`] holds only scratch: buffers reused every step,
//! the candidate list, caches. Nothing in it is needed to continue a run:
//! the state is in [`WorldState`](crate::state::WorldState).

pub(crate) mod boundary_motion;
pub mod broad_phase;
pub(crate) mod cohesion;
pub(crate) mod contact_memory;
pub(crate) mod contact_merge;
pub mod energy_accounting;
pub mod floe_stress;
pub mod force_gathering;
pub mod friction;
pub mod integrator;
pub mod narrow_phase;
pub(crate) mod oriented_vertices;

use broad_phase::BroadPhase;
use energy_accounting::EnergyAccounting;
use force_gathering::ForceGathering;
use narrow_phase::NarrowPhase;

/// Broad-phase skin as a fraction of the mean floe radius. The skin only
/// sets how often the candidate list is rebuilt (far pairs are left out by
/// a distance bound, not by the skin): at 0.05 a floe at 0.1 m/s needs
/// about 2,700 one-second steps to cross half the skin, and a rebuild costs
/// about one step.
pub const SKIN_FRACTION: f64 = 0.05;

/// Which stage of a step comes next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Between steps: the drift starts the next one.
    Drift,
    /// The contacts at the drifted positions.
    DetectContacts,
    /// The forces from those contacts and the forcing.
    GatherForces,
    /// The second half kick, which ends the step.
    Kick,
}

/// The scratch of the step: everything a stage keeps between steps or
/// hands to the next stage that is not part of the world's state.
pub struct Pipeline {
    pub(crate) broad_phase: BroadPhase,
    pub(crate) narrow_phase: NarrowPhase,
    pub(crate) gathering: ForceGathering,
    pub(crate) accounting: EnergyAccounting,
    /// Each floe's `(sin, cos)` of its angle, from the drift.
    pub(crate) trig: Vec<(f64, f64)>,
    /// Each floe's external force rates, from the force gathering for the
    /// kick.
    pub(crate) rates: Vec<crate::forcing::ForceRates>,
    /// A floe moved beyond the broad phase's allowance in the drift.
    pub(crate) moved_far: bool,
    /// Per floe, whether it is a ghost: a copy of another process's floe,
    /// stepped here for its contacts but not counted in the energy sums.
    /// Empty: every floe is this process's.
    pub(crate) ghost: Vec<bool>,
    /// The cohesion stage's scratch: the pairs that turned quiet this
    /// step (where their candidates go, and their contacts).
    pub(crate) bond_fresh: Vec<(usize, usize)>,
    /// Per floe, its bonds' stress moments (floe stress with cohesion).
    pub(crate) bond_moments: Vec<[f64; 3]>,
    /// Bonds broken since the world was made or resumed.
    pub(crate) bonds_broken: u64,
    pub(crate) next: Stage,
}

impl Pipeline {
    /// A pipeline for floes of mean bounding radius `mean_radius_m`.
    pub(crate) fn new(mean_radius_m: f64) -> Self {
        Pipeline {
            broad_phase: BroadPhase::new(SKIN_FRACTION * mean_radius_m),
            narrow_phase: NarrowPhase::default(),
            gathering: ForceGathering::default(),
            accounting: EnergyAccounting::default(),
            trig: Vec::new(),
            rates: Vec::new(),
            moved_far: true,
            ghost: Vec::new(),
            bond_fresh: Vec::new(),
            bond_moments: Vec::new(),
            bonds_broken: 0,
            next: Stage::Drift,
        }
    }

    /// The broad phase (for diagnostics: rebuild count, skin, pairs).
    pub fn broad_phase(&self) -> &BroadPhase {
        &self.broad_phase
    }

    /// The stage the next call must be.
    pub fn next_stage(&self) -> Stage {
        self.next
    }

    /// Times the force gathering built its per-floe contact index.
    pub fn contact_index_builds(&self) -> u64 {
        self.gathering.index_builds
    }

    /// The floe set changed (a floe added or removed): every per-floe and
    /// per-pair cache is stale.
    pub(crate) fn floes_changed(&mut self) {
        self.broad_phase.invalidate();
        self.narrow_phase.invalidate();
        self.gathering.invalidate();
        self.moved_far = true;
        self.ghost.clear();
    }

    /// Moves to the next stage, which must be `stage`.
    pub(crate) fn enter(&mut self, stage: Stage) {
        assert_eq!(
            self.next, stage,
            "the world's stages run in order: drift, detect_contacts, gather_forces, kick"
        );
        self.next = match stage {
            Stage::Drift => Stage::DetectContacts,
            Stage::DetectContacts => Stage::GatherForces,
            Stage::GatherForces => Stage::Kick,
            Stage::Kick => Stage::Drift,
        };
    }
}
