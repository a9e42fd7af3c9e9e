//! What the shear-cell studies (`floe rheology`, `floe pack-friction`)
//! share: the user's `--set` keys applied and blamed on the flag, the
//! check that a scenario is a shear cell, and the job array of their runs
//! (refuse overwriting, write each run's scenario, run them side by side,
//! or leave them to a job array and gather later).

use std::path::{Path, PathBuf};

use floe_friction::LawRegistry;
use floe_run::run_file::RunHooks;
use floe_run::same_file::refuse_overwriting_input;
use floe_run::Error;
use floe_scenario::settings::{apply, find_table, Setting};
use floe_scenario::Scenario;

use crate::side_by_side::{run_side_by_side, Batch};

/// What a cell study (`floe rheology`, `floe pack-friction`) does with
/// its runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Write, run and measure them.
    Run,
    /// Only write their scenario files (for a job array: run each with
    /// `floe run RUN.toml -o RUN.h5`, then gather).
    Emit,
    /// Only measure the runs already in the directory and write the report.
    Gather,
}

impl Mode {
    /// The mode of a command's `--emit` and `--gather` flags.
    pub fn from_flags(emit: bool, gather: bool) -> Self {
        match (emit, gather) {
            (true, _) => Self::Emit,
            (_, true) => Self::Gather,
            _ => Self::Run,
        }
    }
}

/// The setting of the dotted `key` to one `value` (TOML text) that a study
/// makes in each of its runs.
pub(crate) fn setting(key: &str, value: String) -> Setting {
    Setting {
        key: key.split('.').map(str::to_string).collect(),
        values: vec![value],
    }
}

/// Checks a study's `--set` options: one value each, and none of the keys
/// the study sets itself (`sets_itself`; `why` names the flags that set
/// them).
pub(crate) fn check_settings(
    settings: &[Setting],
    sets_itself: impl Fn(&str) -> bool,
    why: &str,
) -> Result<(), Error> {
    if let Some(s) = settings.iter().find(|s| s.values.len() != 1) {
        return Err(Error::Usage(format!(
            "--set {}: one value per key here (floe sweep takes several)",
            s.dotted()
        )));
    }
    if let Some(s) = settings.iter().find(|s| sets_itself(&s.dotted())) {
        return Err(Error::Usage(format!("--set {}: {why}", s.dotted())));
    }
    Ok(())
}

/// Checks a study's `--seeds`: each a scenario `seed` (0 to `i64::MAX`),
/// none twice.
pub(crate) fn check_seeds(seeds: &[u64]) -> Result<(), Error> {
    if let Some(&s) = seeds.iter().find(|&&s| s > i64::MAX as u64) {
        return Err(Error::Usage(format!(
            "--seeds {s}: seeds from 0 to {}",
            i64::MAX
        )));
    }
    let mut sorted = seeds.to_vec();
    sorted.sort_unstable();
    if sorted.windows(2).any(|w| w[0] == w[1]) {
        return Err(Error::Usage("--seeds: a seed is given twice".into()));
    }
    Ok(())
}

/// `text` with the `--set` keys applied. A key the scenario does not take
/// is blamed on the flag: the message's file names the settings, as
/// `floe sweep`'s does.
pub(crate) fn with_user_settings(
    text: &str,
    origin: &Path,
    settings: &[Setting],
    registry: &LawRegistry,
) -> Result<String, Error> {
    if settings.is_empty() {
        return Ok(text.to_string());
    }
    floe_scenario::settings::check_distinct(settings)?;
    let set_text = apply(text, origin, settings, &vec![0; settings.len()])?;
    let given: Vec<String> = settings
        .iter()
        .map(|s| format!("--set {}={}", s.dotted(), s.values[0]))
        .collect();
    let with = PathBuf::from(format!("{} with {}", origin.display(), given.join(" ")));
    Scenario::from_text_with(&set_text, &with, registry)?;
    Ok(set_text)
}

