//! The generator of synthetic FOONs (`foon_core::synth`): text, file, kitchen, goals and
//! motion table.

use foon_core::synth::{self, SynthOptions};

use pyo3::prelude::*;

use crate::convert::{ObjTuple, opt_path_arg, threads_arg, tuple_of};
use crate::errors::enter;
use crate::progress::enter_progress;

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

/// Writes the FOON to `path` (`None`: standard output) through the core's atomic writer (a
/// device or a FIFO is written into); returns (units, bytes, recipes). `progress(done,
/// total)` is called after each batch of units; `bar` draws a progress bar on stderr.
#[pyfunction]
#[pyo3(signature = (units, seed, path = None, threads = None, progress = None, bar = false))]
pub(crate) fn synth_write(
    py: Python<'_>,
    units: &Bound<'_, PyAny>,
    seed: u64,
    path: Option<&Bound<'_, PyAny>>,
    threads: Option<&Bound<'_, PyAny>>,
    progress: Option<Py<PyAny>>,
    bar: bool,
) -> PyResult<(u64, u64, u64)> {
    let opts = options(units, seed, threads_arg(threads)?)?;
    let path = opt_path_arg("path", path)?;
    let broken = std::sync::atomic::AtomicBool::new(false);
    let r = enter_progress(py, bar, false, |cancel, counter| {
        counter.begin("synth", opts.units);
        let mut tick = |done: u64, total: u64| {
            counter.set_total(total);
            counter.add(done.saturating_sub(counter.done()));
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
            synth::synth(&opts, &mut w, &mut tick).map_err(|e| match e {
                foon_core::Error::Io { source, .. } => {
                    if source.kind() == std::io::ErrorKind::BrokenPipe {
                        broken.store(true, std::sync::atomic::Ordering::Relaxed);
                    }
                    foon_core::Error::io(std::path::Path::new("<stdout>"), source)
                }
                other => other,
            })
        }
    });
    if broken.load(std::sync::atomic::Ordering::Relaxed) {
        // The reader went away (`foon synth ... | head`): what the CLI ends quietly on.
        return Err(pyo3::exceptions::PyBrokenPipeError::new_err(
            "standard output closed",
        ));
    }
    let r = r?;
    Ok((r.units, r.bytes, r.recipes))
}

/// The kitchen matching the FOON of these options.
#[pyfunction]
pub(crate) fn synth_kitchen(
    py: Python<'_>,
    units: &Bound<'_, PyAny>,
    seed: u64,
) -> PyResult<crate::kitchen::PyKitchen> {
    let opts = options(units, seed, None)?;
    let k = enter(py, |_| {
        synth::synth_kitchen(&opts).and_then(|v| foon_core::Kitchen::from_specs(&v))
    })?;
    Ok(crate::kitchen::PyKitchen::of(k))
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

/// A side file of the generation (`kitchen`, `goals` with up to `count` goals, `motions`):
/// its text, or, given `path`, written there atomically (returning `None`).
#[pyfunction]
#[pyo3(signature = (units, seed, what, count = 25, path = None))]
pub(crate) fn synth_side(
    py: Python<'_>,
    units: &Bound<'_, PyAny>,
    seed: u64,
    what: &str,
    count: usize,
    path: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<String>> {
    let opts = options(units, seed, None)?;
    let path = opt_path_arg("path", path)?;
    enter(py, |_| {
        let text = synth::synth_side_text(&opts, what, count)?;
        match &path {
            Some(p) => synth::write_atomic(p, |w| {
                w.write_all(text.as_bytes())
                    .map_err(|e| foon_core::Error::io(p, e))
            })
            .map(|()| None),
            None => Ok(Some(text)),
        }
    })
}
