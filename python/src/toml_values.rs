//! Python values as TOML values and back, for editing a scenario's keys:
//! bool, int, float, str, lists and dicts (inline tables).

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use toml_edit::{Array, InlineTable, Item, Value};

/// `value` as a TOML value; `key` names it in the error for a type TOML
/// cannot hold.
pub fn to_toml(key: &str, value: &Bound<'_, PyAny>) -> PyResult<Value> {
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(Value::from(b.is_true()));
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(Value::from(value.extract::<i64>()?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(Value::from(value.extract::<f64>()?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(Value::from(value.extract::<String>()?));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut array = Array::new();
        for item in value.try_iter()? {
            array.push(to_toml(key, &item?)?);
        }
        return Ok(Value::Array(array));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = InlineTable::new();
        for (k, v) in d.iter() {
            let k: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!("{key}: a table's keys must be str, not {k:?}"))
            })?;
            table.insert(&k, to_toml(key, &v)?);
        }
        return Ok(Value::InlineTable(table));
    }
    // NumPy scalars and other numbers: by their own conversions.
    if value.hasattr("__index__")? {
        return Ok(Value::from(value.extract::<i64>()?));
    }
    if value.hasattr("__float__")? {
        return Ok(Value::from(value.extract::<f64>()?));
    }
    Err(PyTypeError::new_err(format!(
        "{key}: a scenario value is a bool, int, float, str, list or dict, not {}",
        value.get_type().name()?
    )))
}

/// A TOML item as a Python value (tables as dicts, arrays of tables as
/// lists of dicts, dates as their text).
pub fn to_python<'py>(py: Python<'py>, item: &Item) -> PyResult<Bound<'py, PyAny>> {
    match item {
        Item::None => Ok(py.None().into_bound(py)),
        Item::Value(v) => value_to_python(py, v),
        Item::Table(t) => {
            let d = PyDict::new(py);
            for (k, v) in t.iter() {
                d.set_item(k, to_python(py, v)?)?;
            }
            Ok(d.into_any())
        }
        Item::ArrayOfTables(a) => {
            let list = PyList::empty(py);
            for t in a.iter() {
                list.append(to_python(py, &Item::Table(t.clone()))?)?;
            }
            Ok(list.into_any())
        }
    }
}

fn value_to_python<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::String(s) => PyString::new(py, s.value()).into_any(),
        Value::Integer(i) => (*i.value()).into_pyobject(py)?.into_any(),
        Value::Float(f) => PyFloat::new(py, *f.value()).into_any(),
        Value::Boolean(b) => PyBool::new(py, *b.value()).to_owned().into_any(),
        Value::Datetime(d) => PyString::new(py, &d.value().to_string()).into_any(),
        Value::Array(a) => {
            let list = PyList::empty(py);
            for v in a.iter() {
                list.append(value_to_python(py, v)?)?;
            }
            list.into_any()
        }
        Value::InlineTable(t) => {
            let d = PyDict::new(py);
            for (k, v) in t.iter() {
                d.set_item(k, value_to_python(py, v)?)?;
            }
            d.into_any()
        }
    })
}
