//! The contact list's update at the end of the narrow phase: the contacts
//! that ended are squeezed out and those that formed merged in, keeping the
//! list sorted by `(a, b)`, in place.

use crate::contacts::ContactRecord;

/// Marks a contact record that ended this step, until the list is compacted
/// (floe handles are below `u32::MAX`: [`crate::floes::MAX_FLOES`]).
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
/// Returns the elastic energy the dead records held, J, summed in list
/// order: the sum depends on the contact list alone, not on how the
/// candidate pairs were cut into tasks (which a resumed run, rebuilding its
/// pair list at another step, does differently).
pub(crate) fn merge_in_place(
    contacts: &mut Vec<ContactRecord>,
    born: &mut [Vec<ContactRecord>],
    first_dead: usize,
) -> f64 {
    let first_dead = first_dead.min(contacts.len());
    let mut live = first_dead;
    let mut released_j = 0.0;
    for r in first_dead..contacts.len() {
        if contacts[r].a != DEAD {
            if live != r {
                contacts[live] = contacts[r];
            }
            live += 1;
        } else {
            released_j += contacts[r].elastic_energy_j();
        }
    }
    contacts.truncate(live);
    let total_born: usize = born.iter().map(Vec::len).sum();
    if total_born == 0 {
        return released_j;
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
        return released_j;
    }
    let Some(&fill) = born.iter().find_map(|b| b.first()) else {
        return released_j;
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
    released_j
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
                    1 => contacts.push(record(DEAD, b, i as f64)),
                    _ => born_all.push(record(a, b, i as f64)),
                }
            }
            let dead_energy = contacts
                .iter()
                .filter(|c| c.a == DEAD)
                .fold(0.0, |sum, c| sum + c.elastic_energy_j());
            let mut expected: Vec<ContactRecord> = contacts
                .iter()
                .filter(|c| c.a != DEAD)
                .chain(&born_all)
                .copied()
                .collect();
            expected.sort_by_key(|c| (c.a, c.b));
            // Born contacts split into consecutive chunks, as the narrow phase makes them.
            let per = born_all.len().div_ceil(chunks).max(1);
            let mut born: Vec<Vec<ContactRecord>> = born_all.chunks(per).map(<[_]>::to_vec).collect();
            // From the first dead record, as the world passes it, or from
            // anywhere before it: the same result.
            let first_dead = contacts.iter().position(|c| c.a == DEAD).unwrap_or(contacts.len());
            let mut from_start = contacts.clone();
            let mut born_again = born.clone();
            let released = merge_in_place(&mut contacts, &mut born, first_dead);
            let released_from_start = merge_in_place(&mut from_start, &mut born_again, start_at.min(first_dead));
            prop_assert_eq!(&from_start, &contacts);
            prop_assert_eq!(released_from_start.to_bits(), released.to_bits());
            prop_assert_eq!(contacts, expected);
            // What the dead held, summed in list order.
            prop_assert_eq!(released.to_bits(), dead_energy.to_bits());
        }
    }
}
