//! `floe render`: PNG maps of the floes of a run (coloured by speed, theta
//! or pressure; walls dark grey, land grey-brown) and PNG plots of its
//! observables; maps of the gridded fields
//! of `floe grid` ([`grid_map`]).

pub mod colour;
pub mod floe_map;
pub mod grid_map;
pub mod per_floe;

use std::path::{Path, PathBuf};

use floe_io::{IoError, RunFile, RunMetadata, Series, Snapshot, StaticFloes};

use crate::error::Error;
use crate::plot::{grid, Axes, Line};
use colour::ColourScale;
use floe_dem::run::format_sim_time;
use floe_map::FloeMap;
use per_floe::ContactView;

/// Which snapshots to draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Snapshots {
    /// One snapshot; negative counts from the end (-1 is the last).
    One(i64),
    /// Every K-th snapshot, starting with the first.
    Every(usize),
}

/// What colours the floes of a map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColourBy {
    /// Floe speed, m/s.
    Speed,
    /// Mean rate-and-state theta over the floe's contacts.
    Theta,
    /// Floe pressure from its contact forces, N/m (compression positive).
    Stress,
}

impl ColourBy {
    fn name(self) -> &'static str {
        match self {
            ColourBy::Speed => "speed",
            ColourBy::Theta => "theta",
            ColourBy::Stress => "stress",
        }
    }

    fn label(self) -> &'static str {
        match self {
            ColourBy::Speed => "speed (m/s)",
            ColourBy::Theta => "theta (mean over contacts)",
            ColourBy::Stress => "pressure (kN/m)",
        }
    }
}

/// The snapshot indices `which` selects among `count`.
pub fn select(which: Snapshots, count: usize) -> Result<Vec<usize>, Error> {
    match which {
        Snapshots::One(k) => {
            let index = if k < 0 { count as i64 + k } else { k };
            if index < 0 || index >= count as i64 {
                return Err(Error::Usage(format!(
                    "--snapshot {k}: the file has {count} snapshots (0..{})",
                    count.saturating_sub(1)
                )));
            }
            Ok(vec![index as usize])
        }
        Snapshots::Every(0) => Err(Error::Usage("--every must be at least 1".into())),
        Snapshots::Every(k) => Ok((0..count).step_by(k).collect()),
    }
}

/// Draws the selected snapshots and the observables into `out_dir`;
/// returns the files written. Refuses to replace pictures unless `force`.
pub fn render(
    file: &Path,
    which: Snapshots,
    colour: ColourBy,
    out_dir: &Path,
    force: bool,
) -> Result<Vec<PathBuf>, Error> {
    // Read with retries: the file may be one a run is writing.
    let count = RunFile::read_retrying(file, RunFile::snapshot_count)?;
    let frames = select(which, count)?;
    let (meta, floes, snapshots, values) =
        RunFile::read_retrying(file, |run| read_frames(run, &frames, colour))?;
    let domain = meta.domain;
    let prescribed: Vec<bool> = floes.prescribed.clone();
    let free_values = values
        .iter()
        .flat_map(|v| v.iter().zip(&prescribed))
        .filter_map(|(v, &p)| if p { None } else { *v });
    let scale = ColourScale::fit(free_values, colour == ColourBy::Theta);

    let mut targets: Vec<PathBuf> = snapshots
        .iter()
        .map(|s| out_dir.join(format!("floes_{}_{:09}.png", colour.name(), s.step)))
        .collect();
    targets.push(out_dir.join("observables.png"));
    if !force {
        if let Some(existing) = targets.iter().find(|p| p.exists()) {
            return Err(Error::WouldOverwrite(existing.clone()));
        }
    }
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let margin = 0.04 * domain.size_m[0].max(domain.size_m[1]);
    let view = (
        (
            domain.min_m[0] - margin,
            domain.min_m[0] + domain.size_m[0] + margin,
        ),
        (
            domain.min_m[1] - margin,
            domain.min_m[1] + domain.size_m[1] + margin,
        ),
    );
    let name = file
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    for ((snap, v), target) in snapshots.iter().zip(&values).zip(&targets) {
        let polygons: Vec<Vec<(f64, f64)>> = (0..floes.len())
            .map(|i| {
                let (s, c) = snap.angle[i].sin_cos();
                let p = snap.position[i];
                floes
                    .local_vertices(i)
                    .iter()
                    .map(|q| (p[0] + c * q[0] - s * q[1], p[1] + s * q[0] + c * q[1]))
                    .collect()
            })
            .collect();
        let title = format!(
            "{name}: step {}, t = {}",
            snap.step,
            format_sim_time(snap.time_s)
        );
        floe_map::draw(
            target,
            &FloeMap {
                title: &title,
                polygons: &polygons,
                values: v,
                prescribed: &prescribed,
                land: &floes.land,
                scale,
                label: colour.label(),
                view,
            },
        )?;
    }
    observables_figure(file, targets.last().expect("observables target"))?;
    Ok(targets)
}

