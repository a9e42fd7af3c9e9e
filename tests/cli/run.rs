//! `floe run`, `floe info`, `floe render` as a user meets them: a run writes
//! a readable file, refuses to overwrite it, stops cleanly on Ctrl-C, on a
//! step budget and on a blow-up, and a resumed run (after a pause, an
//! interrupt or `kill -9`) is bitwise the uninterrupted one.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

use floe_io::RunFile;

use crate::run_support;
use run_support::{
    assert_no_panic, assert_same_run, bits, bits2, code, interrupted_step, run_suggestion,
    suggested_command, text, wait_for_progress, Case, Launch,
};

/// A sheared channel of small diamonds: a few hundred steps, snapshots,
/// observables and checkpoints at different cadences, none of which
/// divides the step budgets used below.
const SMALL: &str = include_str!("../data/run_small.toml");

/// The same channel, long enough to be interrupted while it runs.
const LONG: &str = include_str!("../data/run_long.toml");

/// Walls that close far faster than contacts can push back.
const BLOW_UP: &str = include_str!("../data/run_blow_up.toml");

/// The small channel, its floes breaking against the bottom wall.
const FRACTURE: &str = include_str!("../data/run_fracture.toml");
/// Small channel pressed by a closing wall: floes ridge.
const RIDGING: &str = include_str!("../data/run_ridging.toml");
const WELDING: &str = include_str!("../data/run_welding.toml");

fn floe() -> Command {
    Launch::Alone.command()
}

fn run(args: &[&str]) -> Output {
    floe().args(args).output().expect("floe starts")
}

/// Runs to completion; panics with floe's stderr if it fails.
fn run_ok(args: &[&str]) -> String {
    let out = run(args);
    let err = text(&out.stderr);
    assert_eq!(code(&out), 0, "floe {args:?}: {err}");
    text(&out.stdout)
}

/// `tests/data/run_small_format2_paused.h5`: `run_small.toml` paused at
/// step 37 by floe at commit 676b801, whose checkpoints were of format 2
/// (no time step, three friction slots per contact).
const FORMAT_2_PAUSED: &[u8] = include_bytes!("../data/run_small_format2_paused.h5");

#[test]
fn a_run_writes_a_file_that_info_describes() {
    let case = Case::new(SMALL);
    case.run_ok("run.h5", &[]);
    let file = RunFile::open(Path::new(&case.path("run.h5"))).unwrap();
    assert_eq!(file.status().unwrap(), "completed");
    let checkpoint = file.checkpoint().unwrap().expect("a checkpoint");
    let n = file.snapshot_count().unwrap();
    let last = file.snapshot(n - 1).unwrap();
    assert_eq!(last.step, checkpoint.step, "the run ends with a snapshot");
    assert_eq!(file.snapshot(0).unwrap().step, 0);
    // The energy observables sample the same steps as each other.
    let ke = file.observable("kinetic_translational").unwrap();
    assert_eq!(*ke.step.last().unwrap(), last.step);
    assert_eq!(
        ke.step,
        file.observable("friction_dissipation").unwrap().step
    );

    let info = run_ok(&["info", &case.path("run.h5")]);
    for expected in [
        "completed",
        "snapshots",
        "contacts",
        "kinetic_translational",
    ] {
        assert!(
            info.contains(expected),
            "`{expected}` in floe info:\n{info}"
        );
    }
    let floes = file.static_floes().unwrap().len().to_string();
    assert!(info.contains(&floes), "floe count {floes} in:\n{info}");
    // The observables' last values as numbers read: a count as a whole
    // number, a fraction to five significant digits (not `9.5500e2`).
    let last_value = |name: &str| {
        let line = info
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("{name} in:\n{info}"));
        line.split_whitespace().nth(1).unwrap().to_string()
    };
    let contacts = *file.observable("contacts").unwrap().value.last().unwrap();
    assert_eq!(last_value("contacts"), format!("{}", contacts as u64));
    let mu = *file.observable("mean_mu").unwrap().value.last().unwrap();
    let shown = last_value("mean_mu");
    assert!(!shown.contains('e'), "{shown}");
    let relative = (shown.parse::<f64>().unwrap() / mu - 1.0).abs();
    assert!(relative <= 5e-5, "{shown} for {mu}");
}

#[test]
fn a_run_refuses_to_overwrite_unless_forced() {
    let case = Case::new(SMALL);
    let target = case.path("run.h5");
    std::fs::write(&target, b"precious").unwrap();
    let out = case.run("run.h5", &[]);
    let err = text(&out.stderr);
    assert_eq!(code(&out), 2, "{err}");
    assert!(err.contains("--force"), "{err}");
    assert_eq!(std::fs::read(&target).unwrap(), b"precious");
    case.run_ok("run.h5", &["--force"]);
    assert!(RunFile::open(Path::new(&target)).is_ok());
}

#[test]
fn pausing_and_resuming_on_another_thread_count_is_bitwise_the_uninterrupted_run() {
    let case = Case::new(SMALL);
    case.run_ok("whole.h5", &["--threads", "1"]);
    // 137 steps: off every cadence, so the pause writes an extra checkpoint,
    // snapshot and observables that the resume must drop again.
    case.run_ok("parts.h5", &["--threads", "1", "--max-steps", "137"]);
    let paused = RunFile::open(Path::new(&case.path("parts.h5"))).unwrap();
    assert_eq!(paused.status().unwrap(), "paused at step 137");
    assert_eq!(paused.checkpoint().unwrap().unwrap().step, 137);
    drop(paused);
    case.resume_ok("parts.h5", &["--threads", "2", "--max-steps", "101"]);
    case.resume_ok("parts.h5", &["--threads", "2"]);
    case.assert_same("whole.h5", "parts.h5");
}

