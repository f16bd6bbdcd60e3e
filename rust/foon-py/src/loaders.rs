//! Module functions: the kitchen, goal, rate and utensil loaders, the linter, method names,
//! object checking.

use foon_core::InputKind;
use foon_core::parse;
use foon_core::{MotionRates, ObjectSpec};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::convert::{
    ObjTuple, location, opt_path_arg, path_arg, rate_pairs_arg, spec_arg, spec_fields,
    spec_of_mapping, text_bytes, tuple_of,
};
use crate::errors::{PyFoonErr, enter};
use crate::kitchen::PyKitchen;

fn kind_of(kind: &str) -> PyResult<InputKind> {
    match kind {
        "kitchen" => Ok(InputKind::Kitchen),
        "goal" => Ok(InputKind::Goal),
        _ => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "unknown object list kind '{kind}' (choose from kitchen, goal)"
        ))),
    }
}

/// Checks an object's fields: (label, states tuple, ingredients tuple, container).
#[pyfunction]
#[pyo3(signature = (label, states, ingredients, container))]
pub(crate) fn object_fields<'py>(
    label: &Bound<'py, PyAny>,
    states: &Bound<'py, PyAny>,
    ingredients: &Bound<'py, PyAny>,
    container: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyTuple>> {
    let spec = spec_arg(label, states, ingredients, container)?;
    spec_fields(label.py(), spec)
}

/// Checks an object given as a kitchen/goal JSON-shaped mapping; returns its fields.
#[pyfunction]
pub(crate) fn object_fields_of_mapping<'py>(
    d: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyTuple>> {
    let spec = spec_of_mapping(d)?;
    spec_fields(d.py(), spec)
}

/// An object's identity by the core's rule: (label, sorted states, sorted ingredients,
/// container), for `Object.__eq__` and `__hash__`.
#[pyfunction]
pub(crate) fn object_identity(
    label: String,
    states: Vec<String>,
    ingredients: Vec<String>,
    container: Option<String>,
) -> (String, Vec<String>, Vec<String>, Option<String>) {
    let spec = ObjectSpec {
        label,
        states,
        ingredients,
        container,
    };
    let (label, states, ingredients, container) = spec.identity();
    (
        label.to_owned(),
        states.into_iter().map(str::to_owned).collect(),
        ingredients.into_iter().map(str::to_owned).collect(),
        container.map(str::to_owned),
    )
}

/// An object's one-line text: `label (states) {ingredients} in [container]`.
#[pyfunction]
pub(crate) fn object_text(
    label: String,
    states: Vec<String>,
    ingredients: Vec<String>,
    container: Option<String>,
) -> String {
    ObjectSpec {
        label,
        states,
        ingredients,
        container,
    }
    .describe()
}

/// Reads a list of objects (kitchen or goal; JSON or FOON object blocks) from a file.
#[pyfunction]
pub(crate) fn load_objects(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    kind: &str,
) -> PyResult<Vec<ObjTuple>> {
    let k = kind_of(kind)?;
    let path = path_arg("path", path)?;
    let v = enter(py, |_| parse::load_objects(&path, k))?;
    Ok(v.into_iter().map(tuple_of).collect())
}

