//! `floe info`: what a run's output file holds.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use floe_io::RunFile;
use floe_scenario::numbers::{parameter, significant};
use floe_study::floe_sizes;

use crate::CliError;
use floe_dem::run::format_sim_time;

/// Describe a run's output file: scenario, snapshots, floes, contacts, observables.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The run's HDF5 file.
    pub file: PathBuf,
}

impl Args {
    /// The description to print.
    pub fn run(self) -> Result<String, CliError> {
        describe(&self.file)
    }
}

/// A human-readable description of the run in `file`.
pub fn describe(file: &Path) -> Result<String, CliError> {
    // Retried: the file may be one a run is writing.
    Ok(RunFile::read_retrying(file, describe_open)?)
}

fn describe_open(run: &RunFile) -> Result<String, floe_io::IoError> {
    let file = run.path();
    let meta = run.metadata()?;
    let floes = run.static_floes()?;
    let snapshots = run.snapshot_count()?;
    let mut out = String::new();
    let mut line = |key: &str, value: String| {
        let _ = writeln!(out, "{key:<12} {value}");
    };
    line("file", file.display().to_string());
    line(
        "status",
        floe_io::run_status::describe(&run.status()?, file),
    );
    line("scenario", meta.scenario_path.clone());
    line(
        "created by",
        if meta.processes > 1 {
            format!(
                "floe {} (commit {}), {} processes x {} threads",
                meta.floe_version, meta.git_commit, meta.processes, meta.threads
            )
        } else {
            format!(
                "floe {} (commit {}), {} threads",
                meta.floe_version, meta.git_commit, meta.threads
            )
        },
    );
    line("command", meta.command_line.join(" "));
    for input in &meta.inputs {
        line(
            "input",
            format!("{}: {} (sha256 {})", input.role, input.path, input.sha256),
        );
    }
    let walls = floes.prescribed.iter().filter(|&&p| p).count();
    // Floes that broke: the last snapshot's set differs from the first.
    let now = match snapshots {
        0 => None,
        k => Some(run.floes_at(k - 1)?).filter(|last| last.id != floes.id),
    };
    let broke = now.as_ref().map_or(String::new(), |last| {
        format!(
            "; {} at the last snapshot (floes broke or welded)",
            last.len()
        )
    });
    line(
        "floes",
        format!(
            "{} ({} free, {walls} prescribed: walls){broke}",
            floes.len(),
            floes.len() - walls
        ),
    );
    let d = meta.domain;
    let periodic: Vec<&str> = [("x", d.periodic[0]), ("y", d.periodic[1])]
        .iter()
        .filter(|(_, p)| *p)
        .map(|(a, _)| *a)
        .collect();
    line(
        "domain",
        format!(
            "{} km x {} km from ({}, {}) m, periodic in {}",
            parameter(d.size_m[0] / 1e3),
            parameter(d.size_m[1] / 1e3),
            parameter(d.min_m[0]),
            parameter(d.min_m[1]),
            if periodic.is_empty() {
                "neither".to_string()
            } else {
                periodic.join(" and ")
            }
        ),
    );
    if snapshots > 0 {
        let (first, last) = (run.snapshot(0)?, run.snapshot(snapshots - 1)?);
        line(
            "snapshots",
            format!(
                "{snapshots}, steps {} .. {}, t = {} .. {}",
                first.step,
                last.step,
                format_sim_time(first.time_s),
                format_sim_time(last.time_s)
            ),
        );
        let c = run.contacts(snapshots - 1)?;
        let sliding = c
            .slip_rate_m_per_s
            .iter()
            .filter(|v| v.abs() > 1e-6)
            .count();
        line(
            "contacts",
            format!(
                "{} in the last snapshot ({sliding} slipping faster than 1 um/s)",
                c.pair.len()
            ),
        );
        // The size distribution, at the start and (if floes broke) at the end.
        let sizes = |k: usize| -> Result<Option<String>, floe_io::IoError> {
            Ok(floe_sizes::at_snapshot(run, k)?.map(|s| floe_sizes::describe(&s)))
        };
        if let Some(first) = sizes(0)? {
            line("floe sizes", first);
        }
        if now.is_some() {
            if let Some(last) = sizes(snapshots - 1)? {
                line("", format!("at the last snapshot: {last}"));
            }
            let log = run.fractures()?;
            let splits = log.iter().filter(|e| !e.piece_ids.is_empty()).count();
            line(
                "fractures",
                format!(
                    "{splits} floes broke into {} pieces; {} stayed whole (no split fitted)",
                    log.iter().map(|e| e.piece_ids.len()).sum::<usize>(),
                    log.len() - splits
                ),
            );
        }
        let ridges = run.ridges()?;
        if !ridges.is_empty() {
            let whole = ridges.iter().filter(|r| r.whole).count();
            let volume = |coast: bool| -> f64 {
                ridges
                    .iter()
                    .filter(|r| r.to_coast == coast)
                    .map(|r| r.volume_m3)
                    .sum()
            };
            let thickest = |k: usize| -> Result<f64, floe_io::IoError> {
                let f = run.floes_at(k)?;
                Ok((0..f.len())
                    .filter(|&i| !f.prescribed[i])
                    .map(|i| f.thickness_m[i])
                    .fold(0.0, f64::max))
            };
            line(
                "ridging",
                format!(
                    "{} events ({} cuts, {whole} floes crushed whole): {} m^3 onto floes, {} m^3 to the coast; thickest free floe {} m (at the start {} m)",
                    ridges.len(),
                    ridges.len() - whole,
                    significant(volume(false), 4),
                    significant(volume(true), 4),
                    significant(thickest(snapshots - 1)?, 4),
                    significant(thickest(0)?, 4),
                ),
            );
        }
        let welds = run.welds()?;
        if !welds.is_empty() {
            let added: f64 = welds
                .iter()
                .map(|w| w.area_m2 - w.areas_m2[0] - w.areas_m2[1])
                .sum();
            let released: f64 = welds.iter().map(|w| w.released_j).sum();
            let largest = welds.iter().map(|w| w.area_m2).fold(0.0, f64::max);
            line(
                "welding",
                format!(
                    "{} pairs welded: {} m^2 of open water closed, {} J of contact and bond energy released; largest welded floe {} m^2",
                    welds.len(),
                    significant(added, 4),
                    significant(released, 4),
                    significant(largest, 4),
                ),
            );
        }
    } else {
        line("snapshots", "none".into());
    }
    match run.checkpoint()? {
        Some(info) => line(
            "checkpoint",
            format!("step {}, t = {}", info.step, format_sim_time(info.time_s)),
        ),
        None => line("checkpoint", "none".into()),
    }
    let names = run.observable_names()?;
    let mut samples = 0;
    let mut values = Vec::new();
    for name in &names {
        let s = run.observable(name)?;
        samples = s.time_s.len();
        // A series being written may have fewer values than times.
        let width = s.value.len() / samples.max(1);
        let last = (width > 0 && samples > 0)
            .then(|| s.value.chunks_exact(width).nth(samples - 1))
            .flatten();
        if let Some(last) = last {
            let shown: Vec<String> = last.iter().map(|&v| significant(v, 5)).collect();
            values.push(format!("  {name:<24} {}", shown.join(" ")));
        }
    }
    line(
        "observables",
        format!("{} series, {samples} samples; last values:", names.len()),
    );
    for v in values {
        let _ = writeln!(out, "{v}");
    }
    let _ = writeln!(out, "scenario ({}):", meta.scenario_path);
    for l in meta.scenario_toml.lines() {
        let _ = writeln!(out, "  {l}");
    }
    Ok(out.trim_end().to_string())
}
