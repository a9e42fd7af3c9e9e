//! `floe._floe.compare`: `floe compare` (floe_study::compare) from Python:
//! one scenario under several friction laws, each run into `DIR/<law>.h5`,
//! the report written, and each law's row of the report's table returned.

use std::path::PathBuf;

use floe_friction::LawRegistry;
use floe_scenario::law_variants::{LawChoice, Matching};
use floe_scenario::value_ranges;
use floe_study::compare::metrics::MetricOptions;
use floe_study::compare::report::Summary;
use floe_study::compare::CompareArgs;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::python_words;
use crate::running::{drive_with, provenance, Callbacks};
use crate::scenario::Scenario;

/// Runs the comparison (see ``floe.compare``); returns the report's path
/// and one dict per law.
#[pyfunction]
#[pyo3(signature = (scenario, out_dir, laws, *, threads=None, force=false, reference_slip_m_per_s=1e-2, amontons_mu=None, on_line=None, on_progress=None, command_line=None))]
#[allow(clippy::too_many_arguments)]
pub fn compare<'py>(
    py: Python<'py>,
    scenario: Scenario,
    out_dir: PathBuf,
    laws: Vec<String>,
    threads: Option<usize>,
    force: bool,
    reference_slip_m_per_s: f64,
    amontons_mu: Option<f64>,
    on_line: Option<Py<PyAny>>,
    on_progress: Option<Py<PyAny>>,
    command_line: Option<Vec<String>>,
) -> PyResult<(PathBuf, Bound<'py, PyList>)> {
    let refuse = |name: &str, x: f64, range: String| {
        PyValueError::new_err(format!("{name}={x}: expected {range}"))
    };
    value_ranges::load_point_speed(reference_slip_m_per_s)
        .map_err(|r| refuse("reference_slip_m_per_s", reference_slip_m_per_s, r))?;
    if let Some(mu) = amontons_mu {
        value_ranges::friction_coefficient(mu).map_err(|r| refuse("amontons_mu", mu, r))?;
    }
    if laws.is_empty() {
        return Err(PyValueError::new_err("laws: name at least one law"));
    }
    let registry = LawRegistry::builtin();
    let laws = LawChoice::parse_list(&laws.join(","), &registry)
        .map_err(|e| PyValueError::new_err(python_words(&e.to_string())))?;
    scenario.parsed()?;
    let dir_existed = out_dir.exists();
    let (scenario_file, made) = scenario.as_file(&out_dir, force)?;
    let args = CompareArgs {
        scenario: scenario_file,
        laws,
        out_dir,
        threads,
        force,
        matching: Matching {
            reference_slip_m_per_s,
            amontons_mu,
        },
        metrics: MetricOptions::default(),
        provenance: provenance(command_line),
        registry,
        step_limit: floe_scenario::MAX_RUN_STEPS,
    };
    let callbacks = Callbacks {
        on_line,
        on_progress,
    };
    let comparison = drive_with(py, callbacks, |hooks| {
        floe_study::compare::compare(&args, hooks)
    })
    .inspect_err(|_| {
        // A comparison refused before it wrote anything leaves nothing
        // behind; one stopped later keeps the scenario its runs came from.
        let alone = std::fs::read_dir(&args.out_dir).is_ok_and(|d| d.count() == 1);
        if let (Some(made), true) = (&made, alone) {
            let _ = std::fs::remove_file(made);
            if !dir_existed {
                let _ = std::fs::remove_dir(&args.out_dir);
            }
        }
    })?;
    let rows = PyList::empty(py);
    for v in &comparison.variants {
        let r = Summary::of(&v.metrics);
        let d = PyDict::new(py);
        d.set_item("law", &v.name)?;
        d.set_item("peak_to_steady", r.peak_to_steady)?;
        d.set_item("steady_shear_stress_n_per_m", r.steady_shear_stress_n_per_m)?;
        d.set_item("final_normal_stress_n_per_m", r.final_normal_stress_n_per_m)?;
        d.set_item("velocity_change_m_per_s", r.velocity_change_m_per_s)?;
        d.set_item("band_equivalent_width_m", r.band_equivalent_width_m)?;
        d.set_item("band_10_90_width_m", r.band_10_90_width_m)?;
        d.set_item("slip_events", r.slip_events)?;
        d.set_item("median_event_slip_m", r.median_event_slip_m)?;
        d.set_item("mean_sliding_fraction", r.mean_sliding_fraction)?;
        d.set_item("friction_dissipation_j", r.friction_dissipation_j)?;
        d.set_item("plug_flow", r.plug_flow)?;
        d.set_item("friction", &v.friction_toml)?;
        d.set_item("file", args.out_dir.join(&v.file))?;
        rows.append(d)?;
    }
    Ok((comparison.report, rows))
}
