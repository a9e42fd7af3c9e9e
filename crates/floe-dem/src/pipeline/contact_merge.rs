//! The contact list's update at the end of the narrow phase: the contacts
//! that ended are squeezed out and those that formed merged in, keeping the
//! list sorted by `(a, b)`, in place.

use crate::contacts::ContactRecord;
use crate::exact_sum::ExactSum;
use crate::pipeline::energy_accounting::counted_here;

/// Marks a contact record that ended this step in its `b`, until the list
/// is compacted (floe handles are below `u32::MAX`:
/// [`crate::floes::MAX_FLOES`]); its `a` stays, to tell whose it was.
pub(crate) const DEAD: u32 = u32::MAX;

/// Removes the dead records of `contacts` and merges in the new contacts of
/// every chunk (each sorted, the chunks in order), keeping the list sorted
/// by `(a, b)`. In place: the dead are squeezed out front to back, then the
/// list grows by the number born and is merged back to front, so that no
/// second list is needed. Sequential, one or two moves per record after the
/// first change; it replaced a parallel copy of every record per step.
///
/// No record before index `first_dead` may be dead: the compaction starts
/// there. The contact update knows which chunks ended a contact, and in
/// most steps none did: scanning every record for the dead was most of the
/// merge's time (0.125 ms of a 8.9 ms step at 1e4 floes, one thread).
///
/// Adds the elastic energy the dead records held, J, to `released` (an
/// exact sum: it depends on the set of dead records alone), leaving out
/// the records whose floe `a` is a `ghost` (another process counts them).
pub(crate) fn merge_in_place(
    contacts: &mut Vec<ContactRecord>,
    born: &mut [Vec<ContactRecord>],
    first_dead: usize,
    released: &mut ExactSum,
    ghost: &[bool],
) {
    let first_dead = first_dead.min(contacts.len());
    let mut live = first_dead;
    for r in first_dead..contacts.len() {
        if contacts[r].b != DEAD {
            if live != r {
                contacts[live] = contacts[r];
            }
            live += 1;
        } else if counted_here(ghost, contacts[r].a) {
            released.add(contacts[r].elastic_energy_j());
        }
    }
    contacts.truncate(live);
    let total_born: usize = born.iter().map(Vec::len).sum();
    if total_born == 0 {
        return;
    }
    if live == 0 {
        // The first step, or a pack that had come apart: copy the chunks in
        // order and free each as it is copied, so that the list and the
        // born lists are not both resident in full.
        contacts.reserve_exact(total_born);
        for b in born.iter_mut() {
            contacts.extend_from_slice(b);
            release_if_large(b);
        }
        return;
    }
    let Some(&fill) = born.iter().find_map(|b| b.first()) else {
        return;
    };
    contacts.resize(live + total_born, fill);
    let key = |c: &ContactRecord| (c.a, c.b);
    let (mut old, mut write) = (live, live + total_born);
    for chunk in born.iter().rev() {
        for record in chunk.iter().rev() {
            while old > 0 && key(&contacts[old - 1]) > key(record) {
                write -= 1;
                old -= 1;
                contacts[write] = contacts[old];
            }
            write -= 1;
            contacts[write] = *record;
        }
    }
    debug_assert_eq!(write, old);
    born.iter_mut().for_each(release_if_large);
}

/// Frees a born list that grew beyond what a step usually creates (a few
/// contacts per chunk), so that a burst of new contacts does not stay
/// resident for the rest of the run.
fn release_if_large(born: &mut Vec<ContactRecord>) {
    if born.capacity() > 64 {
        *born = Vec::new();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec2;
    use floe_friction::ContactState;
    use proptest::prelude::*;

    fn record(a: u32, b: u32, tag: f64) -> ContactRecord {
        ContactRecord {
            a,
            b,
            image_offset: Vec2::ZERO,
            friction: ContactState::default(),
            age_steps: 0,
            overlap_m2: tag,
            point: Vec2::ZERO,
            normal: Vec2::X,
            length_m: 0.0,
            normal_force_n: 0.0,
            slip_rate_m_per_s: 0.0,
            friction_power_w: 0.0,
            damping_power_w: 0.0,
            elastic_force_n: 0.0,
            // Energies with round-off in their sums, so that the order of
            // the released-energy sum shows.
            normal_energy_j: tag / 3.0,
            tangential_energy_j: tag.sqrt(),
        }
    }

    proptest! {
        /// The in-place compaction and merge against the obvious way: keep the
        /// live records, add the born ones, sort.
        #[test]
        fn merging_in_place_equals_filtering_and_sorting(
            keys in prop::collection::btree_set((0u32..60, 0u32..60), 0..200),
            fate in prop::collection::vec(0u8..3, 200),
            chunks in 1usize..6,
            start_at in 0usize..200,
        ) {
            // Each key is a surviving old contact, a dead one, or born this step.
            let keys: Vec<(u32, u32)> = keys.into_iter().collect();
            let mut contacts = Vec::new();
            let mut born_all = Vec::new();
            for (i, &(a, b)) in keys.iter().enumerate() {
                match fate[i] {
                    0 => contacts.push(record(a, b, i as f64)),
                    1 => contacts.push(record(a, DEAD, i as f64)),
                    _ => born_all.push(record(a, b, i as f64)),
                }
            }
            // Dead records of even floes count; odd floes are ghosts.
            let ghost: Vec<bool> = (0..60).map(|h| h % 2 == 1).collect();
            let mut dead_energy = ExactSum::new();
            for c in contacts.iter().rev().filter(|c| c.b == DEAD && c.a % 2 == 0) {
                dead_energy.add(c.elastic_energy_j());
            }
            let mut expected: Vec<ContactRecord> = contacts
                .iter()
                .filter(|c| c.b != DEAD)
                .chain(&born_all)
                .copied()
                .collect();
            expected.sort_by_key(|c| (c.a, c.b));
            // Born contacts split into consecutive chunks, as the narrow phase makes them.
            let per = born_all.len().div_ceil(chunks).max(1);
            let mut born: Vec<Vec<ContactRecord>> = born_all.chunks(per).map(<[_]>::to_vec).collect();
            // From the first dead record, as the world passes it, or from
            // anywhere before it: the same result.
            let first_dead = contacts.iter().position(|c| c.b == DEAD).unwrap_or(contacts.len());
            let mut from_start = contacts.clone();
            let mut born_again = born.clone();
            let (mut released, mut released_from_start) = (ExactSum::new(), ExactSum::new());
            merge_in_place(&mut contacts, &mut born, first_dead, &mut released, &ghost);
            merge_in_place(&mut from_start, &mut born_again, start_at.min(first_dead), &mut released_from_start, &ghost);
            prop_assert_eq!(&from_start, &contacts);
            prop_assert_eq!(&released_from_start, &released);
            prop_assert_eq!(contacts, expected);
            // What the dead of the floes not ghosts held, summed in reverse.
            prop_assert_eq!(released, dead_energy);
        }
    }
}
