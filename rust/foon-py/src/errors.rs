//! Error mapping: core errors become typed Python exceptions, in one place.

use pyo3::exceptions::{
    PyException, PyFileNotFoundError, PyKeyboardInterrupt, PyOSError, PyPermissionError,
    PyValueError,
};
use pyo3::prelude::*;

pyo3::create_exception!(foon, FoonError, PyException, "Base class of foon's errors.");
pyo3::create_exception!(
    foon,
    ParseError,
    FoonError,
    "An input file is malformed; `path`, `line`, `column` and `reason` say where and why."
);
pyo3::create_exception!(
    foon,
    GoalNotFoundError,
    FoonError,
    "The goal is not an object of the FOON."
);
pyo3::create_exception!(
    foon,
    MissingRateError,
    FoonError,
    "A motion used by a candidate unit has no success rate (give default_rate to use one)."
);

/// Newtype so that `?` turns core errors into Python exceptions.
pub(crate) struct PyFoonErr(pub(crate) foon_core::Error);

impl From<foon_core::Error> for PyFoonErr {
    fn from(e: foon_core::Error) -> Self {
        Self(e)
    }
}

impl From<PyFoonErr> for PyErr {
    fn from(PyFoonErr(e): PyFoonErr) -> PyErr {
        use foon_core::Error as E;
        let msg = e.to_string();
        match e {
            E::Io { source, path } => {
                let text = format!("{}: {source}", path.display());
                match source.kind() {
                    std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(text),
                    std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(text),
                    _ => PyOSError::new_err(text),
                }
            }
            E::Parse { at, kind, reason } => Python::attach(|py| {
                let err = ParseError::new_err(msg);
                let v = err.value(py);
                let path = at.path.as_ref().map(|p| p.display().to_string());
                let _ = v.setattr("path", path);
                let _ = v.setattr("line", at.line);
                let _ = v.setattr("column", at.column);
                let _ = v.setattr("reason", reason);
                let _ = v.setattr("kind", kind.as_str());
                err
            }),
            E::GoalNotFound { .. } => GoalNotFoundError::new_err(msg),
            E::MissingRate { motion } => Python::attach(|py| {
                let err = MissingRateError::new_err(msg);
                let _ = err.value(py).setattr("motion", motion);
                err
            }),
            E::Cancelled => PyKeyboardInterrupt::new_err("cancelled"),
            E::Invalid(_) => PyValueError::new_err(msg),
            _ => FoonError::new_err(msg),
        }
    }
}

/// Runs core work with the interpreter detached and maps its error.
pub(crate) fn run_detached<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> Result<T, foon_core::Error> + Send,
) -> PyResult<T> {
    py.detach(f).map_err(|e| PyErr::from(PyFoonErr(e)))
}
