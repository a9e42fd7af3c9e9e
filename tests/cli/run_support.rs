//! Running the `floe` binary on a scenario in a scratch directory, alone or
//! under `mpirun`, and comparing run files bitwise.
#![allow(dead_code)] // each test uses its part

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use floe_io::RunFile;

/// How `floe` is started: alone, or as `np` processes under `mpirun`
/// (oversubscribed: this machine may have fewer cores; as root, allowed).
#[derive(Debug, Clone, Copy)]
pub enum Launch {
    /// One process.
    Alone,
    /// `mpirun -np N`.
    Mpi(usize),
}

impl Launch {
    /// The command that starts `floe` this way.
    pub fn command(self) -> Command {
        let mut c = match self {
            Launch::Alone => Command::new(env!("CARGO_BIN_EXE_floe")),
            Launch::Mpi(np) => {
                let mut c = Command::new("mpirun");
                c.args(mpirun_args(np)).arg(env!("CARGO_BIN_EXE_floe"));
                // Containers often forbid the cross-memory attach Open MPI's
                // shared-memory transport tries first; copy through memory.
                c.env("OMPI_MCA_btl_vader_single_copy_mechanism", "none");
                c
            }
        };
        c.env("RUST_BACKTRACE", "1");
        c
    }
}

/// `mpirun`'s arguments for `np` processes on this machine.
pub fn mpirun_args(np: usize) -> Vec<String> {
    let mut args = vec!["--oversubscribe".to_string(), "-np".into(), np.to_string()];
    if is_root() {
        args.push("--allow-run-as-root".into());
    }
    args
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

pub fn code(out: &Output) -> i32 {
    out.status.code().unwrap_or(-1)
}

pub fn assert_no_panic(stderr: &str) {
    assert!(
        !stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"),
        "{stderr}"
    );
}

/// A scenario in a scratch directory, run into files beside it.
pub struct Case {
    pub dir: tempfile::TempDir,
}

impl Case {
    pub fn new(scenario: &str) -> Self {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("scenario.toml"), scenario).unwrap();
        Self { dir }
    }
    pub fn scenario(&self) -> String {
        self.path("scenario.toml")
    }
    pub fn path(&self, name: &str) -> String {
        self.dir.path().join(name).to_string_lossy().into_owned()
    }
    /// `floe run` of the scenario into `name`.
    pub fn run_with(&self, launch: Launch, name: &str, extra: &[&str]) -> Output {
        launch
            .command()
            .args(["run", &self.scenario(), "-o", &self.path(name), "-q"])
            .args(extra)
            .output()
            .expect("floe starts")
    }
    pub fn run(&self, name: &str, extra: &[&str]) -> Output {
        self.run_with(Launch::Alone, name, extra)
    }
    pub fn run_ok(&self, name: &str, extra: &[&str]) {
        let out = self.run(name, extra);
        assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    }
    /// `floe run --resume` of `name`, in the documented form
    /// (`floe run --resume OUT.h5`).
    pub fn resume_with(&self, launch: Launch, name: &str, extra: &[&str]) -> Output {
        launch
            .command()
            .args(["run", "--resume", &self.path(name), "-q"])
            .args(extra)
            .output()
            .expect("floe starts")
    }
    pub fn resume(&self, name: &str, extra: &[&str]) -> Output {
        self.resume_with(Launch::Alone, name, extra)
    }
    /// [`Case::resume`], which must succeed.
    pub fn resume_ok(&self, name: &str, extra: &[&str]) {
        let out = self.resume(name, extra);
        assert_eq!(code(&out), 0, "{}", text(&out.stderr));
    }
    /// [`assert_same_run`] of two of this case's run files.
    pub fn assert_same(&self, a: &str, b: &str) {
        assert_same_run(Path::new(&self.path(a)), Path::new(&self.path(b)));
    }
    pub fn spawn_with(&self, launch: Launch, name: &str, extra: &[&str]) -> Child {
        launch
            .command()
            .args(["run", &self.scenario(), "-o", &self.path(name), "-q"])
            .args(extra)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    }
    pub fn spawn(&self, name: &str, extra: &[&str]) -> Child {
        self.spawn_with(Launch::Alone, name, extra)
    }
}

