//! `floe._floe.grid`: a run's snapshots on a regular grid, the fields
//! `floe grid` writes (floe_study::grid_output), as NumPy arrays.

use std::path::PathBuf;

use floe_study::cadence::Cadence;
use floe_study::grid_output::{field_names, GridPlan};
use numpy::{PyArray1, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{existing, run_error};

/// The gridded fields of `run`: a dict with `x`, `y` (cell centres, m),
/// `time` (s), `snapshot` (the snapshots taken), `start_time` (or None),
/// `fields` (name -> array [time, y, x], NaN without ice) and `attributes`
/// (name -> (standard name, units, description)).
#[pyfunction]
#[pyo3(signature = (run, cell_m, *, every=None, interval_s=None))]
pub fn grid<'py>(
    py: Python<'py>,
    run: PathBuf,
    cell_m: f64,
    every: Option<usize>,
    interval_s: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    existing(&run)?;
    let cadence = match (every, interval_s) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err("give every or interval_s, not both"))
        }
        (Some(k), None) => Cadence::Every(k),
        (None, Some(t)) => Cadence::IntervalS(t),
        (None, None) => Cadence::All,
    };
    let plan = py
        .detach(|| GridPlan::new(&run, cell_m, cadence))
        .map_err(run_error)?;
    py.check_signals()?;
    let [nx, ny] = plan.grid.shape;
    let (records, cells) = (plan.taken.len(), nx * ny);
    // One record at a time, the GIL released while it is computed and
    // Ctrl-C honoured between records; each field filled in place.
    let names = field_names();
    let mut values = vec![Vec::with_capacity(records * cells); names.len()];
    for r in 0..records {
        let record = py.detach(|| plan.record(r)).map_err(run_error)?;
        py.check_signals()?;
        for (all, field) in values.iter_mut().zip(record) {
            all.extend_from_slice(&field);
        }
    }
    let out = PyDict::new(py);
    out.set_item("x", PyArray1::from_vec(py, plan.centres(0)))?;
    out.set_item("y", PyArray1::from_vec(py, plan.centres(1)))?;
    let times: Vec<f64> = plan.taken.iter().map(|&k| plan.times[k]).collect();
    out.set_item("time", PyArray1::from_vec(py, times))?;
    out.set_item("snapshot", PyArray1::from_vec(py, plan.taken.clone()))?;
    out.set_item("start_time", plan.start_time.clone())?;
    let fields = PyDict::new(py);
    let attributes = PyDict::new(py);
    for ((name, standard, units, long), v) in names.iter().zip(values) {
        let array: Bound<'py, PyArray3<f64>> =
            PyArray1::from_vec(py, v).reshape([records, ny, nx])?;
        fields.set_item(name, array)?;
        attributes.set_item(name, (standard, units, long))?;
    }
    out.set_item("fields", fields)?;
    out.set_item("attributes", attributes)?;
    Ok(out)
}
