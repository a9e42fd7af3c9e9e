//! The simulation: floes, contacts, forcing and the time step.
//!
//! # Time integration
//! Velocity Verlet (kick-drift-kick), second order for position-dependent
//! forces: `v += a dt/2; x += v dt; forces at the new positions (with the
//! half-step velocity for drag, damping and friction); v += a dt/2`. The
//! friction state of every contact advances once per step, inside the force
//! evaluation.
//!
//! # Parallelism and determinism
//! Work is spread with rayon on the pool the caller installs (`pool.install(|| world.step())`);
//! the world never creates threads. Every loop either writes one element per
//! index (floes, candidate pairs) or sums in a fixed order: contact forces
//! are gathered per floe through a contact list sorted by pair, never
//! scattered with atomics, and energy sums run sequentially. The result is
//! bitwise identical for any number of threads.

use floe_friction::{BatchItem, ContactLoad, ContactState, StepOutcome};
use rayon::prelude::*;

use crate::broad_phase::{BroadPhase, CandidatePair, Periodicity};
use crate::checkpoint::WorldState;
use crate::contact_kernel::{
    contact_before_friction, contact_force_on_b, finish_friction, force_and_torques,
    overlap_stiffness, Body,
};
use crate::contacts::{BrokenContact, ContactModel, ContactRecord};
use crate::error::DemError;
use crate::floes::{Floes, Motion};
use crate::geometry::{cross, overlap_cached, ClipScratch, Overlap, SeparatingEdge};
use crate::Vec2;

/// Forces on floes from outside the floe assembly (wind, ocean, Coriolis).
pub trait ExternalForces: Sync {
    /// Force (N) and torque (N m) on floe `i` at time `t_s`.
    fn force_and_torque(&self, t_s: f64, floes: &Floes, i: usize) -> (Vec2, f64);
}

/// No external forcing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoForcing;

impl ExternalForces for NoForcing {
    fn force_and_torque(&self, _t: f64, _floes: &Floes, _i: usize) -> (Vec2, f64) {
        (Vec2::ZERO, 0.0)
    }
}

impl ExternalForces for crate::forcing::Forcing {
    fn force_and_torque(&self, t_s: f64, floes: &Floes, i: usize) -> (Vec2, f64) {
        let dynamics = crate::forcing::FloeDynamics {
            position: floes.position[i],
            velocity: floes.velocity[i],
            angular_velocity: floes.angular_velocity[i],
            area_m2: floes.area_m2[i],
            mass_kg: floes.mass_kg[i],
            r3_moment_m5: floes.r3_moment_m5[i],
        };
        crate::forcing::Forcing::force_and_torque(self, t_s, &dynamics)
    }
}

/// Energy bookkeeping since the start of the run, J.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyLedger {
    /// Work done on the floes by external forcing.
    pub forcing_work_j: f64,
    /// Energy dissipated by contact friction.
    pub friction_dissipation_j: f64,
    /// Energy dissipated by the normal dashpots.
    pub damping_dissipation_j: f64,
    /// Work done on the floes by floes with prescribed motion (walls).
    pub boundary_work_j: f64,
    /// Energy held by contacts at the moment they broke: the elastic work
    /// the overlap force did over the contact's life, plus the tangential
    /// spring's energy. An overlap-area force is not the gradient of a
    /// potential (sliding changes the overlap without normal motion), so this
    /// is not zero: it is the model's own non-conservation, reported rather
    /// than hidden. Positive: energy lost from the floes.
    pub released_at_break_j: f64,
}

/// Safety factor on the undamped single-contact limit `2 / omega`: a floe in
/// a packed tessellation has up to about six contacts, and the dashpot and
/// tangential spring shorten the limit further.
pub const STABILITY_SAFETY: f64 = 0.3;

/// Broad-phase skin as a fraction of the mean floe radius. Measured on a
/// sheared 1e5-floe diamond channel (docs/performance.md): with bounding
/// circles alone, candidate pairs were 598 k at 0.2 and at 0.05 alike (a
/// rhombus's bounding circle overlaps its vertex neighbours' whatever the
/// skin), so the skin only sets how often the list is rebuilt; the far
/// pairs are now left out (400 k). At 0.05, a floe at 0.1 m/s needs ~2700
/// steps to cross half the skin, and a rebuild costs about one step.
pub const SKIN_FRACTION: f64 = 0.05;

/// Most candidate pairs per parallel task of the narrow phase.
const PAIR_CHUNK: usize = 1024;

/// Fewest candidate pairs per task (but the last, or a run with fewer
/// pairs in all).
const MIN_PAIR_CHUNK: usize = 128;

/// Tasks wanted for the narrow phase: small runs are cut into this many,
/// not into a few of [`PAIR_CHUNK`] pairs (at 1e3 floes, six), so that two
/// threads share them evenly. Results do not depend on the cut (tested),
/// only the balance does.
const PAIR_TASKS: usize = 32;

/// Candidate pairs per task for a list of `n_pairs`.
fn pair_chunk(n_pairs: usize) -> usize {
    (n_pairs / PAIR_TASKS).clamp(MIN_PAIR_CHUNK, PAIR_CHUNK)
}

/// Contacts whose friction is stepped together (`Law::step_batch`): found
/// by the narrow phase, held until this many wait, then advanced side by
/// side.
const FRICTION_BATCH: usize = 32;

/// The outcome of a friction step not yet taken.
const NO_OUTCOME: StepOutcome = StepOutcome {
    slip_rate_m_per_s: 0.0,
    mu: 0.0,
    iterations: 0,
};

/// Placeholder for the unused slots of the friction batch.
const NO_ITEM: BatchItem = BatchItem {
    state: ContactState {
        tangential_force_n: 0.0,
        theta: 0.0,
        solver_guess: 0.0,
        solver_trend: 0.0,
    },
    load: ContactLoad {
        load_point_velocity_m_per_s: 0.0,
        stiffness_n_per_m: 0.0,
        normal_load_n: 0.0,
    },
    outcome: NO_OUTCOME,
};

