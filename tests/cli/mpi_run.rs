//! `mpirun -np K floe run`: the run file is bitwise the single process's
//! for K = 1..4; a run paused on some processes resumes on others (or on
//! one); SIGTERM to the processes (as Slurm sends at a time limit) ends
//! them with one consistent checkpoint and exit 130; a process killed with
//! SIGKILL stops the job and the last checkpoint resumes; too many
//! processes is one clear error. Needs `mpirun` (`make deps`) and the
//! `mpi` feature (`make test`).

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use floe_io::RunFile;

use crate::run_support;
use run_support::{
    assert_no_panic, assert_same_run, code, interrupted_step, mpirun_args, text, wait_for_progress,
    Case, Launch,
};

/// A sheared periodic channel with walls and contact memory, 2,400 steps.
const CHANNEL: &str = include_str!("../data/mpi_channel.toml");

/// The channel of tests/cli/run.rs run long enough to be interrupted.
const LONG: &str = include_str!("../data/run_long.toml");

/// Walls that close far faster than contacts can push back.
const BLOW_UP: &str = include_str!("../data/run_blow_up.toml");

/// The small channel, its floes breaking against the bottom wall.
const FRACTURE: &str = include_str!("../data/run_fracture.toml");
/// Small channel pressed by a closing wall: floes ridge.
const RIDGING: &str = include_str!("../data/run_ridging.toml");
const WELDING: &str = include_str!("../data/run_welding.toml");

/// Free floes whose x moved by more than half the 6 km period between the
/// first and the last snapshot: they crossed the periodic seam.
fn free_floes_across_the_seam(file: &Path) -> usize {
    let f = RunFile::open(file).unwrap();
    let n = f.snapshot_count().unwrap();
    let (first, last) = (f.snapshot(0).unwrap(), f.snapshot(n - 1).unwrap());
    let prescribed = f.static_floes().unwrap().prescribed;
    (0..first.position.len())
        .filter(|&i| !prescribed[i] && (last.position[i][0] - first.position[i][0]).abs() > 3000.0)
        .count()
}

#[test]
fn one_to_four_processes_write_the_single_process_run_file_bitwise() {
    let case = Case::new(CHANNEL);
    case.run_ok("alone.h5", &["--threads", "1"]);
    assert!(
        free_floes_across_the_seam(Path::new(&case.path("alone.h5"))) > 0,
        "the run is eventful: floes cross the periodic seam"
    );
    for (np, threads) in [(1, "2"), (2, "1"), (3, "1"), (4, "1"), (2, "2")] {
        let name = format!("np{np}x{threads}.h5");
        let out = case.run_with(Launch::Mpi(np), &name, &["--threads", threads]);
        let err = text(&out.stderr);
        assert_eq!(code(&out), 0, "-np {np}: {err}");
        assert_no_panic(&err);
        if np > 1 {
            assert!(
                err.contains(&format!("{np} processes x {threads} threads")),
                "{err}"
            );
            // Process 0 alone talks: the set-up is said once.
            assert_eq!(err.matches("dt: ").count(), 1, "{err}");
            // Floes crossed between subdomains more than once.
            let migrations: u64 = err
                .split("decomposition: ")
                .nth(1)
                .and_then(|s| s.split(' ').next())
                .and_then(|n| n.parse().ok())
                .unwrap_or_else(|| panic!("the run reports its migrations: {err}"));
            assert!(migrations > 2, "{err}");
            let info = Launch::Alone
                .command()
                .args(["info", &case.path(&name)])
                .output()
                .unwrap();
            let info = text(&info.stdout);
            assert!(
                info.contains(&format!("{np} processes x {threads} threads")),
                "floe info says how the run was spread: {info}"
            );
        }
        assert_same_run(
            Path::new(&case.path("alone.h5")),
            Path::new(&case.path(&name)),
        );
    }
}

