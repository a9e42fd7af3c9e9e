//! Fracture over processes, bitwise as in one: each process judges the
//! floes it owns (with the pack's sums added over all), every process
//! learns every split with its pieces, numbered in parent id order from
//! the whole run's next id, and makes those of the floes it holds (its own
//! and its ghosts) in that order; process 0's record of the floes' shapes
//! learns the pieces, and a migration spreads them.

use super::*;
use floe_dem::exact_sum::{ExactSum, EXACT_SUM_WORDS};
use floe_dem::floes::Floe;
use floe_dem::fracture::rule::FractureRule;
use floe_dem::world::{FractureEvent, PackSums, PlannedSplit};

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// Fracture after every step (`try_step`), as
    /// [`World::set_fracturing`]: `Some` checks the rule and turns floe
    /// stress on (default average) if off, on every process.
    pub fn set_fracturing(&mut self, fracturing: Option<Fracturing>) -> Result<(), ParallelError> {
        self.local_mut().set_fracturing(fracturing)?;
        self.fracturing = fracturing;
        Ok(())
    }

    /// [`World::fracture`] over every process: the same pieces, ids and
    /// events as one process would make. Every process returns every
    /// event, in parent id order. Call between steps, on every process.
    pub fn fracture(
        &mut self,
        rule: &FractureRule,
        domain_area_m2: f64,
    ) -> Result<Vec<FractureEvent>, ParallelError> {
        if !rule.due(self.local().steps()) {
            return Ok(Vec::new());
        }
        let sums = self.whole_pack_sums();
        let world = self.local();
        let plans = world.plan_fracture(rule, &sums, domain_area_m2)?;
        let first = self
            .comm
            .all_gather(world.first_free_id().to_le_bytes().to_vec())
            .iter()
            .map(|b| u64::from_le_bytes(b[..8].try_into().expect("8 bytes")))
            .max()
            .unwrap_or(0);
        // Every process's splits (its own floes'), with their pieces, by
        // parent id: each is made by every process that holds the parent,
        // owner or ghost, in that order, so that contacts between pieces
        // of two parents go on as in one process.
        let mut all: Vec<PlannedSplit> = Vec::new();
        for bytes in self.comm.all_gather(encode(&plans)) {
            all.extend(decode::<Vec<PlannedSplit>>(&bytes)?);
        }
        all.sort_by_key(|p| p.event.parent_id);
        let mut owned_ids = self.owned_ids();
        let mut next = first;
        let mut events = Vec::with_capacity(all.len());
        let mut pieces: Vec<Floe> = Vec::new();
        for plan in all {
            let parent = plan.event.parent_id;
            let made = plan.pieces.len() as u64;
            let world = self.local_mut();
            if world.floes().handle_of(parent).is_some() {
                let event = world
                    .apply_fracture(vec![plan], next)?
                    .pop()
                    .expect("one plan, one event");
                if let Ok(k) = owned_ids.binary_search(&parent) {
                    owned_ids.remove(k);
                    owned_ids.extend(&event.piece_ids);
                    owned_ids.sort_unstable();
                    let f = world.floes();
                    pieces.extend(
                        event
                            .piece_ids
                            .iter()
                            .map(|&id| f.get(f.handle_of(id).expect("just made"))),
                    );
                }
                events.push(event);
            } else {
                let mut event = plan.event;
                event.piece_ids = (next..next + made).collect();
                events.push(event);
            }
            next += made;
        }
        self.local_mut().set_next_floe_id(next);
        self.own_ids(&owned_ids);
        // Process 0 keeps every floe's shape for the gathered whole.
        let shared = self.comm.all_gather(encode(&pieces));
        if let Some(whole) = self.whole_floes.as_mut() {
            for e in events.iter().filter(|e| !e.piece_ids.is_empty()) {
                if let Some(h) = whole.handle_of(e.parent_id) {
                    whole.remove(h);
                }
            }
            for bytes in shared {
                for p in decode::<Vec<Floe>>(&bytes)? {
                    whole.insert(p)?;
                }
            }
        }
        events.sort_by_key(|e| e.parent_id);
        // Memory kept aside for a pair with a split floe goes with it.
        let split: Vec<u64> = events
            .iter()
            .filter(|e| !e.piece_ids.is_empty())
            .map(|e| e.parent_id)
            .collect();
        self.forget_parked(&split);
        if !split.is_empty() {
            // The pieces' ghosts, and who sends whom their motion.
            self.migrate()?;
        }
        Ok(events)
    }

    /// The pack's sums over every process's own free floes.
    fn whole_pack_sums(&self) -> PackSums {
        let local = self.local().pack_sums();
        let mut words: Vec<i64> = local
            .thickness_area
            .to_words()
            .into_iter()
            .chain(local.area.to_words())
            .collect();
        self.comm.sum_i64(&mut words);
        let half = |k: usize| -> [i64; EXACT_SUM_WORDS] {
            words[k * EXACT_SUM_WORDS..(k + 1) * EXACT_SUM_WORDS]
                .try_into()
                .expect("two sums")
        };
        PackSums {
            thickness_area: ExactSum::from_words(&half(0)),
            area: ExactSum::from_words(&half(1)),
        }
    }
}