/// The simulation state.
pub struct World<F: ExternalForces> {
    /// The floes.
    pub floes: Floes,
    /// Contacts at the end of the last step, sorted by floe handles `(a, b)`.
    pub contacts: Vec<ContactRecord>,
    /// Contact parameters and friction law.
    pub model: ContactModel,
    /// External forcing.
    pub forcing: F,
    /// Periodic axes of the domain.
    pub periodicity: Periodicity,
    /// Time step, s.
    pub dt_s: f64,
    /// Simulated time, s.
    pub time_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Energy bookkeeping.
    pub energy: EnergyLedger,
    /// Contacts that broke within the last [`ContactModel::memory_s`], sorted by `(a, b)`.
    pub broken: Vec<BrokenContact>,
    broad_phase: BroadPhase,
    force: Vec<Vec2>,
    torque: Vec<f64>,
    external_force: Vec<Vec2>,
    external_torque: Vec<f64>,
    previous_external_force: Vec<Vec2>,
    previous_external_torque: Vec<f64>,
    /// Per floe, where its contacts as `b` start in `adjacency`.
    adjacency_start: Vec<u32>,
    /// Contacts as `b` of each floe, in contact order.
    adjacency: Vec<u32>,
    /// Per floe, where its block of contacts as `a` starts in the list.
    a_start: Vec<u32>,
    trig: Vec<(f64, f64)>,
    /// Per chunk of candidate pairs, where its run of previous contacts starts.
    chunk_start: Vec<usize>,
    /// Per candidate pair, an edge that separated the two floes when last
    /// clipped (reset whenever the broad phase rebuilds the pair list). Only
    /// a shortcut: results do not depend on it, so it is not checkpointed.
    separating: Vec<SeparatingEdge>,
    /// Per chunk of candidate pairs, the contacts that formed this step
    /// (few: most contacts continue in place). Reused every step.
    born: Vec<Vec<ContactRecord>>,
    /// Per chunk of candidate pairs, the contacts that ended, for contact
    /// memory (empty without it).
    ended: Vec<Vec<BrokenContact>>,
    /// Per chunk of candidate pairs, what the step changed in its run of
    /// the contact list (where the merge's compaction must look, and
    /// whether the force gathering's contact index still holds).
    chunk_changes: Vec<ChunkChanges>,
    /// `keys`, `adjacency_start`, `adjacency` and `a_start` describe
    /// `contacts` as the last force gathering left it, and
    /// `update_contacts` found it unchanged since (no contact ended, formed
    /// or moved, the same length): the index need not be rebuilt.
    index_current: bool,
    /// Times the contact index was built (a diagnostic for the tests).
    index_builds: u64,
    /// Candidate pairs per task if set, instead of [`pair_chunk`] (tests
    /// that results do not depend on it).
    fixed_pair_chunk: Option<usize>,
    /// `(a, b)` of every contact, copied out of the records for the
    /// sequential passes of the force gathering.
    keys: Vec<(u32, u32)>,
    /// Per block of contacts, the sums of their powers (reused every step).
    energy_partials: Vec<ContactPower>,
    /// Per block of floes, the power of the external forces (reused every step).
    forcing_partials: Vec<f64>,
}

impl<F: ExternalForces> World<F> {
    /// A world; refuses a time step above the stable limit.
    pub fn new(
        floes: Floes,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
        dt_s: f64,
    ) -> Result<Self, DemError> {
        let mut world = Self::new_checked(floes, model, forcing, periodicity, dt_s)?;
        let moved_far = world.prepare_contacts();
        world.update_contacts(0.0, moved_far);
        world.gather_forces_and_contact_power();
        Ok(world)
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
        dt_s: f64,
    ) -> Result<Self, DemError> {
        state.validate()?;
        let WorldState {
            floes,
            contacts,
            broken,
            time_s,
            steps,
            energy,
            force,
            torque,
            external_force,
            external_torque,
        } = state;
        let mut world = Self::new_checked(floes, model, forcing, periodicity, dt_s)?;
        world.contacts = contacts;
        world.broken = broken;
        world.time_s = time_s;
        world.steps = steps;
        world.energy = energy;
        world.force = force;
        world.torque = torque;
        world.external_force = external_force;
        world.external_torque = external_torque;
        Ok(world)
    }

    /// The state a checkpoint must hold to continue this run bitwise.
    pub fn state(&self) -> WorldState {
        WorldState {
            floes: self.floes.clone(),
            contacts: self.contacts.clone(),
            broken: self.broken.clone(),
            time_s: self.time_s,
            steps: self.steps,
            energy: self.energy,
            force: self.force.clone(),
            torque: self.torque.clone(),
            external_force: self.external_force.clone(),
            external_torque: self.external_torque.clone(),
        }
    }

    /// Checks `dt` and builds the world with no contacts yet.
    fn new_checked(
        floes: Floes,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
        dt_s: f64,
    ) -> Result<Self, DemError> {
        if !(dt_s.is_finite() && dt_s > 0.0) {
            return Err(DemError::InvalidParameter {
                name: "dt_s",
                value: dt_s,
                reason: "must be > 0",
            });
        }
        let (limit, culprit) = stable_time_step(&floes, &model);
        if dt_s > limit {
            return Err(DemError::UnstableTimeStep {
                dt_s,
                limit_s: limit,
                reason: format!(
                    "floe {culprit} against a like neighbour, E = {} Pa",
                    model.youngs_modulus_pa
                ),
            });
        }
        Ok(Self::assemble(floes, model, forcing, periodicity, dt_s))
    }

    fn assemble(
        floes: Floes,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
        dt_s: f64,
    ) -> Self {
        let mean_radius = floes.radius_m.iter().sum::<f64>() / floes.len().max(1) as f64;
        let n = floes.len();
        Self {
            floes,
            contacts: Vec::new(),
            model,
            forcing,
            periodicity,
            dt_s,
            time_s: 0.0,
            steps: 0,
            energy: EnergyLedger::default(),
            broken: Vec::new(),
            broad_phase: BroadPhase::new(SKIN_FRACTION * mean_radius),
            force: vec![Vec2::ZERO; n],
            torque: vec![0.0; n],
            external_force: vec![Vec2::ZERO; n],
            external_torque: vec![0.0; n],
            previous_external_force: vec![Vec2::ZERO; n],
            previous_external_torque: vec![0.0; n],
            adjacency_start: Vec::new(),
            adjacency: Vec::new(),
            a_start: Vec::new(),
            trig: Vec::new(),
            chunk_start: Vec::new(),
            separating: Vec::new(),
            born: Vec::new(),
            ended: Vec::new(),
            chunk_changes: Vec::new(),
            index_current: false,
            index_builds: 0,
            fixed_pair_chunk: None,
            keys: Vec::new(),
            energy_partials: Vec::new(),
            forcing_partials: Vec::new(),
        }
    }

