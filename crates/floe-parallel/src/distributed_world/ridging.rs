//! Ridging over processes, bitwise as in one: each process plans the cuts
//! of the floes it owns, every process learns every cut (by loser id) and
//! makes those of the floes it holds, owner or ghost; the processes' tallies
//! add exactly into every process's ledger; process 0's record of the
//! floes' shapes and masses learns the changed floes, and a migration
//! restores the ghosts.

use super::*;
use floe_dem::exact_sum::{ExactSum, EXACT_SUM_WORDS};
use floe_dem::floes::Floe;
use floe_dem::world::{PlannedRidge, RidgingTally};

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// Ridging after every step (`try_step`), as [`World::set_ridging`],
    /// on every process.
    pub fn set_ridging(&mut self, ridging: Option<Ridging>) -> Result<(), ParallelError> {
        self.local_mut().set_ridging(ridging)?;
        self.ridging = ridging;
        Ok(())
    }

    /// [`World::ridge`] over every process: the same cuts, gains and
    /// ledger as one process would make. Every process returns every
    /// event, by loser id. Call between steps, on every process.
    pub fn ridge(&mut self) -> Result<Vec<PlannedRidge>, ParallelError> {
        let Some(ridging) = self.ridging else {
            return Ok(Vec::new());
        };
        let plans = self.local().plan_ridging(&ridging)?;
        let mut all: Vec<PlannedRidge> = Vec::new();
        for bytes in self.comm.all_gather(encode(&plans)) {
            all.extend(decode::<Vec<PlannedRidge>>(&bytes)?);
        }
        if all.is_empty() {
            return Ok(all);
        }
        all.sort_by_key(|p| p.loser_id);
        let tally = self.local_mut().apply_ridging(&all)?;
        let mut words = vec![tally.events as i64];
        for s in &tally.sums {
            words.extend(s.to_words());
        }
        self.comm.sum_i64(&mut words);
        let mut total = RidgingTally {
            events: words[0] as u64,
            ..RidgingTally::default()
        };
        for (k, s) in total.sums.iter_mut().enumerate() {
            let at = 1 + k * EXACT_SUM_WORDS;
            *s = ExactSum::from_words(&words[at..at + EXACT_SUM_WORDS].try_into().expect("words"));
        }
        self.local_mut().book_ridging(&total);
        // Process 0 keeps every floe's shape and mass for the gathered whole.
        let mut changed: Vec<u64> = all
            .iter()
            .flat_map(|p| [Some(p.loser_id), p.gainer_free.then_some(p.gainer_id)])
            .flatten()
            .collect();
        changed.sort_unstable();
        changed.dedup();
        let f = self.local().floes();
        let mine: Vec<Floe> = changed
            .iter()
            .filter_map(|&id| f.handle_of(id))
            .filter(|&h| self.owned[h])
            .map(|h| f.get(h))
            .collect();
        let shared = self.comm.all_gather(encode(&mine));
        if let Some(whole) = self.whole_floes.as_mut() {
            for bytes in shared {
                for floe in decode::<Vec<Floe>>(&bytes)? {
                    if let Some(h) = whole.handle_of(floe.id) {
                        whole.remove(h);
                    }
                    whole.insert(floe)?;
                }
            }
        }
        // The cuts' edits cleared the ghost marks: a migration sets them.
        self.migrate()?;
        Ok(all)
    }
}