/// Parses a list of objects from text; `path` only names the source in messages.
#[pyfunction]
#[pyo3(signature = (text, kind, path = None))]
pub(crate) fn parse_objects(
    py: Python<'_>,
    text: &Bound<'_, PyAny>,
    kind: &str,
    path: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<ObjTuple>> {
    let k = kind_of(kind)?;
    let data = text_bytes("text", text)?;
    let path = opt_path_arg("path", path)?;
    let v = enter(py, |_| parse::parse_objects(&data, path.as_deref(), k))?;
    Ok(v.into_iter().map(tuple_of).collect())
}

/// Reads a motion table: (motion, rate) pairs in file order.
#[pyfunction]
pub(crate) fn load_rates(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Vec<(String, f64)>> {
    let path = path_arg("path", path)?;
    Ok(enter(py, |_| parse::load_rates(&path))?.entries)
}

#[pyfunction]
#[pyo3(signature = (text, path = None))]
pub(crate) fn parse_rates(
    py: Python<'_>,
    text: &Bound<'_, PyAny>,
    path: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<(String, f64)>> {
    let data = text_bytes("text", text)?;
    let path = opt_path_arg("path", path)?;
    Ok(enter(py, |_| parse::parse_rates(&data, path.as_deref()))?.entries)
}

/// Checks (motion, rate) pairs by the core's rule; returns them.
#[pyfunction]
pub(crate) fn check_rates(pairs: &Bound<'_, PyAny>) -> PyResult<Vec<(String, f64)>> {
    let pairs = rate_pairs_arg("motions", pairs)?;
    Ok(MotionRates::from_pairs(pairs).map_err(PyFoonErr)?.entries)
}

/// Reads a utensil list.
#[pyfunction]
pub(crate) fn load_utensils(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    let path = path_arg("path", path)?;
    enter(py, |_| parse::load_utensils(&path))
}

#[pyfunction]
#[pyo3(signature = (text, path = None))]
pub(crate) fn parse_utensils(
    py: Python<'_>,
    text: &Bound<'_, PyAny>,
    path: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<String>> {
    let data = text_bytes("text", text)?;
    let path = opt_path_arg("path", path)?;
    enter(py, |_| parse::parse_utensils(&data, path.as_deref()))
}

/// A lint finding: (path, line, column, severity, code, message).
type FindingTuple = (Option<String>, u64, u32, &'static str, &'static str, String);

/// Checks FOON files: every error, warning and note of each, in line order.
#[pyfunction]
/// `rates_file` is a rate table read by the linter itself, so that its own problems (a bad
/// line, a motion with two rates) are findings too; `rates` are pairs given directly.
#[pyo3(signature = (paths, kitchen = None, rates = None, utensils = Vec::new(), rates_file = None))]
pub(crate) fn check(
    py: Python<'_>,
    paths: Vec<Bound<'_, PyAny>>,
    kitchen: Option<PyRef<'_, PyKitchen>>,
    rates: Option<Vec<(String, f64)>>,
    utensils: Vec<String>,
    rates_file: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<FindingTuple>> {
    let paths = paths
        .iter()
        .map(|p| path_arg("paths", p))
        .collect::<PyResult<Vec<_>>>()?;
    let rates_file = opt_path_arg("rates_file", rates_file)?;
    let kitchen = kitchen.map(|k| k.inner.specs());
    let rates = rates
        .map(MotionRates::from_pairs)
        .transpose()
        .map_err(PyFoonErr)?;
    let findings = enter(py, |cancel| {
        let mut all = Vec::new();
        let mut rates = rates;
        if let Some(p) = &rates_file {
            let (table, found) = foon_core::lint::lint_rates(p)?;
            all.extend(found);
            rates = Some(table);
        }
        let opts = foon_core::lint::LintOptions {
            kitchen: kitchen.as_deref(),
            rates: rates.as_ref(),
            utensils: &utensils,
        };
        for p in &paths {
            all.extend(foon_core::lint::lint_file_cancellable(p, &opts, cancel)?);
        }
        Ok(all)
    })?;
    Ok(findings
        .into_iter()
        .map(|f| {
            let (p, line, col) = location(&f.at);
            (p, line, col, f.severity.as_str(), f.code, f.message)
        })
        .collect())
}

/// Method names, in the order the comparison table lists them.
#[pyfunction]
pub(crate) fn methods() -> Vec<&'static str> {
    foon_core::Method::ALL.iter().map(|m| m.as_str()).collect()
}

/// The cap on worker threads (the available parallelism).
#[pyfunction]
pub(crate) fn max_threads() -> usize {
    foon_core::search::batch::max_threads()
}
