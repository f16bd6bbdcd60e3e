//! The generator of synthetic FOONs (`foon_core::synth`): text, file, kitchen, goals and
//! motion table.

use foon_core::synth::{self, SynthOptions};
use pyo3::prelude::*;

use crate::convert::{ObjTuple, opt_path_arg, threads_arg, tuple_of};
use crate::errors::enter;

fn options(units: &Bound<'_, PyAny>, seed: u64, threads: Option<usize>) -> PyResult<SynthOptions> {
    // Out-of-range sizes reach the core, whose message names the bounds.
    let units = match units.extract::<i128>() {
        Ok(n) => u64::try_from(n.max(0)).unwrap_or(u64::MAX),
        Err(_) if units.extract::<f64>().is_ok() || units.hasattr("__index__")? => u64::MAX,
        Err(_) => {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "units must be an int, not {}",
                crate::convert::type_name(units)
            )));
        }
    };
    Ok(SynthOptions {
        units,
        seed,
        threads,
    })
}

/// The FOON text of `units` units made with `seed`.
#[pyfunction]
#[pyo3(signature = (units, seed, threads = None))]
pub(crate) fn synth_text(
    py: Python<'_>,
    units: &Bound<'_, PyAny>,
    seed: u64,
    threads: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let opts = options(units, seed, threads_arg(threads)?)?;
    let bytes = enter(py, |cancel| {
        let mut out = Vec::new();
        synth::synth(&opts, &mut out, &mut |_, _| !cancel())?;
        Ok(out)
    })?;
    Ok(String::from_utf8(bytes).unwrap_or_default())
}

/// Writes the FOON to `path` atomically (`None`: standard output); returns (units, bytes,
/// recipes). `progress(done, total)` is called after each batch of units.
#[pyfunction]
#[pyo3(signature = (units, seed, path = None, threads = None, progress = None))]
pub(crate) fn synth_write(
    py: Python<'_>,
    units: &Bound<'_, PyAny>,
    seed: u64,
    path: Option<&Bound<'_, PyAny>>,
    threads: Option<&Bound<'_, PyAny>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<(u64, u64, u64)> {
    let opts = options(units, seed, threads_arg(threads)?)?;
    let path = opt_path_arg("path", path)?;
    let r = enter(py, |cancel| {
        let mut tick = |done: u64, total: u64| {
            if let Some(f) = &progress {
                Python::attach(|py| {
                    let _ = f.call1(py, (done, total));
                });
            }
            !cancel()
        };
        if let Some(p) = &path {
            synth::synth_to_path(&opts, p, &mut tick)
        } else {
            let stdout = std::io::stdout();
            let mut w = std::io::BufWriter::with_capacity(1 << 20, stdout.lock());
            synth::synth(&opts, &mut w, &mut tick)
        }
    })?;
    Ok((r.units, r.bytes, r.recipes))
}

/// The kitchen matching the FOON of these options.
#[pyfunction]
pub(crate) fn synth_kitchen(
    py: Python<'_>,
    units: &Bound<'_, PyAny>,
    seed: u64,
) -> PyResult<Vec<ObjTuple>> {
    let opts = options(units, seed, None)?;
    let v = enter(py, |_| synth::synth_kitchen(&opts))?;
    Ok(v.into_iter().map(tuple_of).collect())
}

/// Up to `count` goals (dishes) spread over the FOON of these options.
#[pyfunction]
pub(crate) fn synth_goals(
    py: Python<'_>,
    units: &Bound<'_, PyAny>,
    seed: u64,
    count: usize,
) -> PyResult<Vec<ObjTuple>> {
    let opts = options(units, seed, None)?;
    let v = enter(py, |_| synth::synth_goals(&opts, count))?;
    Ok(v.into_iter().map(tuple_of).collect())
}

/// The motion table of generated FOONs: (motion, rate) pairs.
#[pyfunction]
pub(crate) fn synth_motions() -> Vec<(String, f64)> {
    synth::synth_motions()
}
