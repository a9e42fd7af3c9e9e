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
    let (plan, records) = py
        .detach(|| -> Result<_, floe_run::Error> {
            let plan = GridPlan::new(&run, cell_m, cadence)?;
            let records = (0..plan.taken.len())
                .map(|r| plan.record(r))
                .collect::<Result<Vec<_>, _>>()?;
            Ok((plan, records))
        })
        .map_err(|e| match e {
            floe_run::Error::Usage(m) => PyValueError::new_err(
                m.replace("--cell-m", "cell_m")
                    .replace("--every", "every")
                    .replace("--interval-s", "interval_s"),
            ),
            other => run_error(other),
        })?;
    let [nx, ny] = plan.grid.shape;
    let out = PyDict::new(py);
    out.set_item("x", PyArray1::from_vec(py, plan.centres(0)))?;
    out.set_item("y", PyArray1::from_vec(py, plan.centres(1)))?;
    let times: Vec<f64> = plan.taken.iter().map(|&k| plan.times[k]).collect();
    out.set_item("time", PyArray1::from_vec(py, times))?;
    out.set_item("snapshot", PyArray1::from_vec(py, plan.taken.clone()))?;
    out.set_item("start_time", plan.start_time.clone())?;
    let fields = PyDict::new(py);
    let attributes = PyDict::new(py);
    for (f, (name, standard, units, long)) in field_names().iter().enumerate() {
        let mut values = Vec::with_capacity(records.len() * nx * ny);
        for record in &records {
            values.extend_from_slice(&record[f]);
        }
        let array = PyArray1::from_vec(py, values).reshape([records.len(), ny, nx])?;
        let array: Bound<'py, PyArray3<f64>> = array;
        fields.set_item(name, array)?;
        attributes.set_item(name, (standard, units, long))?;
    }
    out.set_item("fields", fields)?;
    out.set_item("attributes", attributes)?;
    Ok(out)
}
