//! `floe.Scenario`: a scenario's TOML text with where it lives, edited key
//! by key as Python values and checked after every edit by the scenario
//! reader that `floe run` uses.

use std::path::{Path, PathBuf};

use floe_friction::LawRegistry;
use floe_scenario::settings::{self, Setting};
use floe_scenario::ScenarioError;
use pyo3::exceptions::{PyFileExistsError, PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping};

use crate::errors::scenario_error;
use crate::toml_values::{to_python, to_toml};

/// A floe scenario (docs/scenarios.md): ``Scenario.from_file(path)`` or
/// ``Scenario.from_text(text)``; ``s["friction.mu"] = 0.4`` sets a key
/// (``wall[1].velocity_m_per_s`` names the second ``[[wall]]``), checked at
/// once; ``s.update({...})`` sets several and checks them together.
#[pyclass(module = "floe", from_py_object)]
#[derive(Clone)]
pub struct Scenario {
    /// The TOML text.
    text: String,
    /// The name errors give (the file, or `<string>`).
    origin: PathBuf,
    /// Where relative input files are found (absolute).
    base_dir: PathBuf,
}

impl Scenario {
    /// Reads and checks `text` as the scenario reader does.
    pub fn parsed(&self) -> PyResult<floe_scenario::Scenario> {
        floe_scenario::Scenario::from_text_in(
            &self.text,
            &self.origin,
            &self.base_dir,
            &LawRegistry::builtin(),
        )
        .map_err(scenario_error)
    }

    /// The path a run file records as the scenario's (a resume finds
    /// relative inputs beside it).
    pub fn recorded_path(&self) -> PathBuf {
        let name = self
            .origin
            .file_name()
            .map_or_else(|| "<string>".into(), |n| n.to_os_string());
        self.base_dir.join(name)
    }

    /// A scenario file holding this scenario, for the studies that read
    /// one (`floe compare`): its own file while unedited, else
    /// `dir/scenario.toml` with its relative input paths made absolute.
    /// Refused: replacing the file the scenario was read from, and (without
    /// `force`) a `dir/scenario.toml` with other content. Also returns the
    /// file if this call made it (to remove again if the study refuses).
    pub fn as_file(&self, dir: &Path, force: bool) -> PyResult<(PathBuf, Option<PathBuf>)> {
        if std::fs::read_to_string(&self.origin).is_ok_and(|t| t == self.text) {
            return Ok((self.origin.clone(), None));
        }
        let path = dir.join("scenario.toml");
        let text = floe_scenario::input_paths::anchor_input_paths(&self.text, &self.base_dir);
        let existing = std::fs::read_to_string(&path).ok();
        if existing.is_some() && floe_run::same_file::same_file(&path, &self.origin) {
            return Err(PyValueError::new_err(format!(
                "{}: the edited scenario would replace the file it was read from; \
                 write the comparison to another directory",
                path.display()
            )));
        }
        if existing.as_ref().is_some_and(|t| *t != text) && !force {
            return Err(PyFileExistsError::new_err(format!(
                "{}: already exists with another scenario; pass force=True to replace it",
                path.display()
            )));
        }
        std::fs::create_dir_all(dir).map_err(|e| scenario_error(ScenarioError::io(dir, e)))?;
        std::fs::write(&path, text).map_err(|e| scenario_error(ScenarioError::io(&path, e)))?;
        let made = existing.is_none().then(|| path.clone());
        Ok((path, made))
    }

    fn checked(text: String, origin: PathBuf, base_dir: PathBuf) -> PyResult<Self> {
        let s = Scenario {
            text,
            origin,
            base_dir,
        };
        s.parsed()?;
        Ok(s)
    }

    /// The text with `(key, value)` pairs set, checked.
    fn with_set(&self, pairs: &[(String, Bound<'_, PyAny>)]) -> PyResult<Self> {
        let mut list = Vec::with_capacity(pairs.len());
        for (key, value) in pairs {
            list.push(Setting {
                key: split_key(key)?,
                values: vec![to_toml(key, value)?.to_string()],
            });
        }
        settings::check_distinct(&list).map_err(scenario_error)?;
        let choice = vec![0; list.len()];
        let text =
            settings::apply(&self.text, &self.origin, &list, &choice).map_err(scenario_error)?;
        Self::checked(text, self.origin.clone(), self.base_dir.clone())
    }
}

fn split_key(key: &str) -> PyResult<Vec<String>> {
    let parts: Vec<String> = key.split('.').map(|p| p.trim().to_string()).collect();
    if parts.iter().any(String::is_empty) {
        return Err(PyKeyError::new_err(format!(
            "{key:?}: a key is dotted names, e.g. \"friction.mu\" or \"wall[1].velocity_m_per_s\""
        )));
    }
    Ok(parts)
}

fn absolute_dir(path: &Path) -> PathBuf {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf())
}

#[pymethods]
impl Scenario {
    /// Reads the scenario file at ``path``; raises ``FileNotFoundError`` or
    /// ``floe.ScenarioError`` (with ``file``, ``line``, ``column``, ``key``).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        let text = std::fs::read_to_string(&path)
            .map_err(|e| scenario_error(floe_scenario::ScenarioError::io(path.clone(), e)))?;
        let base_dir = absolute_dir(&path);
        Self::checked(text, path, base_dir)
    }