    /// The broad phase (for diagnostics: rebuild count, skin).
    pub fn broad_phase(&self) -> &BroadPhase {
        &self.broad_phase
    }

    /// The rotation a floe may make before the candidate list is rebuilt
    /// ([`BroadPhase::set_max_rotation_rad`]; default
    /// [`MAX_ROTATION_RAD`](crate::broad_phase::MAX_ROTATION_RAD)). Results
    /// do not depend on it, only how many candidate pairs are tested and
    /// how often the list is rebuilt; `f64::INFINITY` keeps every pair whose
    /// bounding circles come within the skin.
    pub fn set_max_rotation_rad(&mut self, rad: f64) -> Result<(), DemError> {
        self.broad_phase.set_max_rotation_rad(rad)
    }

    /// Advances one time step.
    pub fn step(&mut self) {
        let dt = self.dt_s;
        let periodicity = self.periodicity;
        let f = &mut self.floes;
        let owned = f.owned;
        let (force, torque) = (&self.force, &self.torque);
        // Kick and drift, and in the same pass what the contact update needs
        // per floe: its rotation, and whether it moved far enough for a new
        // candidate list. One parallel region instead of three: at 1e3 floes
        // waking the pool's threads for each region was a visible part of a
        // 1.4 ms step on two threads (docs/performance.md).
        let n = f.len();
        self.trig.resize(n, (0.0, 1.0));
        let bp = &self.broad_phase;
        let moved_far = (
            &mut f.position[..owned],
            &mut f.velocity[..owned],
            (&mut f.angle[..owned], &mut f.angular_velocity[..owned]),
            &mut self.trig[..owned],
        )
            .into_par_iter()
            .enumerate()
            .map(|(i, (x, v, (theta, omega), trig))| {
                if let Motion::Free = f.motion[i] {
                    *v += force[i] / f.mass_kg[i] * (0.5 * dt);
                    *omega += torque[i] / f.inertia_kg_m2[i] * (0.5 * dt);
                }
                *x = periodicity.wrap(*x + *v * dt);
                *theta += *omega * dt;
                *trig = theta.sin_cos();
                bp.moved_beyond_allowance(i, *x, *theta, periodicity)
            })
            .reduce(|| false, |a, b| a || b);
        // Ghost floes (a subdomain's copies of its neighbours' floes) are
        // moved by their owner, not here.
        let mut moved_far = moved_far || bp.built_for() != n;
        for i in owned..n {
            self.trig[i] = f.angle[i].sin_cos();
            moved_far |= bp.moved_beyond_allowance(i, f.position[i], f.angle[i], periodicity);
        }
        self.time_s += dt;
        self.steps += 1;
        // Keep this step's starting external forces for the work integral;
        // gather_forces_and_contact_power overwrites every entry of the other buffer.
        std::mem::swap(&mut self.external_force, &mut self.previous_external_force);
        std::mem::swap(
            &mut self.external_torque,
            &mut self.previous_external_torque,
        );
        self.update_contacts(dt, moved_far);
        self.gather_forces_and_contact_power();
        self.kick_and_account_energy(dt);
    }

    /// Per-floe rotation and broad-phase staleness, when [`World::step`] has
    /// not computed them in its drift (at the start of a run).
    fn prepare_contacts(&mut self) -> bool {
        let f = &self.floes;
        self.trig.clear();
        self.trig
            .par_extend(f.angle.par_iter().map(|a| a.sin_cos()));
        self.broad_phase.is_stale(f, self.periodicity)
    }

