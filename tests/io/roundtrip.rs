//! What is written is read back bitwise, the checkpoint resumes the run
//! bitwise, and a resumed file ends identical to an uninterrupted one.

use crate::support;

use floe_dem::forcing::Forcing;
use floe_dem::world::World;
use floe_friction::rate_state::THETA;
use floe_friction::FrictionLaw;
use floe_io::{OutputOptions, RunFile, RunWriter};
use support::{bits, bits2, domain_area, fingerprint, metadata, pack, vec2_bits};

/// What the run looked like at each snapshot.
struct Expected {
    step: u64,
    time_s: f64,
    world_floes: floe_dem::floes::Floes,
    contacts: Vec<floe_dem::contacts::ContactRecord>,
}

fn observe(w: &mut RunWriter, world: &World<Forcing>) {
    w.write_observables(world.steps(), &world.observables(domain_area()))
        .unwrap();
}

#[test]
fn everything_written_reads_back_bitwise() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.h5");
    let (mut world, parts) = pack();
    let mut w =
        RunWriter::create(&path, &metadata(), world.floes(), &OutputOptions::default()).unwrap();
    assert_eq!(w.path(), path.as_path());
    w.set_status("running").unwrap();
    let mut expected = Vec::new();
    let mut observables = Vec::new();
    let snap = |w: &mut RunWriter, world: &World<Forcing>, expected: &mut Vec<Expected>| {
        w.write_snapshot(world).unwrap();
        expected.push(Expected {
            step: world.steps(),
            time_s: world.time_s(),
            world_floes: world.floes().clone(),
            contacts: world.contacts().to_vec(),
        });
    };
    snap(&mut w, &world, &mut expected);
    for round in 0..4 {
        for _ in 0..150 {
            world.step();
            if world.steps().is_multiple_of(30) {
                observe(&mut w, &world);
                observables.push((world.steps(), world.observables(domain_area())));
            }
        }
        snap(&mut w, &world, &mut expected);
        if round % 2 == 1 {
            w.write_checkpoint(world.state(), world.model().law.state_slots())
                .unwrap();
        }
    }
    let saved = world.state();
    w.set_status("completed").unwrap();
    drop(w);
    assert!(
        expected.iter().any(|e| e.contacts.len() > 10),
        "the pack should be in contact"
    );

    let file = RunFile::open(&path).unwrap();
    assert_eq!(file.status().unwrap(), "completed");
    assert_eq!(file.metadata().unwrap(), metadata());

    // Fixed floe properties, the wall's included.
    let sf = file.static_floes().unwrap();
    let f = &expected[0].world_floes;
    let n = f.len();
    assert_eq!(sf.len(), n);
    assert_eq!(sf.id, f.id[..n]);
    assert_eq!(sf.vertex_offsets, f.vertex_start[..=n]);
    assert_eq!(
        bits2(&sf.vertices),
        vec2_bits(&f.vertices[..f.vertex_start[n] as usize])
    );
    assert_eq!(bits(&sf.thickness_m), bits(&f.thickness_m[..n]));
    assert_eq!(bits(&sf.mass_kg), bits(&f.mass_kg[..n]));
    assert_eq!(bits(&sf.area_m2), bits(&f.area_m2[..n]));
    assert_eq!(bits(&sf.inertia_kg_m2), bits(&f.inertia_kg_m2[..n]));
    let walls: Vec<usize> = (0..n).filter(|&i| sf.prescribed[i]).collect();
    assert_eq!(walls, vec![n - 1], "the last floe is the wall");

    // Snapshots and contacts.
    assert_eq!(file.snapshot_count().unwrap(), expected.len());
    for (k, e) in expected.iter().enumerate() {
        let s = file.snapshot(k).unwrap();
        assert_eq!((s.step, s.time_s.to_bits()), (e.step, e.time_s.to_bits()));
        let f = &e.world_floes;
        assert_eq!(
            bits2(&s.position),
            vec2_bits(&f.position[..n]),
            "snapshot {k}"
        );
        assert_eq!(bits2(&s.velocity), vec2_bits(&f.velocity[..n]));
        assert_eq!(bits(&s.angle), bits(&f.angle[..n]));
        assert_eq!(bits(&s.angular_velocity), bits(&f.angular_velocity[..n]));
        for i in [0, 7, n - 1] {
            let engine: Vec<[f64; 2]> = f.world_vertices(i).iter().map(|v| [v.x, v.y]).collect();
            assert_eq!(
                bits2(&s.world_vertices(&sf, i)),
                bits2(&engine),
                "floe {i} outline"
            );
        }
        let c = file.contacts(k).unwrap();
        assert_eq!((c.step, c.time_s.to_bits()), (e.step, e.time_s.to_bits()));
        let cs = &e.contacts;
        let col = |g: fn(&floe_dem::contacts::ContactRecord) -> f64| -> Vec<u64> {
            cs.iter().map(|c| g(c).to_bits()).collect()
        };
        assert_eq!(c.pair, cs.iter().map(|c| [c.a, c.b]).collect::<Vec<_>>());
        assert_eq!(bits(&c.theta), col(|c| c.friction.law_state[THETA]));
        assert_eq!(bits(&c.mu), col(|c| c.mu()));
        assert_eq!(bits(&c.normal_force_n), col(|c| c.normal_force_n));
        assert_eq!(bits(&c.tangential_force_n), col(|c| c.tangential_force_n()));
        assert_eq!(bits(&c.slip_rate_m_per_s), col(|c| c.slip_rate_m_per_s));
        assert_eq!(bits(&c.overlap_m2), col(|c| c.overlap_m2));
        let points: Vec<_> = cs.iter().map(|c| c.point).collect();
        let normals: Vec<_> = cs.iter().map(|c| c.normal).collect();
        assert_eq!(bits2(&c.point), vec2_bits(&points));
        assert_eq!(bits2(&c.normal), vec2_bits(&normals));
    }
    assert!(file.snapshot(expected.len()).is_err());

    // Observables.
    let names = file.observable_names().unwrap();
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(names, sorted);
    assert_eq!(names.len(), 13);
    let ke = file.observable("kinetic_translational").unwrap();
    assert_eq!(ke.unit, "J");
    assert!(ke.sample_shape.is_empty());
    assert_eq!(
        ke.step,
        observables.iter().map(|(s, _)| *s).collect::<Vec<_>>()
    );
    assert_eq!(
        bits(&ke.time_s),
        observables
            .iter()
            .map(|(_, o)| o.time_s.to_bits())
            .collect::<Vec<_>>()
    );
    assert_eq!(
        bits(&ke.value),
        observables
            .iter()
            .map(|(_, o)| o.kinetic_translational_j.to_bits())
            .collect::<Vec<_>>()
    );
    let stress = file.observable("mean_stress").unwrap();
    assert_eq!(
        (stress.sample_shape.clone(), stress.unit.as_str()),
        (vec![4], "N m-1")
    );
    let flat: Vec<f64> = observables
        .iter()
        .flat_map(|(_, o)| o.mean_stress_n_per_m)
        .collect();
    assert_eq!(bits(&stress.value), bits(&flat));
    let load = file.observable("load_point_force").unwrap();
    assert_eq!(
        (load.sample_shape.clone(), load.unit.as_str()),
        (vec![2], "N")
    );
    let flat: Vec<f64> = observables
        .iter()
        .flat_map(|(_, o)| o.load_point_force_n)
        .collect();
    assert_eq!(bits(&load.value), bits(&flat));
    let friction = file.observable("friction_dissipation").unwrap();
    assert_eq!(
        bits(&friction.value),
        observables
            .iter()
            .map(|(_, o)| o.ledger.friction_dissipation_j.to_bits())
            .collect::<Vec<_>>()
    );
    let contacts = file.observable("contacts").unwrap();
    assert_eq!(
        contacts.value,
        observables
            .iter()
            .map(|(_, o)| o.contacts as f64)
            .collect::<Vec<_>>()
    );
    assert!(file.observable("no_such_thing").is_err());

    // The checkpoint is the last state, and resumes bitwise.
    let info = file.checkpoint().unwrap().unwrap();
    assert_eq!(
        (info.step, info.time_s.to_bits()),
        (saved.steps, saved.time_s.to_bits())
    );
    let state = file.checkpoint_state(|| None).unwrap().unwrap();
    assert_eq!(fingerprint(&state), fingerprint(saved));
    let mut resumed = parts.resume(state);
    for _ in 0..300 {
        world.step();
        resumed.step();
    }
    assert_eq!(fingerprint(resumed.state()), fingerprint(world.state()));
}

