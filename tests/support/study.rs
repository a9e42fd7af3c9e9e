//! A scenario run quietly into a run file, for the floe-run and floe-study
//! tests.
#![allow(dead_code)] // each test uses its part

use std::path::{Path, PathBuf};

use floe_run::run_file::{run, Provenance, Quiet, RunArgs};

/// Arguments of a run of `scenario` into `output` on `threads`, replacing
/// the output if it is there.
pub fn run_args(scenario: &Path, output: &Path, threads: usize) -> RunArgs {
    RunArgs {
        scenario: Some(scenario.to_path_buf()),
        output: output.to_path_buf(),
        threads: Some(threads),
        force: true,
        resume: false,
        max_steps: None,
        step_limit: floe_scenario::MAX_RUN_STEPS,
        provenance: Provenance::of_this_process("test"),
        laws: floe_friction::LawRegistry::builtin(),
    }
}

/// Runs `text`, written to `dir/name.toml`, into `dir/name.h5` on one
/// thread: the run file's path, or the error.
pub fn run_text(dir: &Path, name: &str, text: &str) -> Result<PathBuf, floe_run::Error> {
    let scenario = dir.join(format!("{name}.toml"));
    std::fs::write(&scenario, text).unwrap();
    let out = dir.join(format!("{name}.h5"));
    run(&run_args(&scenario, &out, 1), &Quiet).map(|_| out)
}