    /// Broad phase, narrow phase and contact kernel: the new contact list.
    /// `self.trig` must hold every floe's `(sin, cos)`, and `moved_far` say
    /// whether any floe moved beyond half the skin since the candidate list
    /// was built.
    fn update_contacts(&mut self, dt: f64, moved_far: bool) {
        let f = &self.floes;
        if moved_far {
            self.broad_phase.rebuild(f, &self.trig, self.periodicity);
        }
        if moved_far || self.separating.len() != self.broad_phase.pairs.len() {
            self.separating.clear();
            self.separating
                .resize(self.broad_phase.pairs.len(), SeparatingEdge::NONE);
        }
        // The contact list is updated in place: a step holds one list, not
        // the previous one, per-task outputs and a new one (three 168 B
        // records per contact, 960 B per floe at 1e6 floes: the 1 KB per
        // floe budget, docs/performance.md). Pairs and contacts are both
        // sorted by (a, b), so each fixed chunk of pairs owns the contiguous
        // run of previous contacts from its first pair up to the next
        // chunk's (the first chunk from the start, the last to the end):
        // every previous contact belongs to exactly one chunk.
        let pairs = &self.broad_phase.pairs;
        let chunk = self
            .fixed_pair_chunk
            .unwrap_or_else(|| pair_chunk(pairs.len()));
        debug_assert!(chunk > 0);
        let n_chunks = pairs.len().div_ceil(chunk);
        {
            // One binary search per chunk, in parallel for long lists: each
            // probes records spread over the whole list, a cache miss apiece
            // (about 1 ms per step at 1e5 floes done one after the other).
            // A short list is searched in turn: a parallel region costs more
            // there than its few dozen searches in cache.
            let previous = &self.contacts;
            let start_of = |(j, chunk): (usize, &[CandidatePair])| {
                let first = (chunk[0].a, chunk[0].b);
                if j == 0 {
                    0
                } else {
                    previous.partition_point(|c| (c.a, c.b) < first)
                }
            };
            if n_chunks <= PAIR_TASKS {
                self.chunk_start.clear();
                self.chunk_start
                    .extend(pairs.chunks(chunk).enumerate().map(start_of));
            } else {
                pairs
                    .par_chunks(chunk)
                    .enumerate()
                    .map(start_of)
                    .collect_into_vec(&mut self.chunk_start);
            }
            if self.chunk_start.is_empty() {
                self.chunk_start.push(0);
            }
            self.chunk_start.push(previous.len());
        }
        let model = &self.model;
        let damping_ratio = model.damping_ratio();
        let periodicity = self.periodicity;
        let trig = &self.trig;
        let broken = &self.broken;
        let keys = &self.keys;
        let body = |i: usize, offset: Vec2| Body {
            position: f.position[i] + offset,
            velocity: f.velocity[i],
            angular_velocity: f.angular_velocity[i],
            mass_kg: f.mass_kg[i],
            thickness_m: f.thickness_m[i],
            area_m2: f.area_m2[i],
            free: f.is_free(i),
        };
        let placed = |i: usize, offset: Vec2| f.placed(i, offset, trig[i]);
        // The overlap of a candidate pair, and the offset of the image of `b`
        // that touches `a`.
        let overlap_of_pair = |pair: &CandidatePair,
                               edge: &mut SeparatingEdge,
                               scratch: &mut ClipScratch|
         -> Option<(Overlap, Vec2)> {
            let (a, b) = (pair.a as usize, pair.b as usize);
            if !f.is_free(a) && !f.is_free(b) {
                return None;
            }
            let offset = periodicity.nearest_image(f.position[a], f.position[b]);
            let reach = f.radius_m[a] + f.radius_m[b];
            if (f.position[b] + offset - f.position[a]).length_squared() > reach * reach {
                return None; // bounding circles apart: no clipping needed
            }
            let ov = overlap_cached(placed(a, Vec2::ZERO), placed(b, offset), edge, scratch)?;
            Some((ov, offset))
        };
        // A contact that has just formed; a pair that touched recently
        // resumes its state.
        let new_contact = |pair: &CandidatePair, ov: &Overlap, a: &Body, b: &Body, offset: Vec2| {
            let mut fresh = ContactRecord::new_contact(model, ov, a, b, (pair.a, pair.b), offset);
            if let Ok(k) = broken.binary_search_by(|c| (c.a, c.b).cmp(&(pair.a, pair.b))) {
                fresh.friction.theta = broken[k].friction.theta;
                fresh.friction.solver_guess = broken[k].friction.solver_guess;
            }
            fresh
        };
        let remember = model.memory_s > 0.0;
        let time_s = self.time_s;
        // A contact that did not survive the step is remembered if the model
        // asks for memory, and is marked dead until the list is compacted
        // below (which sums what the dead released).
        let end_contact = |old: &mut ContactRecord,
                           ended: &mut Vec<BrokenContact>,
                           changes: &mut ChunkChanges| {
            changes.ended = true;
            if remember {
                ended.push(BrokenContact {
                    a: old.a,
                    b: old.b,
                    friction: old.friction,
                    broke_at_s: time_s,
                });
            }
            old.a = DEAD;
        };
        // Each chunk's runs of previous contacts, as disjoint mutable slices.
        let mut runs: Vec<&mut [ContactRecord]> = Vec::with_capacity(n_chunks.max(1));
        {
            let mut rest = self.contacts.as_mut_slice();
            for w in self.chunk_start.windows(2) {
                let (head, tail) = rest.split_at_mut(w[1] - w[0]);
                runs.push(head);
                rest = tail;
            }
        }
        if n_chunks == 0 {
            // No candidate pairs: every previous contact ends.
            let mut ended = Vec::new();
            self.chunk_changes.clear();
            self.chunk_changes.push(ChunkChanges::default());
            for old in runs.pop().into_iter().flatten() {
                end_contact(old, &mut ended, &mut self.chunk_changes[0]);
            }
            self.ended.clear();
            self.ended.push(ended);
        } else {
            self.ended.resize_with(n_chunks, Vec::new);
            self.chunk_changes.resize(n_chunks, ChunkChanges::default());
        }
        self.born.resize_with(n_chunks, Vec::new);
        runs.into_par_iter()
            .zip(pairs.par_chunks(chunk))
            .zip(self.separating.par_chunks_mut(chunk))
            .zip(self.born.par_iter_mut())
            .zip(self.ended.par_iter_mut())
            .zip(
                self.chunk_changes
                    .par_iter_mut()
                    .zip(self.chunk_start.par_iter()),
            )
            // One workspace per rayon task, not per chunk (`TaskWorkspace`:
            // the clipper's 4 KB zeroed per chunk was another 1 %).
            .for_each_init(
                TaskWorkspace::default,
                |workspace, (((((run, pairs), edges), born), ended), (changes, &run_start))| {
                    born.clear();
                    ended.clear();
                    *changes = ChunkChanges::default();
                    let TaskWorkspace {
                        clip: scratch,
                        slots,
                        elastic_power,
                        items,
                    } = workspace;
                    let mut waiting = 0;
                    // Steps the waiting contacts' friction and completes their records.
                    let flush = |items: &mut [BatchItem],
                                 slots: &[Slot],
                                 elastic_power: &[f64],
                                 run: &mut [ContactRecord],
                                 born: &mut Vec<ContactRecord>| {
                        if dt > 0.0 {
                            model.law.step_batch(items, dt);
                        }
                        for ((slot, item), &power) in slots.iter().zip(&*items).zip(elastic_power) {
                            let record = match *slot {
                                Slot::Run(k) => &mut run[k],
                                Slot::Born(k) => &mut born[k],
                            };
                            finish_friction(record, item, power, dt);
                        }
                    };
                    let mut k = 0;
                    for (pair, edge) in pairs.iter().zip(edges) {
                        let key = (pair.a, pair.b);
                        // Previous contacts whose pair is no longer a candidate.
                        while k < run.len() && (run[k].a, run[k].b) < key {
                            end_contact(&mut run[k], ended, changes);
                            k += 1;
                        }
                        let old = (k < run.len() && (run[k].a, run[k].b) == key).then(|| {
                            k += 1;
                            k - 1
                        });
                        // A continued contact where the index has it, unless
                        // the list was changed between steps.
                        if let Some(i) = old {
                            changes.moved |= keys.get(run_start + i) != Some(&key);
                        }
                        let Some((ov, offset)) = overlap_of_pair(pair, edge, scratch) else {
                            if let Some(i) = old {
                                end_contact(&mut run[i], ended, changes);
                            }
                            continue;
                        };
                        let (a, b) = (
                            body(pair.a as usize, Vec2::ZERO),
                            body(pair.b as usize, offset),
                        );
                        let (slot, record) = match old {
                            Some(i) => {
                                let record = &mut run[i];
                                record.age_steps += 1;
                                record.image_offset = offset;
                                (Slot::Run(i), record)
                            }
                            None => {
                                born.push(new_contact(pair, &ov, &a, &b, offset));
                                let i = born.len() - 1;
                                (Slot::Born(i), &mut born[i])
                            }
                        };
                        let (load, power) =
                            contact_before_friction(model, damping_ratio, &a, &b, &ov, record);
                        items[waiting] = BatchItem {
                            state: record.friction,
                            load,
                            outcome: NO_OUTCOME,
                        };
                        slots[waiting] = slot;
                        elastic_power[waiting] = power;
                        waiting += 1;
                        if waiting == FRICTION_BATCH {
                            flush(&mut items[..], &slots[..], &elastic_power[..], run, born);
                            waiting = 0;
                        }
                    }
                    if waiting > 0 {
                        let n = waiting;
                        flush(&mut items[..n], &slots[..n], &elastic_power[..n], run, born);
                    }
                    while k < run.len() {
                        end_contact(&mut run[k], ended, changes);
                        k += 1;
                    }
                },
            );
        // No record before the first chunk's run that has a dead one is
        // dead: the compaction starts there (most steps, none at all).
        let first_dead = self
            .chunk_changes
            .iter()
            .position(|changes| changes.ended)
            .map_or(self.contacts.len(), |c| self.chunk_start[c]);
        // The contact index of the force gathering still holds if no contact
        // ended, formed or moved (in most steady steps: 80 of 100 at 1e4
        // floes).
        let formed = self.born[..n_chunks].iter().any(|b| !b.is_empty());
        let changed = formed
            || self
                .chunk_changes
                .iter()
                .any(|changes| changes.ended || changes.moved);
        self.index_current &= !changed && self.keys.len() == self.contacts.len();
        let released = merge_in_place(&mut self.contacts, &mut self.born[..n_chunks], first_dead);
        let contacts = &self.contacts;
        if model.memory_s > 0.0 || !self.broken.is_empty() {
            let (now, memory) = (self.time_s, model.memory_s);
            let touching = |c: &BrokenContact| {
                contacts
                    .binary_search_by(|r| (r.a, r.b).cmp(&(c.a, c.b)))
                    .is_ok()
            };
            let newly_broken = self.ended.iter().flatten();
            let mut merged: Vec<BrokenContact> = self
                .broken
                .iter()
                .chain(newly_broken)
                .filter(|c| now - c.broke_at_s <= memory && !touching(c))
                .copied()
                .collect();
            // Both inputs are sorted; a stable sort keeps the newest entry last.
            merged.sort_by_key(|c| (c.a, c.b));
            merged.dedup_by(|later, earlier| {
                let same = (later.a, later.b) == (earlier.a, earlier.b);
                if same {
                    *earlier = *later;
                }
                same
            });
            self.broken = merged;
        }
        self.energy.released_at_break_j += released;
    }

