//! Friction: the one place the DEM calls the friction law. A contact's
//! tangential spring and state advance here, [`FRICTION_BATCH`] contacts at
//! a time ([`floe_friction::Law::step_batch`]), and a new contact gets its
//! first state here ([`new_contact_state`]).
//!
//! The narrow phase computes each contact's load (normal force, tangential
//! stiffness, relative tangential velocity) and hands it to a
//! `FrictionBatch`; when the batch is full, or the task's pairs are done,
//! `FrictionBatch::flush` steps the law for all waiting contacts side by
//! side and completes their records ([`finish_friction`]).

use floe_friction::{
    BatchItem, ContactLoad, ContactState, FrictionLaw, StepOutcome, LAW_STATE_SLOTS,
};

use crate::contact_kernel::finish_friction;
use crate::contact_model::ContactModel;
use crate::contacts::ContactRecord;

/// Contacts whose friction is stepped together: found by the narrow phase,
/// held until this many wait, then advanced side by side (64 and 128 were
/// measured no better).
pub const FRICTION_BATCH: usize = 32;

/// The friction state of a contact that has just formed: steady sliding at
/// [`ContactModel::new_contact_slip_rate_m_per_s`] with an unloaded spring.
pub fn new_contact_state(model: &ContactModel) -> ContactState {
    let mut s = model
        .law
        .steady_state(model.new_contact_slip_rate_m_per_s, 0.0);
    s.tangential_force_n = 0.0;
    s
}

/// Where a contact's record is while its friction step waits.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Slot {
    /// Updated in place, at this index of the task's run of previous contacts.
    Run(usize),
    /// New this step, at this index of the task's born list.
    Born(usize),
}

/// The outcome of a friction step not yet taken.
const NO_OUTCOME: StepOutcome = StepOutcome {
    slip_rate_m_per_s: 0.0,
    mu: 0.0,
    iterations: 0,
};

/// Placeholder for the unused slots of the batch.
const NO_ITEM: BatchItem = BatchItem {
    state: ContactState {
        tangential_force_n: 0.0,
        law_state: [0.0; LAW_STATE_SLOTS],
    },
    load: ContactLoad {
        load_point_velocity_m_per_s: 0.0,
        stiffness_n_per_m: 0.0,
        normal_load_n: 0.0,
    },
    outcome: NO_OUTCOME,
};

/// Contacts waiting for their friction step. Only a workspace: every entry
/// is written before it is read.
pub(crate) struct FrictionBatch {
    /// Where each waiting contact's record is.
    slots: [Slot; FRICTION_BATCH],
    /// The power of each waiting contact's elastic normal force, W.
    elastic_power: [f64; FRICTION_BATCH],
    /// The waiting friction steps, side by side for `Law::step_batch`.
    items: [BatchItem; FRICTION_BATCH],
    /// How many wait.
    waiting: usize,
}

impl Default for FrictionBatch {
    fn default() -> Self {
        Self {
            slots: [Slot::Run(0); FRICTION_BATCH],
            elastic_power: [0.0; FRICTION_BATCH],
            items: [NO_ITEM; FRICTION_BATCH],
            waiting: 0,
        }
    }
}

impl FrictionBatch {
    /// Adds a contact whose record is at `slot`, in state `state`, under
    /// `load`, with its elastic normal force's power (W); returns whether
    /// the batch is now full (then [`FrictionBatch::flush`] it).
    #[inline]
    pub(crate) fn add(
        &mut self,
        slot: Slot,
        state: ContactState,
        load: ContactLoad,
        elastic_power_w: f64,
    ) -> bool {
        let k = self.waiting;
        self.items[k] = BatchItem {
            state,
            load,
            outcome: NO_OUTCOME,
        };
        self.slots[k] = slot;
        self.elastic_power[k] = elastic_power_w;
        self.waiting = k + 1;
        self.waiting == FRICTION_BATCH
    }

    /// Steps the waiting contacts' friction over `dt` (none with `dt = 0`,
    /// at the start of a run) and completes their records, found in `run`
    /// or `born` by their slots; hands each completed record to `done`.
    #[inline]
    pub(crate) fn flush(
        &mut self,
        model: &ContactModel,
        dt: f64,
        (run, born): (&mut [ContactRecord], &mut [ContactRecord]),
        mut done: impl FnMut(&ContactRecord),
    ) {
        let n = self.waiting;
        self.waiting = 0;
        let items = &mut self.items[..n];
        if dt > 0.0 {
            model.law.step_batch(items, dt);
        }
        for ((slot, item), &power) in self.slots[..n]
            .iter()
            .zip(&*items)
            .zip(&self.elastic_power[..n])
        {
            let record = match *slot {
                Slot::Run(k) => &mut run[k],
                Slot::Born(k) => &mut born[k],
            };
            finish_friction(record, item, power, dt);
            done(record);
        }
    }

    /// Whether contacts wait.
    #[inline]
    pub(crate) fn is_empty(&self) -> bool {
        self.waiting == 0
    }
}
