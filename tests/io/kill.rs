//! A writer killed with SIGKILL at any moment leaves a file that opens and
//! resumes from its last complete checkpoint, bitwise.
//!
//! The test re-runs its own binary as the writer (the `writer_child` test,
//! which does nothing unless the environment variable below names a file),
//! kills it at spread-out moments of its run, and checks each file against
//! an uninterrupted run computed here.

use crate::support;

use floe_friction::FrictionLaw;
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

use floe_io::{IoError, OutputOptions, RunFile, RunWriter};
use support::{bits2, domain_area, fingerprint, metadata, pack, vec2_bits};

const CHILD_ENV: &str = "FLOE_IO_KILL_CHILD";
const STEPS: u64 = 1000;
const SNAPSHOT_EVERY: u64 = 5;
const CHECKPOINT_EVERY: u64 = 10;

/// The writer: observables every step, snapshots every 5, checkpoints every
/// 10, each checkpoint reported on stdout once written.
#[test]
fn writer_child() {
    let Ok(path) = std::env::var(CHILD_ENV) else {
        return;
    };
    let (mut world, _) = pack();
    let mut w = RunWriter::create(
        Path::new(&path),
        &metadata(),
        world.floes(),
        &OutputOptions::default(),
    )
    .unwrap();
    w.set_status("running").unwrap();
    let mut out = std::io::stdout().lock();
    w.write_snapshot(&world).unwrap();
    w.write_observables(0, &world.observables(domain_area()))
        .unwrap();
    w.write_checkpoint(world.state(), world.model().law.state_slots())
        .unwrap();
    writeln!(out, "CHECKPOINT 0").unwrap();
    out.flush().unwrap();
    while world.steps() < STEPS {
        world.step();
        w.write_observables(world.steps(), &world.observables(domain_area()))
            .unwrap();
        if world.steps().is_multiple_of(SNAPSHOT_EVERY) {
            w.write_snapshot(&world).unwrap();
        }
        if world.steps().is_multiple_of(CHECKPOINT_EVERY) {
            w.write_checkpoint(world.state(), world.model().law.state_slots())
                .unwrap();
            writeln!(out, "CHECKPOINT {}", world.steps()).unwrap();
            out.flush().unwrap();
        }
    }
    w.set_status("completed").unwrap();
    w.flush().unwrap();
}

/// Starts the writer on `path`; returns it with its stdout piped.
fn spawn(path: &Path) -> std::process::Child {
    Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "kill::writer_child",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD_ENV, path)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// The last checkpoint the writer reported.
fn last_reported(stdout: &[u8]) -> Option<u64> {
    String::from_utf8_lossy(stdout)
        .lines()
        .filter_map(|l| l.strip_prefix("CHECKPOINT "))
        .filter_map(|s| s.trim().parse().ok())
        .next_back()
}

