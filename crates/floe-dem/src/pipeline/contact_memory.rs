//! Contact memory: the friction state of contacts that broke, kept for
//! [`ContactModel::memory_s`](crate::contact_model::ContactModel::memory_s)
//! so that a pair touching again within that time resumes its `theta`.

use crate::contacts::{BrokenContact, ContactRecord};

/// The remembered contacts after a step: those already remembered and
/// those that broke this step (`newly_broken`, in pair order), less the
/// ones older than `memory_s` at `now_s` and the pairs touching again
/// (`contacts`). Both inputs are sorted by pair; a pair in both keeps its
/// newest entry.
pub(crate) fn remember_broken<'a>(
    broken: &'a [BrokenContact],
    newly_broken: impl Iterator<Item = &'a BrokenContact>,
    contacts: &[ContactRecord],
    now_s: f64,
    memory_s: f64,
) -> Vec<BrokenContact> {
    let touching = |c: &BrokenContact| {
        contacts
            .binary_search_by(|r| (r.a, r.b).cmp(&(c.a, c.b)))
            .is_ok()
    };
    let mut merged: Vec<BrokenContact> = broken
        .iter()
        .chain(newly_broken)
        .filter(|c| now_s - c.broke_at_s <= memory_s && !touching(c))
        .copied()
        .collect();
    // A stable sort keeps the newest entry last.
    merged.sort_by_key(|c| (c.a, c.b));
    merged.dedup_by(|later, earlier| {
        let same = (later.a, later.b) == (earlier.a, earlier.b);
        if same {
            *earlier = *later;
        }
        same
    });
    merged
}

/// The remembered state of pair `(a, b)`, if it broke recently.
#[inline]
pub(crate) fn recall(broken: &[BrokenContact], a: u32, b: u32) -> Option<&BrokenContact> {
    broken
        .binary_search_by(|c| (c.a, c.b).cmp(&(a, b)))
        .ok()
        .map(|k| &broken[k])
}