    /// External forces and the contact forces, gathered per floe in contact
    /// order; before that, the per-floe contact index and, beside it, the
    /// contacts' powers in fixed blocks (summed into the ledger by
    /// [`World::kick_and_account_energy`]).
    fn gather_forces_and_contact_power(&mut self) {
        let n = self.floes.len();
        let (f, contacts) = (&self.floes, &self.contacts);
        let (keys, start, a_start, adjacency) = (
            &mut self.keys,
            &mut self.adjacency_start,
            &mut self.a_start,
            &mut self.adjacency,
        );
        let energy_partials = &mut self.energy_partials;
        // The contacts' powers, summed over fixed blocks of the contact
        // list in parallel and added in block order (in
        // `kick_and_account_energy`): the same sums for any thread count,
        // and, as they depend on the contact list alone, after a resume
        // from a checkpoint too. (Summed instead per chunk of candidate
        // pairs inside the contact update, they depended on the broad
        // phase's pair list, which a resume rebuilds differently, and a
        // resumed run drifted from the uninterrupted one by an ulp.) The
        // velocities they read are the walls', which the kick leaves alone.
        let power_sums = || {
            contacts
                .par_chunks(ENERGY_CHUNK)
                .map(|block| {
                    let mut power = ContactPower::default();
                    for c in block {
                        power.add(c, f);
                    }
                    power
                })
                .collect_into_vec(energy_partials);
        };
        let (forcing, t) = (&self.forcing, self.time_s);
        let (force, torque) = (&mut self.force, &mut self.torque);
        let (external_force, external_torque) =
            (&mut self.external_force, &mut self.external_torque);
        // External and contact forces per floe, from the per-floe index.
        let gather = |start: &[u32], adjacency: &[u32], a_start: &[u32]| {
            (force, torque, (external_force, external_torque))
                .into_par_iter()
                .enumerate()
                .for_each(|(i, (force, torque, (ext_f, ext_t)))| {
                    let (ef, et) = if f.is_free(i) {
                        forcing.force_and_torque(t, f, i)
                    } else {
                        (Vec2::ZERO, 0.0)
                    };
                    *ext_f = ef;
                    *ext_t = et;
                    let (mut fsum, mut tsum) = (ef, et);
                    let as_b = adjacency[start[i] as usize..start[i + 1] as usize]
                        .iter()
                        .map(|&k| &contacts[k as usize]);
                    let as_a = &contacts[a_start[i] as usize..a_start[i + 1] as usize];
                    // Each contact is visited from both its floes; each visit
                    // computes only its own floe's torque (the expressions of
                    // `force_and_torques`, so the same bits).
                    for c in as_b {
                        let fb = contact_force_on_b(c);
                        fsum += fb;
                        tsum += cross(c.point - (f.position[i] + c.image_offset), fb);
                    }
                    for c in as_a {
                        let fb = contact_force_on_b(c);
                        fsum -= fb;
                        tsum += cross(c.point - f.position[i], -fb);
                    }
                    *force = fsum;
                    *torque = tsum;
                });
        };
        // The power sums run beside whatever else reads the contacts: the
        // adjacency build, whose passes are sequential (about 0.15 ms of a
        // 5 ms two-thread step at 1e4 floes), where the contact list is not
        // the one the index was built for (`index_current`, kept by
        // `update_contacts`), else the gathering itself. At 1e3 floes the
        // power sums are one block on one thread (9 us) and the gathering
        // slower on two threads than on one (14 against 10 us): one after
        // the other, they were 8 % of a 0.3 ms two-thread step.
        let rebuild = !self.index_current || a_start.len() != n + 1;
        self.index_builds += u64::from(rebuild);
        if rebuild {
            rayon::join(
                || build_adjacency(contacts, n, keys, start, a_start, adjacency),
                power_sums,
            );
            gather(start, adjacency, a_start);
        } else {
            rayon::join(power_sums, || gather(start, adjacency, a_start));
        }
        self.index_current = true;
    }

