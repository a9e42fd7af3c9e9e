//! Welding over processes, bitwise as in one: each process plans the welds
//! of the bonds whose first floe it owns; every process learns every
//! candidate, the largest overlap its hull would add to a floe any process
//! holds and, from the floes' owners, every contact and bond of their
//! floes, chooses the same welds and makes those of the floes it holds
//! (owner or ghost) from the owners' records; the welded floe belongs to
//! the first floe's owner until the migration that follows; process 0's
//! record of the floes' shapes learns it.

use super::*;
use floe_dem::world::{candidate_ids, choose_welds, Weld, WeldRecords};

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// Welding after every step (`try_step`), as [`World::set_welding`],
    /// on every process (needs cohesion on).
    pub fn set_welding(&mut self, welding: Option<Welding>) -> Result<(), ParallelError> {
        self.local_mut().set_welding(welding)?;
        self.welding = welding;
        Ok(())
    }

    /// [`World::weld`] over every process: the same welds, ids and ledger
    /// as one process would make. Every process returns every weld, in
    /// pair order. Call between steps, on every process.
    pub fn weld(&mut self) -> Result<Vec<Weld>, ParallelError> {
        let Some(welding) = self.welding else {
            return Ok(Vec::new());
        };
        let world = self.local();
        if !welding.due(world.steps(), world.dt_s()) {
            return Ok(Vec::new());
        }
        let plans = self.local().plan_welding(&welding)?;
        let mut all: Vec<Weld> = Vec::new();
        for bytes in self.comm.all_gather(encode(&plans)) {
            all.extend(decode::<Vec<Weld>>(&bytes)?);
        }
        if all.is_empty() {
            return Ok(all);
        }
        all.sort_by_key(|p| p.ids);
        // Each process judges the floes it holds; a floe held by several
        // gets the same number on each.
        let mut fractions = self.local().new_overlap_fractions(&all);
        self.comm.max_f64(&mut fractions);
        for (p, x) in all.iter_mut().zip(fractions) {
            p.new_overlap_fraction = x;
        }
        let ids = candidate_ids(&all);
        let mut records: Vec<WeldRecords> = Vec::new();
        for bytes in self
            .comm
            .all_gather(encode(&self.local().weld_records(&ids)))
        {
            records.extend(decode::<Vec<WeldRecords>>(&bytes)?);
        }
        records.sort_by_key(|r| r.id);
        let chosen = choose_welds(all, &records);
        let first = self
            .comm
            .all_gather(self.local().first_free_id().to_le_bytes().to_vec())
            .iter()
            .map(|b| u64::from_le_bytes(b[..8].try_into().expect("8 bytes")))
            .max()
            .unwrap_or(0);
        let mut owned_ids = self.owned_ids();
        let welds = self.local_mut().apply_welding(chosen, &records, first)?;
        for w in &welds {
            let first_owned = owned_ids.binary_search(&w.ids[0]).is_ok();
            owned_ids.retain(|id| !w.ids.contains(id));
            if first_owned {
                owned_ids.push(w.floe.id);
            }
        }
        owned_ids.sort_unstable();
        self.own_ids(&owned_ids);
        self.local_mut().book_welds(&welds);
        if let Some(whole) = self.whole_floes.as_mut() {
            for w in &welds {
                for id in w.ids {
                    if let Some(h) = whole.handle_of(id) {
                        whole.remove(h);
                    }
                }
                whole.insert(w.floe.clone())?;
            }
        }
        // A welded floe may be the largest yet: the ghosts' reach grows
        // with it (every process sees every weld, so all agree).
        for w in &welds {
            self.largest_radius_m = self.largest_radius_m.max(w.floe.radius_m);
        }
        let gone: Vec<u64> = candidate_ids(&welds);
        // Memory kept aside for a pair with a welded floe goes with it.
        self.forget_parked(&gone);
        if !welds.is_empty() {
            self.migrate()?;
        }
        Ok(welds)
    }
}
