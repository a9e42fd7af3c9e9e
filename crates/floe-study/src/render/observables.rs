//! The observables figure of `floe render`: energies, work and
//! dissipation, mean stress, contacts and friction against time.

use std::path::Path;

use floe_io::{IoError, RunFile, Series};

use crate::plot::{grid, Axes, Line};
use floe_run::Error;

/// Time series of the observables: energies, work and dissipation, mean
/// stress, contacts, friction.
pub(crate) fn observables_figure(file: &Path, path: &Path) -> Result<(), Error> {
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
