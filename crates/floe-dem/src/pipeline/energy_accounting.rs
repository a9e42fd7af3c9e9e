//! Energy accounting: the work of forcing and walls and the dissipation of
//! friction and dashpots over a step, summed into the
//! [`EnergyLedger`].
//!
//! Every sum is exact ([`ExactSum`], rounded once when it is booked), so it
//! depends on the set of terms alone: not on the thread count, on how the
//! narrow phase cut its work, or on how the floes are split between
//! processes. A process counts the floes it owns and the contacts whose
//! floe `a` it owns; a ghost (another process's floe) is counted there.
//! The step's sums ([`StepSums`]) can be combined across processes before
//! they are booked ([`World::kick_with`](crate::world::World::kick_with)).

use crate::contact_kernel::force_and_torques;
use crate::contacts::ContactRecord;
use crate::energy_ledger::EnergyLedger;
use crate::exact_sum::{ExactSum, EXACT_SUM_WORDS};
use crate::floes::FloeColumns;
use crate::Vec2;

/// Floes per block of the forcing's power sums.
pub(crate) const ENERGY_CHUNK: usize = 4096;

/// Whether floe `h`'s terms are summed by this process: it is not a
/// `ghost` (an empty mask: no floe is).
#[inline]
pub(crate) fn counted_here(ghost: &[bool], h: u32) -> bool {
    ghost.get(h as usize) != Some(&true)
}

/// Power of a set of contacts over a step: summed by the narrow phase, per
/// chunk of its work, as each contact's step completes, so that the
/// contact list is not read again for it (measured neither faster nor
/// slower than a pass of its own: CHANGELOG).
#[derive(Debug, Default, Clone)]
pub(crate) struct ContactPower {
    /// Dissipated by friction, W.
    friction_w: ExactSum,
    /// Dissipated by normal damping, W.
    damping_w: ExactSum,
    /// Put in by walls (floes with prescribed motion), W.
    boundary_w: ExactSum,
}

impl ContactPower {
    /// Adds a contact whose step is complete, unless its floe `a` is a
    /// `ghost` (another process counts it).
    #[inline]
    pub(crate) fn add(&mut self, c: &ContactRecord, f: &FloeColumns, ghost: &[bool]) {
        if !counted_here(ghost, c.a) {
            return;
        }
        self.friction_w.add(c.friction_power_w);
        self.damping_w.add(c.damping_power_w);
        // Work done by a wall on the floe it touches: the force the wall
        // exerts (the opposite of the force on it) times its velocity.
        // Only wall contacts need the force.
        let (a, b) = (c.a as usize, c.b as usize);
        if f.is_free(a) && f.is_free(b) {
            return;
        }
        let (fb, _, _) = force_and_torques(c, f.position[a], f.position[b] + c.image_offset);
        if !f.is_free(a) {
            self.boundary_w.add(fb.dot(f.velocity[a]));
        }
        if !f.is_free(b) {
            self.boundary_w.add((-fb).dot(f.velocity[b]));
        }
    }

    /// Adds another set's powers.
    fn merge(&mut self, other: &ContactPower) {
        self.friction_w.merge(&other.friction_w);
        self.damping_w.merge(&other.damping_w);
        self.boundary_w.merge(&other.boundary_w);
    }
}

/// This process's energy sums of the bonds over a step (the cohesion
/// stage adds to them).
#[derive(Debug, Default, Clone)]
pub(crate) struct BondPower {
    /// Dissipated by the bonds' dashpots, W.
    pub(crate) damping_w: ExactSum,
    /// Put in by prescribed floes (land, walls) through bonds, W.
    pub(crate) boundary_w: ExactSum,
    /// Stored in the bonds that broke this step, J.
    pub(crate) released_j: ExactSum,
}

/// The sums of a step that go into the energy ledger, exact, so that
/// partial sums from several processes combine into the same bits
/// ([`StepSums::to_words`], an integer sum of which is the sum of the
/// parts).
#[derive(Debug, Default, Clone, PartialEq)]
pub struct StepSums {
    /// Power of the external forcing on the free floes, W.
    pub forcing_w: ExactSum,
    /// Dissipated by friction, W.
    pub friction_w: ExactSum,
    /// Dissipated by normal damping, W.
    pub damping_w: ExactSum,
    /// Put in by walls, W.
    pub boundary_w: ExactSum,
    /// Elastic energy of the contacts that ended, J.
    pub released_j: ExactSum,
}

/// Words in [`StepSums::to_words`].
pub const STEP_SUM_WORDS: usize = 5 * EXACT_SUM_WORDS;

impl StepSums {
    /// The sums as integers: adding two processes' words element by
    /// element gives the words of their combined sums.
    pub fn to_words(&self) -> Vec<i64> {
        let mut words = Vec::with_capacity(STEP_SUM_WORDS);
        for s in self.sums() {
            words.extend_from_slice(&s.to_words());
        }
        words
    }