    /// A scenario from its TOML text. ``path``: where it would live, for
    /// relative input files and error messages (default: ``<string>`` in
    /// the working directory).
    #[staticmethod]
    #[pyo3(signature = (text, path=None))]
    fn from_text(text: String, path: Option<PathBuf>) -> PyResult<Self> {
        let origin = path.unwrap_or_else(|| PathBuf::from("<string>"));
        let base_dir = absolute_dir(&origin);
        Self::checked(text, origin, base_dir)
    }

    /// The TOML text (comments and layout kept through edits).
    #[getter]
    fn text(&self) -> &str {
        &self.text
    }

    /// Where the scenario came from (the file, or ``<string>``).
    #[getter]
    fn path(&self) -> PathBuf {
        self.origin.clone()
    }

    /// The scenario's ``title``, if it has one.
    #[getter]
    fn title(&self) -> PyResult<Option<String>> {
        Ok(self.parsed()?.title().map(str::to_string))
    }

    /// Simulated duration, s.
    #[getter]
    fn duration_s(&self) -> PyResult<f64> {
        Ok(self.parsed()?.duration_s())
    }

    /// The time step the run will take, s (the scenario's ``dt_s`` or the
    /// automatic one, which builds the floes to find).
    #[getter]
    fn dt_s(&self) -> PyResult<f64> {
        self.parsed()?.time_step().map_err(scenario_error)
    }

    /// The value at a dotted key: a number, str, bool, list or dict (a
    /// table). ``KeyError`` where the file does not set it (the default
    /// applies then; docs/scenarios.md lists them).
    fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let parts = split_key(key)?;
        match settings::get(&self.text, &self.origin, &parts).map_err(scenario_error)? {
            Some(item) => to_python(py, &item),
            None => Err(PyKeyError::new_err(key.to_string())),
        }
    }

    /// Whether the file sets ``key``.
    fn __contains__(&self, key: &str) -> PyResult<bool> {
        let parts = split_key(key)?;
        Ok(settings::get(&self.text, &self.origin, &parts)
            .map_err(scenario_error)?
            .is_some())
    }

    /// Sets a key (tables on the way are made), then checks the whole
    /// scenario: a bad value raises ``floe.ScenarioError`` and leaves the
    /// scenario as it was.
    fn __setitem__(&mut self, key: String, value: Bound<'_, PyAny>) -> PyResult<()> {
        *self = self.with_set(&[(key, value)])?;
        Ok(())
    }

    /// Sets every key of ``values`` (a mapping of dotted keys to values),
    /// then checks once: for keys that are only valid together.
    fn update(&mut self, values: &Bound<'_, PyAny>) -> PyResult<()> {
        let mapping = values
            .cast::<PyMapping>()
            .map_err(|_| PyTypeError::new_err("update takes a dict of dotted keys to values"))?;
        let mut pairs = Vec::new();
        for item in mapping.items()?.iter() {
            let (k, v): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
            let k: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("update: the key {k} is not a str")))?;
            pairs.push((k, v));
        }
        *self = self.with_set(&pairs)?;
        Ok(())
    }

    /// A copy with ``values`` set (the scenario itself unchanged).
    #[pyo3(signature = (values=None, **kwargs))]
    fn with_values(
        &self,
        values: Option<&Bound<'_, PyAny>>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let mut copy = self.clone();
        if let Some(v) = values {
            copy.update(v)?;
        }
        if let Some(kw) = kwargs {
            copy.update(kw.as_any())?;
        }
        Ok(copy)
    }

    /// The whole scenario as nested dicts.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match settings::get(&self.text, &self.origin, &[]).map_err(scenario_error)? {
            Some(item) => to_python(py, &item),
            None => Ok(PyDict::new(py).into_any()),
        }
    }

    /// Writes the text to ``path`` (a scenario file ``floe run`` reads).
    fn write(&self, path: PathBuf) -> PyResult<()> {
        std::fs::write(&path, &self.text)
            .map_err(|e| scenario_error(floe_scenario::ScenarioError::io(path, e)))
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    fn __repr__(&self) -> String {
        let title = self
            .parsed()
            .ok()
            .and_then(|s| s.title().map(str::to_string));
        format!(
            "Scenario({}{})",
            self.origin.display(),
            title.map(|t| format!(": {t}")).unwrap_or_default()
        )
    }
}