#[test]
fn kill_9_at_any_moment_leaves_a_file_that_resumes_bitwise() {
    if std::env::var(CHILD_ENV).is_ok() {
        return;
    }
    // The uninterrupted run: states at checkpoints, positions at snapshots.
    let (mut world, parts) = pack();
    let mut states = HashMap::new();
    let mut positions = HashMap::new();
    states.insert(0, fingerprint(world.state()));
    positions.insert(0, vec2_bits(&world.floes().position));
    while world.steps() < STEPS {
        world.step();
        if world.steps().is_multiple_of(SNAPSHOT_EVERY) {
            positions.insert(world.steps(), vec2_bits(&world.floes().position));
        }
        if world.steps().is_multiple_of(CHECKPOINT_EVERY) {
            states.insert(world.steps(), fingerprint(world.state()));
        }
    }

    let dir = tempfile::tempdir().unwrap();
    // How long a whole run takes here, to spread the kills over it.
    let path = dir.path().join("whole.h5");
    let started = Instant::now();
    let out = spawn(&path).wait_with_output().unwrap();
    let whole = started.elapsed();
    assert!(out.status.success(), "the writer runs to the end");
    assert_eq!(last_reported(&out.stdout), Some(STEPS));
    assert_eq!(RunFile::open(&path).unwrap().status().unwrap(), "completed");

    let kills = 12;
    let (mut resumed, mut early) = (0, 0);
    let mut steps_seen = Vec::new();
    for i in 0..kills {
        let path = dir.path().join(format!("killed{i}.h5"));
        // Spread over the run by the golden ratio (the low-discrepancy
        // sequence), from start-up to near the end.
        let fraction = 0.02 + 0.93 * ((i as f64 * 0.618_034 + 0.1) % 1.0);
        let delay = whole.mul_f64(fraction);
        let mut child = spawn(&path);
        std::thread::sleep(delay);
        child.kill().unwrap(); // SIGKILL
        let out = child.wait_with_output().unwrap();
        let reported = last_reported(&out.stdout);
        let context = format!("kill {i} after {delay:?} (last reported checkpoint {reported:?})");
        if !path.exists() {
            assert_eq!(reported, None, "{context}: a checkpoint without a file");
            early += 1;
            continue;
        }
        match RunWriter::reopen_for_resume(&path, || None, 3) {
            Ok((mut w, state, info)) => {
                if let Some(r) = reported {
                    // The checkpoint after the last reported one may have
                    // been complete before the kill, not the one after that.
                    assert!(
                        info.step == r || info.step == r + CHECKPOINT_EVERY,
                        "{context}: resumed from step {}",
                        info.step
                    );
                }
                let expected = states
                    .get(&info.step)
                    .unwrap_or_else(|| panic!("{context}: no checkpoint at {}", info.step));
                assert!(&fingerprint(&state) == expected, "{context}: state differs");
                // The output was cut back to the checkpoint, and matches.
                let f = RunFile::open(&path).unwrap();
                let n = f.snapshot_count().unwrap();
                assert_eq!(n as u64, info.step / SNAPSHOT_EVERY + 1, "{context}");
                for k in 0..n {
                    let s = f.snapshot(k).unwrap();
                    assert_eq!(s.step, k as u64 * SNAPSHOT_EVERY);
                    assert_eq!(&bits2(&s.position), &positions[&s.step], "{context}: {k}");
                }
                let ke = f.observable("kinetic_translational").unwrap();
                assert_eq!(ke.step, (0..=info.step).collect::<Vec<_>>(), "{context}");
                drop(f);
                // And the run goes on from there.
                let mut world = parts.resume(state);
                for _ in 0..CHECKPOINT_EVERY {
                    world.step();
                }
                w.write_snapshot(&world).unwrap();
                w.write_checkpoint(world.state(), world.model().law.state_slots())
                    .unwrap();
                drop(w);
                let f = RunFile::open(&path).unwrap();
                assert_eq!(
                    f.checkpoint().unwrap().unwrap().step,
                    info.step + CHECKPOINT_EVERY
                );
                // (The reference ends at STEPS; a kill after the writer
                // finished resumes from its last checkpoint, at STEPS.)
                if let Some(next) = states.get(&(info.step + CHECKPOINT_EVERY)) {
                    let state = f.checkpoint_state(|| None).unwrap().unwrap();
                    assert!(&fingerprint(&state) == next, "{context}: continued state");
                }
                steps_seen.push(info.step);
                resumed += 1;
            }
            Err(e @ (IoError::NoCheckpoint { .. } | IoError::NotFloeFile { .. }))
                if reported.is_none() =>
            {
                // Killed while creating the file or before its first checkpoint.
                assert!(e.to_string().contains(&path.display().to_string()));
                early += 1;
            }
            Err(e) => panic!("{context}: {e}"),
        }
    }
    eprintln!(
        "{kills} kills over a {whole:?} run: {resumed} resumed (from steps {steps_seen:?}), {early} before the first checkpoint"
    );
    assert!(
        resumed >= kills - 3,
        "most kills land mid-run: {resumed} of {kills}"
    );
}