/// Writes the reference run: snapshots every 100 steps, observables every
/// 25, checkpoints every 200; `stop_after` ends the run early without
/// closing anything cleanly (as a crash would), after extra output past
/// the last checkpoint.
fn run(path: &std::path::Path, world: &mut World<Forcing>, w: &mut RunWriter, until: u64) {
    while world.steps() < until {
        world.step();
        if world.steps().is_multiple_of(25) {
            observe(w, world);
        }
        if world.steps().is_multiple_of(100) {
            w.write_snapshot(world).unwrap();
        }
        if world.steps().is_multiple_of(200) {
            w.write_checkpoint(world.state(), world.model().law.state_slots())
                .unwrap();
        }
    }
    let _ = path;
}

fn assert_same_file(a: &std::path::Path, b: &std::path::Path) {
    let (fa, fb) = (RunFile::open(a).unwrap(), RunFile::open(b).unwrap());
    let n = fa.snapshot_count().unwrap();
    assert_eq!(n, fb.snapshot_count().unwrap());
    for k in 0..n {
        assert_eq!(
            fa.snapshot(k).unwrap(),
            fb.snapshot(k).unwrap(),
            "snapshot {k}"
        );
        let (sa, sb) = (fa.snapshot(k).unwrap(), fb.snapshot(k).unwrap());
        assert_eq!(bits2(&sa.position), bits2(&sb.position));
        let (ca, cb) = (fa.contacts(k).unwrap(), fb.contacts(k).unwrap());
        assert_eq!(ca.pair, cb.pair);
        assert_eq!(bits(&ca.theta), bits(&cb.theta));
        assert_eq!(bits(&ca.tangential_force_n), bits(&cb.tangential_force_n));
    }
    for name in fa.observable_names().unwrap() {
        let (oa, ob) = (fa.observable(&name).unwrap(), fb.observable(&name).unwrap());
        assert_eq!(oa.step, ob.step, "{name}");
        assert_eq!(bits(&oa.value), bits(&ob.value), "{name}");
    }
    assert_eq!(
        fingerprint(&fa.checkpoint_state(|| None).unwrap().unwrap()),
        fingerprint(&fb.checkpoint_state(|| None).unwrap().unwrap())
    );
}

