//! Bad files and bad places give one clear error naming the file, never a
//! panic, and never touch a file they should not.

use crate::support;

use floe_friction::FrictionLaw;
use std::path::Path;

use floe_io::{IoError, OutputOptions, RunFile, RunWriter};
use support::{metadata, pack};

fn new_run(path: &Path, checkpoint: bool) {
    let (mut world, _) = pack();
    let mut w =
        RunWriter::create(path, &metadata(), world.floes(), &OutputOptions::default()).unwrap();
    w.write_snapshot(&world).unwrap();
    world.step();
    if checkpoint {
        w.write_checkpoint(world.state(), world.model().law.state_slots())
            .unwrap();
    }
}

/// The message names the file.
fn names(e: &IoError, path: &Path) -> String {
    let text = e.to_string();
    assert!(
        text.contains(&path.display().to_string()),
        "`{text}` should name {}",
        path.display()
    );
    assert_eq!(e.path(), path);
    text
}

#[test]
fn creating_over_an_existing_file_is_refused_and_leaves_it_alone() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("precious.h5");
    std::fs::write(&path, b"precious").unwrap();
    let (world, _) = pack();
    let e = RunWriter::create(&path, &metadata(), world.floes(), &OutputOptions::default())
        .err()
        .expect("refused");
    assert!(matches!(e, IoError::AlreadyExists { .. }), "{e}");
    assert!(names(&e, &path).contains("already exists"));
    assert_eq!(std::fs::read(&path).unwrap(), b"precious");
}

#[test]
fn a_missing_file_is_not_found() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing.h5");
    let e = RunFile::open(&path).err().expect("missing");
    assert!(matches!(e, IoError::NotFound { .. }), "{e}");
    names(&e, &path);
    let e = RunWriter::reopen_for_resume(&path, || None, 3)
        .err()
        .expect("missing");
    assert!(matches!(e, IoError::NotFound { .. }), "{e}");
}

#[test]
fn a_file_that_is_not_hdf5_is_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in [
        ("junk.h5", vec![7u8; 4096]),
        ("empty.h5", Vec::new()),
        ("text.h5", b"[run]\nduration_s = 1\n".to_vec()),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, &bytes).unwrap();
        let e = RunFile::open(&path).err().expect("not HDF5");
        assert!(matches!(e, IoError::NotHdf5 { .. }), "{e}");
        assert!(names(&e, &path).contains("not an HDF5 file"));
        let e = RunWriter::reopen_for_resume(&path, || None, 3)
            .err()
            .expect("not HDF5");
        assert!(matches!(e, IoError::NotHdf5 { .. }), "{e}");
        assert_eq!(std::fs::read(&path).unwrap(), bytes, "left as it was");
    }
}

#[test]
fn an_hdf5_file_not_written_by_floe_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.h5");
    {
        let f = hdf5::File::create(&plain).unwrap();
        f.new_dataset_builder()
            .with_data(&[1.0f64, 2.0][..])
            .create("x")
            .unwrap();
    }
    let e = RunFile::open(&plain).err().expect("not floe");
    assert!(matches!(e, IoError::NotFloeFile { .. }), "{e}");
    assert!(names(&e, &plain).contains("not a floe run file"));
    // An H5MD file from another program.
    let other = dir.path().join("other.h5");
    {
        let f = hdf5::File::create(&other).unwrap();
        let c = f
            .create_group("h5md")
            .unwrap()
            .create_group("creator")
            .unwrap();
        c.new_attr::<hdf5::types::VarLenUnicode>()
            .create("name")
            .unwrap()
            .write_scalar(&"halmd".parse::<hdf5::types::VarLenUnicode>().unwrap())
            .unwrap();
    }
    let e = RunWriter::reopen_for_resume(&other, || None, 3)
        .err()
        .expect("not floe");
    assert!(names(&e, &other).contains("halmd"), "{e}");
}