/// The scenario of `text` if it is a shear cell (periodic along x only, a
/// bottom wall and a top wall that holds a normal stress), with the index of
/// its top `[[wall]]` table.
pub(crate) fn checked_cell(
    text: &str,
    origin: &Path,
    registry: &LawRegistry,
) -> Result<(Scenario, usize), Error> {
    let scenario = Scenario::from_text_with(text, origin, registry)?;
    let not_a_cell = |why: &str| {
        Error::Usage(format!(
            "{}: not a shear cell ({why}); see scenarios/shear_cell.toml",
            origin.display()
        ))
    };
    if scenario.domain().periodic != [true, false] {
        return Err(not_a_cell("the domain must be periodic along x only"));
    }
    let top = find_table(text, origin, "wall", "side", "top")?
        .ok_or_else(|| not_a_cell("it has no [[wall]] with side = \"top\""))?;
    find_table(text, origin, "wall", "side", "bottom")?
        .ok_or_else(|| not_a_cell("it has no [[wall]] with side = \"bottom\""))?;
    if scenario.build()?.world.stress_controls().is_empty() {
        return Err(not_a_cell(
            "no wall holds a normal stress (normal_stress_n_per_m)",
        ));
    }
    Ok((scenario, top))
}

/// A study's runs: each `(scenario file, run file)` of `jobs` with its
/// scenario text, and the study's own outputs in `out_dir`.
pub(crate) struct CellJobs<'a> {
    /// The user's scenario (never overwritten).
    pub scenario: &'a Path,
    /// Output directory.
    pub out_dir: &'a Path,
    /// Each run's scenario file and run file.
    pub jobs: &'a [(PathBuf, PathBuf)],
    /// Each run's scenario text, as `jobs`.
    pub texts: &'a [&'a str],
    /// The study's own output files, names in `out_dir`.
    pub outputs: &'a [&'a str],
    /// Run, emit or gather.
    pub mode: Mode,
    /// Thread budget.
    pub budget: usize,
    /// How each run is made.
    pub batch: Batch<'a>,
    /// The study's name in messages.
    pub tag: &'a str,
}

/// What the study does after [`run_jobs`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Next {
    /// Measure the runs (they are all there).
    Measure,
    /// Stop: the scenario files are written for a job array.
    Emitted,
}

/// Checks the outputs, writes the runs' scenario files and runs them (or
/// only writes them, or only checks that the runs are there to gather).
pub(crate) fn run_jobs(c: &CellJobs<'_>, hooks: &dyn RunHooks) -> Result<Next, Error> {
    let mut targets: Vec<PathBuf> = c.outputs.iter().map(|f| c.out_dir.join(f)).collect();
    targets.extend(c.jobs.iter().flat_map(|(t, h)| [t.clone(), h.clone()]));
    refuse_overwriting_input(
        c.scenario,
        "scenario file",
        targets.iter().map(PathBuf::as_path),
    )?;
    if c.mode == Mode::Gather {
        if let Some((_, missing)) = c.jobs.iter().find(|(_, h)| !h.exists()) {
            return Err(Error::Usage(format!(
                "{}: not there to gather (run its .toml with `floe run` first, or drop --gather)",
                missing.display()
            )));
        }
        return Ok(Next::Measure);
    }
    if !c.batch.force {
        if let Some(existing) = targets.iter().find(|p| p.exists()) {
            return Err(Error::WouldOverwrite(existing.clone()));
        }
    }
    std::fs::create_dir_all(c.out_dir).map_err(|e| Error::io(c.out_dir, e))?;
    for ((file, _), text) in c.jobs.iter().zip(c.texts) {
        std::fs::write(file, text).map_err(|e| Error::io(file, e))?;
    }
    if c.mode == Mode::Emit {
        return Ok(Next::Emitted);
    }
    let failed = run_side_by_side(c.jobs, c.budget, &c.batch, c.tag, hooks);
    if !failed.is_empty() {
        return Err(Error::Usage(format!(
            "{}: {} of {} runs failed ({}); nothing was measured",
            c.tag,
            failed.len(),
            c.jobs.len(),
            failed.join(", ")
        )));
    }
    Ok(Next::Measure)
}
