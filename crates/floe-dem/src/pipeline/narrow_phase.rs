//! Narrow phase: which candidate pairs touch, and the persistence of their
//! contacts. A pair that touched at the end of the last step continues its
//! contact record (tangential spring, friction state, stored energy); a new
//! pair starts one (resuming a recently broken contact's `theta` from the
//! contact memory); a contact whose floes no longer overlap ends. For every
//! touching pair the overlap and the normal force are computed here
//! ([`contact_before_friction`]), then the friction stage steps its
//! tangential spring ([`super::friction`]).
//!
//! The candidate pairs are cut into fixed chunks, processed in parallel;
//! the contact list is updated in place, and the result does not depend on
//! the cut (tested).

use rayon::prelude::*;

use super::broad_phase::{BroadPhase, CandidatePair};
use super::contact_memory::{recall, remember_broken};
use super::contact_merge::{merge_in_place, DEAD};
use super::energy_accounting::ContactPower;
use super::friction::{new_contact_state, FrictionBatch, Slot};
use super::oriented_vertices::orient_vertices;
use crate::contact_kernel::{contact_before_friction, Body};
use crate::contact_model::ContactModel;
use crate::contacts::{BrokenContact, ContactRecord};
use crate::exact_sum::ExactSum;
use crate::floes::FloeColumns;
use crate::geometry::{overlap_cached, ClipScratch, Oriented, Overlap, SeparatingEdge};
use crate::periodicity::Periodicity;
use crate::Vec2;
use floe_friction::FrictionLaw;

/// Most candidate pairs per parallel task.
const PAIR_CHUNK: usize = 1024;

/// Fewest candidate pairs per task (but the last, or a run with fewer
/// pairs in all).
const MIN_PAIR_CHUNK: usize = 128;

/// Tasks wanted: small runs are cut into this many, not into a few of
/// [`PAIR_CHUNK`] pairs (at 1e3 floes, six), so that two threads share
/// them evenly. Results do not depend on the cut (tested), only the
/// balance does.
const PAIR_TASKS: usize = 32;

/// Candidate pairs per task for a list of `n_pairs`.
fn pair_chunk(n_pairs: usize) -> usize {
    (n_pairs / PAIR_TASKS).clamp(MIN_PAIR_CHUNK, PAIR_CHUNK)
}

/// What the contact detection reads: the floes as the drift left them.
pub(crate) struct DetectionInput<'a> {
    /// The floes.
    pub(crate) floes: &'a FloeColumns,
    /// Each floe's `(sin, cos)` of its angle.
    pub(crate) trig: &'a [(f64, f64)],
    /// The contact model and friction law.
    pub(crate) model: &'a ContactModel,
    /// The domain's periodic axes.
    pub(crate) periodicity: Periodicity,
    /// The normal dashpot's damping ratio (`ContactModel::damping_ratio`,
    /// computed once per world).
    pub(crate) damping_ratio: f64,
    /// The step (0: detection without a friction step, at the start).
    pub(crate) dt: f64,
    /// Simulated time at the end of the step, s.
    pub(crate) time_s: f64,
    /// Per floe, whether it is a ghost (another process's floe): its
    /// contacts' released energy is counted there. Empty: none is.
    pub(crate) ghost: &'a [bool],
}

/// What the contact detection updates: the contacts and their memory, and
/// the energy held by contacts that ended.
pub(crate) struct ContactSet<'a> {
    /// Contacts, sorted by `(a, b)`.
    pub(crate) contacts: &'a mut Vec<ContactRecord>,
    /// Recently broken contacts, sorted by `(a, b)`.
    pub(crate) broken: &'a mut Vec<BrokenContact>,
    /// The step's energy released at break, J (an exact sum, booked into
    /// the ledger at the end of the step).
    pub(crate) released_at_break_j: &'a mut ExactSum,
    /// Per chunk of candidate pairs, the powers of its contacts over the
    /// step (exact sums: the cut does not change their total).
    pub(crate) power: &'a mut Vec<ContactPower>,
}

/// The narrow phase's buffers, reused every step.
#[derive(Default)]
pub(crate) struct NarrowPhase {
    /// Per chunk of candidate pairs, where its run of previous contacts starts.
    chunk_start: Vec<usize>,
    /// Per candidate pair, an edge that separated the two floes when last
    /// clipped (reset whenever the broad phase rebuilds the pair list). Only
    /// a shortcut: results do not depend on it, so it is not checkpointed.
    separating: Vec<SeparatingEdge>,
    /// Every floe's vertices turned to its orientation, this step (laid
    /// out as `FloeColumns::vertices`).
    oriented: Vec<Vec2>,
    /// Per chunk, the contacts that formed this step (few: most contacts
    /// continue in place).
    pub(crate) born: Vec<Vec<ContactRecord>>,
    /// Per chunk, the contacts that ended, for contact memory (empty without it).
    ended: Vec<Vec<BrokenContact>>,
    /// Per chunk, whether it ended one of its previous contacts.
    pub(crate) chunk_ended: Vec<bool>,
    /// Candidate pairs per task if set, instead of [`pair_chunk`] (tests
    /// that results do not depend on it).
    pub(crate) fixed_pair_chunk: Option<usize>,
}