/// Everything a run writes, compared bitwise: every snapshot, every contact
/// list, every observable, and the final checkpointed state.
pub fn assert_same_run(a: &Path, b: &Path) {
    let (fa, fb) = (RunFile::open(a).unwrap(), RunFile::open(b).unwrap());
    let n = fa.snapshot_count().unwrap();
    assert!(
        n > 2,
        "a run worth comparing has several snapshots, got {n}"
    );
    assert_eq!(n, fb.snapshot_count().unwrap(), "snapshot count");
    for k in 0..n {
        let (sa, sb) = (fa.snapshot(k).unwrap(), fb.snapshot(k).unwrap());
        assert_eq!(sa.step, sb.step, "snapshot {k}");
        assert_eq!(bits2(&sa.position), bits2(&sb.position), "positions {k}");
        assert_eq!(bits2(&sa.velocity), bits2(&sb.velocity), "velocities {k}");
        assert_eq!(bits(&sa.angle), bits(&sb.angle), "angles {k}");
        assert_eq!(
            bits(&sa.angular_velocity),
            bits(&sb.angular_velocity),
            "spins {k}"
        );
        let (ta, tb) = (fa.floe_stress(k).unwrap(), fb.floe_stress(k).unwrap());
        let stress_bits = |t: Option<Vec<[f64; 3]>>| {
            t.map(|t| t.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>())
        };
        assert_eq!(stress_bits(ta), stress_bits(tb), "floe stress {k}");
        let (ca, cb) = (fa.contacts(k).unwrap(), fb.contacts(k).unwrap());
        assert_eq!(ca.pair, cb.pair, "contact pairs {k}");
        assert_eq!(bits(&ca.theta), bits(&cb.theta), "theta {k}");
        assert_eq!(
            bits(&ca.tangential_force_n),
            bits(&cb.tangential_force_n),
            "tangential force {k}"
        );
    }
    for k in 0..n {
        assert_eq!(
            fa.floes_at(k).unwrap(),
            fb.floes_at(k).unwrap(),
            "floes {k}"
        );
    }
    assert_eq!(
        fa.fractures().unwrap(),
        fb.fractures().unwrap(),
        "fracture log"
    );
    // Debug prints every float's shortest round-trip form: equal bits.
    assert_eq!(
        format!("{:?}", fa.ridges().unwrap()),
        format!("{:?}", fb.ridges().unwrap()),
        "ridging log"
    );
    assert_eq!(
        format!("{:?}", fa.welds().unwrap()),
        format!("{:?}", fb.welds().unwrap()),
        "welding log"
    );
    let names = fa.observable_names().unwrap();
    assert_eq!(names, fb.observable_names().unwrap());
    for name in &names {
        let (oa, ob) = (fa.observable(name).unwrap(), fb.observable(name).unwrap());
        assert_eq!(oa.step, ob.step, "{name} steps");
        assert_eq!(bits(&oa.value), bits(&ob.value), "{name} values");
    }
    let (sa, sb) = (
        fa.checkpoint_state(|| None).unwrap(),
        fb.checkpoint_state(|| None).unwrap(),
    );
    assert!(
        format!("{sa:?}") == format!("{sb:?}"),
        "final checkpointed states differ"
    );
}

pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

pub fn bits2(v: &[[f64; 2]]) -> Vec<(u64, u64)> {
    v.iter().map(|p| (p[0].to_bits(), p[1].to_bits())).collect()
}

/// Waits until the run has written a checkpoint past step 0, so that a
/// signal lands in the middle of stepping rather than in start-up.
pub fn wait_for_progress(child: &mut Child, file: &Path) {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        assert!(Instant::now() < deadline, "the run made no progress");
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended before it could be interrupted: {status}");
        }
        // The writer holds the file open; reading it may fail until it
        // flushes, which is fine: try again.
        let step = RunFile::open(file)
            .ok()
            .and_then(|f| f.checkpoint().ok().flatten())
            .map_or(0, |c| c.step);
        if step > 0 {
            return;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The step an interrupted run stopped at, from its status, after checking
/// that its last checkpoint is at that step.
pub fn interrupted_step(file: &RunFile) -> u64 {
    let status = file.status().unwrap();
    let step: u64 = status
        .strip_prefix("interrupted at step ")
        .unwrap_or_else(|| panic!("status {status}"))
        .parse()
        .unwrap();
    assert_eq!(file.checkpoint().unwrap().unwrap().step, step);
    step
}

/// The command in the first pair of backticks of `message` that starts
/// with `floe`, as its words.
pub fn suggested_command(message: &str) -> Vec<String> {
    let start = message
        .find("`floe ")
        .unwrap_or_else(|| panic!("no suggested command in: {message}"));
    let rest = &message[start + 1..];
    let end = rest.find('`').unwrap();
    rest[..end].split_whitespace().map(str::to_string).collect()
}

/// Runs a suggested `floe ...` command verbatim in `dir`.
pub fn run_suggestion(dir: &Path, words: &[String]) -> std::process::Output {
    assert_eq!(words[0], "floe");
    Command::new(env!("CARGO_BIN_EXE_floe"))
        .args(&words[1..])
        .current_dir(dir)
        .output()
        .unwrap()
}
