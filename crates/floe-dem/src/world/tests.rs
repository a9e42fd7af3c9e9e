//! The stages' results do not depend on how their work is cut or cached.

use super::*;
use crate::forcing::NoForcing;
use crate::Vec2;

/// A 12 x 12 grid of squares pressed 2 % into each other and let go:
/// the pack springs apart and most of its contacts break within a few
/// steps of each other, spread over every task of the narrow phase.
fn released_pack() -> World<NoForcing> {
    let square = |c: Vec2| {
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, y)| c + 50.0 * Vec2::new(x, y))
            .to_vec()
    };
    let polys: Vec<Vec<Vec2>> = (0..144)
        .map(|k| {
            square(Vec2::new(
                (k % 12) as f64 * 98.0,
                (k / 12) as f64 * 98.0 + 0.7 * (k % 12) as f64,
            ))
        })
        .collect();
    let thickness: Vec<f64> = (0..144).map(|k| 1.0 + 0.01 * k as f64).collect();
    let floes = Floes::from_polygons(&polys, &thickness, 917.0).unwrap();
    // Restitution 0.5503: the damping ratio (0.2155) these tests were
    // written with, when restitution 0.5 was mapped by the textbook
    // formula (contact_model::damping_ratio_for_restitution).
    let model = ContactModel {
        restitution: 0.5503,
        ..ContactModel::default()
    };
    let dt = 0.5 * stable_time_step(&floes, &model).0;
    World::new(floes, model, NoForcing, Periodicity::default(), dt).unwrap()
}

#[test]
fn results_do_not_depend_on_how_the_candidate_pairs_are_cut_into_tasks() {
    let mut runs: Vec<World<NoForcing>> = [None, Some(7), Some(64)]
        .into_iter()
        .map(|cut| {
            let mut w = released_pack();
            w.pipeline.narrow_phase.fixed_pair_chunk = cut;
            w
        })
        .collect();
    let initial = runs[0].contacts().len();
    let mut most_broken_in_a_step = 0;
    for _ in 0..400 {
        let before = runs[0].contacts().len();
        for w in &mut runs {
            w.step();
        }
        most_broken_in_a_step =
            most_broken_in_a_step.max(before.saturating_sub(runs[0].contacts().len()));
    }
    // The scenario does what it is for: contacts break, many at once.
    assert!(initial > 200, "{initial} initial contacts");
    assert!(
        runs[0].contacts().len() < initial / 2,
        "{} contacts left",
        runs[0].contacts().len()
    );
    assert!(most_broken_in_a_step >= 10, "{most_broken_in_a_step}");
    assert!(runs[0].energy().released_at_break_j != 0.0);
    for w in &runs[1..] {
        assert_eq!(w.energy(), runs[0].energy());
        assert_eq!(w.floes().position, runs[0].floes().position);
        assert_eq!(w.floes().velocity, runs[0].floes().velocity);
        assert_eq!(w.contacts(), runs[0].contacts());
    }
}

/// The force gathering's contact index, kept across steps where the
/// contact list did not change, gives bitwise the results of building
/// it at every step, in a pack where contacts break and form.
#[test]
fn keeping_the_contact_index_gives_the_results_of_rebuilding_it() {
    let (mut kept, mut rebuilt) = (released_pack(), released_pack());
    let builds = kept.pipeline.gathering.index_builds;
    for _ in 0..400 {
        kept.step();
        rebuilt.pipeline.gathering.invalidate();
        rebuilt.step();
    }
    let built = kept.pipeline.gathering.index_builds - builds;
    assert!(built < 200, "the index was built in {built} of 400 steps");
    assert_eq!(kept.energy(), rebuilt.energy());
    assert_eq!(kept.floes().position, rebuilt.floes().position);
    assert_eq!(kept.floes().velocity, rebuilt.floes().velocity);
    assert_eq!(kept.contacts(), rebuilt.contacts());
}

