//! JSON out: kitchens and goals, verify reports, check findings and statistics, written by
//! the core's JSON writer (`foon_core::write::json`); task trees, FOONs and comparisons go
//! through the writers (`writers`) with the `json` format.

use foon_core::verify;
use foon_core::write::json::{self, CheckRow};
use pyo3::prelude::*;

use crate::convert::{ObjTuple, spec_of, specs_of};
use crate::errors::{PyFoonErr, enter};
use crate::foon::PyFoon;

/// A list of objects (a kitchen, goals) as JSON, in the kitchen and goal shape.
#[pyfunction]
pub(crate) fn objects_json(items: Vec<ObjTuple>) -> PyResult<String> {
    json::objects_json(&specs_of(items)).map_err(|e| PyFoonErr(e).into())
}

/// Checks the task tree `tree` against `foon` (as `Foon.verify_tree` does) and returns the
/// report as JSON (what `foon verify --json` prints).
#[pyfunction]
pub(crate) fn verify_json(
    py: Python<'_>,
    foon: &PyFoon,
    tree: &PyFoon,
    kitchen: PyRef<'_, crate::kitchen::PyKitchen>,
    utensils: Vec<String>,
    goal: ObjTuple,
) -> PyResult<String> {
    let kitchen = std::sync::Arc::clone(&kitchen.inner);
    let goal = spec_of(goal);
    let (foon, tree) = (&foon.inner, &tree.inner);
    enter(py, |_| {
        let r = verify::verify_tree(foon, tree, &kitchen, &utensils, &goal)?;
        json::verify_json(&r)
    })
}

/// A finding as `check` returns it: (path, line, column, severity, code, message).
type FindingRow = (Option<String>, u64, u32, String, String, String);

/// Findings of `check` as JSON (what `foon check --json` prints).
#[pyfunction]
pub(crate) fn check_json(findings: Vec<FindingRow>) -> PyResult<String> {
    let rows: Vec<CheckRow> = findings
        .into_iter()
        .map(|(path, line, column, severity, code, message)| CheckRow {
            path,
            line,
            column,
            severity,
            code,
            message,
        })
        .collect();
    json::check_json(&rows).map_err(|e| PyFoonErr(e).into())
}

/// The statistics of FOONs as JSON, each under the file name given (what `foon stats
/// --json` prints).
#[pyfunction]
pub(crate) fn stats_json(rows: Vec<(String, PyRef<'_, PyFoon>)>) -> PyResult<String> {
    let stats: Vec<(&str, foon_core::Stats)> = rows
        .iter()
        .map(|(file, f)| (file.as_str(), f.inner.stats()))
        .collect();
    json::stats_json(&stats).map_err(|e| PyFoonErr(e).into())
}
