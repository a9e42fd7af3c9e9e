//! Migration: every owned floe handed to the processes that hold it from
//! now on, with its contacts, its broken contacts' memory and its bonds, each
//! process's world rebuilt from what it receives, and a new cut of the
//! domain when the work is out of balance.

use super::*;
use floe_dem::pipeline::floe_stress::StressFilter;

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// Builds this process's world from the packets it received.
    pub(super) fn install(
        &mut self,
        incoming: Vec<Packet>,
        clock: Clock,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
    ) -> Result<(), ParallelError> {
        let me = self.comm.rank() as u32;
        let mut migrants: Vec<Migrant> = Vec::new();
        let mut contacts = Vec::new();
        let mut broken = Vec::new();
        let mut bonds = Vec::new();
        for p in incoming {
            migrants.extend(p.floes);
            contacts.extend(p.contacts);
            broken.extend(p.broken);
            bonds.extend(p.bonds);
        }
        migrants.sort_by_key(|m| m.floe.id);
        migrants.dedup_by_key(|m| m.floe.id);
        let ids: Vec<u64> = migrants.iter().map(|m| m.floe.id).collect();
        let handle = |id: u64| ids.binary_search(&id).ok();
        let owned: Vec<bool> = migrants.iter().map(|m| m.owner == me).collect();
        // Contacts of floes both here, by pair.
        let mut local_contacts: Vec<ContactRecord> = contacts
            .into_iter()
            .filter_map(|([x, y], mut c)| {
                let (a, b) = (handle(x)?, handle(y)?);
                (c.a, c.b) = (a as u32, b as u32);
                Some(c)
            })
            .collect();
        local_contacts.sort_by_key(|c| (c.a, c.b));
        local_contacts.dedup_by_key(|c| (c.a, c.b));
        // Bonds of floes both here, by pair, as the contacts.
        let mut local_bonds: Vec<Bond> = bonds
            .into_iter()
            .filter_map(|([x, y], mut b)| {
                (b.a, b.b) = (handle(x)? as u32, handle(y)? as u32);
                Some(b)
            })
            .collect();
        local_bonds.sort_by_key(|b| (b.a, b.b));
        local_bonds.dedup_by_key(|b| (b.a, b.b));
        // Broken contacts: here if both floes are, kept aside for an owned
        // floe whose partner is elsewhere, dropped once forgotten.
        let remembered = |c: &BrokenContact| clock.time_s - c.broke_at_s <= model.memory_s;
        let mut local_broken = Vec::new();
        let mut parked = Vec::new();
        for ([x, y], mut c) in broken {
            if !remembered(&c) {
                continue;
            }
            match (handle(x), handle(y)) {
                (Some(a), Some(b)) => {
                    (c.a, c.b) = (a as u32, b as u32);
                    local_broken.push(c);
                }
                (Some(h), None) | (None, Some(h)) if owned[h] => parked.push(([x, y], c)),
                _ => {}
            }
        }
        local_broken.sort_by_key(|c| (c.a, c.b));
        local_broken.dedup_by_key(|c| (c.a, c.b));
        parked.sort_by_key(|(k, _)| *k);
        parked.dedup_by_key(|(k, _)| *k);
        // Who sends whom motion each step.
        let mut send: Vec<(usize, Vec<usize>)> = Vec::new();
        let mut receive: Vec<(usize, Vec<usize>)> = Vec::new();
        let push = |lists: &mut Vec<(usize, Vec<usize>)>, rank: usize, h: usize| match lists
            .iter_mut()
            .find(|(r, _)| *r == rank)
        {
            Some((_, l)) => l.push(h),
            None => lists.push((rank, vec![h])),
        };
        // A prescribed floe is on every process and moves the same on each
        // (its schedule, or its stress control, which reads the forces
        // `share_wall_forces` hands round): only free floes' motion travels.
        let mut control_ids: Vec<u64> = (self.drivers.stress_controls.iter())
            .flat_map(|c| c.floe_ids.iter().copied())
            .collect();
        control_ids.sort_unstable();
        // A search per controlled piece, not of every control per floe.
        let controlled: Vec<usize> = control_ids
            .iter()
            .filter_map(|id| ids.binary_search(id).ok())
            .collect();
        for (h, m) in migrants.iter().enumerate() {
            if !matches!(m.floe.motion, floe_dem::floes::Motion::Free) {
                continue;
            }
            if owned[h] {
                for &r in m.holders.iter().filter(|&&r| r != me) {
                    push(&mut send, r as usize, h);
                }
            } else {
                push(&mut receive, m.owner as usize, h);
            }
        }
        send.sort_by_key(|(r, _)| *r);
        receive.sort_by_key(|(r, _)| *r);
        let mut floes = Floes::new();
        let (mut force, mut torque) = (Vec::new(), Vec::new());
        let (mut external_force, mut external_torque) = (Vec::new(), Vec::new());
        let stress_filter = clock
            .stress_time_scale_s
            .map(|t| StressFilter { time_scale_s: t });
        let mut floe_stress = Vec::new();
        for m in migrants {
            force.push(m.force);
            torque.push(m.torque);
            external_force.push(m.external_force);
            external_torque.push(m.external_torque);
            if stress_filter.is_some() {
                floe_stress.push(m.stress.unwrap_or_default());
            }
            floes.insert(m.floe)?;
        }
        let here = |id: u64| handle(id).is_some();
        let d = &self.drivers;
        let state = WorldState {
            contacts: local_contacts,
            broken: local_broken,
            bonds: local_bonds,
            time_s: clock.time_s,
            steps: clock.steps,
            dt_s: clock.dt_s,
            energy: clock.energy,
            force,
            torque,
            external_force,
            external_torque,
            schedules: d
                .schedules
                .iter()
                .filter(|s| here(s.floe_id))
                .cloned()
                .collect(),
            load_points: d
                .load_points
                .iter()
                .filter(|l| here(l.floe_id))
                .cloned()
                .collect(),
            stress_controls: d.stress_controls.clone(),
            stress_filter,
            floe_stress,
            next_floe_id: clock.next_floe_id,
            ridging: clock.ridging,
            welding: clock.welding,
            floes,
        };
        let f = state.floes.columns();
        self.reference = (0..f.len()).map(|h| (f.position[h], f.angle[h])).collect();
        let mut world = World::resume(state, model, forcing, periodicity)?;
        world.set_ghosts(owned.iter().map(|&o| !o).collect())?;
        if self.cohesion.is_some() {
            world.set_cohesion(self.cohesion)?;
        }
        let f = world.floes();
        let free = |h: &usize| f.is_free(*h);
        self.stats.owned = (0..owned.len()).filter(free).filter(|&h| owned[h]).count();
        self.stats.ghosts = (0..owned.len()).filter(free).filter(|&h| !owned[h]).count();
        self.stats.prescribed = owned.len() - self.stats.owned - self.stats.ghosts;
        self.stats.migrations += 1;
        self.owned = owned;
        self.stats.parked = parked.len();
        let mut neighbours: Vec<usize> = send.iter().chain(&receive).map(|(r, _)| *r).collect();
        neighbours.sort_unstable();
        neighbours.dedup();
        self.stats.neighbours = neighbours.len();
        self.stats.halo_bytes = send.iter().map(|(_, l)| l.len() * KINEMATICS_BYTES).sum();
        self.send = send;
        self.receive = receive;
        self.controlled = controlled;
        self.parked = parked;
        self.world = Some(world);
        Ok(())
    }

    /// Hands every owned floe to the processes that hold it from now on,
    /// rebalancing first if the work is out of balance, and rebuilds.
    pub(super) fn migrate(&mut self) -> Result<(), ParallelError> {
        self.rebalance_if_needed()?;
        let world = self.world.take().expect("present between calls");
        let (state, model, forcing, periodicity) = world.into_parts();
        // A servo wall's state moved on with every step, the same on every
        // process: the rebuilt world takes it as it is now.
        self.drivers.stress_controls = state.stress_controls.clone();
        let f = state.floes.columns();
        let grid = self.outline_grid(f);
        let k = self.comm.size();
        let mut packets = vec![Packet::default(); k];
        let mut holders_of: Vec<Vec<usize>> = vec![Vec::new(); f.len()];
        for i in (0..f.len()).filter(|&i| self.owned[i]) {
            let (owner, holders) = self.holders(f, i, &grid, periodicity);
            for &r in &holders {
                packets[r]
                    .floes
                    .push(migrant(&state, i, owner, holders.clone()));
            }
            holders_of[i] = holders;
        }
        let id = |h: u32| f.id[h as usize];
        for c in &state.contacts {
            for end in [c.a, c.b].into_iter().filter(|&e| self.owned[e as usize]) {
                for &r in &holders_of[end as usize] {
                    packets[r].contacts.push(([id(c.a), id(c.b)], *c));
                }
            }
        }
        for c in &state.broken {
            for end in [c.a, c.b].into_iter().filter(|&e| self.owned[e as usize]) {
                for &r in &holders_of[end as usize] {
                    packets[r].broken.push(([id(c.a), id(c.b)], *c));
                }
            }
        }
        for b in &state.bonds {
            for end in [b.a, b.b].into_iter().filter(|&e| self.owned[e as usize]) {
                for &r in &holders_of[end as usize] {
                    packets[r].bonds.push(([id(b.a), id(b.b)], *b));
                }
            }
        }
        // A parked memory goes with its owned floe to the floe's new owner.
        for (pair, c) in std::mem::take(&mut self.parked) {
            let Some(h) = pair
                .iter()
                .find_map(|&x| f.handle_of(x).filter(|&h| self.owned[h]))
            else {
                continue;
            };
            let owner = self.decomposition.owner_of(f.position[h]);
            packets[owner].broken.push((pair, c));
        }
        let outgoing = packets.iter().map(encode).collect();
        let incoming = self
            .comm
            .all_to_all(outgoing)
            .iter()
            .map(|b| decode::<Packet>(b))
            .collect::<Result<Vec<_>, _>>()?;
        let clock = Clock::of(&state);
        self.install(incoming, clock, model, forcing, periodicity)
    }

    /// Cuts the domain anew when the busiest process's work exceeds the
    /// mean by more than the threshold.
    pub(super) fn rebalance_if_needed(&mut self) -> Result<(), ParallelError> {
        let (me, k) = (self.comm.rank(), self.comm.size());
        let world = self.local();
        let f = world.floes().columns();
        let mut counts = vec![0u64; f.len()];
        for c in world.contacts() {
            counts[c.a as usize] += 1;
            counts[c.b as usize] += 1;
        }
        let mine: Vec<usize> = (0..f.len())
            .filter(|&i| self.owned[i] && f.is_free(i))
            .collect();
        let mut work = vec![0i64; k];
        work[me] = mine.iter().map(|&i| 1 + counts[i] as i64).sum();
        self.comm.sum_i64(&mut work);
        let mean = work.iter().sum::<i64>() as f64 / k as f64;
        let busiest = work.iter().copied().max().unwrap_or(0) as f64;
        if mean <= 0.0 || busiest / mean - 1.0 <= self.settings.rebalance_threshold {
            return Ok(());
        }
        // Every process cuts the same points, gathered in id order.
        let mut bytes = Vec::with_capacity(mine.len() * 32);
        for &i in &mine {
            bytes.extend_from_slice(&f.id[i].to_le_bytes());
            put_f64s(
                &mut bytes,
                &[f.position[i].x, f.position[i].y, 1.0 + counts[i] as f64],
            );
        }
        let all = self.comm.all_to_all(vec![bytes; k]);
        let mut rows: Vec<(u64, [f64; 3])> = Vec::new();
        for part in &all {
            for row in part.chunks_exact(32) {
                let id = u64::from_le_bytes(row[..8].try_into().expect("8 bytes"));
                let mut rest = &row[8..];
                let v = take_f64s::<3>(&mut rest).expect("24 bytes");
                rows.push((id, v));
            }
        }
        rows.sort_by_key(|r| r.0);
        let points: Vec<Vec2> = rows.iter().map(|r| Vec2::new(r.1[0], r.1[1])).collect();
        let weights: Vec<f64> = rows.iter().map(|r| r.1[2]).collect();
        let domain = cut_domain(&points, self.periodicity);
        // Cuts that cannot be made (floes bunched where no cut fits
        // between them) or that would leave a subdomain narrower than a
        // floe are not taken: the old ones stay (balance is only speed).
        let Ok(decomposition) = Decomposition::rcb(&points, &weights, domain, k) else {
            return Ok(());
        };
        if check_subdomains(
            &decomposition,
            domain,
            self.periodicity,
            self.largest_radius_m,
        )
        .is_ok()
        {
            (self.domain, self.decomposition) = (domain, decomposition);
            self.stats.rebalances += 1;
        }
        Ok(())
    }
}

