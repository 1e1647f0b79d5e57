//! geode's typed errors as Python exceptions: one class per kind of failure, each carrying the kind, node path, parameter and message.

use geode_graph::edit::EditError;
use geode_graph::LoadError;
use geode_op::{CookError, ErrorKind};
use std::sync::OnceLock;

use pyo3::exceptions::{PyException, PyKeyError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyType};

/// The exception classes, apart from the Rust error types they are made from.
mod exc {
    use pyo3::exceptions::PyException;

    pyo3::create_exception!(
    geode,
    GeodeError,
    PyException,
    "Any error geode reports: `kind`, `path` (node), `param`, `message`, and `errors` when there are several."
);
    pyo3::create_exception!(
    geode,
    EditError,
    GeodeError,
    "An edit the network refused (unknown node or parameter, a cycle, a wire between different port types)."
);
    pyo3::create_exception!(
    geode,
    LoadError,
    GeodeError,
    "A network that does not load: a bad parameter value, an unknown node type, a broken reference."
);
    pyo3::create_exception!(
        geode,
        CookError,
        GeodeError,
        "A cook that failed; `kind` says why (parameter, input, resource, kernel, io, network)."
    );
    pyo3::create_exception!(
        geode,
        FileError,
        GeodeError,
        "A file geode could not read or write."
    );
}
use exc::{
    CookError as CookErr, EditError as EditErr, FileError, GeodeError, LoadError as LoadErr,
};

/// One problem as the exception's fields hold it.
pub struct Problem {
    pub kind: &'static str,
    pub path: String,
    pub param: Option<String>,
    pub message: String,
}

impl Problem {
    fn new(
        kind: &'static str,
        path: &str,
        param: Option<&str>,
        message: impl Into<String>,
    ) -> Problem {
        Problem {
            kind,
            path: path.to_owned(),
            param: param.map(str::to_owned),
            message: message.into(),
        }
    }

    fn line(&self) -> String {
        match &self.param {
            Some(p) => format!("{} (parameter `{p}`): {}", self.path, self.message),
            None if self.path.is_empty() => self.message.clone(),
            None => format!("{}: {}", self.path, self.message),
        }
    }
}

impl From<&LoadError> for Problem {
    fn from(e: &LoadError) -> Problem {
        Problem {
            kind: if e.param.is_some() {
                "parameter"
            } else {
                "network"
            },
            path: e.path.clone(),
            param: e.param.clone(),
            message: e.message.clone(),
        }
    }
}

impl From<&CookError> for Problem {
    fn from(e: &CookError) -> Problem {
        Problem {
            kind: e.kind.name(),
            path: e.path.clone(),
            param: e.param.clone(),
            message: e.message.clone(),
        }
    }
}

impl From<&EditError> for Problem {
    fn from(e: &EditError) -> Problem {
        Problem {
            kind: "edit",
            path: e.path.clone(),
            param: None,
            message: e.message.clone(),
        }
    }
}

/// An exception of class `T` whose fields are the first problem's, with
/// every problem in `errors`.
fn raise<T: pyo3::type_object::PyTypeInfo>(problems: Vec<Problem>) -> PyErr {
    Python::attach(|py| {
        let text = problems
            .iter()
            .map(Problem::line)
            .collect::<Vec<_>>()
            .join("\n");
        let err = PyErr::new::<T, _>(text);
        if let Err(e) = fill(py, &err, &problems) {
            return e;
        }
        err
    })
}

fn fill(py: Python<'_>, err: &PyErr, problems: &[Problem]) -> PyResult<()> {
    let value = err.value(py);
    let list = PyList::empty(py);
    for p in problems {
        let d = PyDict::new(py);
        d.set_item("kind", p.kind)?;
        d.set_item("path", Some(p.path.as_str()).filter(|p| !p.is_empty()))?;
        d.set_item("param", p.param.as_deref())?;
        d.set_item("message", &p.message)?;
        list.append(d)?;
    }
    let first = problems.first();
    value.setattr("kind", first.map(|p| p.kind))?;
    value.setattr(
        "path",
        first.map(|p| p.path.as_str()).filter(|p| !p.is_empty()),
    )?;
    value.setattr("param", first.and_then(|p| p.param.as_deref()))?;
    value.setattr("message", first.map(|p| p.message.as_str()))?;
    value.setattr("errors", list)?;
    Ok(())
}

/// The classes that are a `GeodeError` and a built-in error at once, made
/// at import (a class with two exception bases cannot be declared in Rust).
static NOT_FOUND: OnceLock<Py<PyType>> = OnceLock::new();
static INVALID: OnceLock<Py<PyType>> = OnceLock::new();

/// `class name(GeodeError, also)` with its own `__str__` (KeyError's would
/// quote the message as if it were a key).
fn derived<'py>(
    py: Python<'py>,
    name: &str,
    also: Bound<'py, PyType>,
    doc: &str,
) -> PyResult<Bound<'py, PyType>> {
    let body = PyDict::new(py);
    body.set_item("__doc__", doc)?;
    body.set_item("__module__", "geode")?;
    body.set_item("__str__", py.get_type::<PyException>().getattr("__str__")?)?;
    let bases = (py.get_type::<GeodeError>(), also);
    Ok(py
        .get_type::<pyo3::types::PyType>()
        .call1((name, bases, body))?
        .cast_into::<PyType>()?)
}

