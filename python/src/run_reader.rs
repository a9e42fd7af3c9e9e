//! `floe._floe.RunReader`: a run file read through floe's own reader
//! (floe_io::RunFile), one snapshot at a time, as NumPy arrays. Each call
//! opens the file anew and retries a read caught mid-flush, so a file that
//! a run is still writing can be read (docs/output.md).

use std::path::PathBuf;

use floe_io::{IoError, RunFile};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{existing, io_error};

/// A run file (HDF5, docs/output.md) opened for reading.
#[pyclass(module = "floe._floe", frozen)]
pub struct RunReader {
    path: PathBuf,
}

/// `rows x 2` as a NumPy array.
fn pairs<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    rows: &[[T; 2]],
) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<T> = rows.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, flat)
        .reshape([rows.len(), 2])?
        .into_any())
}

/// An event log's `rows` as a dict of columns, one array per name, each
/// value taken from a row by its closure (every log the reader returns).
macro_rules! event_columns {
    ($py:expr, $rows:expr, { $($name:literal => $f:expr),* $(,)? }) => {{
        let d = PyDict::new($py);
        $(d.set_item($name, array($py, $rows.iter().map($f).collect()))?;)*
        d
    }};
}

fn array<'py, T: numpy::Element>(py: Python<'py>, v: Vec<T>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

impl RunReader {
    fn read<T: Send>(
        &self,
        py: Python<'_>,
        read: impl Fn(&RunFile) -> Result<T, IoError> + Send + Sync,
    ) -> PyResult<T> {
        let out = py
            .detach(|| RunFile::read_retrying(&self.path, read))
            .map_err(io_error)?;
        py.check_signals()?;
        Ok(out)
    }

    fn check_snapshot(&self, py: Python<'_>, k: usize) -> PyResult<()> {
        let n = self.read(py, RunFile::snapshot_count)?;
        if k >= n {
            return Err(PyIndexError::new_err(format!(
                "snapshot {k}: the file has {n} (0 to {})",
                n.saturating_sub(1)
            )));
        }
        Ok(())
    }
}

#[pymethods]
impl RunReader {
    /// Opens ``path`` after checking that it is a floe run file.
    #[new]
    fn new(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        existing(&path)?;
        let reader = RunReader { path };
        reader.read(py, |_| Ok(()))?;
        Ok(reader)
    }

    /// The file.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// Complete snapshots in the file.
    fn snapshot_count(&self, py: Python<'_>) -> PyResult<usize> {
        self.read(py, RunFile::snapshot_count)
    }