#[test]
fn a_file_without_checkpoint_cannot_be_resumed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("early.h5");
    new_run(&path, false);
    let f = RunFile::open(&path).unwrap();
    assert_eq!(f.checkpoint().unwrap(), None);
    assert_eq!(f.checkpoint_state(|| None).unwrap(), None);
    drop(f);
    let e = RunWriter::reopen_for_resume(&path, || None, 3)
        .err()
        .expect("no checkpoint");
    assert!(matches!(e, IoError::NoCheckpoint { .. }), "{e}");
    assert!(names(&e, &path).contains("no valid checkpoint"));
}

#[test]
fn a_damaged_checkpoint_is_detected_by_its_checksum() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("damaged.h5");
    new_run(&path, true);
    assert!(RunFile::open(&path)
        .unwrap()
        .checkpoint_state(|| None)
        .unwrap()
        .is_some());
    // Flip one byte of the state (past the header) in the valid slot.
    {
        let f = hdf5::File::open_rw(&path).unwrap();
        let ds = f.dataset("checkpoint/slot0").unwrap();
        let mut bytes = ds.read_raw::<u8>().unwrap();
        bytes[100] ^= 0x10;
        ds.write_raw(&bytes).unwrap();
    }
    let e = RunWriter::reopen_for_resume(&path, || None, 3)
        .err()
        .expect("damaged");
    assert!(matches!(e, IoError::CorruptCheckpoint { .. }), "{e}");
    let text = names(&e, &path);
    assert!(
        text.contains("checksum") && text.contains("slot0"),
        "{text}"
    );
    let e = RunFile::open(&path)
        .unwrap()
        .checkpoint_state(|| None)
        .expect_err("damaged");
    assert!(e.to_string().contains("checksum"), "{e}");
    // The step and time (slot attributes) are still there to report.
    assert!(RunFile::open(&path)
        .unwrap()
        .checkpoint()
        .unwrap()
        .is_some());
}

#[test]
fn a_truncated_or_scrambled_file_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.h5");
    new_run(&path, true);
    let bytes = std::fs::read(&path).unwrap();
    for (name, damaged) in [
        ("half.h5", bytes[..bytes.len() / 2].to_vec()),
        ("head.h5", bytes[..600].to_vec()),
        ("scrambled.h5", {
            let mut b = bytes.clone();
            for i in (64..b.len()).step_by(97) {
                b[i] = b[i].wrapping_mul(31).wrapping_add(7);
            }
            b
        }),
    ] {
        let p = dir.path().join(name);
        std::fs::write(&p, damaged).unwrap();
        // Whatever fails, it fails with an error naming the file.
        let outcome = (|| -> Result<(), IoError> {
            let f = RunFile::open(&p)?;
            f.metadata()?;
            f.static_floes()?;
            for k in 0..f.snapshot_count()? {
                f.snapshot(k)?;
                f.contacts(k)?;
            }
            for n in f.observable_names()? {
                f.observable(&n)?;
            }
            f.checkpoint_state(|| None)?;
            drop(f);
            RunWriter::reopen_for_resume(&p, || None, 3)?;
            Ok(())
        })();
        let e = outcome
            .err()
            .unwrap_or_else(|| panic!("{name} read without error"));
        eprintln!("{name}: {e}");
        names(&e, &p);
    }
}

#[test]
fn an_unwritable_place_is_one_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (world, _) = pack();
    let create = |p: &Path| {
        RunWriter::create(p, &metadata(), world.floes(), &OutputOptions::default())
            .err()
            .expect("cannot create")
    };
    // The parent is a file (works as root too).
    std::fs::write(dir.path().join("plain_file"), b"").unwrap();
    let path = dir.path().join("plain_file/run.h5");
    let e = create(&path);
    assert!(names(&e, &path).contains("not a directory"), "{e}");
    // The directory does not exist.
    let path = dir.path().join("nowhere/run.h5");
    assert!(names(&create(&path), &path).contains("does not exist"));
    // A read-only directory.
    use std::os::unix::fs::PermissionsExt;
    let ro = dir.path().join("read_only");
    std::fs::create_dir(&ro).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    let path = ro.join("run.h5");
    let e = create(&path);
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    assert!(names(&e, &path).contains("read-only"), "{e}");
    assert!(!path.exists());
}