#[test]
fn a_run_with_floe_stress_writes_it_with_every_snapshot_and_resumes_bitwise() {
    let stressed = format!("{SMALL}\n[floe_stress]\ntime_scale_s = 20.0\n");
    let case = Case::new(&stressed);
    case.run_ok("whole.h5", &["--threads", "2"]);
    case.run_ok("parts.h5", &["--threads", "1", "--max-steps", "137"]);
    case.resume_ok("parts.h5", &["--threads", "2"]);
    case.assert_same("whole.h5", "parts.h5");
    let f = RunFile::open(Path::new(&case.path("whole.h5"))).unwrap();
    let n = f.snapshot_count().unwrap();
    let floes = f.static_floes().unwrap();
    let first = f
        .floe_stress(0)
        .unwrap()
        .expect("the file holds floe stress");
    assert_eq!(first.len(), floes.len());
    assert!(
        first.iter().all(|s| *s == [0.0; 3]),
        "the average starts at zero"
    );
    let last = f.floe_stress(n - 1).unwrap().unwrap();
    let compressed = (0..last.len())
        .filter(|&i| !floes.prescribed[i] && last[i][0] + last[i][2] < 0.0)
        .count();
    assert!(
        compressed > 10,
        "the sheared pack is compressed ({compressed} floes)"
    );
    assert!((0..last.len()).all(|i| !floes.prescribed[i] || last[i] == [0.0; 3]));
    // The last snapshot and the final checkpoint hold the same stresses.
    let state = f.checkpoint_state(|| None).unwrap().unwrap();
    assert_eq!(state.steps, f.snapshot(n - 1).unwrap().step);
    assert!(state.floe_stress == last);
    // Without the table, no stress in the file.
    let plain = Case::new(SMALL);
    plain.run_ok("plain.h5", &["--max-steps", "20"]);
    let plain = RunFile::open(Path::new(&plain.path("plain.h5"))).unwrap();
    assert!(!plain.has_floe_stress() && plain.floe_stress(0).unwrap().is_none());
    assert!(
        plain.observable("bonds").is_err(),
        "no bonds without cohesion"
    );
}

#[test]
fn floes_break_keeping_their_mass_and_a_paused_run_resumes_bitwise() {
    let case = Case::new(FRACTURE);
    case.run_ok("whole.h5", &["--threads", "2"]);
    // 1371 steps: between fracture checks, snapshots and checkpoints.
    case.run_ok("parts.h5", &["--threads", "1", "--max-steps", "1371"]);
    case.resume_ok("parts.h5", &["--threads", "2"]);
    case.assert_same("whole.h5", "parts.h5");
    let f = RunFile::open(Path::new(&case.path("whole.h5"))).unwrap();
    let n = f.snapshot_count().unwrap();
    let counts: Vec<usize> = (0..n).map(|k| f.floes_at(k).unwrap().len()).collect();
    assert!(counts.windows(2).all(|w| w[0] <= w[1]), "{counts:?}");
    assert!(counts[n - 1] > counts[0] + 30, "floes broke: {counts:?}");
    // Free ice mass and area are kept through every split.
    let free = |k: usize| {
        let s = f.floes_at(k).unwrap();
        let sum = |v: &[f64]| {
            (0..s.len())
                .filter(|&i| !s.prescribed[i])
                .map(|i| v[i])
                .sum::<f64>()
        };
        [sum(&s.mass_kg), sum(&s.area_m2)]
    };
    let (start, end) = (free(0), free(n - 1));
    for (a, b) in start.iter().zip(end) {
        assert!((b - a).abs() < 1e-12 * a, "{start:?} then {end:?}");
    }
    // The log accounts for every floe: each split adds its pieces less its
    // parent, the parent leaves and its pieces arrive.
    let log = f.fractures().unwrap();
    for k in 0..n {
        let step = f.snapshot(k).unwrap().step;
        let added: usize = log
            .iter()
            .filter(|e| e.step <= step)
            .map(|e| e.piece_ids.len().saturating_sub(1))
            .sum();
        assert_eq!(counts[k], counts[0] + added, "snapshot {k}");
        let floes = f.floes_at(k).unwrap();
        for e in log
            .iter()
            .filter(|e| e.step <= step && !e.piece_ids.is_empty())
        {
            assert!(!floes.id.contains(&e.parent_id), "{} broke", e.parent_id);
            assert!(
                e.principal_pa.1 < -100.0,
                "broken in compression: {:?}",
                e.principal_pa
            );
        }
    }
    // Each later segment names every floe's parent: a piece's is the floe
    // the log says it broke from, a floe of the start has none.
    let start_ids = f.floes_at(0).unwrap().id;
    for k in 0..n {
        let ids = f.floes_at(k).unwrap().id;
        for (id, parent) in ids.iter().zip(f.parent_ids_at(k).unwrap()) {
            match parent {
                Some(p) => assert!(
                    log.iter()
                        .any(|e| e.parent_id == p && e.piece_ids.contains(id)),
                    "snapshot {k}: floe {id} from {p}"
                ),
                None => assert!(start_ids.contains(id), "snapshot {k}: floe {id}"),
            }
        }
    }
    assert!(f.parent_ids_at(n - 1).unwrap().iter().any(Option::is_some));
    // Floes froze together too (cohesion), and bonds count in the file.
    let bonds = f.observable("bonds").unwrap().value;
    assert!(
        bonds.iter().copied().fold(0.0, f64::max) > 100.0,
        "bonds: {bonds:?}"
    );
    let last = f.floes_at(n - 1).unwrap();
    let mut born: Vec<u64> = log.iter().flat_map(|e| e.piece_ids.clone()).collect();
    born.retain(|id| !log.iter().any(|e| e.parent_id == *id));
    assert!(
        born.iter().all(|id| last.id.contains(id)),
        "unbroken pieces remain"
    );
    let info = Launch::Alone
        .command()
        .args(["info", &case.path("whole.h5")])
        .output()
        .unwrap();
    assert!(
        text(&info.stdout).contains("floes broke"),
        "{}",
        text(&info.stdout)
    );
    let info = text(&info.stdout);
    assert!(
        info.contains("floe sizes")
            && info.contains("at the last snapshot: ")
            && info.contains("fractures"),
        "{info}"
    );
    for colour in ["speed", "generation"] {
        let out = Launch::Alone
            .command()
            .args(["render", &case.path("whole.h5"), "-o", &case.path("frames")])
            .args(["--color", colour, "--force"])
            .output()
            .unwrap();
        assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    }
}

