//! Ridging over processes, bitwise as in one: each process plans the cuts
//! of the floes it owns, every process learns every cut (by loser id) and
//! makes those of the floes it holds, owner or ghost; the processes' tallies
//! add exactly into every process's ledger; process 0's record of the
//! floes' shapes and masses learns the changed floes; the ghosts take their
//! owners' forces again, and only a floe gone whole (which renumbers the
//! handles) calls for a migration.

use super::*;
use floe_dem::floes::Floe;
use floe_dem::world::{final_gainers, PlannedRidge, RidgingTally};

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
        // A floe that goes whole leaves: ownership is kept by id.
        let owned_ids = self.owned_ids();
        let tally = self.local_mut().apply_ridging(&all)?;
        self.own_ids(&owned_ids);
        let mut words = tally.to_words();
        self.comm.sum_i64(&mut words);
        let total = RidgingTally::from_words(&words);
        self.local_mut().book_ridging(&total);
        // Process 0 keeps every floe's shape and mass for the gathered whole.
        let targets = final_gainers(&all);
        let mut changed: Vec<u64> = all
            .iter()
            .zip(&targets)
            .flat_map(|(p, t)| {
                [
                    (!p.kept.is_empty()).then_some(p.loser_id),
                    t.free.then_some(t.id),
                ]
            })
            .flatten()
            .collect();
        changed.sort_unstable();
        changed.dedup();
        let gone: Vec<u64> = all
            .iter()
            .filter(|p| p.kept.is_empty())
            .map(|p| p.loser_id)
            .collect();
        let f = self.local().floes();
        let mine: Vec<Floe> = changed
            .iter()
            .filter_map(|&id| f.handle_of(id))
            .filter(|&h| self.owned[h])
            .map(|h| f.get(h))
            .collect();
        let shared = self.comm.all_gather(encode(&mine));
        if let Some(whole) = self.whole_floes.as_mut() {
            for &id in &gone {
                if let Some(h) = whole.handle_of(id) {
                    whole.remove(h);
                }
            }
            for bytes in shared {
                for floe in decode::<Vec<Floe>>(&bytes)? {
                    if let Some(h) = whole.handle_of(floe.id) {
                        whole.remove(h);
                    }
                    whole.insert(floe)?;
                }
            }
        }
        // Memory kept aside for a pair with a floe gone goes with it.
        self.forget_parked(&gone);
        if gone.is_empty() {
            // The ghosts take their owners' forces: a cut moves part of a
            // floe's external force, which only its owner holds.
            self.exchange_ghosts();
        } else {
            self.migrate()?;
        }
        Ok(all)
    }
}