    /// Every complete snapshot's time, s.
    fn snapshot_times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(array(py, self.read(py, RunFile::snapshot_times)?))
    }

    /// Snapshot ``k``'s floes: their fixed properties and their state.
    fn floes<'py>(&self, py: Python<'py>, k: usize) -> PyResult<Bound<'py, PyDict>> {
        self.check_snapshot(py, k)?;
        let (floes, snap, stress, parents) = self.read(py, |run| {
            Ok((
                run.floes_at(k)?,
                run.snapshot(k)?,
                run.floe_stress(k)?,
                run.parent_ids_at(k)?,
            ))
        })?;
        let d = PyDict::new(py);
        d.set_item("step", snap.step)?;
        d.set_item("time", snap.time_s)?;
        d.set_item("id", array(py, floes.id))?;
        let parent: Vec<i64> = parents
            .iter()
            .map(|p| p.map_or(-1, |id| id as i64))
            .collect();
        d.set_item("parent_id", array(py, parent))?;
        d.set_item("vertex_offsets", array(py, floes.vertex_offsets))?;
        d.set_item("vertices", pairs(py, &floes.vertices)?)?;
        d.set_item("thickness", array(py, floes.thickness_m))?;
        d.set_item("mass", array(py, floes.mass_kg))?;
        d.set_item("area", array(py, floes.area_m2))?;
        d.set_item("inertia", array(py, floes.inertia_kg_m2))?;
        d.set_item("prescribed", array(py, floes.prescribed))?;
        d.set_item("land", array(py, floes.land))?;
        d.set_item("position", pairs(py, &snap.position)?)?;
        d.set_item("velocity", pairs(py, &snap.velocity)?)?;
        d.set_item("angle", array(py, snap.angle))?;
        d.set_item("angular_velocity", array(py, snap.angular_velocity))?;
        match stress {
            Some(s) => {
                let flat: Vec<f64> = s.iter().flatten().copied().collect();
                let a = PyArray1::from_vec(py, flat).reshape([s.len(), 3])?;
                d.set_item("stress", a)?;
            }
            None => d.set_item("stress", py.None())?,
        }
        Ok(d)
    }

    /// Snapshot ``k``'s contacts (``pair`` indexes that snapshot's floes).
    fn contacts<'py>(&self, py: Python<'py>, k: usize) -> PyResult<Bound<'py, PyDict>> {
        self.check_snapshot(py, k)?;
        let c = self.read(py, |run| run.contacts(k))?;
        let d = PyDict::new(py);
        d.set_item("step", c.step)?;
        d.set_item("time", c.time_s)?;
        d.set_item("pair", pairs(py, &c.pair)?)?;
        d.set_item("theta", array(py, c.theta))?;
        d.set_item("mu", array(py, c.mu))?;
        d.set_item("normal_force", array(py, c.normal_force_n))?;
        d.set_item("tangential_force", array(py, c.tangential_force_n))?;
        d.set_item("slip_rate", array(py, c.slip_rate_m_per_s))?;
        d.set_item("overlap_area", array(py, c.overlap_m2))?;
        d.set_item("point", pairs(py, &c.point)?)?;
        d.set_item("normal", pairs(py, &c.normal)?)?;
        Ok(d)
    }

    /// The observables' names.
    fn observable_names(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        self.read(py, RunFile::observable_names)
    }

    /// One observable: ``step``, ``time``, ``value`` (``[T]`` or
    /// ``[T, k]``) and ``unit``.
    fn observable<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
        let s = self.read(py, |run| run.observable(name))?;
        let d = PyDict::new(py);
        let samples = s.step.len();
        d.set_item("step", array(py, s.step))?;
        d.set_item("time", array(py, s.time_s))?;
        let mut shape = vec![samples];
        shape.extend(&s.sample_shape);
        d.set_item("value", PyArray1::from_vec(py, s.value).reshape(shape)?)?;
        d.set_item("unit", s.unit)?;
        Ok(d)
    }

    /// The run's parameters and provenance.
    fn metadata<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (m, status, checkpoint) = self.read(py, |run| {
            Ok((run.metadata()?, run.status()?, run.checkpoint()?))
        })?;
        let d = PyDict::new(py);
        d.set_item("scenario_toml", m.scenario_toml)?;
        d.set_item("scenario_path", m.scenario_path)?;
        d.set_item("floe_version", m.floe_version)?;
        d.set_item("git_commit", m.git_commit)?;
        d.set_item("command_line", m.command_line)?;
        d.set_item("threads", m.threads)?;
        d.set_item("processes", m.processes)?;
        d.set_item("author", m.author)?;
        d.set_item("domain_min", m.domain.min_m.to_vec())?;
        d.set_item("domain_size", m.domain.size_m.to_vec())?;
        d.set_item("periodic", m.domain.periodic.to_vec())?;
        d.set_item("status", status)?;
        d.set_item("checkpoint", checkpoint.map(|c| (c.step, c.time_s)))?;
        Ok(d)
    }

    /// The fracture log as columns (empty for a run without fracture).
    fn fractures<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let events = self.read(py, RunFile::fractures)?;
        Ok(event_columns!(py, events, {
            "step" => |e| e.step,
            "time" => |e| e.time_s,
            "parent" => |e| e.parent_id,
            "pieces" => |e| e.piece_ids.len() as u64,
            "first_piece" => |e| e.piece_ids.first().copied().unwrap_or(0),
            "sigma_1" => |e| e.principal_pa.0,
            "sigma_2" => |e| e.principal_pa.1,
            "area" => |e| e.area_m2,
        }))
    }

    /// The ridging log as columns (empty for a run without one).
    fn ridges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let rows = self.read(py, RunFile::ridges)?;
        Ok(event_columns!(py, rows, {
            "step" => |r| r.step,
            "time" => |r| r.time_s,
            "loser" => |r| r.loser_id,
            "gainer" => |r| r.gainer_id,
            "ice_to" => |r| r.ice_to_id,
            "to_coast" => |r| r.to_coast,
            "whole" => |r| r.whole,
            "area_before" => |r| r.area_before_m2,
            "area_removed" => |r| r.area_removed_m2,
            "volume" => |r| r.volume_m3,
            "mass" => |r| r.mass_kg,
            "force_before" => |r| r.force_before_n,
            "force_after" => |r| r.force_after_n,
        }))
    }

    /// The welding log as columns (empty for a run without one).
    fn welds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let rows = self.read(py, RunFile::welds)?;
        Ok(event_columns!(py, rows, {
            "step" => |r| r.step,
            "time" => |r| r.time_s,
            "first" => |r| r.ids[0],
            "second" => |r| r.ids[1],
            "welded" => |r| r.welded_id,
            "area_first" => |r| r.areas_m2[0],
            "area_second" => |r| r.areas_m2[1],
            "area" => |r| r.area_m2,
            "mass" => |r| r.mass_kg,
            "thickness" => |r| r.thickness_m,
            "centre_shift" => |r| r.centre_shift_m,
            "kinetic_energy_lost" => |r| r.kinetic_energy_lost_j,
            "energy_released" => |r| r.released_j,
        }))
    }

    fn __repr__(&self) -> String {
        format!("RunReader({})", self.path.display())
    }
}

/// Writes the run file's XDMF description for ParaView (``floe export
/// --xdmf``): `xdmf` and its sidecar `xdmf + ".h5"`; returns both paths.
#[pyfunction]
#[pyo3(signature = (run, xdmf, *, force=false))]
pub fn export_xdmf(
    py: Python<'_>,
    run: PathBuf,
    xdmf: PathBuf,
    force: bool,
) -> PyResult<(PathBuf, PathBuf)> {
    existing(&run)?;
    let done = py
        .detach(|| floe_io::xdmf::write_xdmf(&run, &xdmf, force))
        .map_err(io_error)?;
    // A Ctrl-C while it wrote: raised now, the files written whole.
    py.check_signals()?;
    Ok((done.xdmf, done.sidecar))
}