#[test]
fn a_run_paused_in_the_middle_of_a_wall_schedule_resumes_bitwise() {
    // The top wall slides, slows over a ramp, holds and reverses; the pauses
    // at steps 137 (t = 68.5 s, in the ramp) and 238 (119 s, in the hold)
    // fall inside segments and between them.
    let scheduled = SMALL.replace(
        "side = \"top\"\nvelocity_m_per_s = [0.5, 0.0]\n",
        "side = \"top\"\n\n[[wall.segment]]\nduration_s = 50.0\nvelocity_m_per_s = [0.5, 0.0]\n\n\
         [[wall.segment]]\nduration_s = 20.0\nvelocity_m_per_s = [0.5, 0.0]\n\
         end_velocity_m_per_s = [0.0, 0.0]\n\n[[wall.segment]]\nduration_s = 60.0\n\n\
         [[wall.segment]]\nduration_s = 70.0\nvelocity_m_per_s = [-0.5, -0.002]\n",
    );
    assert_ne!(scheduled, SMALL, "the scenario has a top wall to schedule");
    let case = Case::new(&scheduled);
    case.run_ok("whole.h5", &["--threads", "2"]);
    case.run_ok("parts.h5", &["--threads", "1", "--max-steps", "137"]);
    case.resume_ok("parts.h5", &["--threads", "2", "--max-steps", "101"]);
    case.resume_ok("parts.h5", &["--threads", "1"]);
    case.assert_same("whole.h5", "parts.h5");
    // The wall went where its schedule says: 25 + 5 + 0 - 35 m along x,
    // -0.14 m across, at t = 200 s.
    let f = RunFile::open(Path::new(&case.path("whole.h5"))).unwrap();
    let (first, last) = (
        f.snapshot(0).unwrap(),
        f.snapshot(f.snapshot_count().unwrap() - 1).unwrap(),
    );
    assert_eq!(last.time_s, 200.0);
    let n = first.position.len();
    let dx = last.position[n - 1][0] - first.position[n - 1][0];
    let dy = last.position[n - 1][1] - first.position[n - 1][1];
    assert!(
        (dx + 5.0).abs() < 1e-9 && (dy + 0.14).abs() < 1e-9,
        "{dx}, {dy}"
    );
}

#[test]
fn ctrl_c_writes_a_final_snapshot_and_checkpoint_and_resume_is_bitwise() {
    let case = Case::new(LONG);
    case.run_ok("whole.h5", &["--threads", "2"]);
    let target = case.path("parts.h5");
    let mut child = case.spawn("parts.h5", &["--threads", "2"]);
    wait_for_progress(&mut child, Path::new(&target));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert_no_panic(&err);
    // The message says how to go on, and that command works as written.
    let suggestion = suggested_command(&err);
    assert_eq!(suggestion[..3], ["floe", "run", "--resume"], "{err}");

    let file = RunFile::open(Path::new(&target)).unwrap();
    let step = interrupted_step(&file);
    let n = file.snapshot_count().unwrap();
    assert_eq!(file.snapshot(n - 1).unwrap().step, step, "a final snapshot");
    drop(file);

    let out = run_suggestion(case.dir.path(), &suggestion);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    assert_same_run(Path::new(&case.path("whole.h5")), Path::new(&target));
}

#[test]
fn kill_9_in_the_middle_of_a_run_then_resume_is_bitwise() {
    let case = Case::new(LONG);
    case.run_ok("whole.h5", &["--threads", "2"]);
    let target = case.path("parts.h5");
    let mut child = case.spawn("parts.h5", &["--threads", "2"]);
    wait_for_progress(&mut child, Path::new(&target));
    std::thread::sleep(Duration::from_millis(150));
    child.kill().unwrap(); // SIGKILL: no handler runs
    child.wait().unwrap();

    case.resume_ok("parts.h5", &["--threads", "2"]);
    assert_same_run(Path::new(&case.path("whole.h5")), Path::new(&target));
}

