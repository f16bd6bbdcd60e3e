//! Error mapping and the one way into the core for heavy calls ([`enter`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

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

pyo3::create_exception!(
    foon,
    OutputError,
    FoonError,
    "An output could not be written: Graphviz's `dot` is missing or failed, or the graph is too large to draw."
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
            E::GoalNotFound { .. } | E::GoalAmbiguous { .. } => GoalNotFoundError::new_err(msg),
            E::MissingRate { motion } => Python::attach(|py| {
                let err = MissingRateError::new_err(msg);
                let _ = err.value(py).setattr("motion", motion);
                err
            }),
            E::Cancelled => PyKeyboardInterrupt::new_err("cancelled"),
            E::Invalid(_) => PyValueError::new_err(msg),
            E::Output(_) => OutputError::new_err(msg),
            E::BadIndex { path, reason } => Python::attach(|py| {
                let err = FoonError::new_err(msg);
                let v = err.value(py);
                let _ = v.setattr("path", path.display().to_string());
                let _ = v.setattr("reason", reason);
                err
            }),
            _ => FoonError::new_err(msg),
        }
    }
}

/// The cancel callback [`enter`] hands to the work: true once Ctrl-C was pressed.
pub(crate) type Cancel<'a> = &'a (dyn Fn() -> bool + Sync);

/// How often the waiting thread looks at Python's signals.
const POLL: Duration = Duration::from_millis(20);

/// Runs heavy core work the one way every call does: with the interpreter detached, on a
/// worker thread, while the calling thread looks at Python's signals every 20 ms. A signal
/// whose handler raises (Ctrl-C) turns the `cancel` callback given to the work true; the
/// work stops at its next check with `Error::Cancelled`, and the handler's exception
/// (`KeyboardInterrupt`) is what the call raises, even when the work finished anyway. Core
/// errors become typed Python exceptions; a panic becomes `PanicException`.
pub(crate) fn enter<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(Cancel<'_>) -> foon_core::Result<T> + Send,
) -> PyResult<T> {
    enter_watching(py, &|| false, work)
}

/// As [`enter`], also stopping the work (as Ctrl-C does: `Error::Cancelled`, raised as
/// `KeyboardInterrupt`) once `event` (a `threading.Event`, or anything with `is_set()`) is
/// set: how a call made on a thread other than the main one, which sees no signals, is
/// cancelled by its caller.
pub(crate) fn enter_until<T: Send>(
    py: Python<'_>,
    event: Option<&Py<PyAny>>,
    work: impl FnOnce(Cancel<'_>) -> foon_core::Result<T> + Send,
) -> PyResult<T> {
    let Some(event) = event else {
        return enter(py, work);
    };
    let set = || {
        Python::attach(|py| {
            event
                .bind(py)
                .call_method0("is_set")
                .and_then(|v| v.is_truthy())
                .unwrap_or(true)
        })
    };
    enter_watching(py, &set, work)
}

/// As [`enter`], calling `watch` on the waiting thread at every look at the signals (every
/// 20 ms) while the work runs: how a progress bar is drawn from the core's counters. When
/// `watch` answers true the work is cancelled as by Ctrl-C.
#[allow(clippy::redundant_closure_for_method_calls)] // `Python::check_signals` is not general enough
pub(crate) fn enter_watching<T: Send>(
    py: Python<'_>,
    watch: &(dyn Fn() -> bool + Sync),
    work: impl FnOnce(Cancel<'_>) -> foon_core::Result<T> + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let done = AtomicBool::new(false);
    let work = Mutex::new(Some(work));
    let take = || work.lock().unwrap_or_else(PoisonError::into_inner).take();
    let mut raised: Option<PyErr> = None;
    let outcome = py.detach(|| {
        let caller = std::thread::current();
        let stopped = || stop.load(Ordering::Relaxed);
        std::thread::scope(|s| {
            let spawned = std::thread::Builder::new()
                .name("foon-call".into())
                .spawn_scoped(s, || {
                    let r = take().map(|w| w(&stopped));
                    done.store(true, Ordering::Release);
                    caller.unpark();
                    r
                });
            let Ok(handle) = spawned else {
                // No thread to spare: run the work here, without watching for Ctrl-C.
                return Ok(take().map(|w| w(&|| false)));
            };
            while !done.load(Ordering::Acquire) {
                std::thread::park_timeout(POLL);
                if done.load(Ordering::Acquire) {
                    continue;
                }
                if watch() {
                    stop.store(true, Ordering::Relaxed);
                }
                if raised.is_some() {
                    continue;
                }
                if let Err(e) = Python::attach(|py| py.check_signals()) {
                    raised = Some(e);
                    stop.store(true, Ordering::Relaxed);
                }
            }
            handle.join()
        })
    });
    if let Some(e) = raised {
        return Err(e);
    }
    finish(outcome)
}

/// As [`enter`], for work that runs on one thread: it runs here, with the interpreter
/// detached, and its `cancel` callback looks at Python's signals itself (at most every
/// 20 ms), so a short call costs no thread. Used where the work never waits on other
/// threads (a batch that runs on the calling thread alone).
#[allow(clippy::redundant_closure_for_method_calls)] // `Python::check_signals` is not general enough
pub(crate) fn enter_here<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(Cancel<'_>) -> foon_core::Result<T> + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let raised: Mutex<Option<PyErr>> = Mutex::new(None);
    let last = Mutex::new(Instant::now());
    let cancel = || {
        if stop.load(Ordering::Relaxed) {
            return true;
        }
        {
            let mut at = last.lock().unwrap_or_else(PoisonError::into_inner);
            if at.elapsed() < POLL {
                return false;
            }
            *at = Instant::now();
        }
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            *raised.lock().unwrap_or_else(PoisonError::into_inner) = Some(e);
            stop.store(true, Ordering::Relaxed);
        }
        stop.load(Ordering::Relaxed)
    };
    let outcome = py
        .detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| Some(work(&cancel)))));
    if let Some(e) = raised.into_inner().unwrap_or_else(PoisonError::into_inner) {
        return Err(e);
    }
    finish(outcome)
}

/// The result of a call's work: core errors as typed exceptions, a panic as
/// `PanicException`.
fn finish<T>(outcome: std::thread::Result<Option<foon_core::Result<T>>>) -> PyResult<T> {
    match outcome {
        Ok(Some(r)) => r.map_err(|e| PyErr::from(PyFoonErr(e))),
        Ok(None) => Err(pyo3::panic::PanicException::new_err(
            "internal error in foon: the work of a call ran twice",
        )),
        Err(p) => {
            let what = p
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_owned());
            Err(pyo3::panic::PanicException::new_err(format!(
                "internal error in foon: {what}"
            )))
        }
    }
}
