//! `floe sweep`: a scenario over the cartesian product of `--set` values,
//! run in parallel up to the thread budget (or written out with `--emit`
//! for an HPC job array), with the metrics of every variant tabulated.
//!
//! A sweep directory holds `variants.csv` (the manifest: id, the swept
//! values, scenario and output file names), one `variant_NNN.toml` per
//! variant, their `variant_NNN.h5` outputs once run, and `results.csv` /
//! `results.md`. `floe sweep --gather DIR` tabulates whatever outputs are
//! there, so a job array's results are collected the same way.

use std::path::{Path, PathBuf};

use floe_io::RunFile;

use crate::compare::metrics::{measure, MetricOptions, RunMetrics};
use floe_friction::LawRegistry;
use floe_run::same_file::refuse_overwriting_input;
use floe_run::Error;
use floe_scenario::numbers::sig;
use floe_scenario::settings::{apply, cartesian, label, Setting};
use floe_scenario::Scenario;

use crate::side_by_side::{run_side_by_side, Batch};
use floe_run::run_file::{thread_count, Provenance, RunHooks};

/// What `floe sweep` was asked to do.
#[derive(Debug, Clone)]
pub struct SweepArgs {
    /// The base scenario.
    pub scenario: PathBuf,
    /// The swept keys and their values.
    pub settings: Vec<Setting>,
    /// The sweep directory.
    pub out_dir: PathBuf,
    /// Total thread budget (default: all cores).
    pub threads: Option<usize>,
    /// Replace existing files.
    pub force: bool,
    /// Only write the variants' scenario files and the manifest.
    pub emit_only: bool,
    /// Metric choices.
    pub metrics: MetricOptions,
    /// Who runs the sweep (recorded in each run file).
    pub provenance: Provenance,
    /// The friction laws the scenario may name.
    pub laws: LawRegistry,
    /// Most time steps a variant may take ([`floe_scenario::MAX_RUN_STEPS`]
    /// by default): a longer one is refused before anything runs.
    pub step_limit: f64,
}

const MANIFEST: &str = "variants.csv";

/// Writes the variants (and runs them unless `emit_only`); returns the
/// results table, or the manifest when only emitting.
/// `hooks` hear what the runs say and may interrupt them.
pub fn sweep(args: &SweepArgs, hooks: &dyn RunHooks) -> Result<PathBuf, Error> {
    if args.settings.is_empty() {
        return Err(Error::Usage(
            "give at least one --set KEY=VALUE[,VALUE...]".into(),
        ));
    }
    floe_scenario::settings::check_distinct(&args.settings)?;
    let budget = thread_count(args.threads)?;
    let text = floe_run::run_file::read_anchored(&args.scenario)?;
    Scenario::from_text_with(&text, &args.scenario, &args.laws)?;
    let combos = cartesian(&args.settings);
    // Every variant is made and built (floes, time step, step limit)
    // before anything is written, so a bad one is found at once.
    let mut variants = Vec::with_capacity(combos.len());
    for choice in &combos {
        let variant_text = apply(&text, &args.scenario, &args.settings, choice)?;
        let origin = PathBuf::from(format!(
            "{} with {}",
            args.scenario.display(),
            label(&args.settings, choice)
        ));
        Scenario::from_text_with(&variant_text, &origin, &args.laws)?
            .with_max_steps(args.step_limit)
            .build()?;
        variants.push(variant_text);
    }
    let manifest = args.out_dir.join(MANIFEST);
    refuse_overwriting_input(&args.scenario, "scenario file", [manifest.as_path()])?;
    if manifest.exists() && !args.force {
        return Err(Error::WouldOverwrite(manifest));
    }
    std::fs::create_dir_all(&args.out_dir).map_err(|e| Error::io(&args.out_dir, e))?;
    let mut rows = Vec::with_capacity(combos.len());
    for (id, (choice, variant_text)) in combos.iter().zip(variants).enumerate() {
        let name = format!("variant_{:03}", id + 1);
        let file = args.out_dir.join(format!("{name}.toml"));
        refuse_overwriting_input(&args.scenario, "scenario file", [file.as_path()])?;
        if file.exists() && !args.force {
            return Err(Error::WouldOverwrite(file));
        }
        std::fs::write(&file, variant_text).map_err(|e| Error::io(&file, e))?;
        rows.push(Row {
            name,
            values: args
                .settings
                .iter()
                .zip(choice)
                .map(|(s, &k)| s.values[k].clone())
                .collect(),
        });
    }
    write_manifest(&manifest, &args.settings, &rows)?;
    if args.emit_only {
        for (name, text) in [
            ("array.slurm", slurm_array(rows.len())),
            ("mpi.slurm", slurm_mpi(rows.len())),
        ] {
            let script = args.out_dir.join(name);
            std::fs::write(&script, text).map_err(|e| Error::io(&script, e))?;
        }
        return Ok(manifest);
    }
    let jobs: Vec<(PathBuf, PathBuf)> = rows
        .iter()
        .map(|row| {
            (
                args.out_dir.join(format!("{}.toml", row.name)),
                args.out_dir.join(format!("{}.h5", row.name)),
            )
        })
        .collect();
    let failed = run_side_by_side(
        &jobs,
        budget,
        &Batch {
            force: args.force,
            step_limit: args.step_limit,
            provenance: &args.provenance,
            laws: &args.laws,
        },
        "sweep",
        hooks,
    );
    let table = gather(&args.out_dir, &args.metrics)?;
    if !failed.is_empty() {
        return Err(Error::VariantsFailed {
            failed: failed.len(),
            total: rows.len(),
            names: failed.join(", "),
            table,
        });
    }
    Ok(table)
}

