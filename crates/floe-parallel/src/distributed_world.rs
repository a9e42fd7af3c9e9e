//! A world spread over processes by spatial domain decomposition, stepped
//! so that the result is bitwise the single process's.
//!
//! Each process holds a [`World`] of the floes it owns and their ghosts
//! (copies of floes owned elsewhere that its floes could touch), sorted by
//! id as the whole world's are. Its contact list is then the whole list's
//! pairs among those floes in the same order, each contact computed from
//! the same bits, so each owned floe's force sums the same terms in the
//! same order. After every step the owners send their ghosts' motion and
//! forces ([`Kinematics`]), so a ghost drifts as its owner's floe does. The
//! energy ledger's sums are exact and added over the processes
//! ([`World::kick_with`]).
//!
//! When a floe has moved half the halo's skin since the last migration,
//! every process hands its floes to their owners under the current (or,
//! when the work is out of balance, a new) decomposition, each with its
//! contacts' springs and friction state and the memory of its broken
//! contacts, and rebuilds its world from what it receives.

use std::sync::atomic::{AtomicBool, Ordering};

use floe_dem::contact_model::ContactModel;
use floe_dem::contacts::{BrokenContact, ContactRecord};
use floe_dem::decomposition::Decomposition;
use floe_dem::floes::{FloeColumns, Floes, Motion};
use floe_dem::forcing::{ExternalForces, NoForcing};
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::ScheduledMotion;
use floe_dem::periodicity::Periodicity;
use floe_dem::pipeline::energy_accounting::StepSums;
use floe_dem::run::{check_health, BlowUp, StepReport, Stepper};
use floe_dem::state::WorldState;
use floe_dem::stress_control::StressControl;
use floe_dem::tessellation::Rect;
use floe_dem::world::{Kinematics, World};
use floe_dem::Vec2;

use crate::comm::Communicator;
use crate::error::ParallelError;
use crate::reach::{box_distance, images, Outline, OutlineGrid};
use crate::wire::{decode, encode, put_f64s, take_f64s, Migrant, Packet};

/// How a run is spread and kept in balance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// The halo's reach beyond contact, as a fraction of the largest free
    /// floe's bounding radius: floes migrate when one has moved half of
    /// it. Larger: more ghosts, fewer migrations.
    pub skin_fraction: f64,
    /// A migration also rebalances when the busiest process's work (its
    /// floes plus their contacts) exceeds the mean by this fraction.
    pub rebalance_threshold: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            skin_fraction: 0.25,
            rebalance_threshold: 0.2,
        }
    }
}

/// What the processes hold of the whole run that is not per floe: the
/// schedules, load points and stress controls of every floe.
#[derive(Debug, Clone, Default)]
struct Drivers {
    schedules: Vec<ScheduledMotion>,
    load_points: Vec<LoadPoint>,
    stress_controls: Vec<StressControl>,
}

/// Counts of what the decomposition did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DecompositionStats {
    /// Migrations (ghosts and owners redone), the first set-up included.
    pub migrations: u64,
    /// Migrations that also cut the domain anew.
    pub rebalances: u64,
    /// Free floes this process owns now.
    pub owned: usize,
    /// Free floes it holds as ghosts now.
    pub ghosts: usize,
    /// Prescribed floes (walls, land), which every process holds.
    pub prescribed: usize,
    /// Broken contacts of its floes it keeps aside (the other floe is
    /// not here) now.
    pub parked: usize,
    /// Processes it exchanges ghosts with each step now.
    pub neighbours: usize,
    /// Bytes of ghost motion it sends each step now.
    pub halo_bytes: usize,
    /// Times the whole world was gathered for output.
    pub gathers: u64,
    /// Wall-clock time spent gathering the world and handing it to the
    /// writer (on process 0: and writing it), s.
    pub output_s: f64,
}