/// Time series of the observables: energies, work and dissipation, mean
/// stress, contacts, friction.
fn observables_figure(file: &Path, path: &Path) -> Result<(), Error> {
    const SERIES: [&str; 10] = [
        "kinetic_translational",
        "kinetic_rotational",
        "forcing_work",
        "boundary_work",
        "friction_dissipation",
        "damping_dissipation",
        "contacts",
        "sliding_fraction",
        "mean_mu",
        "mean_stress",
    ];
    let series: std::collections::HashMap<&str, Series> = RunFile::read_retrying(file, |run| {
        SERIES
            .iter()
            .map(|&name| {
                let s = run.observable(name)?;
                let width = if name == "mean_stress" { 4 } else { 1 };
                if s.sample_shape.iter().product::<usize>() != width {
                    return Err(IoError::Invalid {
                        path: file.to_path_buf(),
                        reason: format!(
                            "observable {name} has samples of shape {:?}, expected {width} values",
                            s.sample_shape
                        ),
                    });
                }
                Ok((name, s))
            })
            .collect()
    })?;
    let hours = |t: f64| t / 3600.0;
    // Component `c` of each sample of `name` (shapes checked above).
    let samples = |name: &str, c: usize, scale: f64| -> Vec<(f64, f64)> {
        series.get(name).map_or_else(Vec::new, |s| {
            let width = s.value.len() / s.time_s.len().max(1);
            s.time_s
                .iter()
                .zip(s.value.chunks_exact(width.max(1)))
                .map(|(&t, v)| (hours(t), v[c] * scale))
                .collect()
        })
    };
    let line = |name: &str, label: &str, scale: f64| -> Result<Line, Error> {
        Ok(Line::new(label, samples(name, 0, scale)))
    };
    let component = |c: usize, label: &str| Line::new(label, samples("mean_stress", c, 1e-3));
    let panels = vec![
        (
            Axes {
                title: "kinetic energy",
                x: "time (h)",
                y: "energy (MJ)",
            },
            vec![
                line("kinetic_translational", "translational", 1e-6)?,
                line("kinetic_rotational", "rotational", 1e-6)?,
            ],
        ),
        (
            Axes {
                title: "work and dissipation (cumulative)",
                x: "time (h)",
                y: "energy (MJ)",
            },
            vec![
                line("forcing_work", "forcing work", 1e-6)?,
                line("boundary_work", "wall work", 1e-6)?,
                line("friction_dissipation", "friction", 1e-6)?,
                line("damping_dissipation", "damping", 1e-6)?,
            ],
        ),
        (
            Axes {
                title: "mean stress (tension positive)",
                x: "time (h)",
                y: "stress (kN/m)",
            },
            vec![component(0, "xx"), component(1, "xy"), component(3, "yy")],
        ),
        (
            Axes {
                title: "contacts",
                x: "time (h)",
                y: "number of contacts",
            },
            vec![line("contacts", "", 1.0)?],
        ),
        (
            Axes {
                title: "sliding fraction",
                x: "time (h)",
                y: "fraction of contacts sliding",
            },
            vec![line("sliding_fraction", "", 1.0)?],
        ),
        (
            Axes {
                title: "mean friction coefficient",
                x: "time (h)",
                y: "sum |F_t| / sum F_n",
            },
            vec![line("mean_mu", "", 1.0)?],
        ),
    ];
    grid(path, 2, &panels)
}

/// The run's metadata, floes, and the selected snapshots with the value
/// each floe is coloured by.
#[allow(clippy::type_complexity)]
fn read_frames(
    run: &RunFile,
    frames: &[usize],
    colour: ColourBy,
) -> Result<
    (
        RunMetadata,
        StaticFloes,
        Vec<Snapshot>,
        Vec<Vec<Option<f64>>>,
    ),
    IoError,
> {
    let meta = run.metadata()?;
    let floes = run.static_floes()?;
    let domain = meta.domain;
    let period = [0, 1].map(|d| domain.periodic[d].then_some(domain.size_m[d]));
    // Every value first, so that all frames share one colour scale.
    let mut snapshots = Vec::with_capacity(frames.len());
    let mut values = Vec::with_capacity(frames.len());
    for &k in frames {
        let snap = run.snapshot(k)?;
        let v: Vec<Option<f64>> = match colour {
            ColourBy::Speed => snap
                .velocity
                .iter()
                .map(|v| Some(v[0].hypot(v[1])))
                .collect(),
            ColourBy::Theta | ColourBy::Stress => {
                let c = run.contacts(k)?;
                let view = ContactView {
                    pair: &c.pair,
                    normal: &c.normal,
                    normal_force_n: &c.normal_force_n,
                    tangential_force_n: &c.tangential_force_n,
                    point: &c.point,
                    theta: &c.theta,
                };
                if colour == ColourBy::Theta {
                    per_floe::mean_theta(floes.len(), &view)
                } else {
                    per_floe::pressure(&snap.position, &floes.area_m2, &view, period)
                        .into_iter()
                        .map(|p| p.map(|p| p * 1e-3))
                        .collect()
                }
            }
        };
        values.push(v);
        snapshots.push(snap);
    }
    Ok((meta, floes, snapshots, values))
}