/// A Slurm job-array script that runs (or resumes) every variant; see docs/hpc.md.
fn slurm_array(variants: usize) -> String {
    format!(
        r#"#!/bin/bash
# Written by `floe sweep --emit`; see docs/hpc.md. Adjust the resources.
#SBATCH --job-name=floe-sweep
#SBATCH --array=1-{variants}
#SBATCH --cpus-per-task=8
#SBATCH --time=04:00:00
#SBATCH --signal=B:TERM@120
set -euo pipefail
cd "$SLURM_SUBMIT_DIR"
v=$(printf 'variant_%03d' "$SLURM_ARRAY_TASK_ID")
if [ -f "$v.h5" ]; then
    exec floe run --resume "$v.h5" --threads "$SLURM_CPUS_PER_TASK" --quiet
fi
exec floe run "$v.toml" -o "$v.h5" --threads "$SLURM_CPUS_PER_TASK" --quiet
"#
    )
}

/// A Slurm job-array script that runs (or resumes) each variant as one
/// run spread over several nodes by MPI (`srun floe run`); see docs/hpc.md.
fn slurm_mpi(variants: usize) -> String {
    format!(
        r#"#!/bin/bash
# Written by `floe sweep --emit`: each variant as one MPI run over several
# nodes (docs/hpc.md). Adjust the resources: processes x threads = cores.
#SBATCH --job-name=floe-sweep-mpi
#SBATCH --array=1-{variants}
#SBATCH --nodes=2
#SBATCH --ntasks-per-node=16
#SBATCH --cpus-per-task=4
#SBATCH --time=24:00:00
#SBATCH --signal=TERM@120
set -euo pipefail
cd "$SLURM_SUBMIT_DIR"
v=$(printf 'variant_%03d' "$SLURM_ARRAY_TASK_ID")
if [ -f "$v.h5" ]; then
    exec srun floe run --resume "$v.h5" --threads "$SLURM_CPUS_PER_TASK" --quiet
fi
exec srun floe run "$v.toml" -o "$v.h5" --threads "$SLURM_CPUS_PER_TASK" --quiet
"#
    )
}

struct Row {
    name: String,
    values: Vec<String>,
}

