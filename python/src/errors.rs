//! floe's errors as the Python exceptions of `floe.errors`: a scenario
//! problem as `ScenarioError` with its file, line, column and key; a file
//! that is not there as `FileNotFoundError`; an interrupt as
//! `KeyboardInterrupt`; the rest as `RunError` or `RunFileError`.

use std::path::Path;

use floe_io::IoError;
use floe_run::Error;
use floe_scenario::ScenarioError;
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyKeyboardInterrupt, PyOSError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// An instance of `floe.errors.<class>` with `message`, its keyword
/// attributes set by `attributes`.
fn floe_error(
    class: &str,
    message: String,
    attributes: impl FnOnce(&Bound<'_, PyDict>) -> PyResult<()>,
) -> PyErr {
    Python::attach(|py| {
        let made = (|| -> PyResult<PyErr> {
            let class = py.import("floe.errors")?.getattr(class)?;
            let kwargs = PyDict::new(py);
            attributes(&kwargs)?;
            let error = class.call((message,), Some(&kwargs))?;
            Ok(PyErr::from_value(error))
        })();
        made.unwrap_or_else(|e| e)
    })
}

fn no_attributes(_: &Bound<'_, PyDict>) -> PyResult<()> {
    Ok(())
}

/// A scenario error: located ones carry file, line, column and key.
pub fn scenario_error(e: ScenarioError) -> PyErr {
    match e {
        ScenarioError::Input {
            ref file,
            line,
            column,
            ref key,
            ref message,
        } => floe_error("ScenarioError", e.to_string(), |kw| {
            kw.set_item("file", file.display().to_string())?;
            kw.set_item("line", line)?;
            kw.set_item("column", column)?;
            kw.set_item("key", key)?;
            kw.set_item("reason", message)
        }),
        ScenarioError::Io { ref source, .. } => os_error(source.kind(), e.to_string()),
        other => floe_error("ScenarioError", other.to_string(), no_attributes),
    }
}

fn os_error(kind: std::io::ErrorKind, message: String) -> PyErr {
    match kind {
        std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
        std::io::ErrorKind::AlreadyExists => PyFileExistsError::new_err(message),
        _ => PyOSError::new_err(message),
    }
}

/// A run file's error.
pub fn io_error(e: IoError) -> PyErr {
    match e {
        IoError::NotFound { .. } => PyFileNotFoundError::new_err(e.to_string()),
        IoError::AlreadyExists { .. } => PyFileExistsError::new_err(e.to_string()),
        IoError::NotHdf5 { .. } | IoError::NotFloeFile { .. } => {
            floe_error("RunFileError", e.to_string(), no_attributes)
        }
        // The system's refusals (a full disk, no permission): OSError.
        IoError::CannotCreate { .. } | IoError::NoSpace { .. } | IoError::Os { .. } => {
            PyOSError::new_err(python_words(&e.to_string()))
        }
        other => floe_error("RunFileError", other.to_string(), no_attributes),
    }
}

/// A run's error.
pub fn run_error(e: Error) -> PyErr {
    match e {
        Error::Scenario(e) => scenario_error(e),
        Error::Output(e) => io_error(e),
        Error::Usage(m) => PyValueError::new_err(python_words(&m)),
        Error::WouldOverwrite(_) => PyFileExistsError::new_err(format!(
            "{}; pass force=True to overwrite it",
            e.to_string()
                .trim_end_matches("; pass --force to overwrite it")
        )),
        Error::Io { ref source, .. } => os_error(source.kind(), e.to_string()),
        Error::Interrupted { .. } => PyKeyboardInterrupt::new_err(e.to_string()),
        other => floe_error("RunError", other.to_string(), no_attributes),
    }
}

/// A message written for the command line in the Python API's words
/// (flags become keyword arguments).
pub fn python_words(message: &str) -> String {
    message
        .replace("--threads", "threads")
        .replace("--max-steps", "max_steps")
        .replace("--cell-m", "cell_m")
        .replace("--every", "every")
        .replace("--interval-s", "interval_s")
        .replace("--laws", "laws")
        .replace("pass --force", "pass force=True")
        .replace("run with --force", "pass force=True")
        .replace("--force", "force=True")
}

/// A path argument that must name a file that exists.
pub fn existing(path: &Path) -> PyResult<()> {
    if path.exists() {
        Ok(())
    } else {
        Err(PyFileNotFoundError::new_err(format!(
            "{}: no such file",
            path.display()
        )))
    }
}

/// An error of floe itself (a panic caught), as `floe.errors.RunError`.
pub fn internal_error(message: String) -> PyErr {
    floe_error("RunError", message, no_attributes)
}