    /// The sums from [`StepSums::to_words`]'s words (`STEP_SUM_WORDS` of them).
    pub fn from_words(words: &[i64]) -> Self {
        let part = |k: usize| {
            let mut w = [0i64; EXACT_SUM_WORDS];
            w.copy_from_slice(&words[k * EXACT_SUM_WORDS..(k + 1) * EXACT_SUM_WORDS]);
            ExactSum::from_words(&w)
        };
        StepSums {
            forcing_w: part(0),
            friction_w: part(1),
            damping_w: part(2),
            boundary_w: part(3),
            released_j: part(4),
        }
    }

    fn sums(&self) -> [&ExactSum; 5] {
        [
            &self.forcing_w,
            &self.friction_w,
            &self.damping_w,
            &self.boundary_w,
            &self.released_j,
        ]
    }
}

/// What the accounting keeps between the stages of a step (reused every step).
#[derive(Debug, Default)]
pub(crate) struct EnergyAccounting {
    /// Per chunk of the narrow phase's work, the sums of its contacts'
    /// powers (the narrow phase fills it).
    pub(crate) contact_partials: Vec<ContactPower>,
    /// Per block of floes, the power of the external forces.
    pub(crate) forcing_partials: Vec<ExactSum>,
    /// The step's energy released at break (the narrow phase adds to it).
    pub(crate) released_j: ExactSum,
    /// The bonds' sums of the step (the cohesion stage adds to them).
    pub(crate) bonds: BondPower,
    /// The external forces at the start of the step, N, for the work
    /// integral (trapezoidal in the force).
    pub(crate) previous_external_force: Vec<Vec2>,
    /// The external torques at the start of the step, N m.
    pub(crate) previous_external_torque: Vec<f64>,
}

impl EnergyAccounting {
    /// Keeps this step's starting external forces: swaps them with the
    /// buffers the force gathering fills next.
    pub(crate) fn begin_step(
        &mut self,
        external_force: &mut Vec<Vec2>,
        external_torque: &mut Vec<f64>,
    ) {
        let n = external_force.len();
        self.previous_external_force.resize(n, Vec2::ZERO);
        self.previous_external_torque.resize(n, 0.0);
        std::mem::swap(external_force, &mut self.previous_external_force);
        std::mem::swap(external_torque, &mut self.previous_external_torque);
    }

    /// This process's sums of the step, and resets them for the next.
    pub(crate) fn take_step_sums(&mut self) -> StepSums {
        let mut forcing_w = ExactSum::new();
        for p in &self.forcing_partials {
            forcing_w.merge(p);
        }
        let mut power = ContactPower::default();
        for p in &self.contact_partials {
            power.merge(p);
        }
        let bonds = std::mem::take(&mut self.bonds);
        power.damping_w.merge(&bonds.damping_w);
        power.boundary_w.merge(&bonds.boundary_w);
        let mut released_j = std::mem::take(&mut self.released_j);
        released_j.merge(&bonds.released_j);
        StepSums {
            forcing_w,
            friction_w: power.friction_w,
            damping_w: power.damping_w,
            boundary_w: power.boundary_w,
            released_j,
        }
    }
}

/// Adds a step's work and dissipation (`sums`, of every process) to `ledger`.
pub(crate) fn book_step(sums: &StepSums, ledger: &mut EnergyLedger, dt: f64) {
    ledger.forcing_work_j += dt * sums.forcing_w.value();
    ledger.friction_dissipation_j += dt * sums.friction_w.value();
    ledger.damping_dissipation_j += dt * sums.damping_w.value();
    ledger.boundary_work_j += dt * sums.boundary_w.value();
    ledger.released_at_break_j += sums.released_j.value();
}

/// Power of the external forcing on a free floe over the step, W:
/// trapezoidal in the force (`previous` at the start, `now` at the end),
/// with the half-step velocity, as the contacts' powers are. With the
/// velocity after the kick instead, each step would add `dt^2/2m F_ext .
/// F`, a bias that grows with the run (a spring-driven block gained 30 %
/// of its kinetic energy in 10 s); with the half-step velocity the
/// difference from the kinetic energy's change telescopes and stays
/// `O(dt^2)` (`tests/dem/load_point.rs`).
#[inline(always)]
pub(crate) fn forcing_power(
    (previous_force, previous_torque): (Vec2, f64),
    (force, torque): (Vec2, f64),
    velocity: Vec2,
    angular_velocity: f64,
) -> f64 {
    let mean_f = 0.5 * (previous_force + force);
    let mean_t = 0.5 * (previous_torque + torque);
    mean_f.dot(velocity) + mean_t * angular_velocity
}
