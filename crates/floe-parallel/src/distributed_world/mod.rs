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
//! When a floe will have moved half the halo's skin since the last
//! migration by the end of the next drift (so the next step's contacts all
//! lie within the halo), every process hands its floes to their owners
//! under the current (or, when the work is out of balance, a new)
//! decomposition, each with its
//! contacts' springs and friction state and the memory of its broken
//! contacts, and rebuilds its world from what it receives.

use std::sync::atomic::{AtomicBool, Ordering};

use floe_dem::bonds::Bond;
use floe_dem::cohesion::Cohesion;
use floe_dem::contact_model::ContactModel;
use floe_dem::contacts::{BrokenContact, ContactRecord};
use floe_dem::decomposition::Decomposition;
use floe_dem::floes::{FloeColumns, Floes, Motion};
use floe_dem::forcing::{ExternalForces, NoForcing};
use floe_dem::fracture::rule::Fracturing;
use floe_dem::load_point::LoadPoint;
use floe_dem::motion_schedule::ScheduledMotion;
use floe_dem::periodicity::Periodicity;
use floe_dem::pipeline::energy_accounting::StepSums;
use floe_dem::ridging::Ridging;
use floe_dem::run::{check_health, BlowUp, StepReport, Stepper};
use floe_dem::state::WorldState;
use floe_dem::stress_control::StressControl;
use floe_dem::tessellation::Rect;
use floe_dem::welding::Welding;
use floe_dem::world::{Kinematics, World};
use floe_dem::Vec2;

use crate::comm::Communicator;
use crate::error::ParallelError;
use crate::reach::{box_distance, images, Outline, OutlineGrid};
use crate::wire::{decode, encode, put_f64s, take_f64s, Migrant, Packet};

mod fracture;
mod gather;
mod halo;
mod migration;
mod placement;
mod ridging;
mod welding;

use halo::KINEMATICS_BYTES;
use migration::{migrant, Clock};
use placement::{check_subdomains, cut_domain};

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
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
struct Drivers {
    schedules: Vec<ScheduledMotion>,
    load_points: Vec<LoadPoint>,
    stress_controls: Vec<StressControl>,
}

/// How process 0 cut the domain at the start, for every process.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
struct Plan {
    decomposition: Decomposition,
    domain: Rect,
    largest_radius_m: f64,
    skin_m: f64,
    drivers: Drivers,
    clock: Clock,
}

/// Why the world cannot be spread, as every process learns it.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
enum PlanError {
    MoreProcesses {
        processes: usize,
        floes: usize,
    },
    TooSmall {
        rank: usize,
        width_m: f64,
        height_m: f64,
        diameter_m: f64,
    },
    Other(String),
}

impl From<PlanError> for ParallelError {
    fn from(e: PlanError) -> Self {
        match e {
            PlanError::MoreProcesses { processes, floes } => {
                ParallelError::MoreProcessesThanFloes { processes, floes }
            }
            PlanError::TooSmall {
                rank,
                width_m,
                height_m,
                diameter_m,
            } => ParallelError::SubdomainTooSmall {
                rank,
                width_m,
                height_m,
                diameter_m,
            },
            PlanError::Other(message) => ParallelError::Wire(message),
        }
    }
}