    /// The second kick, and the work of forcing and walls and the
    /// dissipation over the step just taken.
    fn kick_and_account_energy(&mut self, dt: f64) {
        let Floes {
            velocity,
            angular_velocity,
            motion,
            mass_kg,
            inertia_kg_m2,
            owned,
            ..
        } = &mut self.floes;
        let owned = *owned;
        let (force, torque) = (&self.force, &self.torque);
        let (external_force, external_torque) = (&self.external_force, &self.external_torque);
        let (previous_force, previous_torque) = (
            &self.previous_external_force,
            &self.previous_external_torque,
        );
        // The kick, and in the same pass the power of the external forces:
        // trapezoidal in the force, with the velocity at the end of the step
        // and at the half step averaged through the kicks. Summed over fixed
        // blocks of floes and added in block order: the same sum for any
        // thread count (summed in one pass after the other, it was 1-2 % of
        // a step on two threads).
        (
            velocity[..owned].par_chunks_mut(ENERGY_CHUNK),
            angular_velocity[..owned].par_chunks_mut(ENERGY_CHUNK),
        )
            .into_par_iter()
            .enumerate()
            .map(|(block, (vs, omegas))| {
                let mut power_w = 0.0;
                for (k, (v, omega)) in vs.iter_mut().zip(omegas).enumerate() {
                    let i = block * ENERGY_CHUNK + k;
                    if let Motion::Free = motion[i] {
                        *v += force[i] / mass_kg[i] * (0.5 * dt);
                        *omega += torque[i] / inertia_kg_m2[i] * (0.5 * dt);
                        let mean_f = 0.5 * (previous_force[i] + external_force[i]);
                        let mean_t = 0.5 * (previous_torque[i] + external_torque[i]);
                        power_w += mean_f.dot(*v) + mean_t * *omega;
                    }
                }
                power_w
            })
            .collect_into_vec(&mut self.forcing_partials);
        for p in &self.forcing_partials {
            self.energy.forcing_work_j += dt * p;
        }
        let mut power = ContactPower::default();
        for p in &self.energy_partials {
            power.friction_w += p.friction_w;
            power.damping_w += p.damping_w;
            power.boundary_w += p.boundary_w;
        }
        self.energy.friction_dissipation_j += dt * power.friction_w;
        self.energy.damping_dissipation_j += dt * power.damping_w;
        self.energy.boundary_work_j += dt * power.boundary_w;
    }
}

/// Contacts (or floes) per block of the energy sums: the contacts' powers
/// and the forcing work of `kick_and_account_energy` are summed block by
/// block in parallel, then the blocks' sums in order. Fixed, so that the
/// sums do not depend on the thread count.
const ENERGY_CHUNK: usize = 4096;

/// Power of a set of contacts over a step.
#[derive(Debug, Default, Clone, Copy)]
struct ContactPower {
    /// Dissipated by friction, W.
    friction_w: f64,
    /// Dissipated by normal damping, W.
    damping_w: f64,
    /// Put in by walls (floes with prescribed motion), W.
    boundary_w: f64,
}

impl ContactPower {
    /// Adds a contact whose step is complete.
    #[inline]
    fn add(&mut self, c: &ContactRecord, f: &Floes) {
        self.friction_w += c.friction_power_w;
        self.damping_w += c.damping_power_w;
        // Work done by a wall on the floe it touches: the force the wall
        // exerts (the opposite of the force on it) times its velocity.
        // Only wall contacts need the force.
        let (a, b) = (c.a as usize, c.b as usize);
        if f.is_free(a) && f.is_free(b) {
            return;
        }
        let (fb, _, _) = force_and_torques(c, f.position[a], f.position[b] + c.image_offset);
        if !f.is_free(a) {
            self.boundary_w += fb.dot(f.velocity[a]);
        }
        if !f.is_free(b) {
            self.boundary_w += (-fb).dot(f.velocity[b]);
        }
    }
}

/// Marks a contact record that ended this step, until the list is compacted
/// (floe handles are below `u32::MAX`: checkpoints and floe sets check it).
const DEAD: u32 = u32::MAX;

/// What a task of the contact update works in, made once per rayon task
/// rather than per chunk of pairs: zeroing the friction batch's arrays for
/// every chunk was a `memset` of 5 KB apiece, 1.2 % of a step's
/// instructions with the small chunks of small runs. Only a workspace: every
/// entry is written before it is read, so results do not depend on which
/// chunks share one.
struct TaskWorkspace {
    /// The clipper's buffers.
    clip: ClipScratch,
    /// Where the records of the friction steps waiting ([`FRICTION_BATCH`]
    /// at a time) are: in place in the run, or among the born.
    slots: [Slot; FRICTION_BATCH],
    /// The power of the waiting contacts' elastic normal force, W.
    elastic_power: [f64; FRICTION_BATCH],
    /// The waiting friction steps' items, side by side for
    /// `Law::step_batch`.
    items: [BatchItem; FRICTION_BATCH],
}

impl Default for TaskWorkspace {
    fn default() -> Self {
        Self {
            clip: ClipScratch::default(),
            slots: [Slot::Run(0); FRICTION_BATCH],
            elastic_power: [0.0; FRICTION_BATCH],
            items: [NO_ITEM; FRICTION_BATCH],
        }
    }
}

/// What a chunk of the contact update changed in its run of the contact
/// list.
#[derive(Debug, Clone, Copy, Default)]
struct ChunkChanges {
    /// It ended one of its previous contacts.
    ended: bool,
    /// A contact it continued is not where the force gathering's index has
    /// it: the list was changed between steps, through `World::contacts`
    /// (or, on the first step after `World::new` or `World::resume`, no
    /// index has been built yet).
    moved: bool,
}

/// Where a contact's record is while its friction step waits.
#[derive(Debug, Clone, Copy)]
enum Slot {
    /// Updated in place, at this index of the chunk's run of previous contacts.
    Run(usize),
    /// New this step, at this index of the chunk's born list.
    Born(usize),
}

