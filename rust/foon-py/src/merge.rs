//! `foon._foon` merging: many FOON sources into one with provenance and support
//! (`foon_core::merge`), and where a unit came from.

use std::path::PathBuf;

use foon_core::ParseOptions;
use foon_core::merge::{self, MergeOptions, Merged};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{fu_index, opt_path_arg, path_arg, text_bytes};
use crate::errors::enter;
use crate::foon::PyFoon;
use crate::progress::enter_progress;

fn options(level: u8, min_support: u32, strict: bool) -> MergeOptions {
    MergeOptions {
        level,
        min_support,
        strict,
    }
}

/// The merge report as a dict (counts, the options and the one-line summary).
fn report<'py>(py: Python<'py>, m: &Merged) -> PyResult<Bound<'py, PyDict>> {
    let r = &m.report;
    let d = PyDict::new(py);
    d.set_item("sources", r.sources)?;
    d.set_item("units_read", r.units_read)?;
    d.set_item("faulty", r.faulty)?;
    d.set_item("duplicates", r.duplicates)?;
    d.set_item("same_at_level", r.same_at_level)?;
    d.set_item("below_support", r.below_support)?;
    d.set_item("kept", r.kept)?;
    d.set_item("objects", r.objects)?;
    d.set_item("motions", r.motions)?;
    d.set_item("level", m.options.level)?;
    d.set_item("min_support", m.options.min_support)?;
    d.set_item("summary", m.summary())?;
    d.set_item("header", merge::header_line(m))?;
    Ok(d)
}

/// Merges files and folders (a folder: its `.txt` and `.json` files, sorted); with `out`,
/// writes the merged text with its provenance there, atomically, never over an input.
/// Returns (FOON, report).
#[pyfunction]
#[pyo3(signature = (paths, *, level = 3, min_support = 1, strict = false, out = None, progress = false))]
pub(crate) fn merge_paths<'py>(
    py: Python<'py>,
    paths: Vec<Bound<'py, PyAny>>,
    level: u8,
    min_support: u32,
    strict: bool,
    out: Option<&Bound<'py, PyAny>>,
    progress: bool,
) -> PyResult<(PyFoon, Bound<'py, PyDict>)> {
    let paths: Vec<PathBuf> = paths
        .iter()
        .map(|p| path_arg("paths", p))
        .collect::<PyResult<_>>()?;
    let out = opt_path_arg("out", out)?;
    let opts = options(level, min_support, strict);
    let m = enter_progress(py, progress, false, |cancel, bar| {
        let m = merge::merge_files_with(&paths, opts, cancel, Some(bar))?;
        if let Some(o) = &out {
            merge::write_merged(&m, o)?;
        }
        Ok(m)
    })?;
    let d = report(py, &m)?;
    Ok((PyFoon::new(m.foon), d))
}

/// Merges sources given in memory as (name, text) pairs, in order. Returns (FOON, report).
#[pyfunction]
#[pyo3(signature = (sources, *, level = 3, min_support = 1, strict = false))]
pub(crate) fn merge_texts<'py>(
    py: Python<'py>,
    sources: Vec<(String, Bound<'py, PyAny>)>,
    level: u8,
    min_support: u32,
    strict: bool,
) -> PyResult<(PyFoon, Bound<'py, PyDict>)> {
    let data: Vec<(PathBuf, Vec<u8>)> = sources
        .iter()
        .map(|(n, t)| Ok((PathBuf::from(n), text_bytes("sources", t)?)))
        .collect::<PyResult<_>>()?;
    let opts = options(level, min_support, strict);
    let m = enter(py, |cancel| {
        let refs: Vec<(&std::path::Path, &[u8])> = data
            .iter()
            .map(|(p, d)| (p.as_path(), d.as_slice()))
            .collect();
        merge::merge_sources(&refs, opts, cancel)
    })?;
    let d = report(py, &m)?;
    Ok((PyFoon::new(m.foon), d))
}

/// The FOON as FOON text with its provenance as `#` comment lines (`header`: the text of the
/// first comment line).
#[pyfunction]
#[pyo3(signature = (foon, header = ""))]
pub(crate) fn merged_text(foon: &PyFoon, header: &str) -> String {
    merge::merged_text(&foon.inner, header)
}

/// Parses FOON text, reading the provenance comments of a merged file.
#[pyfunction]
#[pyo3(signature = (text, *, strict = false, path = None))]
pub(crate) fn parse_merged(
    py: Python<'_>,
    text: &Bound<'_, PyAny>,
    strict: bool,
    path: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyFoon> {
    let data = text_bytes("text", text)?;
    let path = opt_path_arg("path", path)?;
    let foon = enter(py, |_| {
        merge::parse_merged(&data, path.as_deref(), ParseOptions { strict })
    })?;
    Ok(PyFoon::new(foon))
}

/// Reads a FOON file, reading the provenance comments of a merged file.
#[pyfunction]
#[pyo3(signature = (path, *, strict = false))]
pub(crate) fn load_merged(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    strict: bool,
) -> PyResult<PyFoon> {
    let path = path_arg("path", path)?;
    let foon = enter(py, |_| merge::load_merged(&path, ParseOptions { strict }))?;
    Ok(PyFoon::new(foon))
}

/// Every (source path, line) where unit `fu` was found, its kept copy first.
#[pyfunction]
pub(crate) fn fu_sources(foon: &PyFoon, fu: &Bound<'_, PyAny>) -> PyResult<Vec<(String, u32)>> {
    let f = fu_index(&foon.inner, fu)?;
    Ok(merge::sources_of(&foon.inner, f)
        .into_iter()
        .map(|(s, l)| (s.to_owned(), l))
        .collect())
}

/// The number of distinct sources that hold unit `fu`.
#[pyfunction]
pub(crate) fn fu_support(foon: &PyFoon, fu: &Bound<'_, PyAny>) -> PyResult<usize> {
    let f = fu_index(&foon.inner, fu)?;
    Ok(foon.inner.support(f))
}

/// One line per unit: `unit I: support N: path:line, ...`.
#[pyfunction]
pub(crate) fn provenance_text(foon: &PyFoon) -> String {
    merge::provenance_text(&foon.inner)
}