fn raise_as(cls: &'static OnceLock<Py<PyType>>, problem: Problem) -> PyErr {
    Python::attach(|py| {
        let Some(ty) = cls.get() else {
            return PyValueError::new_err(problem.line());
        };
        let err = PyErr::from_type(ty.bind(py).clone(), problem.line());
        match fill(py, &err, &[problem]) {
            Ok(()) => err,
            Err(e) => e,
        }
    })
}

/// A node, parameter or attribute that is not there: a `GeodeError` and a `KeyError`.
pub fn not_found(
    kind: &'static str,
    path: &str,
    param: Option<&str>,
    message: impl Into<String>,
) -> PyErr {
    raise_as(&NOT_FOUND, Problem::new(kind, path, param, message))
}

/// A value geode cannot use (a shape, a type, a range): a `GeodeError` and a `ValueError`.
pub fn invalid(message: impl Into<String>) -> PyErr {
    invalid_at("", None, message)
}

/// [`invalid`] for the value given to parameter `param` of node `path`.
pub fn invalid_at(path: &str, param: Option<&str>, message: impl Into<String>) -> PyErr {
    raise_as(&INVALID, Problem::new("value", path, param, message))
}

/// A refused edit; `param` names the parameter it was about, where one was.
pub fn edit_error(e: &EditError, param: Option<&str>) -> PyErr {
    let mut problem = Problem::from(e);
    problem.param = param.map(str::to_owned);
    raise::<EditErr>(vec![problem])
}

pub fn load_errors(errors: &[LoadError]) -> PyErr {
    raise::<LoadErr>(errors.iter().map(Problem::from).collect())
}

/// A failed cook; a cancelled one becomes `KeyboardInterrupt`.
pub fn cook_errors(errors: &[CookError]) -> PyErr {
    if errors.iter().any(|e| e.kind == ErrorKind::Cancelled) {
        return pyo3::exceptions::PyKeyboardInterrupt::new_err("the cook was cancelled");
    }
    raise::<CookErr>(errors.iter().map(Problem::from).collect())
}

/// A problem of geode's own making in Python's terms (a bad argument).
pub fn usage(
    kind: &'static str,
    path: &str,
    param: Option<&str>,
    message: impl Into<String>,
) -> PyErr {
    raise::<GeodeError>(vec![Problem::new(kind, path, param, message)])
}

/// A file geode-io refused: over the memory budget it is of kind
/// `resource`, as a cook's is; anything else `io`.
pub fn read_error(path: &std::path::Path, e: &geode_io::IoError) -> PyErr {
    let kind = match e {
        geode_io::IoError::TooLarge { .. } => "resource",
        _ => "io",
    };
    file_problem(path, e, kind)
}

/// A file read refused before it began: too big for the memory budget is
/// `resource`, a cancelled read Ctrl-C's `KeyboardInterrupt`.
pub fn refused_error(path: &std::path::Path, e: &geode_op::FileRefusal) -> PyErr {
    match e {
        geode_op::FileRefusal::TooLarge { .. } => file_problem(path, e, "resource"),
        geode_op::FileRefusal::Cancelled => {
            pyo3::exceptions::PyKeyboardInterrupt::new_err("the read was cancelled")
        }
        _ => file_problem(path, e, "io"),
    }
}

pub fn file_error(path: &std::path::Path, e: impl std::fmt::Display) -> PyErr {
    file_problem(path, e, "io")
}

fn file_problem(path: &std::path::Path, e: impl std::fmt::Display, kind: &'static str) -> PyErr {
    let shown = path.display().to_string();
    let text = e.to_string();
    // geode's I/O errors begin with the path already: say it once.
    let message = text
        .strip_prefix(&format!("{shown}: "))
        .unwrap_or(&text)
        .to_owned();
    raise::<FileError>(vec![Problem::new(kind, &shown, None, message)])
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("GeodeError", py.get_type::<GeodeError>())?;
    m.add("EditError", py.get_type::<EditErr>())?;
    m.add("LoadError", py.get_type::<LoadErr>())?;
    m.add("CookError", py.get_type::<CookErr>())?;
    m.add("FileError", py.get_type::<FileError>())?;
    let not_found = derived(
        py,
        "NotFoundError",
        py.get_type::<PyKeyError>(),
        "A node, parameter or attribute that is not there; a KeyError too.",
    )?;
    let invalid = derived(
        py,
        "InvalidValueError",
        py.get_type::<PyValueError>(),
        "A value geode cannot use (an array's shape or type, a number out of range); a ValueError too.",
    )?;
    m.add("NotFoundError", &not_found)?;
    m.add("InvalidValueError", &invalid)?;
    let _ = NOT_FOUND.set(not_found.unbind());
    let _ = INVALID.set(invalid.unbind());
    Ok(())
}