#[test]
fn requests_that_do_not_fit_the_file_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.h5");
    new_run(&path, true);
    let f = RunFile::open(&path).unwrap();
    assert_eq!(f.snapshot_count().unwrap(), 1);
    let e = f.snapshot(1).expect_err("past the end");
    assert!(names(&e, &path).contains("no snapshot 1"));
    assert!(f.contacts(5).is_err());
    let e = f.observable("kinetic").expect_err("unknown");
    assert!(
        names(&e, &path).contains("kinetic_translational"),
        "lists the names: {e}"
    );
    drop(f);
    // A world with other floes than the file's (one taken out, then
    // another put in its place) is written in a new floe group (segment)
    // each time; the reader gives each snapshot with its own floes.
    let (mut w, _, _) = RunWriter::reopen_for_resume(&path, || None, 3).unwrap();
    let (mut world, _) = pack();
    let n = world.floes().len();
    let mut taken = world.remove_floe(3).unwrap();
    w.write_snapshot(&world).unwrap();
    taken.floe.id = 1000;
    taken.contacts.clear();
    taken.broken.clear();
    world.insert_detached(taken).unwrap();
    w.write_snapshot(&world).unwrap();
    w.write_snapshot(&world).unwrap();
    drop(w);
    let f = RunFile::open(&path).unwrap();
    let k = f.snapshot_count().unwrap();
    assert_eq!(
        f.static_floes().unwrap().len(),
        n,
        "the floes the run began with"
    );
    let ids = |k: usize| f.floes_at(k).unwrap().id;
    assert_eq!(ids(k - 3).len(), n - 1);
    assert!(!ids(k - 3).contains(&3));
    assert_eq!(ids(k - 2), ids(k - 1));
    assert!(ids(k - 1).contains(&1000) && ids(k - 1).len() == n);
    assert_eq!(f.snapshot(k - 1).unwrap().position.len(), n);
    assert_eq!(f.snapshot(k - 3).unwrap().position.len(), n - 1);
    let times = f.snapshot_times().unwrap();
    assert_eq!(times.len(), k);
}

#[test]
fn checkpoint_bytes_that_pass_the_checksum_but_lie_are_refused_without_panic() {
    use floe_io::checkpoint::{decode, encode, fnv1a64, OutputCounts, HEADER_LEN};
    let (mut world, _) = pack();
    for _ in 0..200 {
        world.step();
    }
    let state = world.state();
    let good = encode(state, &OutputCounts::default(), 3);
    let (back, _) = decode(&good, || None, None).unwrap();
    assert_eq!(format!("{back:?}"), format!("{state:?}"));
    // Re-sign a damaged payload so that only the structural checks remain.
    let resign = |mut b: Vec<u8>| {
        let len = (b.len() - HEADER_LEN) as u64;
        b[16..24].copy_from_slice(&len.to_le_bytes());
        let sum = fnv1a64(&b[HEADER_LEN..]);
        b[24..32].copy_from_slice(&sum.to_le_bytes());
        b
    };
    for cut in [HEADER_LEN, HEADER_LEN + 9, good.len() / 2, good.len() - 1] {
        let e = decode(&resign(good[..cut].to_vec()), || None, None).expect_err("truncated");
        assert!(e.contains("truncated") || e.contains("exceeds"), "{e}");
    }
    // A vector length of 2^60 (the floe count, after the three counts).
    let mut huge = good.clone();
    huge[HEADER_LEN + 24..HEADER_LEN + 32].copy_from_slice(&(1u64 << 60).to_le_bytes());
    assert!(decode(&resign(huge), || None, None).is_err());
    // Every byte of the payload in turn set to 0xff: errors or a state, never a panic.
    for at in (HEADER_LEN..good.len()).step_by(7) {
        let mut b = good.clone();
        b[at] = 0xff;
        let _ = decode(&resign(b), || None, None);
    }
    // The checksum itself.
    let mut b = good.clone();
    b[good.len() - 3] ^= 1;
    assert!(decode(&b, || None, None)
        .expect_err("checksum")
        .contains("checksum"));
}