#[test]
fn a_blow_up_stops_the_run_with_the_step_the_floes_and_a_smaller_dt() {
    let case = Case::new(BLOW_UP);
    let out = case.run("run.h5", &[]);
    let err = text(&out.stderr);
    assert_eq!(code(&out), 1, "{err}");
    assert_no_panic(&err);
    for expected in ["blow-up at step", "floes", "try dt_s"] {
        assert!(err.contains(expected), "`{expected}` in: {err}");
    }
    let file = RunFile::open(Path::new(&case.path("run.h5"))).unwrap();
    assert!(file.status().unwrap().starts_with("stopped"));
    // The last snapshot shows the bad state, after the last checkpoint.
    let n = file.snapshot_count().unwrap();
    let last = file.snapshot(n - 1).unwrap();
    assert!(last.step > file.checkpoint().unwrap().unwrap().step);
}

#[test]
fn an_unwritable_output_is_one_clear_error() {
    let case = Case::new(SMALL);
    // A directory that cannot exist (its parent is a file): works as root too.
    std::fs::write(case.path("plain_file"), b"").unwrap();
    let out = case.run("plain_file/run.h5", &[]);
    let err = text(&out.stderr);
    assert_ne!(code(&out), 0);
    assert_no_panic(&err);
    // The set-up report may come first; then exactly one error line.
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert_eq!(err.trim_end().lines().last(), Some(errors[0]), "{err}");
    assert!(
        errors[0].contains("plain_file/run.h5"),
        "names the file: {err}"
    );
}

#[test]
fn a_corrupt_or_foreign_resume_file_is_one_clear_error() {
    let case = Case::new(SMALL);
    std::fs::write(case.path("junk.h5"), vec![7u8; 4096]).unwrap();
    for (name, expected) in [("junk.h5", "junk.h5"), ("missing.h5", "missing.h5")] {
        let out = case.resume(name, &[]);
        let err = text(&out.stderr);
        assert_ne!(code(&out), 0, "{err}");
        assert_no_panic(&err);
        assert!(
            err.starts_with("error: ") && err.contains(expected),
            "{err}"
        );
    }
}

#[test]
fn render_draws_the_floes_and_the_observables() {
    let case = Case::new(SMALL);
    case.run_ok("run.h5", &[]);
    let file = case.path("run.h5");
    let dir = PathBuf::from(case.path("pictures"));
    let snapshots = RunFile::open(Path::new(&file))
        .unwrap()
        .snapshot_count()
        .unwrap();
    let dir_s = dir.to_string_lossy().into_owned();
    run_ok(&["render", &file, "--every", "2", "-o", &dir_s]);
    run_ok(&[
        "render",
        &file,
        "--snapshot",
        "-1",
        "--color",
        "stress",
        "-o",
        &dir_s,
        "--force",
    ]);
    run_ok(&[
        "render",
        &file,
        "--snapshot",
        "0",
        "--color",
        "theta",
        "-o",
        &dir_s,
        "--force",
    ]);
    let pngs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    let speed = pngs
        .iter()
        .filter(|p| p.to_string_lossy().contains("floes_speed_"))
        .count();
    assert_eq!(speed, snapshots.div_ceil(2), "{pngs:?}");
    assert!(
        dir.join("observables.png").exists(),
        "observables.png in {pngs:?}"
    );
    assert!(pngs.iter().any(|p| p.to_string_lossy().contains("stress")));
    assert!(pngs.iter().any(|p| p.to_string_lossy().contains("theta")));
    for p in &pngs {
        let bytes = std::fs::read(p).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", p.display());
    }
    // Pictures are not overwritten without --force.
    let out = run(&["render", &file, "--every", "2", "-o", &dir_s]);
    assert_eq!(code(&out), 2, "{}", text(&out.stderr));
}