#[test]
fn floes_break_on_two_and_three_processes_as_on_one_and_resume_across_counts() {
    let case = Case::new(FRACTURE);
    case.run_ok("alone.h5", &["--threads", "1"]);
    let broke = RunFile::open(Path::new(&case.path("alone.h5")))
        .unwrap()
        .fractures()
        .unwrap()
        .len();
    assert!(broke > 30, "floes broke ({broke})");
    // And froze together: bonds migrate and are gathered with their floes.
    let bonds = RunFile::open(Path::new(&case.path("alone.h5")))
        .unwrap()
        .observable("bonds")
        .unwrap()
        .value;
    assert!(bonds.iter().any(|&b| b > 100.0), "bonds: {bonds:?}");
    for np in [2, 3] {
        let name = format!("np{np}.h5");
        let out = case.run_with(Launch::Mpi(np), &name, &["--threads", "1"]);
        assert_eq!(code(&out), 0, "-np {np}: {}", text(&out.stderr));
        assert_same_run(
            Path::new(&case.path("alone.h5")),
            Path::new(&case.path(&name)),
        );
    }
    let out = case.run_with(Launch::Mpi(2), "parts.h5", &["--max-steps", "1371"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let out = case.resume_with(Launch::Mpi(3), "parts.h5", &[]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    case.assert_same("alone.h5", "parts.h5");
}

/// `scenario` on two and three processes, and paused on two and resumed on
/// `resumed_on`, gives one process's run file.
fn on_two_and_three_processes_as_on_one(scenario: &str, resumed_on: usize) {
    let case = Case::new(scenario);
    case.run_ok("alone.h5", &["--threads", "1"]);
    for np in [2, 3] {
        let name = format!("np{np}.h5");
        let out = case.run_with(Launch::Mpi(np), &name, &["--threads", "1"]);
        assert_eq!(code(&out), 0, "-np {np}: {}", text(&out.stderr));
        assert_same_run(
            Path::new(&case.path("alone.h5")),
            Path::new(&case.path(&name)),
        );
    }
    let out = case.run_with(Launch::Mpi(2), "parts.h5", &["--max-steps", "137"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let out = case.resume_with(Launch::Mpi(resumed_on), "parts.h5", &[]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    case.assert_same("alone.h5", "parts.h5");
}

#[test]
fn floes_ridge_on_two_and_three_processes_as_on_one() {
    on_two_and_three_processes_as_on_one(RIDGING, 3);
}

#[test]
fn floes_weld_on_two_and_three_processes_as_on_one() {
    // Resumed on two: by step 137 the welded floes are wider than a third
    // of the channel, which three processes would refuse to split.
    on_two_and_three_processes_as_on_one(WELDING, 2);
}

#[test]
fn a_run_paused_on_two_processes_resumes_on_three_and_on_one_bitwise() {
    let case = Case::new(CHANNEL);
    case.run_ok("alone.h5", &[]);
    let out = case.run_with(Launch::Mpi(2), "parts.h5", &["--max-steps", "137"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("paused"),
        "{}",
        text(&out.stdout)
    );
    let out = case.resume_with(Launch::Mpi(3), "parts.h5", &["--max-steps", "300"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    case.resume_ok("parts.h5", &[]);
    case.assert_same("alone.h5", "parts.h5");
}

/// The processes `mpirun` started (its children).
fn ranks_of(mpirun: u32) -> Vec<u32> {
    let out = Command::new("pgrep")
        .args(["-P", &mpirun.to_string()])
        .output()
        .unwrap();
    text(&out.stdout)
        .split_whitespace()
        .map(|p| p.parse().unwrap())
        .collect()
}

fn signal(signal: &str, pids: &[u32]) {
    let mut kill = Command::new("kill");
    kill.arg(format!("-{signal}"));
    for p in pids {
        kill.arg(p.to_string());
    }
    assert!(kill.status().unwrap().success());
}

#[test]
fn sigterm_to_every_process_writes_one_checkpoint_exits_130_and_resumes_bitwise() {
    let case = Case::new(LONG);
    case.run_ok("whole.h5", &["--threads", "2"]);
    let target = case.path("parts.h5");
    let mut child = case.spawn_with(Launch::Mpi(2), "parts.h5", &["--threads", "1"]);
    wait_for_progress(&mut child, Path::new(&target));
    // As Slurm does at a time limit: every process of the job step.
    signal("TERM", &ranks_of(child.id()));
    let out = child.wait_with_output().unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert_no_panic(&err);
    assert_eq!(
        err.matches("continue with `floe run --resume").count(),
        1,
        "{err}"
    );
    let file = RunFile::open(Path::new(&target)).unwrap();
    interrupted_step(&file);
    drop(file);
    let out = case.resume_with(Launch::Mpi(2), "parts.h5", &["--threads", "1"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    assert_same_run(Path::new(&case.path("whole.h5")), Path::new(&target));
}

#[test]
fn sigusr1_to_mpirun_writes_one_checkpoint_exits_130_and_resumes_bitwise() {
    let case = Case::new(LONG);
    case.run_ok("whole.h5", &["--threads", "2"]);
    let target = case.path("parts.h5");
    let mut child = case.spawn_with(Launch::Mpi(2), "parts.h5", &["--threads", "1"]);
    wait_for_progress(&mut child, Path::new(&target));
    // mpirun passes SIGUSR1 on to every process at once.
    signal("USR1", &[child.id()]);
    let out = child.wait_with_output().unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert_no_panic(&err);
    let status = RunFile::open(Path::new(&target)).unwrap().status().unwrap();
    assert!(status.starts_with("interrupted at step "), "{status}");
    let out = case.resume_with(Launch::Mpi(3), "parts.h5", &["--threads", "1"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    assert_same_run(Path::new(&case.path("whole.h5")), Path::new(&target));
}

#[test]
fn ctrl_c_to_mpirun_reaches_every_process_which_checkpoint_and_the_run_resumes() {
    // Ten times longer than LONG: still running when the signal arrives.
    let case = Case::new(&LONG.replace("duration_s = 5400.0", "duration_s = 54000.0"));
    let target = case.path("parts.h5");
    // Open MPI's mpirun passes SIGINT on as SIGTERM after this many seconds
    // and kills as long after: time for the final checkpoint.
    let mut child = Launch::Mpi(2)
        .command()
        .env("OMPI_MCA_odls_base_sigkill_timeout", "3")
        .args([
            "run",
            &case.scenario(),
            "-o",
            &target,
            "-q",
            "--threads",
            "1",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_progress(&mut child, Path::new(&target));
    signal("INT", &[child.id()]);
    let out = child.wait_with_output().unwrap();
    let err = text(&out.stderr);
    // mpirun itself reports 1 for a job it was told to end; the processes
    // stopped cleanly.
    assert_ne!(out.status.code(), Some(0), "{err}");
    assert_no_panic(&err);
    assert_eq!(
        err.matches("continue with `floe run --resume").count(),
        1,
        "{err}"
    );
    let file = RunFile::open(Path::new(&target)).unwrap();
    let step = interrupted_step(&file);
    drop(file);
    let out = case.resume_with(Launch::Mpi(3), "parts.h5", &["--max-steps", "20"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    let resumed = RunFile::open(Path::new(&target)).unwrap();
    assert_eq!(resumed.checkpoint().unwrap().unwrap().step, step + 20);
}

#[test]
fn a_process_killed_with_sigkill_stops_the_job_and_the_last_checkpoint_resumes() {
    let case = Case::new(LONG);
    case.run_ok("whole.h5", &["--threads", "2"]);
    let target = case.path("parts.h5");
    let mut child = case.spawn_with(Launch::Mpi(3), "parts.h5", &["--threads", "1"]);
    wait_for_progress(&mut child, Path::new(&target));
    std::thread::sleep(Duration::from_millis(150));
    let ranks = ranks_of(child.id());
    assert_eq!(ranks.len(), 3, "three processes");
    signal("KILL", &ranks[1..2]);
    let out = child.wait_with_output().unwrap();
    let err = text(&out.stderr);
    assert_ne!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("signal 9"),
        "mpirun says which process died: {err}"
    );
    let out = case.resume_with(Launch::Mpi(2), "parts.h5", &["--threads", "1"]);
    assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    assert_same_run(Path::new(&case.path("whole.h5")), Path::new(&target));
}

#[test]
fn more_processes_than_floes_or_subdomains_narrower_than_a_floe_are_one_clear_error() {
    let few = CHANNEL.replace("side_m = 500.0", "side_m = 2000.0");
    let case = Case::new(&few);
    let alone = case.run("probe.h5", &["--max-steps", "1"]);
    let said = text(&alone.stderr);
    assert_eq!(code(&alone), 0, "{said}");
    // "  N free floes, M prescribed ..."
    let floes: usize = said
        .lines()
        .find_map(|l| l.trim().split_once(" free floes"))
        .and_then(|(n, _)| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("the set-up counts the free floes: {said}"));
    assert!(floes < 8, "a few floes: {floes}");
    let out = case.run_with(Launch::Mpi(floes + 1), "many.h5", &[]);
    let err = text(&out.stderr);
    assert_eq!(code(&out), 2, "{err}");
    assert_no_panic(&err);
    assert_eq!(err.matches("error:").count(), 1, "one message: {err}");
    assert!(err.contains("each process needs a floe"), "{err}");
    let out = case.run_with(Launch::Mpi(4), "narrow.h5", &[]);
    let err = text(&out.stderr);
    assert_eq!(code(&out), 2, "{err}");
    assert!(
        err.contains("narrower than the largest floe") && err.contains("fewer processes"),
        "{err}"
    );
}

/// `floe sweep --emit`'s mpi.slurm, run as Slurm would run task 2 of the
/// array, with `srun` standing for `mpirun -np 2`: the variant's run file
/// is the single process's.
#[test]
fn the_emitted_mpi_job_script_runs_a_variant_over_processes() {
    let case = Case::new(CHANNEL);
    let out = std::path::PathBuf::from(case.path("sweep"));
    let sweep = Launch::Alone
        .command()
        .args([
            "sweep",
            &case.scenario(),
            "--set",
            "contact.memory_s=50,100",
        ])
        .args(["--emit", "-o", &out.display().to_string()])
        .output()
        .unwrap();
    assert_eq!(code(&sweep), 0, "{}", text(&sweep.stderr));
    let script = out.join("mpi.slurm");
    assert!(std::fs::read_to_string(&script)
        .unwrap()
        .contains("#SBATCH --array=1-2"));
    // `floe` and `srun` on the PATH, as on a cluster.
    let bin = out.join("bin");
    std::fs::create_dir(&bin).unwrap();
    let shim = |name: &str, body: String| {
        let path = bin.join(name);
        std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
        Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    };
    shim(
        "floe",
        format!("exec '{}' \"$@\"", env!("CARGO_BIN_EXE_floe")),
    );
    shim(
        "srun",
        format!("exec mpirun {} \"$@\"", mpirun_args(2).join(" ")),
    );
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap());
    let job = Command::new("bash")
        .arg(&script)
        .env("PATH", path)
        .env("SLURM_SUBMIT_DIR", &out)
        .env("SLURM_ARRAY_TASK_ID", "2")
        .env("SLURM_CPUS_PER_TASK", "1")
        .output()
        .unwrap();
    let err = text(&job.stderr);
    assert_eq!(code(&job), 0, "{err}");
    assert!(err.contains("2 processes x 1 threads"), "{err}");
    let alone = case.run_with(Launch::Alone, "alone.h5", &["--threads", "1"]);
    assert_eq!(code(&alone), 0);
    // Variant 2 is memory_s = 100, the scenario's own value.
    assert_same_run(
        Path::new(&case.path("alone.h5")),
        &out.join("variant_002.h5"),
    );
}

#[test]
fn a_blow_up_over_processes_stops_at_the_step_and_with_the_message_of_one_process() {
    let case = Case::new(BLOW_UP);
    let alone = case.run("alone.h5", &[]);
    assert_eq!(code(&alone), 1, "{}", text(&alone.stderr));
    let out = case.run_with(Launch::Mpi(2), "two.h5", &[]);
    let err = text(&out.stderr);
    assert_eq!(code(&out), 1, "{err}");
    assert_no_panic(&err);
    assert_eq!(
        err.matches("numerical blow-up").count(),
        1,
        "said once: {err}"
    );
    let status = |name: &str| {
        RunFile::open(Path::new(&case.path(name)))
            .unwrap()
            .status()
            .unwrap()
    };
    assert!(
        status("alone.h5").contains("blow-up"),
        "{}",
        status("alone.h5")
    );
    assert_eq!(status("alone.h5"), status("two.h5"));
}

#[test]
fn commands_other_than_run_refuse_to_be_several_processes() {
    let case = Case::new(CHANNEL);
    let out = Launch::Mpi(2)
        .command()
        .args(["compare", &case.scenario(), "-o", &case.path("cmp")])
        .output()
        .unwrap();
    let err = text(&out.stderr);
    assert_eq!(code(&out), 2, "{err}");
    assert!(
        err.contains("only `floe run` spreads over processes"),
        "{err}"
    );
    assert!(!Path::new(&case.path("cmp")).exists());
}
