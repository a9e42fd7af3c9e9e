//! `floe rheology`: a constant-pressure simple-shear cell (periodic along
//! x, a fixed bottom wall, a top wall that holds a normal stress and
//! slides along x) run at several wall speeds under several friction laws,
//! each run measured ([`measure`]) and each law's `mu(I)` fitted. Writes
//! `DIR/<law>_v<speed>.{toml,h5}`, `DIR/results.csv`, `DIR/report.md` and
//! `DIR/rheology.png`; [`Mode::Emit`] and [`Mode::Gather`] split the runs
//! from the measuring, for a job array.

pub mod measure;
pub mod over_seeds;
mod report;

use std::path::{Path, PathBuf};

use floe_analysis::rheology::fit_mu_of_i;
use floe_friction::LawRegistry;
use floe_scenario::law_variants::{variant, LawChoice, Matching};

pub use crate::cell_study::Mode;
use crate::cell_study::{
    check_seeds, check_settings, checked_cell, run_jobs, setting, with_user_settings, CellJobs,
    Next,
};
use crate::compare::reference_of;
use floe_scenario::settings::{apply, Setting};
use floe_scenario::Scenario;

use crate::side_by_side::Batch;
use floe_run::run_file::{thread_count, Provenance, RunHooks};
use floe_run::Error;
use measure::{cell_samples, steady, SteadyCell};
use over_seeds::over_seeds;

/// Parameters of the fitted `mu(I)` (`mu_s`, `mu_2`, `I_0`).
const MU_OF_I_PARAMETERS: usize = 3;

/// What `floe rheology` was asked to do.
#[derive(Debug, Clone)]
pub struct RheologyArgs {
    /// The shear-cell scenario.
    pub scenario: PathBuf,
    /// Keys set in the scenario before anything else (`--set KEY=VALUE`,
    /// one value each: e.g. the contact stiffness or `dt_s` of a
    /// convergence check); the laws' and speeds' own keys are set after.
    pub settings: Vec<Setting>,
    /// The laws, in report order.
    pub laws: Vec<LawChoice>,
    /// The top wall's speeds along x, m/s.
    pub speeds_m_per_s: Vec<f64>,
    /// Seeds of the tessellation (the scenario's `seed`), each run at every
    /// law and speed; empty: the scenario's own seed, and run names
    /// without a seed.
    pub seeds: Vec<u64>,
    /// Shear strain each run lasts: duration = strain x domain height / speed.
    pub strain: f64,
    /// Snapshots each run writes (the measured samples).
    pub snapshots: usize,
    /// Fraction of each run left out of the means (the start-up).
    pub transient_fraction: f64,
    /// Output directory.
    pub out_dir: PathBuf,
    /// Thread budget: runs go side by side, one thread each.
    pub threads: Option<usize>,
    /// Replace existing outputs.
    pub force: bool,
    /// Run the cells, only write their scenario files, or only measure runs
    /// already in the directory.
    pub mode: Mode,
    /// How Amontons and the rate law are matched to rate-and-state.
    pub matching: Matching,
    /// Who runs it (recorded in each run file).
    pub provenance: Provenance,
    /// The friction laws the scenario may name.
    pub registry: LawRegistry,
    /// Most time steps a run may take.
    pub step_limit: f64,
    /// Whether the free floes start with the cell's linear shear profile
    /// (the top wall's speed over the domain height, `[ice]
    /// initial_shear_rate_per_s`) or at rest.
    pub linear_start: bool,
}

/// One run's steady state.
#[derive(Debug, Clone)]
pub struct CellRun {
    /// The law's name.
    pub law: String,
    /// The top wall's speed, m/s.
    pub speed_m_per_s: f64,
    /// The seed set by `--seeds` (`None`: the scenario's own).
    pub seed: Option<u64>,
    /// The run's measured steady state.
    pub steady: SteadyCell,
}