/// The per-floe contact index of the force gathering, in contact order.
/// The list is sorted by (a, b) with a < b, so a floe's contacts as `a`
/// are one block of it (from `a_start`), and come after all its contacts
/// as `b` (whose `a` is smaller). So only the contacts as `b` need a list
/// of their own: `adjacency[start[i]..start[i + 1]]` (CSR). At 1e5 floes
/// building a list of both sides took 4.4-5.9 ms of a step, with the
/// sides' random increments and writes (docs/performance.md).
///
/// The keys are first copied out of the 168 B records in parallel: the
/// sequential passes then stream 8 B per contact instead of a cache line or
/// two per record (at 1e5 floes, 3.7-4.9 ms of sequential reading before).
fn build_adjacency(
    contacts: &[ContactRecord],
    n: usize,
    keys: &mut Vec<(u32, u32)>,
    start: &mut Vec<u32>,
    a_start: &mut Vec<u32>,
    adjacency: &mut Vec<u32>,
) {
    contacts
        .par_iter()
        .map(|c| (c.a, c.b))
        .collect_into_vec(keys);
    start.clear();
    start.resize(n + 1, 0);
    a_start.clear();
    a_start.reserve(n + 1);
    for (k, &(a, b)) in keys.iter().enumerate() {
        debug_assert!(a < b);
        while a_start.len() <= a as usize {
            a_start.push(k as u32);
        }
        start[b as usize] += 1;
    }
    a_start.resize(n + 1, keys.len() as u32);
    // Each floe's end, then filled back to front: every entry moves down
    // to its floe's start, and each floe's list is in contact order.
    for i in 1..=n {
        start[i] += start[i - 1];
    }
    adjacency.resize(keys.len(), 0);
    for (k, &(_, b)) in keys.iter().enumerate().rev() {
        let end = &mut start[b as usize];
        *end -= 1;
        adjacency[*end as usize] = k as u32;
    }
}

/// Removes the dead records of `contacts` and merges in the new contacts of
/// every chunk (each sorted, the chunks in order), keeping the list sorted
/// by `(a, b)`. In place: the dead are squeezed out front to back, then the
/// list grows by the number born and is merged back to front, so that no
/// second list is needed. Sequential, one or two moves per record after the
/// first change; it replaced a parallel copy of every record per step.
///
/// No record before index `first_dead` may be dead: the compaction starts
/// there. The contact update knows which chunks ended a contact, and in
/// most steps none did: scanning every record for the dead was most of the
/// merge's time (0.125 ms of a 8.9 ms step at 1e4 floes, one thread).
///
/// Returns the elastic energy the dead records held, J, summed in list
/// order: the sum depends on the contact list alone, not on how the
/// candidate pairs were cut into tasks (which a resumed run, rebuilding its
/// pair list at another step, does differently).
fn merge_in_place(
    contacts: &mut Vec<ContactRecord>,
    born: &mut [Vec<ContactRecord>],
    first_dead: usize,
) -> f64 {
    let first_dead = first_dead.min(contacts.len());
    let mut live = first_dead;
    let mut released_j = 0.0;
    for r in first_dead..contacts.len() {
        if contacts[r].a != DEAD {
            if live != r {
                contacts[live] = contacts[r];
            }
            live += 1;
        } else {
            released_j += contacts[r].elastic_energy_j();
        }
    }
    contacts.truncate(live);
    let total_born: usize = born.iter().map(Vec::len).sum();
    if total_born == 0 {
        return released_j;
    }
    if live == 0 {
        // The first step, or a pack that had come apart: copy the chunks in
        // order and free each as it is copied, so that the list and the
        // born lists are not both resident in full.
        contacts.reserve_exact(total_born);
        for b in born.iter_mut() {
            contacts.extend_from_slice(b);
            release_if_large(b);
        }
        return released_j;
    }
    let Some(&fill) = born.iter().find_map(|b| b.first()) else {
        return released_j;
    };
    contacts.resize(live + total_born, fill);
    let key = |c: &ContactRecord| (c.a, c.b);
    let (mut old, mut write) = (live, live + total_born);
    for chunk in born.iter().rev() {
        for record in chunk.iter().rev() {
            while old > 0 && key(&contacts[old - 1]) > key(record) {
                write -= 1;
                old -= 1;
                contacts[write] = contacts[old];
            }
            write -= 1;
            contacts[write] = *record;
        }
    }
    debug_assert_eq!(write, old);
    born.iter_mut().for_each(release_if_large);
    released_j
}

/// Frees a born list that grew beyond what a step usually creates (a few
/// contacts per chunk), so that a burst of new contacts does not stay
/// resident for the rest of the run.
fn release_if_large(born: &mut Vec<ContactRecord>) {
    if born.capacity() > 64 {
        *born = Vec::new();
    }
}

