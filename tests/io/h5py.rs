//! The h5py example of docs/output.md runs against a fresh run file and
//! draws the floes: the file is readable without floe. Skipped (with a
//! message) where python3 lacks h5py, numpy or matplotlib (`make deps`
//! installs them).

use crate::support;

use floe_friction::FrictionLaw;
use std::process::Command;

use floe_io::{OutputOptions, RunWriter};
use support::{domain_area, metadata, pack};

/// The first ```python block of docs/output.md.
fn snippet() -> String {
    let doc = include_str!("../../docs/output.md");
    let start = doc
        .find("```python\n")
        .expect("a ```python block in docs/output.md")
        + 10;
    let len = doc[start..].find("```").expect("the block ends");
    doc[start..start + len].to_string()
}

#[test]
fn the_documented_h5py_snippet_reads_a_run_and_draws_it() {
    let code = snippet();
    let has_python = Command::new("python3")
        .args(["-c", "import h5py, numpy, matplotlib"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_python {
        eprintln!("skipped: no h5py (python3 with h5py, numpy and matplotlib; `make deps`)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.h5");
    let (mut world, _) = pack();
    let mut w =
        RunWriter::create(&path, &metadata(), world.floes(), &OutputOptions::default()).unwrap();
    w.write_snapshot(&world).unwrap();
    for _ in 0..3 {
        for _ in 0..100 {
            world.step();
            if world.steps().is_multiple_of(20) {
                w.write_observables(world.steps(), &world.observables(domain_area()))
                    .unwrap();
            }
        }
        w.write_snapshot(&world).unwrap();
    }
    w.write_checkpoint(world.state(), world.model().law.state_slots())
        .unwrap();
    w.set_status("completed").unwrap();
    drop(w);
    let script = dir.path().join("snippet.py");
    std::fs::write(&script, &code).unwrap();
    let png = dir.path().join("floes.png");
    let out = Command::new("python3")
        .arg(&script)
        .arg(&path)
        .arg(&png)
        .env("MPLBACKEND", "Agg")
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        out.status.success(),
        "the snippet failed:\n{stdout}\n{stderr}"
    );
    let bytes = std::fs::read(&png).expect("the snippet writes the PNG");
    assert!(bytes.starts_with(b"\x89PNG"), "a PNG");
    assert!(bytes.len() > 5_000, "a picture, not an empty canvas");
    // The snippet prints what it read: the last snapshot's step and the floe count.
    assert!(
        stdout.contains(&format!("step {}", world.steps())) && stdout.contains("31 floes"),
        "{stdout}"
    );
}