/// A world spread over the processes of `C`.
pub struct DistributedWorld<F: ExternalForces, C: Communicator> {
    /// This process's part (taken out only while it is rebuilt).
    world: Option<World<F>>,
    comm: C,
    settings: Settings,
    decomposition: Decomposition,
    /// Where the cuts were made: the period on periodic axes, the floes'
    /// extent on open ones (whose outer boxes reach to infinity).
    domain: Rect,
    /// The largest free floe's bounding radius, m.
    largest_radius_m: f64,
    /// The halo's reach beyond contact, m.
    skin_m: f64,
    /// The domain's periodic axes.
    periodicity: Periodicity,
    /// Per local floe: owned here.
    owned: Vec<bool>,
    /// Per process, the owned floes (handles) whose motion it receives.
    send: Vec<(usize, Vec<usize>)>,
    /// Per process, the ghosts (handles) whose motion it sends.
    receive: Vec<(usize, Vec<usize>)>,
    /// The stress-controlled walls (handles, by id).
    controlled: Vec<usize>,
    /// Each local floe's position and angle at the last migration.
    reference: Vec<(Vec2, f64)>,
    /// Broken contacts of owned floes whose other floe is not here.
    parked: Vec<([u64; 2], BrokenContact)>,
    drivers: Drivers,
    /// On process 0: the whole set of floes as it began, for what never
    /// changes (shapes, masses) when the world is gathered.
    whole_floes: Option<Floes>,
    stats: DecompositionStats,
}

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// Spreads a whole world (every process passes the same `state`: a
    /// fresh world's or a checkpoint's) over the processes of `comm`.
    pub fn from_whole(
        state: WorldState,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
        comm: C,
        settings: Settings,
    ) -> Result<Self, ParallelError> {
        let f = state.floes.columns();
        let free: Vec<usize> = (0..f.len()).filter(|&i| f.is_free(i)).collect();
        if comm.size() > free.len() {
            return Err(ParallelError::MoreProcessesThanFloes {
                processes: comm.size(),
                floes: free.len(),
            });
        }
        let largest_radius_m = free.iter().map(|&i| f.radius_m[i]).fold(0.0, f64::max);
        let mut counts = vec![0u64; f.len()];
        for c in &state.contacts {
            counts[c.a as usize] += 1;
            counts[c.b as usize] += 1;
        }
        let points: Vec<Vec2> = free.iter().map(|&i| f.position[i]).collect();
        let weights: Vec<f64> = free.iter().map(|&i| 1.0 + counts[i] as f64).collect();
        let domain = cut_domain(&points, periodicity);
        let decomposition = Decomposition::rcb(&points, &weights, domain, comm.size())?;
        check_subdomains(&decomposition, domain, periodicity, largest_radius_m)?;
        let comm_rank_is_root = comm.rank() == 0;
        let drivers = Drivers {
            schedules: state.schedules.clone(),
            load_points: state.load_points.clone(),
            stress_controls: state.stress_controls.clone(),
        };
        let mut this = DistributedWorld {
            world: None,
            comm,
            settings,
            decomposition,
            domain,
            largest_radius_m,
            skin_m: settings.skin_fraction * largest_radius_m,
            periodicity,
            owned: Vec::new(),
            send: Vec::new(),
            receive: Vec::new(),
            controlled: Vec::new(),
            reference: Vec::new(),
            parked: Vec::new(),
            drivers,
            whole_floes: (comm_rank_is_root).then(|| state.floes.clone()),
            stats: DecompositionStats::default(),
        };
        // Every process has the whole: each takes what it holds.
        let me = this.comm.rank();
        let grid = this.outline_grid(f);
        let mut mine = Packet::default();
        for i in 0..f.len() {
            let (owner, holders) = this.holders(f, i, &grid, periodicity);
            if holders.contains(&me) {
                mine.floes.push(migrant(&state, i, owner, holders));
            }
        }
        let id = |h: u32| f.id[h as usize];
        mine.contacts = state
            .contacts
            .iter()
            .map(|c| ([id(c.a), id(c.b)], *c))
            .collect();
        mine.broken = state
            .broken
            .iter()
            .map(|c| ([id(c.a), id(c.b)], *c))
            .collect();
        let clock = Clock::of(&state);
        this.install(vec![mine], clock, model, forcing, periodicity)?;
        Ok(this)
    }

    /// This process's part of the world: its floes and their ghosts.
    pub fn local(&self) -> &World<F> {
        self.world.as_ref().expect("present between calls")
    }

    fn local_mut(&mut self) -> &mut World<F> {
        self.world.as_mut().expect("present between calls")
    }

    /// The communicator.
    pub fn comm(&self) -> &C {
        &self.comm
    }

    /// What the decomposition did so far, and this process's share now.
    pub fn stats(&self) -> DecompositionStats {
        self.stats
    }

    /// The subdomains' boxes, by process.
    pub fn boxes(&self) -> &[Rect] {
        self.decomposition.boxes()
    }

    /// The prescribed floes' outlines with their owners, on a grid.
    fn outline_grid(&self, f: &FloeColumns) -> OutlineGrid {
        let outlines = (0..f.len())
            .filter(|&i| !f.is_free(i))
            .map(|i| Outline {
                owner: self.decomposition.owner_of(f.position[i]),
                vertices: f.world_vertices(i),
            })
            .collect();
        OutlineGrid::new(outlines, self.largest_radius_m + self.skin_m)
    }

    /// Floe `i`'s owner and every process that holds it, sorted.
    fn holders(
        &self,
        f: &FloeColumns,
        i: usize,
        grid: &OutlineGrid,
        periodicity: Periodicity,
    ) -> (usize, Vec<usize>) {
        let p = f.position[i];
        let owner = self.decomposition.owner_of(p);
        if !f.is_free(i) {
            return (owner, (0..self.comm.size()).collect());
        }
        let pts = images(p, periodicity);
        let reach = f.radius_m[i] + self.largest_radius_m + self.skin_m;
        let mut ranks: Vec<usize> = (0..self.comm.size())
            .filter(|&k| k == owner || box_distance(self.open_box(k), &pts) < reach)
            .collect();
        grid.owners_near(&pts, f.radius_m[i] + self.skin_m, &mut ranks);
        ranks.sort_unstable();
        ranks.dedup();
        (owner, ranks)
    }

    /// Process `k`'s box, reaching to infinity on open sides.
    fn open_box(&self, k: usize) -> Rect {
        open_box(&self.decomposition, k, self.domain, self.periodicity)
    }

    /// Builds this process's world from the packets it received.
    fn install(
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
        for p in incoming {
            migrants.extend(p.floes);
            contacts.extend(p.contacts);
            broken.extend(p.broken);
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
        let controlled: Vec<usize> = migrants
            .iter()
            .enumerate()
            .filter(|(_, m)| {
                self.drivers
                    .stress_controls
                    .iter()
                    .any(|c| c.floe_ids.contains(&m.floe.id))
            })
            .map(|(h, _)| h)
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
        for m in migrants {
            force.push(m.force);
            torque.push(m.torque);
            external_force.push(m.external_force);
            external_torque.push(m.external_torque);
            floes.insert(m.floe)?;
        }
        let here = |id: u64| handle(id).is_some();
        let d = &self.drivers;
        let state = WorldState {
            contacts: local_contacts,
            broken: local_broken,
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
            floes,
        };
        let f = state.floes.columns();
        self.reference = (0..f.len()).map(|h| (f.position[h], f.angle[h])).collect();
        let mut world = World::resume(state, model, forcing, periodicity)?;
        world.set_ghosts(owned.iter().map(|&o| !o).collect())?;
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
    fn migrate(&mut self) -> Result<(), ParallelError> {
        self.rebalance_if_needed()?;
        let world = self.world.take().expect("present between calls");
        let (state, model, forcing, periodicity) = world.into_parts();
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
    fn rebalance_if_needed(&mut self) -> Result<(), ParallelError> {
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
        let decomposition = Decomposition::rcb(&points, &weights, domain, k)?;
        // Cuts that would leave a subdomain narrower than a floe are not
        // taken: the old ones stay (balance is only speed).
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

    /// Sends each ghost its owner's motion and forces.
    fn exchange_ghosts(&mut self) {
        let world = self.world.as_ref().expect("present between calls");
        let sends = self
            .send
            .iter()
            .map(|(r, list)| {
                let mut out = Vec::with_capacity(list.len() * KINEMATICS_BYTES);
                for &h in list {
                    let k = world.kinematics(h);
                    put_f64s(
                        &mut out,
                        &[
                            k.position.x,
                            k.position.y,
                            k.angle,
                            k.velocity.x,
                            k.velocity.y,
                            k.angular_velocity,
                            k.force.x,
                            k.force.y,
                            k.torque,
                        ],
                    );
                }
                (*r, out)
            })
            .collect();
        let receives: Vec<(usize, usize)> = self
            .receive
            .iter()
            .map(|(r, list)| (*r, list.len() * KINEMATICS_BYTES))
            .collect();
        let incoming = self.comm.exchange(sends, &receives);
        let world = self.world.as_mut().expect("present between calls");
        for ((_, list), bytes) in self.receive.iter().zip(&incoming) {
            let mut bytes = bytes.as_slice();
            for &h in list {
                let v = take_f64s::<9>(&mut bytes).expect("the owner sends every ghost it listed");
                let k = Kinematics {
                    position: Vec2::new(v[0], v[1]),
                    angle: v[2],
                    velocity: Vec2::new(v[3], v[4]),
                    angular_velocity: v[5],
                    force: Vec2::new(v[6], v[7]),
                    torque: v[8],
                };
                world
                    .set_kinematics(h, &k)
                    .expect("between steps, after the kick");
            }
        }
    }

    /// Hands the force on each stress-controlled wall from its owner to
    /// every process: the next drift moves the walls by their sum.
    fn share_wall_forces(&mut self) -> Result<(), ParallelError> {
        if self.controlled.is_empty() {
            return Ok(());
        }
        let world = self.local();
        let ids = &world.floes().id;
        let mut mine = Vec::new();
        for &h in self.controlled.iter().filter(|&&h| self.owned[h]) {
            let k = world.kinematics(h);
            mine.extend_from_slice(&ids[h].to_le_bytes());
            put_f64s(&mut mine, &[k.force.x, k.force.y, k.torque]);
        }
        let all = self.comm.all_gather(mine);
        let world = self.world.as_mut().expect("present between calls");
        for part in &all {
            for row in part.chunks_exact(32) {
                let id = u64::from_le_bytes(row[..8].try_into().expect("8 bytes"));
                let mut rest = &row[8..];
                let v = take_f64s::<3>(&mut rest).expect("24 bytes");
                let h = world.floes().handle_of(id).ok_or_else(|| {
                    ParallelError::Wire(format!("wall {id} is not on every process"))
                })?;
                if !self.owned[h] {
                    let k = Kinematics {
                        force: Vec2::new(v[0], v[1]),
                        torque: v[2],
                        ..world.kinematics(h)
                    };
                    world.set_kinematics(h, &k)?;
                }
            }
        }
        Ok(())
    }

    /// How far any owned floe's outline has moved since the last
    /// migration, m (a free floe's centre: its reach is a circle).
    fn largest_move_m(&self) -> f64 {
        let world = self.local();
        let f = world.floes().columns();
        let periodicity = world.periodicity();
        (0..f.len())
            .filter(|&h| self.owned[h])
            .map(|h| {
                let (p0, a0) = self.reference[h];
                let p = f.position[h];
                let moved = (p + periodicity.nearest_image(p0, p) - p0).length();
                if f.is_free(h) {
                    moved
                } else {
                    moved + f.radius_m[h] * (f.angle[h] - a0).abs()
                }
            })
            .fold(0.0, f64::max)
    }

    /// The whole world's state on process 0 (`None` elsewhere): every
    /// process sends its owned floes' motion and forces (a fixed row each;
    /// process 0 keeps what never changes, the shapes and masses) and the
    /// contacts it counts.
    pub fn gather_whole(&self) -> Result<Option<WorldState>, ParallelError> {
        let world = self.local();
        let state = world.state();
        let f = state.floes.columns();
        let id = |h: u32| f.id[h as usize];
        let mut part = WholePart::default();
        let owned: Vec<usize> = (0..f.len()).filter(|&h| self.owned[h]).collect();
        part.rows.reserve(owned.len() * ROW_BYTES);
        for &h in &owned {
            put_row(&mut part.rows, state, h);
        }
        part.contacts = state
            .contacts
            .iter()
            .filter(|c| self.owned[c.a as usize])
            .map(|c| ([id(c.a), id(c.b)], *c))
            .collect();
        part.broken = state
            .broken
            .iter()
            .filter(|c| self.owned[c.a as usize])
            .map(|c| ([id(c.a), id(c.b)], *c))
            .collect();
        // A parked memory is counted by the owner of its lower id, if
        // it is still remembered.
        let memory_s = world.model().memory_s;
        part.broken.extend(self.parked.iter().filter(|([x, _], c)| {
            f.handle_of(*x).is_some_and(|h| self.owned[h])
                && state.time_s - c.broke_at_s <= memory_s
        }));
        let parts = self.comm.gather_to_root(encode(&part));
        let Some(template) = self.whole_floes.as_ref() else {
            return Ok(None);
        };
        let mut columns = template.columns().clone();
        let n = columns.len();
        let (mut force, mut torque) = (vec![Vec2::ZERO; n], vec![0.0; n]);
        let (mut external_force, mut external_torque) = (vec![Vec2::ZERO; n], vec![0.0; n]);
        let mut seen = vec![false; n];
        let (mut contacts, mut broken) = (Vec::new(), Vec::new());
        for bytes in parts {
            let p: WholePart = decode(&bytes)?;
            for row in p.rows.chunks_exact(ROW_BYTES) {
                let floe_id = u64::from_le_bytes(row[..8].try_into().expect("8 bytes"));
                let mut rest = &row[8..];
                let v = take_f64s::<16>(&mut rest).expect("a whole row");
                let h = match template.handle_of(floe_id) {
                    Some(h) if !seen[h] => h,
                    _ => {
                        return Err(ParallelError::Wire(format!(
                            "floe {floe_id} gathered twice, or not in the run"
                        )))
                    }
                };
                seen[h] = true;
                columns.position[h] = Vec2::new(v[0], v[1]);
                columns.angle[h] = v[2];
                columns.velocity[h] = Vec2::new(v[3], v[4]);
                columns.angular_velocity[h] = v[5];
                columns.motion[h] = if v[6] == 0.0 {
                    Motion::Free
                } else {
                    Motion::Prescribed {
                        velocity: Vec2::new(v[7], v[8]),
                    }
                };
                force[h] = Vec2::new(v[9], v[10]);
                torque[h] = v[11];
                external_force[h] = Vec2::new(v[12], v[13]);
                external_torque[h] = v[14];
            }
            contacts.extend(p.contacts);
            broken.extend(p.broken);
        }
        if let Some(h) = seen.iter().position(|s| !s) {
            return Err(ParallelError::Wire(format!(
                "floe {} was gathered from no process",
                columns.id[h]
            )));
        }
        contacts.sort_unstable_by_key(|(k, _)| *k);
        broken.sort_unstable_by_key(|(k, _)| *k);
        let rehandle = |[x, y]: [u64; 2]| -> Result<(u32, u32), ParallelError> {
            match (template.handle_of(x), template.handle_of(y)) {
                (Some(a), Some(b)) => Ok((a as u32, b as u32)),
                _ => Err(ParallelError::Wire(format!(
                    "a contact names floes {x} and {y}, not both in the run"
                ))),
            }
        };
        let contacts = contacts
            .into_iter()
            .map(|(pair, mut c)| {
                (c.a, c.b) = rehandle(pair)?;
                Ok(c)
            })
            .collect::<Result<Vec<_>, ParallelError>>()?;
        let broken = broken
            .into_iter()
            .map(|(pair, mut c)| {
                (c.a, c.b) = rehandle(pair)?;
                Ok(c)
            })
            .collect::<Result<Vec<_>, ParallelError>>()?;
        let d = &self.drivers;
        Ok(Some(WorldState {
            floes: Floes::from_columns(columns)?,
            contacts,
            broken,
            time_s: state.time_s,
            steps: state.steps,
            dt_s: state.dt_s,
            energy: state.energy,
            force,
            torque,
            external_force,
            external_torque,
            schedules: d.schedules.clone(),
            load_points: d.load_points.clone(),
            stress_controls: d.stress_controls.clone(),
        }))
    }

    /// The whole world on process 0, as a world without forcing (what the
    /// writer and the observables read).
    fn whole_world(&self) -> Result<Option<World<NoForcing>>, ParallelError> {
        let world = self.local();
        Ok(match self.gather_whole()? {
            Some(state) => Some(World::resume(
                state,
                world.model().clone(),
                NoForcing,
                world.periodicity(),
            )?),
            None => None,
        })
    }

    /// Why the forcing failed, as the single process says it (the whole's
    /// first floe off the grid), on every process.
    fn forcing_failure_message(&mut self) -> Result<String, ParallelError> {
        let whole = self.gather_whole()?;
        let mut message = String::new();
        if let Some(state) = whole {
            let t = state.time_s;
            let world = self.local_mut();
            message = match world.forcing_mut().prepare(t, state.floes.columns()) {
                Err(failure) => failure.to_string(),
                Ok(()) => world
                    .forcing_failure()
                    .map_or_else(|| "the forcing failed".into(), ToString::to_string),
            };
        }
        let bytes = self.comm.broadcast_from_root(message.into_bytes());
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The blow-up as the single process finds it, on every process.
    fn blow_up(&self) -> Result<Option<BlowUp>, ParallelError> {
        let found = self.whole_world()?.and_then(|w| check_health(&w));
        let bytes = self.comm.broadcast_from_root(encode(&found));
        decode(&bytes)
    }

    /// One step of every process, the ghosts' exchange, and a migration
    /// when a floe has moved half the skin.
    pub fn try_step(&mut self, interrupt: &AtomicBool) -> Result<StepReport, ParallelError> {
        let comm = &self.comm;
        let world = self.world.as_mut().expect("present between calls");
        world.drift();
        world.detect_contacts();
        world.gather_forces();
        world.kick_with(|sums| {
            let mut words = sums.to_words();
            comm.sum_i64(&mut words);
            *sums = StepSums::from_words(&words);
        });
        self.exchange_ghosts();
        self.share_wall_forces()?;
        let world = self.local();
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        let mut v = [
            self.largest_move_m(),
            flag(interrupt.load(Ordering::SeqCst)),
            flag(world.forcing_failure().is_some()),
            flag(check_health(world).is_some()),
        ];
        self.comm.max_f64(&mut v);
        let mut report = StepReport {
            interrupted: v[1] > 0.0,
            ..StepReport::default()
        };
        if v[2] > 0.0 {
            report.forcing_failure = Some(self.forcing_failure_message()?);
        } else if v[3] > 0.0 {
            report.blow_up = self.blow_up()?;
        } else if v[0] > 0.5 * self.skin_m {
            self.migrate()?;
        }
        Ok(report)
    }
}

/// Bytes of a ghost's motion and forces ([`Kinematics`]: nine `f64`).
const KINEMATICS_BYTES: usize = 72;

/// Bytes of a floe's row in the gathered whole: its id and sixteen `f64`.
const ROW_BYTES: usize = 136;

/// What a process sends process 0 for the whole world: its floes' rows
/// ([`put_row`]) and the contacts it counts, named by floe ids.
#[derive(Debug, Default, serde::Serialize, serde::Deserialize)]
struct WholePart {
    rows: Vec<u8>,
    contacts: Vec<([u64; 2], ContactRecord)>,
    broken: Vec<([u64; 2], BrokenContact)>,
}

/// Floe `h`'s row: id, position, angle, velocity, angular velocity,
/// motion (0 free, 1 prescribed, and the prescribed velocity), force,
/// torque, external force and torque.
fn put_row(out: &mut Vec<u8>, state: &WorldState, h: usize) {
    let f = state.floes.columns();
    out.extend_from_slice(&f.id[h].to_le_bytes());
    let (kind, v) = match f.motion[h] {
        Motion::Free => (0.0, Vec2::ZERO),
        Motion::Prescribed { velocity } => (1.0, velocity),
    };
    put_f64s(
        out,
        &[
            f.position[h].x,
            f.position[h].y,
            f.angle[h],
            f.velocity[h].x,
            f.velocity[h].y,
            f.angular_velocity[h],
            kind,
            v.x,
            v.y,
            state.force[h].x,
            state.force[h].y,
            state.torque[h],
            state.external_force[h].x,
            state.external_force[h].y,
            state.external_torque[h],
            0.0,
        ],
    );
}

/// The clock and ledger every process shares.
#[derive(Debug, Clone, Copy)]
struct Clock {
    time_s: f64,
    steps: u64,
    dt_s: f64,
    energy: floe_dem::energy_ledger::EnergyLedger,
}

impl Clock {
    fn of(state: &WorldState) -> Self {
        Clock {
            time_s: state.time_s,
            steps: state.steps,
            dt_s: state.dt_s,
            energy: state.energy,
        }
    }
}

/// Floe `i` of `state` with its forces, for `owner` and `holders`.
fn migrant(state: &WorldState, i: usize, owner: usize, holders: Vec<usize>) -> Migrant {
    Migrant {
        floe: state.floes.get(i),
        force: state.force[i],
        torque: state.torque[i],
        external_force: state.external_force[i],
        external_torque: state.external_torque[i],
        owner: owner as u32,
        holders: holders.into_iter().map(|r| r as u32).collect(),
    }
}

/// The rectangle the cuts are made in: the period on periodic axes, the
/// points' extent (a metre wider) on open ones.
fn cut_domain(points: &[Vec2], periodicity: Periodicity) -> Rect {
    let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    lo -= Vec2::splat(1.0);
    hi += Vec2::splat(1.0);
    if let Some(p) = periodicity.x {
        (lo.x, hi.x) = (p.min_m, p.min_m + p.length_m);
    }
    if let Some(p) = periodicity.y {
        (lo.y, hi.y) = (p.min_m, p.min_m + p.length_m);
    }
    Rect::new(lo, hi)
}

/// Box `k` of `d`, reaching to infinity where it meets an open side of
/// the `domain` it was cut in (floes may drift out of it).
fn open_box(d: &Decomposition, k: usize, domain: Rect, periodicity: Periodicity) -> Rect {
    let b = d.boxes()[k];
    let open = |v: f64, edge: f64, periodic: bool, inf: f64| {
        if !periodic && v == edge {
            inf
        } else {
            v
        }
    };
    let (px, py) = (periodicity.x.is_some(), periodicity.y.is_some());
    Rect::new(
        Vec2::new(
            open(b.min.x, domain.min.x, px, f64::NEG_INFINITY),
            open(b.min.y, domain.min.y, py, f64::NEG_INFINITY),
        ),
        Vec2::new(
            open(b.max.x, domain.max.x, px, f64::INFINITY),
            open(b.max.y, domain.max.y, py, f64::INFINITY),
        ),
    )
}

/// Refuses a subdomain narrower than the largest floe (an open side
/// reaches to infinity).
fn check_subdomains(
    d: &Decomposition,
    domain: Rect,
    periodicity: Periodicity,
    largest_radius_m: f64,
) -> Result<(), ParallelError> {
    let diameter_m = 2.0 * largest_radius_m;
    if d.boxes().len() == 1 {
        return Ok(());
    }
    for rank in 0..d.boxes().len() {
        let b = open_box(d, rank, domain, periodicity);
        if b.width_m() < diameter_m || b.height_m() < diameter_m {
            return Err(ParallelError::SubdomainTooSmall {
                rank,
                width_m: b.width_m(),
                height_m: b.height_m(),
                diameter_m,
            });
        }
    }
    Ok(())
}

impl<F: ExternalForces, C: Communicator> Stepper for DistributedWorld<F, C> {
    type Whole = NoForcing;

    fn step(&mut self, interrupt: &AtomicBool) -> StepReport {
        self.try_step(interrupt)
            .unwrap_or_else(|e| panic!("a distributed step failed: {e}"))
    }

    fn steps(&self) -> u64 {
        self.local().steps()
    }

    fn time_s(&self) -> f64 {
        self.local().time_s()
    }

    fn dt_s(&self) -> f64 {
        self.local().dt_s()
    }

    fn with_whole<R>(&mut self, write: impl FnOnce(&World<NoForcing>) -> R) -> Option<R> {
        let started = std::time::Instant::now();
        let written = self
            .whole_world()
            .unwrap_or_else(|e| panic!("gathering the world failed: {e}"))
            .map(|w| write(&w));
        self.stats.gathers += 1;
        self.stats.output_s += started.elapsed().as_secs_f64();
        written
    }
}