#[test]
fn a_resumed_file_drops_what_followed_the_checkpoint_and_ends_as_the_uninterrupted_one() {
    let dir = tempfile::tempdir().unwrap();
    let (whole, parts_path) = (dir.path().join("whole.h5"), dir.path().join("parts.h5"));
    let opts = OutputOptions::default();

    let (mut world, _) = pack();
    let mut w = RunWriter::create(&whole, &metadata(), world.floes(), &opts).unwrap();
    w.write_snapshot(&world).unwrap();
    run(&whole, &mut world, &mut w, 1000);
    drop(w);

    let (mut world, parts) = pack();
    let mut w = RunWriter::create(&parts_path, &metadata(), world.floes(), &opts).unwrap();
    w.write_snapshot(&world).unwrap();
    // Up to step 700: the last checkpoint is at 600, followed by a snapshot
    // at 700 and observables at 625..700, which the resume must drop.
    run(&parts_path, &mut world, &mut w, 700);
    drop(w);
    {
        let f = RunFile::open(&parts_path).unwrap();
        assert_eq!(f.snapshot_count().unwrap(), 8);
        assert_eq!(f.checkpoint().unwrap().unwrap().step, 600);
        assert_eq!(f.observable("mean_mu").unwrap().step.len(), 28);
    }
    let (mut w, state, info) = RunWriter::reopen_for_resume(&parts_path, || None, 3).unwrap();
    assert_eq!(info.step, 600);
    {
        let f = RunFile::open(&parts_path).unwrap();
        assert_eq!(
            f.snapshot_count().unwrap(),
            7,
            "the snapshot at 700 is dropped"
        );
        let last = f.snapshot(6).unwrap();
        assert_eq!(last.step, 600);
        for name in f.observable_names().unwrap() {
            let s = f.observable(&name).unwrap();
            assert_eq!(*s.step.last().unwrap(), 600, "{name}");
            assert_eq!(s.step.len(), 24, "{name}");
        }
    }
    let mut world = parts.resume(state);
    run(&parts_path, &mut world, &mut w, 1000);
    drop(w);
    assert_same_file(&whole, &parts_path);
}