/// Two copies of the released pack stepped in lockstep (the steps are
/// deterministic), each with the index its own last step built, until
/// `edit`, shown the contact list now and the one the next step would
/// make, returns an edited list. Both copies then take it and step: the
/// first keeping its index if it can, the second made to rebuild it.
/// Asks that the edited step formed no contact, built the first copy's
/// index once, and gave both copies the same floes and contacts; returns
/// the first copy for the caller's own checks.
fn step_after_an_edit(
    edit: impl Fn(&[ContactRecord], &[ContactRecord]) -> Option<Vec<ContactRecord>>,
) -> World<NoForcing> {
    let (mut checked, mut rebuilt) = (released_pack(), released_pack());
    let (model, periodicity) = (checked.model.clone(), checked.periodicity);
    for _ in 0..400 {
        let mut ahead = World::resume(
            checked.state().clone(),
            model.clone(),
            NoForcing,
            periodicity,
        )
        .unwrap();
        ahead.step();
        let Some(edited) = edit(checked.contacts(), ahead.contacts()) else {
            checked.step();
            rebuilt.step();
            continue;
        };
        checked.edit_contacts(|c| c.clone_from(&edited)).unwrap();
        rebuilt.edit_contacts(|c| *c = edited).unwrap();
        let builds = checked.pipeline.gathering.index_builds;
        checked.step();
        rebuilt.pipeline.gathering.invalidate();
        rebuilt.step();
        assert!(checked.pipeline.narrow_phase.born.iter().all(Vec::is_empty));
        assert_eq!(checked.pipeline.gathering.index_builds, builds + 1);
        assert_eq!(checked.floes().velocity, rebuilt.floes().velocity);
        assert_eq!(checked.contacts(), rebuilt.contacts());
        return checked;
    }
    panic!("no step allowed the edit");
}

/// No task of the narrow phase ended a contact in `world`'s last step.
fn assert_no_task_ended_a_contact(world: &World<NoForcing>) {
    assert!(world.pipeline.narrow_phase.chunk_ended.iter().all(|&e| !e));
}

fn key(c: &ContactRecord) -> (u32, u32) {
    (c.a, c.b)
}

/// A contact list edited between steps so that the step neither ends
/// nor forms a contact, yet the list is not the one the index was built
/// for: the edit marks the index stale and it is rebuilt. The edit
/// swaps the contacts that end in the next step for those that form in
/// it; without the mark, the step would gather forces through a stale
/// index.
#[test]
fn an_index_of_a_list_edited_between_steps_is_rebuilt() {
    let checked = step_after_an_edit(|now, next| {
        let ending = now
            .iter()
            .filter(|c| next.binary_search_by_key(&key(c), key).is_err())
            .count();
        let forming = next
            .iter()
            .filter(|c| now.binary_search_by_key(&key(c), key).is_err());
        if ending == 0 || ending != forming.clone().count() {
            return None;
        }
        let mut edited: Vec<ContactRecord> = now
            .iter()
            .filter(|c| next.binary_search_by_key(&key(c), key).is_ok())
            .chain(forming)
            .copied()
            .collect();
        edited.sort_by_key(key);
        Some(edited)
    });
    assert_no_task_ended_a_contact(&checked);
}

/// A contact list shortened between steps by the contacts at its end
/// that the next step would end anyway: the step ends and forms
/// nothing, but the list is shorter than the index: rebuilt.
#[test]
fn an_index_of_a_list_shortened_between_steps_is_rebuilt() {
    let checked = step_after_an_edit(|now, next| {
        let ends = |c: &&ContactRecord| next.binary_search_by_key(&key(c), key).is_err();
        let forming = next
            .iter()
            .filter(|c| now.binary_search_by_key(&key(c), key).is_err())
            .count();
        // The contacts after the last one that continues, all ending.
        let tail = now.iter().rev().take_while(ends).count();
        let ending = now.iter().filter(ends).count();
        (tail > 0 && ending == tail && forming == 0 && tail < now.len())
            .then(|| now[..now.len() - tail].to_vec())
    });
    assert_no_task_ended_a_contact(&checked);
}
