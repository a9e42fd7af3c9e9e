//! `floe pack-friction`: the shear cell as a friction sample. The top
//! wall follows the scenario's schedule of speeds and holds (the
//! laboratory's velocity steps and slide-hold-slide, at pack scale); the
//! pack's friction `mu(t) = tau / P` (the Love-Weber mean stress of the
//! free floes) is read as a laboratory reads its sample's
//! ([`floe_analysis::step_response`]): the direct effect `a`, `a - b`, the
//! slip distance of the transient, and the healing of each hold, per law
//! and over seeds. Writes `DIR/<law>_s<seed>.{toml,h5}`, `events.csv`,
//! `series.csv`, `report.md` and `pack_friction.png`.

mod events;
mod report;

use std::path::{Path, PathBuf};

use floe_friction::LawRegistry;
use floe_scenario::law_variants::{variant, LawChoice, Matching};
use floe_scenario::settings::{apply, Setting};
use floe_scenario::Scenario;

pub use crate::cell_study::Mode;
use crate::cell_study::{
    check_seeds, check_settings, checked_cell, run_jobs, setting, with_user_settings, CellJobs,
    Next,
};
use crate::compare::reference_of;
use crate::side_by_side::Batch;
use floe_run::run_file::{thread_count, Provenance, RunHooks};
use floe_run::Error;

pub use events::{Event, EventKind, FrictionSeries, LawEvents, Measured, Schedule};

/// What `floe pack-friction` was asked to do.
#[derive(Debug, Clone)]
pub struct PackFrictionArgs {
    /// The shear-cell scenario, its top wall on a `[[wall.segment]]`
    /// schedule.
    pub scenario: PathBuf,
    /// Keys set before anything else (`--set KEY=VALUE`, one value each).
    pub settings: Vec<Setting>,
    /// The laws, in report order.
    pub laws: Vec<LawChoice>,
    /// Seeds of the tessellation; every law is run once per seed.
    pub seeds: Vec<u64>,
    /// Spacing of the friction samples (the observables), s.
    pub sample_every_s: f64,
    /// Output directory.
    pub out_dir: PathBuf,
    /// Thread budget: runs go side by side, one thread each.
    pub threads: Option<usize>,
    /// Replace existing outputs.
    pub force: bool,
    /// Run, only write the runs' scenario files, or only measure.
    pub mode: Mode,
    /// How Amontons and the rate law are matched to rate-and-state.
    pub matching: Matching,
    /// Who runs it (recorded in each run file).
    pub provenance: Provenance,
    /// The friction laws the scenario may name.
    pub registry: LawRegistry,
    /// Most time steps a run may take.
    pub step_limit: f64,
    /// Whether the free floes start with the linear shear profile of the
    /// first segment's speed.
    pub linear_start: bool,
}

/// One law's runs, one per seed, in seed order.
#[derive(Debug, Clone)]
pub struct LawRuns {
    /// The law's name.
    pub law: String,
    /// Each seed and its run's friction series on the common times.
    pub runs: Vec<(u64, FrictionSeries)>,
}