fn write_manifest(path: &Path, settings: &[Setting], rows: &[Row]) -> Result<(), Error> {
    let mut w = csv::Writer::from_path(path).map_err(|e| csv_error(path, e))?;
    let mut header = vec!["variant".to_string()];
    header.extend(settings.iter().map(Setting::dotted));
    w.write_record(&header).map_err(|e| csv_error(path, e))?;
    for r in rows {
        let mut rec = vec![r.name.clone()];
        rec.extend(r.values.iter().cloned());
        w.write_record(&rec).map_err(|e| csv_error(path, e))?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

fn csv_error(path: &Path, e: csv::Error) -> Error {
    Error::Usage(format!("{}: {e}", path.display()))
}

/// The metric columns of the results table.
const COLUMNS: [&str; 8] = [
    "status",
    "peak_to_steady",
    "steady_shear_kn_per_m",
    "band_equivalent_width_km",
    "band_10_90_width_km",
    "slip_events",
    "mean_sliding_fraction",
    "friction_dissipation_mj",
];

/// The metrics of a run in the order of [`COLUMNS`] after `status`
/// (empty: not measurable).
fn metric_values(m: &RunMetrics) -> Vec<Option<f64>> {
    vec![
        m.peak_to_steady.map(|p| p.ratio),
        m.peak_to_steady.map(|p| p.steady * 1e-3),
        m.band.map(|b| b.equivalent_width_m * 1e-3),
        m.band.map(|b| b.width_10_90_m * 1e-3),
        Some(m.slip_events.len() as f64),
        Some(m.mean_sliding_fraction()),
        m.friction_dissipation_j.last().map(|x| x * 1e-6),
    ]
}

/// Tabulates the outputs listed in `dir/variants.csv` into `results.csv`
/// and `results.md`; variants whose output is missing or incomplete get a
/// row saying so. Returns the CSV's path.
pub fn gather(dir: &Path, options: &MetricOptions) -> Result<PathBuf, Error> {
    let manifest = dir.join(MANIFEST);
    let mut reader = csv::Reader::from_path(&manifest).map_err(|e| csv_error(&manifest, e))?;
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| csv_error(&manifest, e))?
        .iter()
        .map(String::from)
        .collect();
    // Rows of the CSV (every digit: a data file) and of the markdown table
    // (four significant digits: for reading).
    let (mut table, mut shown) = (Vec::new(), Vec::new());
    for rec in reader.records() {
        let rec = rec.map_err(|e| csv_error(&manifest, e))?;
        let mut row: Vec<String> = rec.iter().map(String::from).collect();
        let output = dir.join(format!("{}.h5", row[0]));
        let (status, values) = if !output.exists() {
            ("missing".to_string(), Vec::new())
        } else {
            let status = RunFile::open(&output).and_then(|f| f.status())?;
            if status == "completed" {
                (status, metric_values(&measure(&output, options)?))
            } else {
                (status, Vec::new())
            }
        };
        row.push(status);
        let mut md_row = row.clone();
        let cells = |f: fn(f64) -> String| values.iter().map(move |v| v.map_or(String::new(), f));
        row.extend(cells(|x| format!("{x}")));
        md_row.extend(cells(sig));
        for r in [&mut row, &mut md_row] {
            r.resize(header.len() + COLUMNS.len(), String::new());
        }
        table.push(row);
        shown.push(md_row);
    }
    let mut full_header = header.clone();
    full_header.extend(COLUMNS.iter().map(|c| c.to_string()));
    let csv_path = dir.join("results.csv");
    let mut w = csv::Writer::from_path(&csv_path).map_err(|e| csv_error(&csv_path, e))?;
    w.write_record(&full_header)
        .map_err(|e| csv_error(&csv_path, e))?;
    for row in &table {
        w.write_record(row).map_err(|e| csv_error(&csv_path, e))?;
    }
    w.flush().map_err(|e| Error::io(&csv_path, e))?;
    let mut md = format!(
        "| {} |\n|{}\n",
        full_header.join(" | "),
        "---|".repeat(full_header.len())
    );
    for row in &shown {
        md.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    let md_path = dir.join("results.md");
    std::fs::write(&md_path, md).map_err(|e| Error::io(&md_path, e))?;
    Ok(csv_path)
}
