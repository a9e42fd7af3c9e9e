//! A run whose floes break: each change of the floe set starts a floe
//! group (segment) of the file, snapshots read back with their own floes
//! and stresses, and a run resumed from a checkpoint taken before a break
//! drops the later segment and ends identical to the uninterrupted run.

use crate::support;

use floe_dem::forcing::Forcing;
use floe_dem::fracture::split::{split_polygon, SplitKey, SplitRule};
use floe_dem::geometry::rotate;
use floe_dem::pipeline::floe_stress::StressFilter;
use floe_dem::world::World;
use floe_dem::Vec2;
use floe_friction::FrictionLaw;
use floe_io::{OutputOptions, RunFile, RunWriter};
use support::{bits, bits2, metadata, pack};

/// The pack at a quarter of its time step (room for pieces) with floe
/// stress, 50 steps on.
fn stressed_pack() -> World<Forcing> {
    let (state, model, forcing, periodicity) = pack().0.into_parts();
    let mut state = state;
    state.dt_s *= 0.25;
    let mut w = World::resume(state, model, forcing, periodicity).unwrap();
    w.set_stress_filter(Some(StressFilter::new(20.0).unwrap()));
    for _ in 0..50 {
        w.step();
    }
    w
}

/// Breaks the largest free floe into three, keyed on the step.
fn break_one(w: &mut World<Forcing>) {
    let f = w.floes();
    let h = (0..f.len())
        .filter(|&h| f.is_free(h))
        .max_by(|&i, &j| f.area_m2[i].total_cmp(&f.area_m2[j]))
        .unwrap();
    let id = f.id[h];
    let (s, c) = f.angle[h].sin_cos();
    let polygon: Vec<Vec2> = f
        .local_vertices(h)
        .iter()
        .map(|&v| rotate(v, c, s))
        .collect();
    let key = SplitKey {
        seed: 1,
        floe_id: id,
        step: w.steps(),
    };
    let (pieces, _) = split_polygon(&polygon, &SplitRule::default(), key).unwrap();
    let first = w.first_free_id();
    let ids: Vec<u64> = (first..first + 3).collect();
    w.split_floe(id, &pieces, &ids).unwrap();
}

/// Snapshot at step 50; 20 steps; snapshot; checkpoint; a break; 20
/// steps; snapshot; a break; 20 steps; snapshot; checkpoint. With
/// `crash_after`, the writer is dropped (no final checkpoint) after that
/// many snapshots, and the run resumed from the file.
fn run(path: &std::path::Path, crash_after: Option<usize>) {
    let mut world = stressed_pack();
    let slots = world.model().law.state_slots();
    let opts = OutputOptions {
        floe_stress: true,
        ..OutputOptions::default()
    };
    let mut w = RunWriter::create(path, &metadata(), world.floes(), &opts).unwrap();
    w.write_snapshot(&world).unwrap();
    let mut snapshots = 1;
    for round in 0..4 {
        if round >= 2 {
            break_one(&mut world);
        }
        for _ in 0..20 {
            world.step();
        }
        w.write_snapshot(&world).unwrap();
        snapshots += 1;
        if round == 0 || round == 3 {
            w.write_checkpoint(world.state(), slots).unwrap();
        }
        if crash_after == Some(snapshots) {
            drop(w);
            let (resumed, state, _) = RunWriter::reopen_for_resume(path, || None, slots).unwrap();
            w = resumed;
            let (_, model, forcing, periodicity) = world.into_parts();
            world = World::resume(state, model, forcing, periodicity).unwrap();
            // Back at the checkpoint after round 0: rounds 1.. again.
            for round in 1..4 {
                if round >= 2 {
                    break_one(&mut world);
                }
                for _ in 0..20 {
                    world.step();
                }
                w.write_snapshot(&world).unwrap();
                if round == 3 {
                    w.write_checkpoint(world.state(), slots).unwrap();
                }
            }
            return;
        }
    }
}

#[test]
fn breaks_start_segments_and_a_resume_before_a_break_drops_the_later_one() {
    let dir = tempfile::tempdir().unwrap();
    let (whole, parts) = (dir.path().join("whole.h5"), dir.path().join("parts.h5"));
    run(&whole, None);
    // Crash after the fourth snapshot: one break written in a segment the
    // checkpoint (after the second snapshot) does not know.
    run(&parts, Some(4));
    let (a, b) = (
        RunFile::open(&whole).unwrap(),
        RunFile::open(&parts).unwrap(),
    );
    let n = a.snapshot_count().unwrap();
    assert_eq!(n, 5);
    assert_eq!(b.snapshot_count().unwrap(), n);
    let counts: Vec<usize> = (0..n).map(|k| a.floes_at(k).unwrap().len()).collect();
    let n0 = counts[0];
    assert_eq!(
        counts,
        vec![n0, n0, n0, n0 + 2, n0 + 4],
        "two breaks, two pieces more each"
    );
    for k in 0..n {
        let (fa, fb) = (a.floes_at(k).unwrap(), b.floes_at(k).unwrap());
        assert_eq!(fa, fb, "floes at {k}");
        let (sa, sb) = (a.snapshot(k).unwrap(), b.snapshot(k).unwrap());
        assert_eq!(sa.step, sb.step);
        assert_eq!(sa.position.len(), fa.len());
        assert_eq!(bits2(&sa.position), bits2(&sb.position), "positions {k}");
        assert_eq!(bits(&sa.angle), bits(&sb.angle), "angles {k}");
        let (ta, tb) = (
            a.floe_stress(k).unwrap().unwrap(),
            b.floe_stress(k).unwrap().unwrap(),
        );
        assert_eq!(ta.len(), fa.len());
        assert_eq!(ta, tb, "stress {k}");
        let (ca, cb) = (a.contacts(k).unwrap(), b.contacts(k).unwrap());
        assert_eq!(ca.pair, cb.pair, "contacts {k}");
        assert!(
            ca.pair.iter().all(|p| (p[1] as usize) < fa.len()),
            "pairs index the snapshot's floes"
        );
    }
    assert_eq!(a.snapshot_times().unwrap(), b.snapshot_times().unwrap());
    // Three new ids, one parent gone.
    let (before, after) = (a.floes_at(2).unwrap(), a.floes_at(3).unwrap());
    assert_eq!(
        after.id.iter().filter(|id| !before.id.contains(id)).count(),
        3
    );
    assert_eq!(
        before.id.iter().filter(|id| !after.id.contains(id)).count(),
        1
    );
    let (sa, sb) = (
        a.checkpoint_state(|| None).unwrap().unwrap(),
        b.checkpoint_state(|| None).unwrap().unwrap(),
    );
    assert_eq!(format!("{sa:?}"), format!("{sb:?}"));
}