/// `floe render --movie`: a GIF of every snapshot by default; an MP4
/// without ffmpeg is refused with a message that says so and offers a GIF;
/// no extension gives a GIF without ffmpeg; no overwrite without --force.
#[test]
fn render_writes_a_movie_and_explains_a_missing_ffmpeg() {
    let case = Case::new(SMALL);
    case.run_ok("run.h5", &[]);
    let file = case.path("run.h5");
    let snapshots = RunFile::open(Path::new(&file))
        .unwrap()
        .snapshot_count()
        .unwrap();
    let gif = case.path("run.gif");
    let out = run_ok(&["render", &file, "--movie", &gif, "--fps", "4"]);
    assert!(
        out.contains(&format!("{snapshots} frames")) && out.contains("GIF"),
        "{out}"
    );
    assert_eq!(&std::fs::read(&gif).unwrap()[..6], b"GIF89a");
    let out = run(&["render", &file, "--movie", &gif]);
    assert_eq!(code(&out), 2, "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("--force"));
    run_ok(&["render", &file, "--movie", &gif, "--every", "3", "--force"]);

    // Without ffmpeg on PATH.
    let empty = case.path("no-programs");
    std::fs::create_dir(&empty).unwrap();
    let without_ffmpeg = |args: &[&str]| floe().args(args).env("PATH", &empty).output().unwrap();
    let mp4 = case.path("run.mp4");
    let out = without_ffmpeg(&["render", &file, "--movie", &mp4]);
    let err = text(&out.stderr);
    assert_eq!(code(&out), 2, "{err}");
    assert_no_panic(&err);
    assert!(err.contains("ffmpeg") && err.contains("run.gif"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!Path::new(&mp4).exists());
    let out = without_ffmpeg(&["render", &file, "--movie", &case.path("plain")]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    assert!(Path::new(&case.path("plain.gif")).exists());

    // An ffmpeg that fails: its message, exit 1, no file left.
    let broken = case.path("broken-ffmpeg");
    std::fs::create_dir(&broken).unwrap();
    let script = Path::new(&broken).join("ffmpeg");
    std::fs::write(
        &script,
        "#!/bin/sh\n[ \"$1\" = -version ] && exit 0\necho 'Unknown encoder libx264' >&2\nexit 1\n",
    )
    .unwrap();
    let mut mode = std::fs::metadata(&script).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut mode, 0o755);
    std::fs::set_permissions(&script, mode).unwrap();
    let out = floe()
        .args(["render", &file, "--movie", &mp4])
        .env("PATH", &broken)
        .output()
        .unwrap();
    let err = text(&out.stderr);
    assert_eq!(code(&out), 1, "{err}");
    assert_no_panic(&err);
    assert!(
        err.contains("ffmpeg failed") && err.contains("Unknown encoder libx264"),
        "{err}"
    );
    assert!(!Path::new(&mp4).exists() && !Path::new(&format!("{mp4}.partial")).exists());

    // Bad flags: one message, exit 2, nothing written.
    for args in [
        vec!["--movie", "m.avi"],
        vec!["--movie", "m.gif", "--fps", "0"],
        vec!["--movie", "m.gif", "--fps", "nan"],
        vec!["--fps", "10", "-o", "pictures"],
        vec!["--field", "u", "-o", "pictures"],
        vec!["--movie", "m.gif", "-o", "pictures"],
        vec![],
    ] {
        let mut all = vec!["render", file.as_str()];
        all.extend_from_slice(&args);
        let out = floe()
            .args(&all)
            .current_dir(case.dir.path())
            .output()
            .unwrap();
        let err = text(&out.stderr);
        assert_eq!(code(&out), 2, "{args:?}: {err}");
        assert_no_panic(&err);
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    }
    assert!(!case.dir.path().join("m.gif").exists() && !case.dir.path().join("pictures").exists());
}

/// A run paused by the previous checkpoint format (2) resumes, taking its
/// time step from the stored scenario, and ends bitwise as a fresh run of
/// the same scenario does.
#[test]
fn a_run_paused_in_the_previous_checkpoint_format_resumes_from_its_state() {
    // The physics has changed since that floe (drag at second order,
    // restitution with the clipped dashpot), so the resumed run cannot
    // equal a fresh one; what must hold is that the checkpoint decodes to
    // the state the old floe wrote beside it (its step-37 snapshot).
    let case = Case::new(SMALL);
    let old = case.path("old.h5");
    std::fs::write(&old, FORMAT_2_PAUSED).unwrap();
    let info = run_ok(&["info", &old]);
    assert!(info.contains("paused at step 37"), "{info}");
    let (last, snap, contacts, state) = {
        let f = RunFile::open(Path::new(&old)).unwrap();
        let last = f.snapshot_count().unwrap() - 1;
        let state = f.checkpoint_state(|| Some(0.5)).unwrap().unwrap();
        (
            last,
            f.snapshot(last).unwrap(),
            f.contacts(last).unwrap(),
            state,
        )
    };
    assert_eq!((snap.step, state.steps), (37, 37));
    let floes = state.floes.columns();
    let pos: Vec<[f64; 2]> = floes.position.iter().map(|p| [p.x, p.y]).collect();
    let vel: Vec<[f64; 2]> = floes.velocity.iter().map(|v| [v.x, v.y]).collect();
    assert_eq!(bits2(&pos), bits2(&snap.position), "positions");
    assert_eq!(bits2(&vel), bits2(&snap.velocity), "velocities");
    assert_eq!(bits(&floes.angle), bits(&snap.angle), "angles");
    assert_eq!(bits(&floes.angular_velocity), bits(&snap.angular_velocity));
    let pairs: Vec<[u32; 2]> = state.contacts.iter().map(|c| [c.a, c.b]).collect();
    assert_eq!(pairs, contacts.pair, "contact pairs");
    let theta: Vec<f64> = state
        .contacts
        .iter()
        .map(|c| c.friction.law_state[floe_friction::rate_state::THETA])
        .collect();
    assert_eq!(bits(&theta), bits(&contacts.theta), "theta");
    let force: Vec<f64> = state
        .contacts
        .iter()
        .map(|c| c.friction.tangential_force_n.abs())
        .collect();
    let snap_force: Vec<f64> = contacts
        .tangential_force_n
        .iter()
        .map(|f| f.abs())
        .collect();
    assert_eq!(bits(&force), bits(&snap_force), "tangential forces");
    // It resumes to the end, writing where the uninterrupted run would
    // (the pause's own snapshot gives way to the cadence's).
    let first = RunFile::open(Path::new(&old)).unwrap().snapshot(0).unwrap();
    case.resume_ok("old.h5", &[]);
    assert!(run_ok(&["info", &old]).contains("completed"));
    let f = RunFile::open(Path::new(&old)).unwrap();
    assert_eq!(
        bits2(&f.snapshot(0).unwrap().position),
        bits2(&first.position)
    );
    assert_eq!(f.snapshot(last).unwrap().step, 50);
}

/// The snapshot count `floe info` reports.
fn info_snapshots(stdout: &str) -> usize {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("snapshots"))
        .unwrap_or_else(|| panic!("no snapshot line: {stdout}"));
    line.split_whitespace()
        .nth(1)
        .unwrap()
        .trim_end_matches(',')
        .parse()
        .unwrap()
}

#[test]
fn floe_info_reads_a_file_while_a_run_writes_it() {
    // A snapshot about every 15 steps and a checkpoint every 40: the file
    // is flushed every few milliseconds while `floe info` reads it.
    let busy = LONG
        .replace("snapshot_every_s = 300.0", "snapshot_every_s = 10.0")
        .replace("checkpoint_every_s = 60.0", "checkpoint_every_s = 30.0");
    let case = Case::new(&busy);
    let target = case.path("busy.h5");
    let mut child = case.spawn("busy.h5", &["--threads", "1"]);
    wait_for_progress(&mut child, Path::new(&target));
    let (mut calls, mut last) = (0, 0);
    while child.try_wait().unwrap().is_none() {
        let out = run(&["info", &target]);
        let err = text(&out.stderr);
        assert_eq!(code(&out), 0, "call {calls}: {err}");
        let n = info_snapshots(&text(&out.stdout));
        assert!(n >= last, "snapshots went from {last} to {n}");
        (calls, last) = (calls + 1, n);
    }
    assert!(child.wait().unwrap().success());
    assert!(calls >= 30, "only {calls} reads while the run wrote");
}

/// `run_small.toml` (dt = 0.5 s, 400 steps; snapshots every 25 s,
/// observables every 3.5 s) with a window from 61 s to 131.2 s of snapshots
/// every 2.5 s and observables every 1 s.
const WINDOW: &str = "\n[[output.window]]\nfrom_s = 61.0\nto_s = 131.2\n\
                      snapshot_every_s = 2.5\nobservables_every_s = 1.0\n";

/// The times `t = n dt` (n = 0..=400, dt = 0.5 s) that are multiples of
/// `base_s`, or of `window_s` within [61, 131.2] s, or the first or last.
fn expected_times(base_s: f64, window_s: f64) -> Vec<f64> {
    let multiple = |t: f64, every: f64| (t / every).fract() == 0.0;
    (0..=400)
        .map(|n| 0.5 * f64::from(n))
        .filter(|&t| {
            t == 0.0
                || t == 200.0
                || multiple(t, base_s)
                || ((61.0..=131.2).contains(&t) && multiple(t, window_s))
        })
        .collect()
}

#[test]
fn a_window_adds_its_cadence_inside_it_and_leaves_the_base_cadence_outside() {
    let case = Case::new(&format!("{SMALL}{WINDOW}"));
    case.run_ok("window.h5", &["--threads", "1"]);
    let plain = Case::new(SMALL);
    plain.run_ok("plain.h5", &["--threads", "1"]);
    let f = RunFile::open(Path::new(&case.path("window.h5"))).unwrap();
    let snapshots = f.snapshot_times().unwrap();
    assert_eq!(snapshots, expected_times(25.0, 2.5));
    assert_eq!(
        snapshots.len(),
        9 + 28 - 3,
        "base and window, 75, 100 and 125 s in both"
    );
    let samples = f.observable("kinetic_translational").unwrap();
    assert_eq!(samples.time_s, expected_times(3.5, 1.0));
    // Writing more does not change the run: the samples outside the
    // window are those of the run without it, bitwise.
    let p = RunFile::open(Path::new(&plain.path("plain.h5"))).unwrap();
    let base = p.observable("kinetic_translational").unwrap();
    assert_eq!(base.time_s, expected_times(3.5, 3.5));
    for (t, v) in base.time_s.iter().zip(&base.value) {
        let k = samples.time_s.iter().position(|s| s == t).unwrap();
        assert_eq!(samples.value[k].to_bits(), v.to_bits(), "t = {t}");
    }
    assert_eq!(
        f.checkpoint_state(|| None).unwrap(),
        p.checkpoint_state(|| None).unwrap()
    );
}

#[test]
fn a_run_paused_inside_a_window_resumes_bitwise() {
    // Pauses at steps 137 (68.5 s) and 238 (119 s), both in the window and
    // off its snapshot cadence (5 steps); 137 is off its observable cadence
    // (2 steps), so the extras written there must be dropped on resume.
    let case = Case::new(&format!("{SMALL}{WINDOW}"));
    case.run_ok("whole.h5", &["--threads", "2"]);
    case.run_ok("parts.h5", &["--threads", "1", "--max-steps", "137"]);
    let paused = RunFile::open(Path::new(&case.path("parts.h5"))).unwrap();
    assert_eq!(paused.snapshot_times().unwrap().last(), Some(&68.5));
    drop(paused);
    case.resume_ok("parts.h5", &["--threads", "2", "--max-steps", "101"]);
    case.resume_ok("parts.h5", &["--threads", "1"]);
    case.assert_same("whole.h5", "parts.h5");
}

#[test]
fn ctrl_c_inside_a_window_then_resume_is_bitwise() {
    // The long channel with a window over all but its first minute: the
    // interrupt, after the first checkpoint past step 0 (60 s), lands in it.
    let windowed = format!(
        "{LONG}\n[[output.window]]\nfrom_s = 60.0\nto_s = 5400.0\n\
         snapshot_every_s = 40.0\nobservables_every_s = 4.0\n"
    );
    let case = Case::new(&windowed);
    case.run_ok("whole.h5", &["--threads", "2"]);
    let target = case.path("parts.h5");
    let mut child = case.spawn("parts.h5", &["--threads", "2"]);
    wait_for_progress(&mut child, Path::new(&target));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", text(&out.stderr));
    case.resume_ok("parts.h5", &["--threads", "1"]);
    assert_same_run(Path::new(&case.path("whole.h5")), Path::new(&target));
}

#[test]
fn floes_weld_keeping_their_volume_and_a_paused_run_resumes_bitwise() {
    let case = Case::new(WELDING);
    case.run_ok("whole.h5", &["--threads", "2"]);
    case.run_ok("parts.h5", &["--threads", "1", "--max-steps", "137"]);
    case.resume_ok("parts.h5", &["--threads", "2"]);
    case.assert_same("whole.h5", "parts.h5");
    let f = RunFile::open(Path::new(&case.path("whole.h5"))).unwrap();
    let n = f.snapshot_count().unwrap();
    let log = f.welds().unwrap();
    let chained = log
        .iter()
        .filter(|r| log.iter().any(|q| r.ids.contains(&q.welded_id)))
        .count();
    eprintln!("{} welds, {chained} of a welded floe", log.len());
    assert!(log.len() >= 10 && chained >= 1, "{} welds", log.len());
    // Every snapshot's free ice volume and mass are the start's; the floe
    // count falls by one a weld; each welded floe names the first of its
    // pair as its parent, and its area and mass are the log's.
    let free = |k: usize, what: fn(&floe_io::StaticFloes, usize) -> f64| {
        let s = f.floes_at(k).unwrap();
        (0..s.len())
            .filter(|&i| !s.prescribed[i])
            .map(|i| what(&s, i))
            .sum::<f64>()
    };
    let volume = |s: &floe_io::StaticFloes, i: usize| s.area_m2[i] * s.thickness_m[i];
    let mass = |s: &floe_io::StaticFloes, i: usize| s.mass_kg[i];
    let (v0, m0) = (free(0, volume), free(0, mass));
    let count0 = f.floes_at(0).unwrap().len();
    for k in 0..n {
        let (v, m) = (free(k, volume), free(k, mass));
        assert!((v - v0).abs() < 1e-12 * v0, "snapshot {k}: {v} vs {v0}");
        assert!((m - m0).abs() < 1e-12 * m0, "snapshot {k}: {m} vs {m0}");
        let step = f.snapshot(k).unwrap().step;
        let welded = log.iter().filter(|r| r.step <= step).count();
        let s = f.floes_at(k).unwrap();
        assert_eq!(s.len(), count0 - welded, "snapshot {k}");
        let parents = f.parent_ids_at(k).unwrap();
        for r in log.iter().filter(|r| r.step <= step) {
            if let Some(i) = s.id.iter().position(|&id| id == r.welded_id) {
                assert_eq!(parents[i], Some(r.ids[0]), "{r:?}");
                assert_eq!(s.area_m2[i], r.area_m2);
                assert_eq!(s.mass_kg[i], r.mass_kg);
            }
        }
    }
    let end = f.snapshot(n - 1).unwrap();
    let dt = end.time_s / end.step as f64;
    for (r, next) in log.iter().zip(log.iter().skip(1)) {
        assert!(r.step <= next.step, "in step order");
        assert!(
            r.step < next.step || r.ids < next.ids,
            "by pair within a step"
        );
        assert_eq!(next.welded_id, r.welded_id + 1, "numbered in order");
    }
    // `floe info` reports the welds and the last snapshot's floe count.
    let info = run_ok(&["info", &case.path("whole.h5")]);
    assert!(
        info.contains(&format!("{} pairs welded", log.len()))
            && info.contains(&format!("{} at the last snapshot", count0 - log.len())),
        "{info}"
    );
    for r in &log {
        assert!((r.time_s - r.step as f64 * dt).abs() <= 1e-9 * end.time_s);
        // The hull is at most 30 % larger than the pair (the scenario's
        // limit) and never smaller than the pair less its overlap.
        let pair = r.areas_m2[0] + r.areas_m2[1];
        assert!(r.area_m2 <= 1.3 * pair && r.area_m2 > 0.99 * pair, "{r:?}");
        assert!(r.released_j >= 0.0, "{r:?}");
    }
}

#[test]
fn floes_ridge_keeping_their_volume_and_a_paused_run_resumes_bitwise() {
    let case = Case::new(RIDGING);
    case.run_ok("whole.h5", &["--threads", "2"]);
    case.run_ok("parts.h5", &["--threads", "1", "--max-steps", "137"]);
    case.resume_ok("parts.h5", &["--threads", "2"]);
    case.assert_same("whole.h5", "parts.h5");
    let f = RunFile::open(Path::new(&case.path("whole.h5"))).unwrap();
    let n = f.snapshot_count().unwrap();
    let volume = f.observable("ridged_volume").unwrap();
    let events = f.observable("ridging_events").unwrap();
    // Free ice volume at each snapshot and the volume lost to the coast by
    // then (an observable sample at the snapshot's step) add up to the
    // start's; the floes' shapes and thicknesses follow the ridging.
    let free_volume = |k: usize| {
        let s = f.floes_at(k).unwrap();
        (0..s.len())
            .filter(|&i| !s.prescribed[i])
            .map(|i| s.area_m2[i] * s.thickness_m[i])
            .sum::<f64>()
    };
    let thickest = |k: usize| {
        let s = f.floes_at(k).unwrap();
        (0..s.len())
            .filter(|&i| !s.prescribed[i])
            .map(|i| s.thickness_m[i])
            .fold(0.0, f64::max)
    };
    let v0 = free_volume(0);
    for k in 0..n {
        let step = f.snapshot(k).unwrap().step;
        let j = volume
            .step
            .iter()
            .position(|&s| s == step)
            .expect("a sample");
        let to_coast = volume.value[2 * j + 1];
        let v = free_volume(k) + to_coast;
        assert!((v - v0).abs() < 1e-12 * v0, "snapshot {k}: {v} vs {v0}");
    }
    let last_events = *events.value.last().unwrap();
    let (to_floes, to_coast) = (
        volume.value[volume.value.len() - 2],
        volume.value[volume.value.len() - 1],
    );
    eprintln!("{last_events} events, {to_floes:.4e} m^3 to floes, {to_coast:.4e} m^3 to the coast");
    assert!(last_events > 100.0 && to_floes > 0.0 && to_coast > 0.0);
    assert!(thickest(n - 1) > thickest(0) + 0.1, "floes thickened");
    let areas = |k: usize| f.floes_at(k).unwrap().area_m2;
    assert_ne!(areas(0), areas(n - 1), "the losers' shapes follow");
    // The event log: one row per event the ledger counted, whose volumes
    // (summed here in plain floating point) are the ledger's (summed
    // exactly by the engine), split the same way between floes and coast.
    let log = f.ridges().unwrap();
    assert_eq!(log.len() as f64, last_events, "a row per event");
    let logged = |coast: bool| {
        log.iter()
            .filter(|r| r.to_coast == coast)
            .map(|r| r.volume_m3)
            .sum::<f64>()
    };
    assert!(
        (logged(false) - to_floes).abs() <= 1e-9 * to_floes,
        "{} vs {to_floes}",
        logged(false)
    );
    assert!(
        (logged(true) - to_coast).abs() <= 1e-9 * to_coast,
        "{} vs {to_coast}",
        logged(true)
    );
    let end = f.snapshot(n - 1).unwrap();
    for (r, next) in log.iter().zip(log.iter().skip(1)) {
        assert!(r.step <= next.step && r.step <= end.step, "in step order");
        assert!(
            r.step < next.step || r.loser_id < next.loser_id,
            "by loser within a step"
        );
    }
    let dt = end.time_s / end.step as f64;
    for r in &log {
        assert!(
            (r.time_s - r.step as f64 * dt).abs() <= 1e-9 * end.time_s,
            "{r:?}"
        );
        assert!(
            r.area_removed_m2 > 0.0 && r.area_removed_m2 <= r.area_before_m2,
            "{r:?}"
        );
        // A crushed floe leaves no contact; a cut one at most its cap
        // (none where the cut had to go past the gainer's edge).
        assert_eq!(r.whole, r.area_removed_m2 == r.area_before_m2, "{r:?}");
        assert!(r.force_after_n < r.force_before_n, "{r:?}");
        assert!(!r.whole || r.force_after_n == 0.0, "{r:?}");
        assert!(r.to_coast || r.ice_to_id != r.loser_id, "{r:?}");
    }
    assert!(log.iter().any(|r| r.to_coast) && log.iter().any(|r| !r.to_coast));
    // Without `[output] ridging_log` the same run writes no log.
    let unlogged = Case::new(&RIDGING.replacen("ridging_log = true\n", "", 1));
    unlogged.run_ok("plain.h5", &["--threads", "1"]);
    let plain = RunFile::open(Path::new(&unlogged.path("plain.h5"))).unwrap();
    assert!(plain.ridges().unwrap().is_empty());
    assert_eq!(
        bits2(&plain.snapshot(n - 1).unwrap().position),
        bits2(&f.snapshot(n - 1).unwrap().position),
        "the log changes nothing else"
    );
    let info = floe()
        .args(["info", &case.path("whole.h5")])
        .output()
        .unwrap();
    let info = text(&info.stdout);
    let crushed = log.iter().filter(|r| r.whole).count();
    assert!(
        info.contains(&format!(
            "ridging      {} events ({} cuts, {crushed} floes crushed whole)",
            log.len(),
            log.len() - crushed
        )),
        "floe info reports the log: {info}"
    );
}

/// `floe run --xdmf` leaves the ParaView description beside the run file,
/// the same one `floe export --xdmf` writes (python/tests/test_xdmf.py
/// reads it back against the run file, also with ParaView's reader).
#[test]
fn run_with_xdmf_writes_what_export_writes() {
    let case = Case::new(SMALL);
    case.run_ok("a.h5", &["--threads", "1", "--xdmf"]);
    let written = std::fs::read_to_string(case.path("a.xdmf")).unwrap();
    assert!(Path::new(&case.path("a.xdmf.h5")).exists());
    let n = RunFile::open(Path::new(&case.path("a.h5")))
        .unwrap()
        .snapshot_count()
        .unwrap();
    assert_eq!(written.matches(r#"<Grid Name="floes "#).count(), n);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_floe"))
        .args([
            "export",
            &case.path("a.h5"),
            "--xdmf",
            "-o",
            &case.path("b.xdmf"),
        ])
        .output()
        .unwrap();
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let exported = std::fs::read_to_string(case.path("b.xdmf")).unwrap();
    assert_eq!(written.replace("a.xdmf.h5", "b.xdmf.h5"), exported);
}
