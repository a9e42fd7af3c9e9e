//! Running one case: the real binary in its own temporary directory, with a
//! hard timeout, and what it left behind.

use std::fs;
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use super::base_inputs::SMALL_SCENARIO;
use super::cases::{Case, Fixtures};
use super::text::strings;

/// A case still running after this long is a hang.
pub const TIMEOUT: Duration = Duration::from_secs(30);

/// What a case's run did.
pub struct Outcome {
    pub status: Option<ExitStatus>,
    pub stderr: String,
    pub elapsed: Duration,
    /// Input files that differ after the run.
    pub changed: Vec<String>,
    /// Non-finite numbers in a successful run's standard output or
    /// series.csv: bad numbers in must not come out as inf or NaN.
    pub bad_output: Vec<String>,
}

pub fn execute(case: &Case) -> Outcome {
    let dir = tempfile::tempdir().expect("temporary directory");
    let work = dir.path().join("work");
    fs::create_dir(&work).expect("work directory");
    for name in &case.dirs {
        fs::create_dir(work.join(name)).expect("input directory");
    }
    for (name, bytes) in &case.files {
        fs::write(work.join(name), bytes).expect("input file");
    }
    let (status, elapsed) = run_with_timeout(&work, &case.args, dir.path());
    let stderr = fs::read(dir.path().join("stderr")).unwrap_or_default();
    let changed = case
        .files
        .iter()
        .filter(|(name, bytes)| fs::read(work.join(name)).ok().as_ref() != Some(bytes))
        .map(|(name, _)| name.clone())
        .collect();
    let mut bad_output = Vec::new();
    if status.is_some_and(|s| s.success()) {
        let stdout = fs::read(dir.path().join("stdout")).unwrap_or_default();
        let stdout = String::from_utf8_lossy(&stdout);
        bad_output.extend(non_finite_word(&stdout, &case.args));
        if let Some(series) = slider_series(&case.args) {
            bad_output.extend(non_finite_cell(&work.join(series)));
        }
    }
    Outcome {
        status,
        stderr: String::from_utf8_lossy(&stderr).into_owned(),
        elapsed,
        changed,
        bad_output,
    }
}

/// The series.csv that `floe slider run ... --out DIR` writes.
fn slider_series(args: &[String]) -> Option<String> {
    if args.get(..2)? != ["slider", "run"] {
        return None;
    }
    let at = args.iter().rposition(|a| a == "--out" || a == "-o")?;
    Some(format!("{}/series.csv", args.get(at + 1)?))
}

/// `inf` or `NaN` in what a successful command printed (not an argument
/// echoed, such as an output directory called `nan`).
fn non_finite_word(stdout: &str, args: &[String]) -> Option<String> {
    let word = stdout
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-' || c == '+'))
        .find(|w| {
            let lower = w.trim_start_matches(['-', '+']).to_ascii_lowercase();
            let non_finite = lower == "inf" || lower == "infinity" || lower == "nan";
            non_finite && !args.iter().any(|a| a == w)
        })?;
    Some(format!("exit 0 but standard output holds `{word}`"))
}

/// A successful slider run writes only finite numbers: the first cell that
/// is not one, or why the file cannot be read.
fn non_finite_cell(series: &Path) -> Option<String> {
    let Ok(text) = fs::read_to_string(series) else {
        return Some(format!("exit 0 but {} is missing", series.display()));
    };
    for (row, line) in text.lines().enumerate().skip(1) {
        for cell in line.split(',') {
            if !cell.trim().parse::<f64>().is_ok_and(f64::is_finite) {
                return Some(format!(
                    "series.csv row {}: `{cell}` is not a finite number",
                    row + 1
                ));
            }
        }
    }
    None
}

/// Runs floe in `work`, its output in files of `logs` (a pipe nobody reads
/// could block it); `None` if it had to be killed after `TIMEOUT`.
pub fn run_with_timeout(
    work: &Path,
    args: &[String],
    logs: &Path,
) -> (Option<ExitStatus>, Duration) {
    let stdout = fs::File::create(logs.join("stdout")).expect("stdout file");
    let stderr = fs::File::create(logs.join("stderr")).expect("stderr file");
    let mut child = Command::new(env!("CARGO_BIN_EXE_floe"))
        .args(args)
        .current_dir(work)
        .env("RUST_BACKTRACE", "1")
        // A NetCDF call looping on a damaged file is cut short after 2 s of
        // processor time (5 s by default), well within the timeout.
        .env("FLOE_NETCDF_CPU_LIMIT_S", "2")
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(stderr)
        .spawn()
        .expect("floe starts");
    let start = Instant::now();
    let mut pause = Duration::from_millis(1);
    loop {
        if let Some(status) = child.try_wait().expect("waiting for floe") {
            return (Some(status), start.elapsed());
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return (None, start.elapsed());
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(20));
    }
}

/// Runs the small scenario once, for `info` and `render` to read.
pub fn fixtures() -> Fixtures {
    let dir = tempfile::tempdir().expect("temporary directory");
    fs::write(dir.path().join("s.toml"), SMALL_SCENARIO).expect("fixture");
    let args = strings(&["run", "s.toml", "-o", "run.h5", "-q", "--threads", "1"]);
    let (status, _) = run_with_timeout(dir.path(), &args, dir.path());
    assert!(
        status.is_some_and(|s| s.success()),
        "the fixture run failed: {}",
        fs::read_to_string(dir.path().join("stderr")).unwrap_or_default()
    );
    Fixtures {
        run_h5: fs::read(dir.path().join("run.h5")).expect("fixture run file"),
    }
}