impl Plan {
    /// The cuts of `state`'s free floes (weighted by their contacts) into
    /// `processes` subdomains.
    fn of(
        state: &WorldState,
        periodicity: Periodicity,
        processes: usize,
        skin_fraction: f64,
    ) -> Result<Self, PlanError> {
        let f = state.floes.columns();
        let free: Vec<usize> = (0..f.len()).filter(|&i| f.is_free(i)).collect();
        if processes > free.len() {
            return Err(PlanError::MoreProcesses {
                processes,
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
        let decomposition = Decomposition::rcb(&points, &weights, domain, processes)
            .map_err(|e| PlanError::Other(e.to_string()))?;
        match check_subdomains(&decomposition, domain, periodicity, largest_radius_m) {
            Ok(()) => {}
            Err(ParallelError::SubdomainTooSmall {
                rank,
                width_m,
                height_m,
                diameter_m,
            }) => {
                return Err(PlanError::TooSmall {
                    rank,
                    width_m,
                    height_m,
                    diameter_m,
                })
            }
            Err(e) => return Err(PlanError::Other(e.to_string())),
        }
        // At least two steps of the fastest floe (see `try_step`).
        let dt = state.dt_s;
        let step_m = state
            .next_drift_velocities()
            .iter()
            .enumerate()
            .map(|(i, (v, w))| {
                let turn = if f.is_free(i) {
                    0.0
                } else {
                    f.radius_m[i] * w.abs() * dt
                };
                v.length() * dt + turn
            })
            .fold(0.0, f64::max);
        Ok(Plan {
            decomposition,
            domain,
            largest_radius_m,
            skin_m: (skin_fraction * largest_radius_m).max(4.0 * step_m),
            drivers: Drivers {
                schedules: state.schedules.clone(),
                load_points: state.load_points.clone(),
                stress_controls: state.stress_controls.clone(),
            },
            clock: Clock::of(state),
        })
    }
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
    /// Fracture after every step, if on (kept here: each migration
    /// rebuilds the local world).
    fracturing: Option<Fracturing>,
    /// Bonds form and break, if on (kept here for the same reason).
    cohesion: Option<Cohesion>,
    /// Floes ridge after every step, if on (kept here for the same reason).
    ridging: Option<Ridging>,
    /// Bonded floes weld after every step, if on (kept here for the same
    /// reason).
    welding: Option<Welding>,
}

impl<F: ExternalForces, C: Communicator> DistributedWorld<F, C> {
    /// Spreads a whole world that every process has (the same `state`)
    /// over the processes of `comm`: [`DistributedWorld::from_root`] with
    /// process 0's copy.
    pub fn from_whole(
        state: WorldState,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
        comm: C,
        settings: Settings,
    ) -> Result<Self, ParallelError> {
        let whole = (comm.rank() == 0).then_some(state);
        Self::from_root(whole, model, forcing, periodicity, comm, settings)
    }

    /// Spreads the whole world process 0 holds (a fresh world's or a
    /// checkpoint's state; `None` on the others) over the processes of
    /// `comm`: process 0 cuts the domain and sends each process the floes
    /// it holds, so no other process ever holds the whole. Every process
    /// passes the scenario's model, forcing and periodicity.
    pub fn from_root(
        whole: Option<WorldState>,
        model: ContactModel,
        forcing: F,
        periodicity: Periodicity,
        comm: C,
        settings: Settings,
    ) -> Result<Self, ParallelError> {
        let plan = match &whole {
            Some(state) => Plan::of(state, periodicity, comm.size(), settings.skin_fraction),
            None => Err(PlanError::Other("no world on process 0".into())),
        };
        let bytes = comm.broadcast_from_root(encode(&plan));
        let plan = decode::<Result<Plan, PlanError>>(&bytes)?.map_err(ParallelError::from)?;
        let mut this = DistributedWorld {
            world: None,
            comm,
            settings,
            decomposition: plan.decomposition,
            domain: plan.domain,
            largest_radius_m: plan.largest_radius_m,
            skin_m: plan.skin_m,
            periodicity,
            owned: Vec::new(),
            send: Vec::new(),
            receive: Vec::new(),
            controlled: Vec::new(),
            reference: Vec::new(),
            parked: Vec::new(),
            drivers: plan.drivers,
            whole_floes: None,
            stats: DecompositionStats::default(),
            fracturing: None,
            cohesion: None,
            ridging: None,
            welding: None,
        };
        let packets = match &whole {
            Some(state) => this.scatter_packets(state),
            None => vec![Vec::new(); this.comm.size()],
        };
        let mine = decode::<Packet>(&this.comm.all_to_all(packets)[0])?;
        this.whole_floes = whole.map(|state| state.floes);
        this.install(vec![mine], plan.clock, model, forcing, periodicity)?;
        Ok(this)
    }

    /// Process 0's packets for a start: each process's floes with their
    /// contacts and broken contacts (those of an owned floe whose partner
    /// is elsewhere too, to be kept aside).
    fn scatter_packets(&self, state: &WorldState) -> Vec<Vec<u8>> {
        let f = state.floes.columns();
        let grid = self.outline_grid(f);
        let mut packets = vec![Packet::default(); self.comm.size()];
        let placed: Vec<(usize, Vec<usize>)> = (0..f.len())
            .map(|i| self.holders(f, i, &grid, self.periodicity))
            .collect();
        for (i, (owner, holders)) in placed.iter().enumerate() {
            for &r in holders {
                packets[r]
                    .floes
                    .push(migrant(state, i, *owner, holders.clone()));
            }
        }
        let id = |h: u32| f.id[h as usize];
        let both = |a: u32, b: u32| {
            let (ha, hb) = (&placed[a as usize].1, &placed[b as usize].1);
            ha.iter().copied().filter(move |r| hb.contains(r))
        };
        for c in &state.contacts {
            for r in both(c.a, c.b) {
                packets[r].contacts.push(([id(c.a), id(c.b)], *c));
            }
        }
        for b in &state.bonds {
            for r in both(b.a, b.b) {
                packets[r].bonds.push(([id(b.a), id(b.b)], *b));
            }
        }
        for c in &state.broken {
            let mut ranks: Vec<usize> = both(c.a, c.b).collect();
            ranks.extend([placed[c.a as usize].0, placed[c.b as usize].0]);
            ranks.sort_unstable();
            ranks.dedup();
            for r in ranks {
                packets[r].broken.push(([id(c.a), id(c.b)], *c));
            }
        }
        packets.iter().map(encode).collect()
    }

    /// The halo's skin the settings ask for, m.
    fn base_skin_m(&self) -> f64 {
        self.settings.skin_fraction * self.largest_radius_m
    }

    /// Bonds form and break from the next step on, as
    /// [`World::set_cohesion`], on every process (`None` drops them).
    pub fn set_cohesion(&mut self, cohesion: Option<Cohesion>) -> Result<(), ParallelError> {
        self.local_mut().set_cohesion(cohesion)?;
        self.cohesion = cohesion;
        Ok(())
    }

    /// The ids of the floes this process owns, sorted: what fracture and
    /// ridging keep across edits that renumber the handles.
    fn owned_ids(&self) -> Vec<u64> {
        let f = self.local().floes().columns();
        (0..f.len())
            .filter(|&h| self.owned[h])
            .map(|h| f.id[h])
            .collect()
    }

    /// Marks as owned the local floes whose ids are in `ids` (sorted).
    fn own_ids(&mut self, ids: &[u64]) {
        let f = self.local().floes().columns();
        self.owned =
            f.id.iter()
                .map(|id| ids.binary_search(id).is_ok())
                .collect();
    }

    /// Forgets the broken-contact memory kept aside for pairs with a floe
    /// in `gone` (sorted): split or crushed floes.
    fn forget_parked(&mut self, gone: &[u64]) {
        self.parked
            .retain(|(pair, _)| !pair.iter().any(|id| gone.binary_search(id).is_ok()));
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
        let (moved, next_step) = self.motion_bounds();
        let mut v = [
            moved,
            flag(interrupt.load(Ordering::SeqCst)),
            flag(world.forcing_failure().is_some()),
            flag(check_health(world).is_some()),
            next_step,
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
        } else {
            if v[0] > 0.5 * self.skin_m {
                // The skin also covers two steps of the fastest floe, so that
                // the step after a migration stays inside it.
                self.skin_m = self.base_skin_m().max(4.0 * v[4]);
                self.migrate()?;
            }
            report.ridges = self.ridge()?;
            report.welds = self.weld()?;
            if let Some(f) = self.fracturing {
                report.fractures = self.fracture(&f.rule, f.domain_area_m2)?;
            }
        }
        Ok(report)
    }
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