/// The largest stable time step and the floe that sets it: `0.3 x 2/omega`
/// with `omega^2 = k / m_eff` for the stiffest contact the floe can have
/// with a like neighbour: contact length a diameter, `k = kappa 2 r`,
/// `m_eff = min(m/2, I / r^2)` (translation or rotation at the rim).
pub fn stable_time_step(floes: &Floes, model: &ContactModel) -> (f64, usize) {
    let mut best = (f64::INFINITY, 0);
    for i in 0..floes.len() {
        if !floes.is_free(i) {
            continue;
        }
        let body = Body {
            position: Vec2::ZERO,
            velocity: Vec2::ZERO,
            angular_velocity: 0.0,
            mass_kg: floes.mass_kg[i],
            thickness_m: floes.thickness_m[i],
            area_m2: floes.area_m2[i],
            free: true,
        };
        let k = overlap_stiffness(model, &body, &body) * 2.0 * floes.radius_m[i];
        let r = floes.radius_m[i];
        let m_eff = (0.5 * floes.mass_kg[i]).min(floes.inertia_kg_m2[i] / (r * r));
        let limit = STABILITY_SAFETY * 2.0 * (m_eff / k).sqrt();
        if limit < best.0 {
            best = (limit, i);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn record(a: u32, b: u32, tag: f64) -> ContactRecord {
        ContactRecord {
            a,
            b,
            image_offset: Vec2::ZERO,
            friction: ContactState::default(),
            age_steps: 0,
            overlap_m2: tag,
            point: Vec2::ZERO,
            normal: Vec2::X,
            length_m: 0.0,
            normal_force_n: 0.0,
            slip_rate_m_per_s: 0.0,
            friction_power_w: 0.0,
            damping_power_w: 0.0,
            elastic_force_n: 0.0,
            // Energies with round-off in their sums, so that the order of
            // the released-energy sum shows.
            normal_energy_j: tag / 3.0,
            tangential_energy_j: tag.sqrt(),
        }
    }

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
        let model = ContactModel::default();
        let dt = 0.5 * stable_time_step(&floes, &model).0;
        World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap()
    }

    #[test]
    fn results_do_not_depend_on_how_the_candidate_pairs_are_cut_into_tasks() {
        let mut runs: Vec<World<NoForcing>> = [None, Some(7), Some(64)]
            .into_iter()
            .map(|cut| {
                let mut w = released_pack();
                w.fixed_pair_chunk = cut;
                w
            })
            .collect();
        let initial = runs[0].contacts.len();
        let mut most_broken_in_a_step = 0;
        for _ in 0..400 {
            let before = runs[0].contacts.len();
            for w in &mut runs {
                w.step();
            }
            most_broken_in_a_step =
                most_broken_in_a_step.max(before.saturating_sub(runs[0].contacts.len()));
        }
        // The scenario does what it is for: contacts break, many at once.
        assert!(initial > 200, "{initial} initial contacts");
        assert!(
            runs[0].contacts.len() < initial / 2,
            "{} contacts left",
            runs[0].contacts.len()
        );
        assert!(most_broken_in_a_step >= 10, "{most_broken_in_a_step}");
        assert!(runs[0].energy.released_at_break_j != 0.0);
        for w in &runs[1..] {
            assert_eq!(w.energy, runs[0].energy);
            assert_eq!(w.floes.position, runs[0].floes.position);
            assert_eq!(w.floes.velocity, runs[0].floes.velocity);
            assert_eq!(w.contacts, runs[0].contacts);
        }
    }

    /// The force gathering's contact index, kept across steps where the
    /// contact list did not change, gives bitwise the results of building
    /// it at every step, in a pack where contacts break and form.
    #[test]
    fn keeping_the_contact_index_gives_the_results_of_rebuilding_it() {
        let (mut kept, mut rebuilt) = (released_pack(), released_pack());
        let builds = kept.index_builds;
        for _ in 0..400 {
            kept.step();
            rebuilt.index_current = false;
            rebuilt.step();
        }
        let built = kept.index_builds - builds;
        assert!(built < 200, "the index was built in {built} of 400 steps");
        assert_eq!(kept.energy, rebuilt.energy);
        assert_eq!(kept.floes.position, rebuilt.floes.position);
        assert_eq!(kept.floes.velocity, rebuilt.floes.velocity);
        assert_eq!(kept.contacts, rebuilt.contacts);
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
        let (model, periodicity, dt) = (checked.model, checked.periodicity, checked.dt_s);
        for _ in 0..400 {
            let mut ahead =
                World::resume(checked.state(), model, NoForcing, periodicity, dt).unwrap();
            ahead.step();
            let Some(edited) = edit(&checked.contacts, &ahead.contacts) else {
                checked.step();
                rebuilt.step();
                continue;
            };
            checked.contacts.clone_from(&edited);
            rebuilt.contacts = edited;
            let builds = checked.index_builds;
            checked.step();
            rebuilt.index_current = false;
            rebuilt.step();
            assert!(checked.born.iter().all(Vec::is_empty));
            assert_eq!(checked.index_builds, builds + 1);
            assert_eq!(checked.floes.velocity, rebuilt.floes.velocity);
            assert_eq!(checked.contacts, rebuilt.contacts);
            return checked;
        }
        panic!("no step allowed the edit");
    }

    fn key(c: &ContactRecord) -> (u32, u32) {
        (c.a, c.b)
    }

    /// A contact list edited between steps (through the public field) so
    /// that the step neither ends nor forms a contact, yet the list is not
    /// the one the index was built for: the index is rebuilt. The edit
    /// swaps the contacts that end in the next step for those that form in
    /// it; without the check of the continued contacts' places, the step
    /// would gather forces through a stale index.
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
        assert!(
            checked.chunk_changes.iter().any(|c| c.moved),
            "the edit was seen as moved contacts"
        );
        assert!(checked.chunk_changes.iter().all(|c| !c.ended));
    }

    /// A contact list shortened between steps by the contacts at its end
    /// that the next step would end anyway: the step ends, forms and moves
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
        assert!(checked.chunk_changes.iter().all(|c| !c.ended && !c.moved));
    }

    proptest! {
        /// The in-place compaction and merge against the obvious way: keep the
        /// live records, add the born ones, sort.
        #[test]
        fn merging_in_place_equals_filtering_and_sorting(
            keys in prop::collection::btree_set((0u32..60, 0u32..60), 0..200),
            fate in prop::collection::vec(0u8..3, 200),
            chunks in 1usize..6,
            start_at in 0usize..200,
        ) {
            // Each key is a surviving old contact, a dead one, or born this step.
            let keys: Vec<(u32, u32)> = keys.into_iter().collect();
            let mut contacts = Vec::new();
            let mut born_all = Vec::new();
            for (i, &(a, b)) in keys.iter().enumerate() {
                match fate[i] {
                    0 => contacts.push(record(a, b, i as f64)),
                    1 => contacts.push(record(DEAD, b, i as f64)),
                    _ => born_all.push(record(a, b, i as f64)),
                }
            }
            let dead_energy = contacts
                .iter()
                .filter(|c| c.a == DEAD)
                .fold(0.0, |sum, c| sum + c.elastic_energy_j());
            let mut expected: Vec<ContactRecord> = contacts
                .iter()
                .filter(|c| c.a != DEAD)
                .chain(&born_all)
                .copied()
                .collect();
            expected.sort_by_key(|c| (c.a, c.b));
            // Born contacts split into consecutive chunks, as the narrow phase makes them.
            let per = born_all.len().div_ceil(chunks).max(1);
            let mut born: Vec<Vec<ContactRecord>> = born_all.chunks(per).map(<[_]>::to_vec).collect();
            // From the first dead record, as the world passes it, or from
            // anywhere before it: the same result.
            let first_dead = contacts.iter().position(|c| c.a == DEAD).unwrap_or(contacts.len());
            let mut from_start = contacts.clone();
            let mut born_again = born.clone();
            let released = merge_in_place(&mut contacts, &mut born, first_dead);
            let released_from_start = merge_in_place(&mut from_start, &mut born_again, start_at.min(first_dead));
            prop_assert_eq!(&from_start, &contacts);
            prop_assert_eq!(released_from_start.to_bits(), released.to_bits());
            prop_assert_eq!(contacts, expected);
            // What the dead held, summed in list order.
            prop_assert_eq!(released.to_bits(), dead_energy.to_bits());
        }
    }
}
