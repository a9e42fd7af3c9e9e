//! Force gathering: the external forces and the contact forces on every
//! floe, summed per floe in contact order (never scattered with atomics),
//! so the sums are the same for any thread count.

use rayon::prelude::*;

use crate::contact_kernel::contact_force_on_b;
use crate::contacts::ContactRecord;
use crate::floes::FloeColumns;
use crate::forcing::{ExternalForces, ForceRates};
use crate::geometry::cross;
use crate::Vec2;

/// The per-floe contact index (reused every step) and whether it still
/// describes the contact list.
#[derive(Debug, Default)]
pub(crate) struct ForceGathering {
    /// `(a, b)` of every contact, copied out of the records for the
    /// sequential passes of the index build.
    keys: Vec<(u32, u32)>,
    /// Per floe, where its contacts as `b` start in `adjacency`.
    adjacency_start: Vec<u32>,
    /// Contacts as `b` of each floe, in contact order.
    adjacency: Vec<u32>,
    /// Per floe, where its block of contacts as `a` starts in the list.
    a_start: Vec<u32>,
    /// The index describes the contact list: no contact ended, formed or
    /// was edited, and no floe was added or removed, since it was built.
    index_current: bool,
    /// Times the index was built (a diagnostic for the tests).
    pub(crate) index_builds: u64,
}

/// Where the gathered forces go: per floe, the total force (N) and torque
/// (N m), their external parts, and the external parts' rates with the
/// floe's velocity.
pub(crate) struct ForceBuffers<'a> {
    pub(crate) force: &'a mut [Vec2],
    pub(crate) torque: &'a mut [f64],
    pub(crate) external_force: &'a mut [Vec2],
    pub(crate) external_torque: &'a mut [f64],
    pub(crate) rates: &'a mut [ForceRates],
}

impl ForceGathering {
    /// The contact list or the floe set changed: the next gathering
    /// rebuilds the index.
    pub(crate) fn invalidate(&mut self) {
        self.index_current = false;
    }

    /// External and contact forces per floe at time `t_s`, from the
    /// per-floe index (rebuilt first if stale).
    pub(crate) fn gather<F: ExternalForces>(
        &mut self,
        f: &FloeColumns,
        contacts: &[ContactRecord],
        forcing: &F,
        t_s: f64,
        out: ForceBuffers<'_>,
    ) {
        let n = f.len();
        let rebuild = !self.index_current;
        self.index_builds += u64::from(rebuild);
        let Self {
            keys,
            adjacency_start,
            adjacency,
            a_start,
            ..
        } = self;
        if rebuild {
            build_adjacency(contacts, n, keys, adjacency_start, a_start, adjacency);
        }
        debug_assert_eq!(a_start.len(), n + 1, "index built for another floe set");
        gather_per_floe(
            f,
            contacts,
            forcing,
            t_s,
            out,
            adjacency_start,
            adjacency,
            a_start,
        );
        self.index_current = true;
    }

    /// Floe `i`'s contacts as `b`, then as `a`, each in contact order,
    /// from the index of the last gathering (which must describe
    /// `contacts`).
    pub(crate) fn contacts_of<'c>(
        &'c self,
        i: usize,
        contacts: &'c [ContactRecord],
    ) -> (
        impl Iterator<Item = &'c ContactRecord> + 'c,
        &'c [ContactRecord],
    ) {
        debug_assert!(
            self.index_current,
            "the index describes another contact list"
        );
        let as_b = self.adjacency
            [self.adjacency_start[i] as usize..self.adjacency_start[i + 1] as usize]
            .iter()
            .map(move |&k| &contacts[k as usize]);
        let as_a = &contacts[self.a_start[i] as usize..self.a_start[i + 1] as usize];
        (as_b, as_a)
    }
}

/// Each floe's forces: its external force, then its contacts as `b`, then
/// as `a`, each group in contact order.
#[allow(clippy::too_many_arguments)] // the index's three arrays
fn gather_per_floe<F: ExternalForces>(
    f: &FloeColumns,
    contacts: &[ContactRecord],
    forcing: &F,
    t: f64,
    out: ForceBuffers<'_>,
    start: &[u32],
    adjacency: &[u32],
    a_start: &[u32],
) {
    let ForceBuffers {
        force,
        torque,
        external_force,
        external_torque,
        rates,
    } = out;
    (force, torque, (external_force, external_torque, rates))
        .into_par_iter()
        .enumerate()
        .for_each(|(i, (force, torque, (ext_f, ext_t, rate)))| {
            let (ef, et, r) = if f.is_free(i) {
                forcing.force_torque_and_rates(t, f, i)
            } else {
                (Vec2::ZERO, 0.0, ForceRates::ZERO)
            };
            *ext_f = ef;
            *ext_t = et;
            *rate = r;
            let (mut fsum, mut tsum) = (ef, et);
            let as_b = adjacency[start[i] as usize..start[i + 1] as usize]
                .iter()
                .map(|&k| &contacts[k as usize]);
            let as_a = &contacts[a_start[i] as usize..a_start[i + 1] as usize];
            // Each contact is visited from both its floes; each visit
            // computes only its own floe's torque (the expressions of
            // `force_and_torques`, so the same bits).
            for c in as_b {
                let fb = contact_force_on_b(c);
                fsum += fb;
                tsum += cross(c.point - (f.position[i] + c.image_offset), fb);
            }
            for c in as_a {
                let fb = contact_force_on_b(c);
                fsum -= fb;
                tsum += cross(c.point - f.position[i], -fb);
            }
            *force = fsum;
            *torque = tsum;
        });
}

/// The per-floe contact index, in contact order. The list is sorted by
/// (a, b) with a < b, so a floe's contacts as `a` are one block of it
/// (from `a_start`), and come after all its contacts as `b` (whose `a` is
/// smaller). So only the contacts as `b` need a list of their own:
/// `adjacency[start[i]..start[i + 1]]` (CSR).
///
/// The keys are first copied out of the 168 B records in parallel: the
/// sequential passes then stream 8 B per contact instead of a cache line or
/// two per record.
fn build_adjacency(
    contacts: &[ContactRecord],
    n: usize,
    keys: &mut Vec<(u32, u32)>,
    start: &mut Vec<u32>,
    a_start: &mut Vec<u32>,
    adjacency: &mut Vec<u32>,
) {
    contacts
        .par_iter()
        .map(|c| (c.a, c.b))
        .collect_into_vec(keys);
    start.clear();
    start.resize(n + 1, 0);
    a_start.clear();
    a_start.reserve(n + 1);
    for (k, &(a, b)) in keys.iter().enumerate() {
        debug_assert!(a < b);
        while a_start.len() <= a as usize {
            a_start.push(k as u32);
        }
        start[b as usize] += 1;
    }
    a_start.resize(n + 1, keys.len() as u32);
    // Each floe's end, then filled back to front: every entry moves down
    // to its floe's start, and each floe's list is in contact order.
    for i in 1..=n {
        start[i] += start[i - 1];
    }
    adjacency.resize(keys.len(), 0);
    for (k, &(_, b)) in keys.iter().enumerate().rev() {
        let end = &mut start[b as usize];
        *end -= 1;
        adjacency[*end as usize] = k as u32;
    }
}