/// Runs the cells, writes the results; returns the report's path (the
/// directory with [`Mode::Emit`]).
pub fn rheology(args: &RheologyArgs, hooks: &dyn RunHooks) -> Result<PathBuf, Error> {
    let budget = thread_count(args.threads)?;
    check_args(args)?;
    let text = floe_run::run_file::read_anchored(&args.scenario)?;
    let origin = args.scenario.as_path();
    let text = with_user_settings(&text, origin, &args.settings, &args.registry)?;
    let (scenario, top) = checked_cell(&text, origin, &args.registry)?;
    let domain = scenario.domain();
    let (reference, reference_text) = reference_of(&text, origin, &args.registry)?;

    // Every variant is made and built before anything is written.
    let height = domain.size_m.y;
    let mut jobs = Vec::new();
    let mut plan = Vec::new();
    let seeds: Vec<Option<u64>> = if args.seeds.is_empty() {
        vec![None]
    } else {
        args.seeds.iter().copied().map(Some).collect()
    };
    for &law in &args.laws {
        let (law_text, _) = variant(
            &text,
            origin,
            law,
            &reference,
            &reference_text,
            args.matching,
        )?;
        for (&v, seed) in args
            .speeds_m_per_s
            .iter()
            .flat_map(|v| seeds.iter().map(move |s| (v, *s)))
        {
            let duration = args.strain * height / v;
            let settings = [
                setting(
                    &format!("wall[{top}].velocity_m_per_s"),
                    format!("[{v:?}, 0.0]"),
                ),
                setting("duration_s", format!("{duration:?}")),
                setting(
                    "output.snapshot_every_s",
                    format!("{:?}", duration / args.snapshots as f64),
                ),
                setting(
                    "output.observables_every_s",
                    format!("{:?}", duration / 500.0),
                ),
                setting(
                    "output.checkpoint_every_s",
                    format!("{:?}", duration / 10.0),
                ),
            ];
            let mut settings = settings.to_vec();
            if args.linear_start {
                settings.push(setting(
                    "ice.initial_shear_rate_per_s",
                    format!("{:?}", v / height),
                ));
            }
            let mut name = format!("{}_v{v}", law.name());
            if let Some(seed) = seed {
                settings.push(setting("seed", seed.to_string()));
                name.push_str(&format!("_s{seed}"));
            }
            let variant_text = apply(&law_text, origin, &settings, &vec![0; settings.len()])?;
            let file = args.out_dir.join(format!("{name}.toml"));
            Scenario::from_text_with(&variant_text, &file, &args.registry)?
                .with_max_steps(args.step_limit)
                .build()?;
            jobs.push((file, args.out_dir.join(format!("{name}.h5"))));
            plan.push((law.name().to_string(), v, seed, variant_text));
        }
    }
    let report_path = args.out_dir.join("report.md");
    let texts: Vec<&str> = plan.iter().map(|p| p.3.as_str()).collect();
    let next = run_jobs(
        &CellJobs {
            scenario: &args.scenario,
            out_dir: &args.out_dir,
            jobs: &jobs,
            texts: &texts,
            outputs: &["report.md", "results.csv", "over_seeds.csv"],
            mode: args.mode,
            budget,
            batch: Batch {
                force: args.force,
                step_limit: args.step_limit,
                provenance: &args.provenance,
                laws: &args.registry,
            },
            tag: "rheology",
        },
        hooks,
    )?;
    if next == Next::Emitted {
        return Ok(args.out_dir.clone());
    }
    measure_and_report(args, &jobs, &plan, &report_path)
}

/// Whether `floe rheology` sets the dotted `key` of each run itself, so
/// that a `--set` of it would be overridden.
fn set_by_rheology(key: &str, args: &RheologyArgs) -> bool {
    key == "duration_s"
        || key.starts_with("output.")
        || (key.starts_with("wall[") && key.ends_with(".velocity_m_per_s"))
        || (key == "seed" && !args.seeds.is_empty())
        || (key == "ice.initial_shear_rate_per_s" && args.linear_start)
}