/// Runs (or emits, or gathers) the cells; returns the report's path (the
/// directory with [`Mode::Emit`]).
pub fn pack_friction(args: &PackFrictionArgs, hooks: &dyn RunHooks) -> Result<PathBuf, Error> {
    let budget = thread_count(args.threads)?;
    check_args(args)?;
    let origin = args.scenario.as_path();
    let text = floe_run::run_file::read_anchored(origin)?;
    let text = with_user_settings(&text, origin, &args.settings, &args.registry)?;
    let (scenario, _) = checked_cell(&text, origin, &args.registry)?;
    let segments = scenario
        .wall_schedule("top")
        .map_or(&[][..], |s| s.segments());
    let schedule = Schedule::new(segments).map_err(|why| {
        Error::Usage(format!(
            "{}: the top wall's schedule: {why} (see scenarios/shear_cell_wide_steps.toml)",
            origin.display()
        ))
    })?;
    let height = scenario.domain().size_m.y;
    let duration = schedule.duration_s();
    let (reference, reference_text) = reference_of(&text, origin, &args.registry)?;

    let mut jobs = Vec::new();
    let mut plan = Vec::new();
    for &law in &args.laws {
        let (law_text, _) = variant(
            &text,
            origin,
            law,
            &reference,
            &reference_text,
            args.matching,
        )?;
        for &seed in &args.seeds {
            let mut settings = vec![
                setting("seed", seed.to_string()),
                setting("duration_s", format!("{duration:?}")),
                setting(
                    "output.observables_every_s",
                    format!("{:?}", args.sample_every_s),
                ),
                setting("output.snapshot_every_s", format!("{:?}", duration / 20.0)),
                setting(
                    "output.checkpoint_every_s",
                    format!("{:?}", duration / 10.0),
                ),
            ];
            if args.linear_start {
                settings.push(setting(
                    "ice.initial_shear_rate_per_s",
                    format!("{:?}", schedule.first_speed_m_per_s() / height),
                ));
            }
            let name = format!("{}_s{seed}", law.name());
            let file = args.out_dir.join(format!("{name}.toml"));
            let variant_text = apply(&law_text, origin, &settings, &vec![0; settings.len()])?;
            Scenario::from_text_with(&variant_text, &file, &args.registry)?
                .with_max_steps(args.step_limit)
                .build()?;
            jobs.push((file, args.out_dir.join(format!("{name}.h5"))));
            plan.push((law.name().to_string(), seed, variant_text));
        }
    }
    let report_path = args.out_dir.join("report.md");
    let texts: Vec<&str> = plan.iter().map(|p| p.2.as_str()).collect();
    let next = run_jobs(
        &CellJobs {
            scenario: &args.scenario,
            out_dir: &args.out_dir,
            jobs: &jobs,
            texts: &texts,
            outputs: &["report.md", "events.csv", "series.csv", "pack_friction.png"],
            mode: args.mode,
            budget,
            batch: Batch {
                force: args.force,
                step_limit: args.step_limit,
                provenance: &args.provenance,
                laws: &args.registry,
            },
            tag: "pack-friction",
        },
        hooks,
    )?;
    if next == Next::Emitted {
        return Ok(args.out_dir.clone());
    }
    measure_and_report(args, (&schedule, &reference), &jobs, &plan, &report_path)
}

/// Reads every run's friction series, measures each law's events and
/// writes the outputs.
fn measure_and_report(
    args: &PackFrictionArgs,
    (schedule, contact_law): (&Schedule, &floe_friction::Law),
    jobs: &[(PathBuf, PathBuf)],
    plan: &[(String, u64, String)],
    report_path: &Path,
) -> Result<PathBuf, Error> {
    let times = schedule.sample_times(args.sample_every_s);
    let mut laws: Vec<LawRuns> = args
        .laws
        .iter()
        .map(|l| LawRuns {
            law: l.name().to_string(),
            runs: Vec::new(),
        })
        .collect();
    for ((_, output), (law, seed, _)) in jobs.iter().zip(plan) {
        let series = events::read_series(output, &times)?;
        if let Some(l) = laws.iter_mut().find(|l| &l.law == law) {
            l.runs.push((*seed, series));
        }
    }
    let measured = events::measure(schedule, &times, &laws).map_err(Error::analysis)?;
    report::write(
        &args.out_dir,
        args,
        (schedule, &times),
        contact_law,
        &measured,
    )?;
    Ok(report_path.to_path_buf())
}

/// Whether `floe pack-friction` sets the dotted `key` itself.
fn set_by_pack_friction(key: &str, args: &PackFrictionArgs) -> bool {
    key == "duration_s"
        || key == "seed"
        || key.starts_with("output.")
        || (key == "ice.initial_shear_rate_per_s" && args.linear_start)
}

fn check_args(args: &PackFrictionArgs) -> Result<(), Error> {
    if args.laws.is_empty() {
        return Err(Error::Usage("--laws: give at least one law".into()));
    }
    if args.seeds.is_empty() {
        return Err(Error::Usage("--seeds: give at least one seed".into()));
    }
    check_seeds(&args.seeds)?;
    check_settings(
        &args.settings,
        |key| set_by_pack_friction(key, args),
        "floe pack-friction sets this key itself (--seeds, --sample-every, --initial-profile; the schedule is the top wall's [[wall.segment]] tables)",
    )?;
    if !(args.sample_every_s.is_finite() && args.sample_every_s > 0.0) {
        return Err(Error::Usage(format!(
            "--sample-every {}: a spacing in seconds > 0",
            args.sample_every_s
        )));
    }
    Ok(())
}