/// The clock and ledger every process shares.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(super) struct Clock {
    time_s: f64,
    steps: u64,
    dt_s: f64,
    energy: floe_dem::energy_ledger::EnergyLedger,
    /// The floe stress filter's time scale, s, when floe stress is on.
    stress_time_scale_s: Option<f64>,
    /// Where fracture numbers new floes from.
    next_floe_id: u64,
    /// What ridging moved (the same on every process).
    ridging: floe_dem::ridging::RidgingLedger,
    /// What welding did (the same on every process).
    welding: floe_dem::welding::WeldingLedger,
}

impl Clock {
    pub(super) fn of(state: &WorldState) -> Self {
        Clock {
            time_s: state.time_s,
            steps: state.steps,
            dt_s: state.dt_s,
            energy: state.energy,
            stress_time_scale_s: state.stress_filter.map(|f| f.time_scale_s),
            next_floe_id: state.next_floe_id,
            ridging: state.ridging,
            welding: state.welding,
        }
    }
}

/// Floe `i` of `state` with its forces, for `owner` and `holders`.
pub(super) fn migrant(state: &WorldState, i: usize, owner: usize, holders: Vec<usize>) -> Migrant {
    Migrant {
        floe: state.floes.get(i),
        force: state.force[i],
        torque: state.torque[i],
        external_force: state.external_force[i],
        external_torque: state.external_torque[i],
        stress: state.stress_filter.map(|_| state.floe_stress[i]),
        owner: owner as u32,
        holders: holders.into_iter().map(|r| r as u32).collect(),
    }
}
