//! `floe compare`: one scenario under several friction laws (same ice,
//! forcing and seed; only `[friction]` differs), run to `DIR/<law>.h5`, then
//! measured and reported side by side in `DIR/report.md`.

pub mod metrics;
pub mod report;

use std::path::PathBuf;

use floe_friction::{FrictionLaw, LawRegistry};
use floe_scenario::law_variants::{reference_law, variant, LawChoice, Matching};

use crate::render::{render, ColourBy, Snapshots};
use floe_run::run_file::{run, thread_count, Provenance, RunArgs, RunHooks};
use floe_run::same_file::refuse_overwriting_input;
use floe_run::Error;
use floe_scenario::numbers::{short, sig};
use floe_scenario::Scenario;
use metrics::{measure, MetricOptions};
use report::{figures, markdown, Variant};

/// What `floe compare` was asked to do.
#[derive(Debug, Clone)]
pub struct CompareArgs {
    /// The scenario file.
    pub scenario: PathBuf,
    /// The laws, in report order.
    pub laws: Vec<LawChoice>,
    /// Output directory.
    pub out_dir: PathBuf,
    /// Worker threads for each run.
    pub threads: Option<usize>,
    /// Replace existing outputs.
    pub force: bool,
    /// How Amontons and the rate law are matched to rate-and-state.
    pub matching: Matching,
    /// Metric choices.
    pub metrics: MetricOptions,
    /// Who runs the comparison (recorded in each run file).
    pub provenance: Provenance,
    /// The friction laws the scenario may name.
    pub registry: LawRegistry,
    /// Most time steps a run may take ([`floe_scenario::MAX_RUN_STEPS`] by
    /// default): a longer scenario is refused before anything runs.
    pub step_limit: f64,
}

/// The rate-and-state law the variants of `text` are matched to, and the
/// scenario text that builds it ([`reference_law`], built with `registry`).
pub(crate) fn reference_of(
    text: &str,
    origin: &std::path::Path,
    registry: &LawRegistry,
) -> Result<(floe_friction::Law, String), Error> {
    Ok(reference_law(text, origin, |t| {
        Ok(Scenario::from_text_with(t, origin, registry)?
            .contact_model()
            .law
            .clone())
    })?)
}

/// What a comparison made: the report and each variant's metrics.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// `DIR/report.md`.
    pub report: PathBuf,
    /// The variants in the order of the laws asked for.
    pub variants: Vec<Variant>,
}

/// Runs the variants and writes the report. `hooks` hear what each run
/// says and may interrupt it.
pub fn compare(args: &CompareArgs, hooks: &dyn RunHooks) -> Result<Comparison, Error> {
    thread_count(args.threads)?;
    if args.matching.amontons_mu.is_some() && !args.laws.iter().any(|l| l.is_amontons()) {
        return Err(Error::Usage(
            "--amontons-mu applies to the amontons law, which --laws does not include".into(),
        ));
    }
    let text = floe_run::run_file::read_anchored(&args.scenario)?;
    let origin = args.scenario.as_path();
    // Checks and builds the user's file as written first, so its errors
    // (time step, step limit, floes) point into it; only friction differs
    // between the variants.
    Scenario::from_text_with(&text, origin, &args.registry)?
        .with_max_steps(args.step_limit)
        .build()?;
    let (reference, reference_text) = reference_of(&text, origin, &args.registry)?;
    let report_path = args.out_dir.join("report.md");
    let mut targets = vec![report_path.clone()];
    for law in &args.laws {
        targets.push(args.out_dir.join(format!("{}.h5", law.name())));
        targets.push(args.out_dir.join(format!("{}.toml", law.name())));
    }
    refuse_overwriting_input(
        &args.scenario,
        "scenario file",
        targets.iter().map(PathBuf::as_path),
    )?;
    if !args.force {
        if let Some(existing) = targets.iter().find(|p| p.exists()) {
            return Err(Error::WouldOverwrite(existing.clone()));
        }
    }
    // Every variant is made and checked before anything is written.
    let mut variants = Vec::with_capacity(args.laws.len());
    for &law in &args.laws {
        let (variant_text, friction) = variant(
            &text,
            origin,
            law,
            &reference,
            &reference_text,
            args.matching,
        )?;
        let scenario_file = args.out_dir.join(format!("{}.toml", law.name()));
        if let Err(e) = Scenario::from_text_with(&variant_text, &scenario_file, &args.registry) {
            return Err(match (law.is_amontons(), args.matching.amontons_mu) {
                // The only value of the built-in laws' variants that the
                // user did not write: Amontons' mu from the reference speed.
                (true, None) => {
                    let v = args.matching.reference_slip_m_per_s;
                    Error::Usage(format!(
                        "--reference-slip-speed {}: the rate-and-state steady state there, \
                         mu = {}, is not an Amontons friction coefficient (0 to 10); choose \
                         another speed or give --amontons-mu",
                        short(v),
                        sig(reference.mu_steady(v))
                    ))
                }
                _ => e.into(),
            });
        }
        variants.push((law, variant_text, friction, scenario_file));
    }
    std::fs::create_dir_all(&args.out_dir).map_err(|e| Error::io(&args.out_dir, e))?;

    // One note per derived law, in the registry's order.
    let notes: Vec<String> = args
        .registry
        .entries()
        .iter()
        .filter_map(|e| args.laws.iter().find(|l| l.name() == e.name))
        .filter_map(|law| law.note(&reference, args.matching))
        .collect();

    let mut out = Vec::new();
    for (law, variant_text, friction, scenario_file) in variants {
        std::fs::write(&scenario_file, &variant_text).map_err(|e| Error::io(&scenario_file, e))?;
        let output = args.out_dir.join(format!("{}.h5", law.name()));
        hooks.say(&format!("compare: {} -> {}", law.name(), output.display()));
        let summary = run(
            &RunArgs {
                scenario: Some(scenario_file),
                output: output.clone(),
                threads: args.threads,
                force: args.force,
                resume: false,
                max_steps: None,
                step_limit: args.step_limit,
                provenance: args.provenance.clone(),
                laws: args.registry.clone(),
            },
            hooks,
        )?;
        hooks.say(&summary.describe(&output));
        let map_dir = args.out_dir.join(law.name());
        std::fs::create_dir_all(&map_dir).map_err(|e| Error::io(&map_dir, e))?;
        render(&output, Snapshots::One(-1), ColourBy::Speed, &map_dir, true)?;
        out.push(Variant {
            name: law.name().to_string(),
            friction_toml: friction,
            metrics: measure(&output, &args.metrics)?,
            file: PathBuf::from(format!("{}.h5", law.name())),
        });
    }
    figures(&args.out_dir, &out)?;
    let md = markdown(&args.scenario, &out, &notes);
    std::fs::write(&report_path, md).map_err(|e| Error::io(&report_path, e))?;
    Ok(Comparison {
        report: report_path,
        variants: out,
    })
}
