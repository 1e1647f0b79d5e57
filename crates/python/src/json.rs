//! Python values to the document's JSON and back, depth-limited both ways (a self-containing list must not overflow the stack).

use pyo3::prelude::*;

use crate::errors::{invalid, invalid_at};
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Number, Value as Json};

/// Deeper than any parameter value a network holds (list rows of channels).
const MAX_DEPTH: usize = 32;

/// A Python value (numbers, strings, lists, tuples, dicts, numpy arrays
/// and scalars) as JSON, for parameter `param` of node `path` (which a
/// refusal names).
pub fn to_json(v: &Bound<'_, PyAny>, path: &str, param: &str) -> PyResult<Json> {
    to_json_at(v, 0).map_err(|e| match e {
        Refused::Python(e) => e,
        Refused::Value(message) => invalid_at(path, Some(param), message),
    })
}

/// Why a value was refused: geode's reason, or Python's own error.
enum Refused {
    Value(String),
    Python(PyErr),
}

impl From<PyErr> for Refused {
    fn from(e: PyErr) -> Refused {
        Refused::Python(e)
    }
}

fn to_json_at(v: &Bound<'_, PyAny>, depth: usize) -> Result<Json, Refused> {
    if depth > MAX_DEPTH {
        return Err(Refused::Value(format!(
            "a parameter value nests deeper than {MAX_DEPTH} levels"
        )));
    }
    if v.is_none() {
        return Ok(Json::Null);
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(Json::Bool(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return match v.extract::<i64>() {
            Ok(i) => Ok(Json::from(i)),
            Err(_) => Err(Refused::Value(format!("{v} does not fit 64 bits"))),
        };
    }
    if v.is_instance_of::<PyFloat>() {
        return float(v.extract()?);
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(Json::String(s.to_str()?.to_owned()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut m = Map::new();
        for (k, x) in d.iter() {
            let k: String = k.extract().map_err(|_| {
                Refused::Value("a dict in a parameter value has keys that are not strings".into())
            })?;
            m.insert(k, to_json_at(&x, depth + 1)?);
        }
        return Ok(Json::Object(m));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for x in v.try_iter()? {
            out.push(to_json_at(&x?, depth + 1)?);
        }
        return Ok(Json::Array(out));
    }
    // numpy arrays and scalars (and anything else with `tolist`).
    if v.hasattr("tolist")? {
        let plain = v.call_method0("tolist")?;
        if !plain.is(v) {
            return to_json_at(&plain, depth + 1);
        }
    }
    Err(Refused::Value(format!(
        "a parameter value cannot be a {}",
        v.get_type().name()?
    )))
}

fn float(x: f64) -> Result<Json, Refused> {
    Number::from_f64(x)
        .map(Json::Number)
        .ok_or_else(|| Refused::Value(format!("{x} is not a finite number")))
}

/// JSON as plain Python values.
pub fn to_py<'py>(py: Python<'py>, j: &Json) -> PyResult<Bound<'py, PyAny>> {
    to_py_at(py, j, 0)
}

fn to_py_at<'py>(py: Python<'py>, j: &Json, depth: usize) -> PyResult<Bound<'py, PyAny>> {
    if depth > 4 * MAX_DEPTH {
        return Err(invalid("a document value nests too deeply"));
    }
    Ok(match j {
        Json::Null => py.None().into_bound(py),
        Json::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Json::Number(n) => match n.as_i64() {
            Some(i) => i.into_pyobject(py)?.into_any(),
            None => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Json::String(s) => PyString::new(py, s).into_any(),
        Json::Array(a) => {
            let list = PyList::empty(py);
            for x in a {
                list.append(to_py_at(py, x, depth + 1)?)?;
            }
            list.into_any()
        }
        Json::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, to_py_at(py, x, depth + 1)?)?;
            }
            d.into_any()
        }
    })
}