/// What a task works in, made once per rayon task rather than per chunk of
/// pairs (zeroing the batch's arrays per chunk was 1.2 % of a step).
#[derive(Default)]
struct TaskWorkspace {
    /// The clipper's buffers.
    clip: ClipScratch,
    /// The contacts waiting for their friction step.
    friction: FrictionBatch,
}

impl NarrowPhase {
    /// Updates the contact list for the floes of `input`: rebuilds the
    /// candidate list first if `moved_far` (a floe moved beyond the broad
    /// phase's allowance since it was built). Returns whether a contact
    /// formed or ended (the force gathering's index is then stale).
    pub(crate) fn update_contacts(
        &mut self,
        broad_phase: &mut BroadPhase,
        moved_far: bool,
        input: &DetectionInput<'_>,
        set: ContactSet<'_>,
    ) -> bool {
        let f = input.floes;
        if moved_far {
            broad_phase.rebuild(f, input.trig, input.periodicity);
        }
        if moved_far || self.separating.len() != broad_phase.pairs.len() {
            self.separating.clear();
            self.separating
                .resize(broad_phase.pairs.len(), SeparatingEdge::NONE);
        }
        // The contact list is updated in place: a step holds one list, not
        // the previous one, per-task outputs and a new one (the 1 KB per
        // floe budget at 1e6 floes). Pairs and contacts are both sorted by
        // (a, b), so each fixed chunk of pairs owns the contiguous run of
        // previous contacts from its first pair up to the next chunk's (the
        // first chunk from the start, the last to the end): every previous
        // contact belongs to exactly one chunk.
        let pairs = &broad_phase.pairs;
        let chunk = self
            .fixed_pair_chunk
            .unwrap_or_else(|| pair_chunk(pairs.len()));
        debug_assert!(chunk > 0);
        let n_chunks = pairs.len().div_ceil(chunk);
        self.find_runs(pairs, chunk, n_chunks, set.contacts);
        let model = input.model;
        let dt = input.dt;
        let damping_ratio = input.damping_ratio;
        let periodicity = input.periodicity;
        orient_vertices(f, input.trig, &mut self.oriented);
        let oriented = &self.oriented;
        let broken = &*set.broken;
        let body = |i: usize, offset: Vec2| Body::of(f, i, offset);
        let placed = |i: usize, offset: Vec2| Oriented {
            vertices: &oriented[f.vertex_start[i] as usize..f.vertex_start[i + 1] as usize],
            position: f.position[i] + offset,
            radius_m: f.radius_m[i],
        };
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
            let mut fresh = ContactRecord::new_contact(
                model,
                new_contact_state(model),
                ov,
                a,
                b,
                (pair.a, pair.b),
                offset,
            );
            if let Some(old) = recall(broken, pair.a, pair.b) {
                fresh.friction = model.law.reformed(&old.friction, fresh.friction);
            }
            fresh
        };
        let remember = model.memory_s > 0.0;
        let time_s = input.time_s;
        // A contact that did not survive the step is remembered if the model
        // asks for memory, and is marked dead until the list is compacted
        // below (which sums what the dead released).
        let end_contact =
            |old: &mut ContactRecord, ended: &mut Vec<BrokenContact>, chunk_ended: &mut bool| {
                *chunk_ended = true;
                if remember {
                    ended.push(BrokenContact {
                        a: old.a,
                        b: old.b,
                        friction: old.friction,
                        broke_at_s: time_s,
                    });
                }
                old.b = DEAD;
            };
        // Each chunk's runs of previous contacts, as disjoint mutable slices.
        let mut runs: Vec<&mut [ContactRecord]> = Vec::with_capacity(n_chunks.max(1));
        {
            let mut rest = set.contacts.as_mut_slice();
            for w in self.chunk_start.windows(2) {
                let (head, tail) = rest.split_at_mut(w[1] - w[0]);
                runs.push(head);
                rest = tail;
            }
        }
        if n_chunks == 0 {
            // No candidate pairs: every previous contact ends.
            let mut ended = Vec::new();
            self.chunk_ended.clear();
            self.chunk_ended.push(false);
            for old in runs.pop().into_iter().flatten() {
                end_contact(old, &mut ended, &mut self.chunk_ended[0]);
            }
            self.ended.clear();
            self.ended.push(ended);
        } else {
            self.ended.resize_with(n_chunks, Vec::new);
            self.chunk_ended.resize(n_chunks, false);
        }
        self.born.resize_with(n_chunks, Vec::new);
        set.power.resize_with(n_chunks, ContactPower::default);
        let ghost = input.ghost;
        runs.into_par_iter()
            .zip(pairs.par_chunks(chunk))
            .zip(self.separating.par_chunks_mut(chunk))
            .zip(self.born.par_iter_mut())
            .zip(self.ended.par_iter_mut())
            .zip(self.chunk_ended.par_iter_mut())
            .zip(set.power.par_iter_mut())
            .for_each_init(
                TaskWorkspace::default,
                |workspace, ((((((run, pairs), edges), born), ended), chunk_ended), power)| {
                    born.clear();
                    ended.clear();
                    *chunk_ended = false;
                    *power = ContactPower::default();
                    let mut count_power = |c: &ContactRecord| power.add(c, f, ghost);
                    let TaskWorkspace {
                        clip: scratch,
                        friction,
                    } = workspace;
                    let mut k = 0;
                    for (pair, edge) in pairs.iter().zip(edges) {
                        let key = (pair.a, pair.b);
                        // Previous contacts whose pair is no longer a candidate.
                        while k < run.len() && (run[k].a, run[k].b) < key {
                            end_contact(&mut run[k], ended, chunk_ended);
                            k += 1;
                        }
                        let old = (k < run.len() && (run[k].a, run[k].b) == key).then(|| {
                            k += 1;
                            k - 1
                        });
                        let Some((ov, offset)) = overlap_of_pair(pair, edge, scratch) else {
                            if let Some(i) = old {
                                end_contact(&mut run[i], ended, chunk_ended);
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
                        let (load, elastic_power) =
                            contact_before_friction(model, damping_ratio, &a, &b, &ov, record);
                        if friction.add(slot, record.friction, load, elastic_power) {
                            friction.flush(model, dt, (run, born), &mut count_power);
                        }
                    }
                    if !friction.is_empty() {
                        friction.flush(model, dt, (run, born), &mut count_power);
                    }
                    while k < run.len() {
                        end_contact(&mut run[k], ended, chunk_ended);
                        k += 1;
                    }
                },
            );
        // No record before the first chunk's run that has a dead one is
        // dead: the compaction starts there (most steps, none at all).
        let first_dead = self
            .chunk_ended
            .iter()
            .position(|&ended| ended)
            .map_or(set.contacts.len(), |c| self.chunk_start[c]);
        let formed = self.born[..n_chunks].iter().any(|b| !b.is_empty());
        let changed = formed || self.chunk_ended.iter().any(|&ended| ended);
        merge_in_place(
            set.contacts,
            &mut self.born[..n_chunks],
            first_dead,
            set.released_at_break_j,
            input.ghost,
        );
        if model.memory_s > 0.0 || !set.broken.is_empty() {
            *set.broken = remember_broken(
                set.broken,
                self.ended.iter().flatten(),
                set.contacts,
                input.time_s,
                model.memory_s,
            );
        }
        changed
    }

    /// Where each chunk of pairs' run of previous contacts starts, and the
    /// list's length at the end. One binary search per chunk, in parallel
    /// for long lists: each probes records spread over the whole list, a
    /// cache miss apiece (about 1 ms per step at 1e5 floes one after the
    /// other). A short list is searched in turn: a parallel region costs
    /// more there than its few dozen searches in cache.
    fn find_runs(
        &mut self,
        pairs: &[CandidatePair],
        chunk: usize,
        n_chunks: usize,
        previous: &[ContactRecord],
    ) {
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

    /// The candidate list changed under the narrow phase (floes added or
    /// removed): forget the separating edges cached per pair.
    pub(crate) fn invalidate(&mut self) {
        self.separating.clear();
    }

    /// The floes marked in `reshaped` changed shape (ridging): forget the
    /// separating edges cached for their pairs of `pairs` (the candidate
    /// list the cache follows), which name their old edges.
    pub(crate) fn forget_shapes(&mut self, pairs: &[CandidatePair], reshaped: &[bool]) {
        if self.separating.len() != pairs.len() {
            return;
        }
        for (edge, p) in self.separating.iter_mut().zip(pairs) {
            if reshaped[p.a as usize] || reshaped[p.b as usize] {
                *edge = SeparatingEdge::NONE;
            }
        }
    }
}