/// Measures each run of `jobs`, fits each law and writes the report.
fn measure_and_report(
    args: &RheologyArgs,
    jobs: &[(PathBuf, PathBuf)],
    plan: &[(String, f64, Option<u64>, String)],
    report_path: &Path,
) -> Result<PathBuf, Error> {
    let mut runs = Vec::with_capacity(jobs.len());
    let mut unconfined = Vec::new();
    for ((_, output), (law, v, seed, _)) in jobs.iter().zip(plan) {
        let samples = cell_samples(output)?;
        let contact_mu = floe_io::RunFile::open(output)?.observable("mean_mu")?;
        match steady(&samples, &contact_mu, args.transient_fraction) {
            Some(steady) => runs.push(CellRun {
                law: law.clone(),
                speed_m_per_s: *v,
                seed: *seed,
                steady,
            }),
            None => unconfined.push(output.clone()),
        }
    }
    if runs.is_empty() {
        return Err(Error::Usage(format!(
            "no run has two snapshots in its steady part in which the floes touch both walls \
             ({} runs); more snapshots (--snapshots) or a lower speed",
            unconfined.len()
        )));
    }
    // Each law's fit goes through its means over seeds (the runs
    // themselves without --seeds).
    let points = over_seeds(&runs, args.laws[0].name());
    let mut fits = Vec::new();
    for law in &args.laws {
        let (i, mu): (Vec<f64>, Vec<f64>) = points
            .iter()
            .filter(|p| p.law == law.name())
            .map(|p| (p.inertial_number.mean, p.mu.mean))
            .unzip();
        // Three parameters: through three points any curve fits exactly,
        // so a fit needs a fourth to say anything.
        let fit = (i.len() > MU_OF_I_PARAMETERS)
            .then(|| fit_mu_of_i(&i, &mu).ok())
            .flatten();
        fits.push((law.name().to_string(), fit));
    }
    report::write(
        &args.out_dir,
        &args.scenario,
        args,
        (&runs, &unconfined),
        &points,
        &fits,
    )?;
    Ok(report_path.to_path_buf())
}

fn check_args(args: &RheologyArgs) -> Result<(), Error> {
    let usage = |flag: &str, value: f64, accepted: &str| {
        Err(Error::Usage(format!("{flag} {value}: {accepted}")))
    };
    if args.speeds_m_per_s.is_empty() {
        return Err(Error::Usage("--speeds: give at least one speed".into()));
    }
    if let Some(&v) = args
        .speeds_m_per_s
        .iter()
        .find(|v| !(v.is_finite() && **v >= 1e-6 && **v <= 100.0))
    {
        return usage("--speeds", v, "speeds from 1e-6 to 100 m/s");
    }
    let mut sorted = args.speeds_m_per_s.clone();
    sorted.sort_by(f64::total_cmp);
    if sorted.windows(2).any(|w| w[0] == w[1]) {
        return Err(Error::Usage("--speeds: a speed is given twice".into()));
    }
    check_settings(
        &args.settings,
        |key| set_by_rheology(key, args),
        "floe rheology sets this key itself (--speeds, --strain, --snapshots, --seeds, --initial-profile)",
    )?;
    check_seeds(&args.seeds)?;
    if !(args.strain.is_finite() && args.strain > 0.0 && args.strain <= 1e3) {
        return usage("--strain", args.strain, "a shear strain in (0, 1000]");
    }
    if !(2..=100_000).contains(&args.snapshots) {
        return usage(
            "--snapshots",
            args.snapshots as f64,
            "2 to 100000 snapshots",
        );
    }
    if !(0.0..0.95).contains(&args.transient_fraction) {
        return usage(
            "--transient",
            args.transient_fraction,
            "a fraction of the run in [0, 0.95)",
        );
    }
    Ok(())
}
