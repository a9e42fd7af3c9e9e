//! A friction law registered outside floe-friction (floe-scenario's
//! `custom_law` example) runs into a run file and resumes from its
//! checkpoint bitwise: the checkpoint stores the one state slot the law
//! declares, and the resumed run reads the stored scenario with the same
//! registry.

use crate::custom_law_example as custom_law;

use floe_friction::LawRegistry;
use floe_io::RunFile;
use floe_run::run_file::{run, Provenance, Quiet, RunArgs};

fn args(
    scenario: Option<std::path::PathBuf>,
    output: std::path::PathBuf,
    laws: LawRegistry,
) -> RunArgs {
    RunArgs {
        scenario,
        output,
        threads: Some(2),
        force: true,
        resume: false,
        max_steps: None,
        step_limit: floe_scenario::MAX_RUN_STEPS,
        provenance: Provenance::of_this_process("test"),
        laws,
    }
}

#[test]
fn a_custom_law_runs_into_a_file_and_resumes_bitwise() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("slip_weakening.toml");
    std::fs::write(
        &scenario,
        custom_law::SCENARIO.replace("duration_s = 50.0", "duration_s = 2.0"),
    )
    .unwrap();
    let (whole, parts) = (dir.path().join("whole.h5"), dir.path().join("parts.h5"));
    run(
        &args(
            Some(scenario.clone()),
            whole.clone(),
            custom_law::registry(),
        ),
        &Quiet,
    )
    .unwrap();
    let mut first = args(
        Some(scenario.clone()),
        parts.clone(),
        custom_law::registry(),
    );
    first.max_steps = Some(24321);
    let paused = run(&first, &Quiet).unwrap();
    assert_eq!(paused.final_step, 24321);
    // Without the law registered, the stored scenario cannot be read back.
    let mut unknown = args(None, parts.clone(), LawRegistry::builtin());
    unknown.resume = true;
    let e = run(&unknown, &Quiet).unwrap_err().to_string();
    assert!(e.contains("unknown law `slip-weakening`"), "{e}");
    let mut resumed = args(None, parts.clone(), custom_law::registry());
    resumed.resume = true;
    let done = run(&resumed, &Quiet).unwrap();
    assert_eq!(done.final_step, done.total_steps);
    let (a, b) = (
        RunFile::open(&whole).unwrap(),
        RunFile::open(&parts).unwrap(),
    );
    let (sa, sb) = (
        a.checkpoint_state(|| None).unwrap().unwrap(),
        b.checkpoint_state(|| None).unwrap().unwrap(),
    );
    assert!(sa.contacts.iter().any(|c| c.friction.law_state[0] > 0.0));
    assert_eq!(format!("{sa:?}"), format!("{sb:?}"));
    let n = a.snapshot_count().unwrap();
    assert_eq!(n, b.snapshot_count().unwrap());
    let (ca, cb) = (a.contacts(n - 1).unwrap(), b.contacts(n - 1).unwrap());
    assert_eq!(
        format!("{:?}", ca.tangential_force_n),
        format!("{:?}", cb.tangential_force_n)
    );
}
